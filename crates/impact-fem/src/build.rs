//! Building the FEM: the whole mesh on one rank ([`Fem::new`]), or a box of its elements
//! (`slab.rs`, through [`Fem::on_box`]): the lumped mass, the shape-function gradients,
//! the boundary loads of the stored nodes (found on the whole mesh by global index, so a
//! box's cut faces carry none), the initial fields and `a^0`.
use crate::place::Place;
use crate::{loads, stencil, Fem, FemSolver, FemState, GaussPlasticity, MAX_NODES};
use impact_core::method::{MethodConfig, Model};
use impact_core::parallel::{threads, worth_parallel};
use impact_core::{CoreError, Grid, Problem, Vector};
use std::ops::Range;

impl<const D: usize> Fem<D> {
    /// Build the FEM for `problem`.
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Result<Self, CoreError> {
        let all: [Range<usize>; D] = std::array::from_fn(|k| 0..problem.grid.cells[k]);
        Self::on_box(problem, config, &all, &all)
    }

    /// The FEM of the elements `stored` (per axis, global indices) of `problem`'s mesh, of
    /// which it owns `owned` (`slab.rs`): its mesh is that box, its loads, prescribed
    /// velocities and initial fields those of the whole problem at the stored nodes (a face
    /// of the box inside the mesh is free), its energy, momentum, work, impulse, samples and
    /// checks those of the owned nodes and elements. With every element stored and owned,
    /// the whole problem.
    pub fn on_box(
        problem: &Problem<D>,
        config: MethodConfig,
        stored: &[Range<usize>; D],
        owned: &[Range<usize>; D],
    ) -> Result<Self, CoreError> {
        problem.check_config(&config)?;
        let place = Place::new(&problem.grid, stored, owned);
        let grid = (problem.grid).cut(
            stored.clone().map(|r| r.start),
            stored.clone().map(|r| r.len()),
        );
        let nodes = grid.vertex_count();
        let mass = lumped_mass(&grid, &place, problem.material.density);
        let (gauss_gradient, centre_gradient) = shape_gradients(&grid);
        let gauss_count = Grid::<D>::NODES_PER_CELL;
        let grid_cells = grid.cell_count();
        let global_nodes = (0..nodes).map(|i| place.global_node(i));
        let (loaded, constraints) = loads::boundary_loads(problem, global_nodes);
        let mut free_mask = vec![Vector::<D>::from_element(1.0); nodes];
        for c in &constraints {
            free_mask[c.carrier][c.axis] = 0.0;
        }
        let parallel = worth_parallel(grid.cell_count());
        let mut loaded_nodes: Vec<usize> = loaded.iter().map(|l| l.0).collect();
        loaded_nodes.sort_unstable();
        loaded_nodes.dedup();
        let mut solver = FemSolver {
            loaded_nodes,
            free_mask,
            config,
            grid,
            place,
            material: problem.material,
            model: problem.model,
            wave_speed: problem.max_wave_speed(),
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            mass,
            external: vec![Vector::<D>::zeros(); nodes],
            loaded,
            constraints,
            force: vec![Vector::<D>::zeros(); nodes],
            parallel,
            gauss_gradient,
            gauss_weight: 1.0 / gauss_count as f64,
            centre_gradient,
            plastic: match problem.model {
                Model::J2(j2) => Some(GaussPlasticity::new(j2, grid_cells * gauss_count)),
                _ => None,
            },
            stencil: None,
            fuse_step: true,
            band_layers: 0,
            halo: Vec::new(),
        };
        if problem.model == Model::LinearElastic {
            let stencil = stencil::Stencil::new(&solver.grid, &solver.element_stiffness());
            let band_layers = stencil.band_layers(threads(), parallel);
            let bands = stencil.layers().div_ceil(band_layers);
            solver.halo = vec![Vector::<D>::zeros(); 2 * bands * stencil.layer_nodes()];
            solver.band_layers = band_layers;
            solver.stencil = Some(stencil);
            // the stencil writes the acceleration only: no force array
            solver.force = Vec::new();
        }
        // v^{-1/2} holds v(0): the first step's half step Δt/2 then gives v^{1/2}
        let at = |v: usize| solver.place.node_position(v);
        let velocity_half = (0..nodes)
            .map(|v| problem.initial.velocity(&at(v)))
            .collect();
        // u(0): zero but for a plane wave, whose stress FEM takes as its displacement
        let displacement = (0..nodes)
            .map(|v| problem.initial.displacement(&at(v)))
            .collect();
        let mut state = FemState {
            displacement,
            velocity_half,
            acceleration: vec![Vector::<D>::zeros(); nodes],
            last_dt: 0.0,
            work: 0.0,
            impulse: Vector::<D>::zeros(),
            initial_energy: 0.0,
        };
        solver.set_load_window((0.0, 0.0));
        solver.internal_forces_into(&state.displacement, &mut state.acceleration);
        let mut fem = Self { solver, state };
        fem.state.initial_energy = impact_core::Method::energy(&fem);
        Ok(fem)
    }
}

/// Row-sum lumped mass: each element's `ρ V_e` shared equally among its nodes, so a node's
/// mass is that share added once per element of the WHOLE mesh around it
/// ([`Place::elements_around`]; the same additions, in the same order, as a loop over the
/// elements). A box's halo nodes on a cut face thus carry their whole-mesh mass, not the
/// part of the stored elements: a load's change of step mean at such a node
/// (`hold_velocities`, `f Δḡ / m`) then moves it as on one rank, which the owned nodes next
/// to it read.
fn lumped_mass<const D: usize>(grid: &Grid<D>, place: &Place<D>, density: f64) -> Vec<f64> {
    let share = density * grid.cell_volume() / Grid::<D>::NODES_PER_CELL as f64;
    (0..grid.vertex_count())
        .map(|i| (0..place.elements_around(i)).fold(0.0, |m, _| m + share))
        .collect()
}

/// Shape-function gradients at the `2^D` Gauss points `ξ = ½ ± 1/(2√3)` per axis (node
/// `a` of point `q` at `[q·npc + a]`) and at the element centre.
fn shape_gradients<const D: usize>(grid: &Grid<D>) -> (Vec<Vector<D>>, [Vector<D>; MAX_NODES]) {
    let npc = Grid::<D>::NODES_PER_CELL;
    let g = 0.5 / 3f64.sqrt();
    let mut gauss_gradient = vec![Vector::<D>::zeros(); npc * npc];
    let mut values = [0.0; MAX_NODES];
    for q in 0..npc {
        let xi = Vector::<D>::from_fn(|l, _| if (q >> l) & 1 == 1 { 0.5 + g } else { 0.5 - g });
        grid.shape(
            &xi,
            &mut values[..npc],
            &mut gauss_gradient[q * npc..(q + 1) * npc],
        );
    }
    let mut centre_gradient = [Vector::<D>::zeros(); MAX_NODES];
    grid.shape(
        &Vector::<D>::from_element(0.5),
        &mut values[..npc],
        &mut centre_gradient[..npc],
    );
    (gauss_gradient, centre_gradient)
}

//! Building the FEM: the whole mesh on one rank ([`Fem::new`]), or a slab of its element
//! layers (`slab.rs`, through [`Fem::on_layers`]): the lumped mass, the shape-function
//! gradients, the boundary loads of the stored nodes (found on the whole mesh by global
//! index, so a slab's cut faces carry none), the initial fields and `a^0`.
use crate::place::Place;
use crate::{loads, stencil, Fem, FemSolver, FemState, GaussPlasticity, MAX_NODES};
use impact_core::method::{MethodConfig, Model};
use impact_core::parallel::{threads, worth_parallel};
use impact_core::{CoreError, Grid, Problem, Vector};
use std::ops::Range;

impl<const D: usize> Fem<D> {
    /// Build the FEM for `problem`.
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Result<Self, CoreError> {
        let layers = 0..problem.grid.cells[D - 1];
        Self::on_layers(problem, config, &layers, &layers)
    }

    /// The FEM of the element layers `stored` (along the last axis, global indices) of
    /// `problem`'s mesh, of which it owns `owned` (`slab.rs`): its mesh is those layers,
    /// its loads, prescribed velocities and initial fields those of the whole problem at
    /// the stored nodes (a face of the stored layers inside the mesh is free), its
    /// energy, momentum, work, impulse, samples and checks those of the owned nodes and
    /// elements. With every layer stored and owned, the whole problem.
    pub fn on_layers(
        problem: &Problem<D>,
        config: MethodConfig,
        stored: &Range<usize>,
        owned: &Range<usize>,
    ) -> Result<Self, CoreError> {
        problem.check_config(&config)?;
        let place = Place::new(&problem.grid, stored, owned);
        let grid = problem.grid.layers(stored.start, stored.len());
        let nodes = grid.vertex_count();
        let mass = lumped_mass(&grid, problem.material.density);
        let (gauss_gradient, centre_gradient) = shape_gradients(&grid);
        let gauss_count = Grid::<D>::NODES_PER_CELL;
        let grid_cells = grid.cell_count();
        let first_node = place.global_node(0);
        let (loaded, constraints) = loads::boundary_loads(problem, first_node..first_node + nodes);
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

/// Row-sum lumped mass: each element's `ρ V_e` shared equally among its nodes.
fn lumped_mass<const D: usize>(grid: &Grid<D>, density: f64) -> Vec<f64> {
    let npc = Grid::<D>::NODES_PER_CELL;
    let mut mass = vec![0.0; grid.vertex_count()];
    let element_mass = density * grid.cell_volume();
    for c in 0..grid.cell_count() {
        for a in 0..npc {
            mass[grid.vertex_of(c, a)] += element_mass / npc as f64;
        }
    }
    mass
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

//! Update-stress-last material point method (Sulsky, Zhou & Schreyer 1995) on a fixed,
//! padded background grid, with the shape functions of [`shape`] (linear hats by default;
//! uniform GIMP, quadratic and cubic B-splines as options).
//!
//! One step, one phase per function:
//! 1. [`MpmSolver::particles_to_grid`]: nodal mass `m_i = Σ_p N_ip m_p`, momentum
//!    `p_i = Σ_p N_ip m_p v_p`, internal force `f_i = -Σ_p V_p σ_p ∇N_ip`; external forces
//!    (a pressure `p` on a loaded edge is the nodal force `f_i = N_i(x_s) p A` at the
//!    body's surface `x_s`).
//! 2. [`MpmSolver::grid_update`]: `p_i += Δt f_i`; prescribed velocities are imposed on
//!    their nodes; symmetry edges zero the normal component.
//! 3. [`MpmSolver::grid_to_particles`]: `v_p += Δt Σ_i N_ip f_i/m_i` (FLIP, the default;
//!    the transfer is an option, [`MpmTransfer`](impact_core::method::MpmTransfer): PIC `v_p = Σ_i N_ip p_i/m_i`, a blend of
//!    the two, or APIC with an affine velocity per point, `affine.rs`) and
//!    `x_p += Δt Σ_i N_ip p_i/m_i`.
//! 4. MUSL only ([`MpmSolver::remap_momentum`]): `p_i = Σ_p N_ip m_p v_p^{n+1}` again.
//! 5. [`MpmSolver::update_stress`]: with the nodal velocity `v_i = p_i/m_i`,
//!    `ε̇_p = sym(Σ_i v_i ⊗ ∇N_ip)`, `σ_p += Δt C:ε̇_p` (and `V_p *= 1 + Δt tr ε̇_p` in the
//!    updated Lagrangian frame).
//!
//! Under USL with small strain and no CPDI domains, phases 3 and 5 run in one gather of
//! each point's nodes ([`MpmSolver::grid_to_particles_and_stress`]: nothing between them
//! touches the nodes); [`MpmSolver::set_fused_gather`] runs them apart, the reference it is
//! tested against (to 1e-13). In the total Lagrangian frame, where every point's weights
//! are the same (one point at the same place in every cell), one row of weights is stored
//! for all ([`MpmSolver::shares_weights`]); otherwise each distinct row once, and per point
//! its index in that table ([`MpmSolver::weight_rows`]).
//!
//! Variants ([`StressUpdate`]): `Usl` (default) takes the grid-updated velocity
//! `v_i + Δt f_i/m_i` for the strain rate; `Musl` remaps it from the updated point
//! velocities first (phase 4; damps, and is stable past Courant 1 here); `Usf` updates
//! the stress before the internal force, from the velocity mapped at the start of the step.
//!
//! Frame ([`MpmFrame`](impact_core::method::MpmFrame)): the default is the total Lagrangian form the paper uses for its
//! comparisons (§5.3: "MPM, DGMPM (both in total Lagrangian formulation)"): shape
//! functions at the points' reference positions and reference volumes, so the grid is the
//! reference configuration, as for DGMPM and FEM. Positions are still integrated
//! (`x_p += Δt v`) for output. The updated Lagrangian form (points move through the
//! grid) is the option: with linear shape functions it suffers cell-crossing errors that do
//! not shrink under refinement (measured on the bar: L1 error 0.10 at 300 cells, 0.22 at
//! 1200) and, with plain USL, a vanishing nodal mass when a node's last point leaves it.
//!
//! With these defaults (TL, USL, 1 point per cell) the bar is stable at the paper's
//! Courant 0.5 and unstable above 0.708 (the limit `impact`'s guard measures; the loaded
//! bar blows up at 0.72 and above), as the paper reports ("the MPM is unstable with
//! α = 1").
//!
//! Other choices where the paper is silent: the background grid is the body's grid
//! extended by [`PADDING`] cells on every side so points may move in the updated frame;
//! nodes with no mass are skipped; a surface load is spread over the nodes of the
//! surface's cell that carry mass (renormalised shape functions), so the whole load
//! reaches the body when the outer node of that cell has lost its points.
//!
//! Layout: `shape.rs` (the shape functions and their stencils: a new one goes there),
//! `weights.rs` (their values at the points: one row per point, one shared row, or a table
//! of the distinct rows),
//! `transfer.rs` (phases 1, 3, 4, 5: the scatters, coloured by node layer, and the gathers),
//! `affine.rs` (APIC's gather), `loads.rs` (the loads' nodal forces and the prescribed point
//! velocities), `grid_update.rs`
//! (phase 2), `method.rs` (the `Method` impl), `build.rs` (building the solver on the whole
//! body or one rank's box, and where it lies in the whole run), `slab.rs` (a rank's box of a
//! run split over several: issue 27), `migrate.rs` (slabs in the updated Lagrangian frame,
//! points migrating between them); this file holds the solver and its buffers.
//!
//! Every piece is dimension-generic (`const D`): in 3D the stencils have 8, 27 or 64 nodes
//! (tensor products of the 1D weights) and CPDI domains are parallelepipeds with 8 corners
//! (`cpdi.rs`). A 3D block invariant along z gives its 2D plane-strain section, and one
//! invariant along y and z with `ν = 0` the 1D bar, to round-off for every option
//! (`tests/reductions.rs`).

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
mod affine;
mod build;
mod cpdi;
mod edges;
mod face_lists;
mod grid_update;
mod loads;
mod method;
pub mod migrate;
mod migrate_rows;
pub mod shape;
pub mod slab;
use build::Place;
use edges::{MirrorConstraint, SurfaceLoad};
mod transfer;
mod weights;
use impact_core::method::{MethodConfig, Model, MpmOptions, StressUpdate};
use impact_core::points::MaterialPoints;
use impact_core::{Constraint, CoreError, Grid, LinearElastic, Problem, Tensor, Vector};

/// Cells added on every side of the body's grid for the background grid.
pub const PADDING: usize = 4;
const MAX_NODES: usize = 8;

/// The MPM state: points and the work done on them by the loads.
#[derive(Debug, Clone)]
pub struct MpmState<const D: usize> {
    /// Material points.
    pub points: MaterialPoints<D>,
    /// Work done by the loads since `t = 0`.
    pub work: f64,
    /// Impulse of the loads and of the prescribed velocities since `t = 0`.
    pub impulse: Vector<D>,
    /// Energy of the state at `t = 0` (J).
    pub initial_energy: f64,
    /// APIC's affine velocity `C_p = B_p D_p⁻¹` of each point (`crate::affine`; empty with
    /// the other transfers), zero at `t = 0`.
    pub affine: Vec<Tensor<D>>,
}

/// Nodal sums of the background grid (struct of arrays).
#[derive(Debug, Clone, Default)]
pub(crate) struct NodeSums<const D: usize> {
    /// `m_i`.
    pub mass: Vec<f64>,
    /// `p_i`.
    pub momentum: Vec<Vector<D>>,
    /// `f_i`.
    pub force: Vec<Vector<D>>,
    /// The total Lagrangian frame's `m_i = Σ_p N_ip m_p` as phase 1's default scatter
    /// (`transfer/plain.rs`) added it (before the padding's fold, `grid_update.rs`): the
    /// weights, the points' masses and the order of the additions are the same every step,
    /// so are these sums, and that scatter copies them into `mass` instead of adding the
    /// masses again (3 instructions a node-point pair and the zeroing of `mass` less).
    /// Empty in the updated Lagrangian frame (the weights change every step).
    pub point_mass: Vec<f64>,
    /// Whether `point_mass` holds the sums of the current weights (formed by the first
    /// scatter after the weights were evaluated: `MpmSolver::update_shapes`,
    /// `MpmSolver::unshare_weights`).
    pub point_mass_ready: bool,
    /// `Δv_i = f_i (Δt (1/m_i))` after the grid update and its constraints (0 for an
    /// empty node), with the step's `Δt`: the velocity increment the FLIP gathers
    /// interpolate, formed once per node instead of `f_i (N_ip Δt (1/m_i))` once per
    /// node-point pair (a different rounding: `transfer/tests.rs`).
    pub increment: Vec<Vector<D>>,
    /// The `Δt` of `increment` (the last grid update's step).
    pub increment_dt: f64,
    /// `v_i = p_i (1/m_i)` after the grid update and its constraints (0 for an empty
    /// node): formed once per node instead of once per node-point pair in the gathers (the
    /// same product).
    pub velocity: Vec<Vector<D>>,
}

/// A band of the nodal sums (two node layers of a colour pass) that a scatter writes:
/// node `i` is entry `i - offset`.
pub(crate) struct Band<'a, const D: usize> {
    /// `m_i`.
    pub mass: &'a mut [f64],
    /// `p_i`.
    pub momentum: &'a mut [Vector<D>],
    /// `f_i`.
    pub force: &'a mut [Vector<D>],
    /// The first node of the band.
    pub offset: usize,
}

impl<const D: usize> NodeSums<D> {
    /// The sums of `nodes` nodes, zero; with `fixed_mass` (the total Lagrangian frame) room
    /// for `point_mass`.
    fn new(nodes: usize, fixed_mass: bool) -> Self {
        Self {
            mass: vec![0.0; nodes],
            momentum: vec![Vector::<D>::zeros(); nodes],
            force: vec![Vector::<D>::zeros(); nodes],
            point_mass: if fixed_mass {
                vec![0.0; nodes]
            } else {
                Vec::new()
            },
            point_mass_ready: false,
            increment: vec![Vector::<D>::zeros(); nodes],
            increment_dt: 0.0,
            velocity: vec![Vector::<D>::zeros(); nodes],
        }
    }
}

/// The nodes that count as empty: a node is empty when its mass is at most
/// `m_floor 2^{-w_i}`, `m_floor = 10⁻¹⁰ n min_p m_p` (`n` points per cell: a cell's mass,
/// whatever the seeding, as the nodal masses are), with `w_i` the number of mirror planes
/// (wall layers of velocity and symmetry edges, `edges.rs`) node `i` lies on. A smooth
/// stencil (GIMP, B-splines) gives round-off weights (~1e-15) to nodes at its edge; with USL
/// their velocity `p_i/m_i` would be divided by that round-off. The factor `2^{-w_i}`
/// tests the mass the node would have in the body mirrored across its walls (`2^{w_i} m_i`:
/// a wall node holds half of its mirrored sums per wall), so the test does not depend on
/// how many cells a symmetric direction has: a 3D block invariant along z (symmetry on both
/// z faces, every node on one or two of them) keeps the empty nodes of the 2D run.
#[derive(Debug, Clone)]
pub(crate) struct EmptyNodes {
    /// `w_i` per node.
    walls: Vec<u8>,
    /// `m_floor 2^{-w}` for `w = 0..=3`.
    floors: [f64; 4],
}

impl EmptyNodes {
    /// `lightest`: `min_p m_p` over every point of the body (a slab's floor is the whole
    /// run's).
    fn new(lightest: f64, per_cell: usize, walls: Vec<u8>) -> Self {
        let floor = 1e-10 * per_cell as f64 * lightest;
        Self {
            walls,
            floors: std::array::from_fn(|w| floor * 0.5f64.powi(w as i32)),
        }
    }

    /// The floor as `fraction n min_p m_p` instead of `10⁻¹⁰ n min_p m_p`.
    fn rescale(&mut self, fraction: f64) {
        let scale = fraction / 1e-10;
        self.floors.iter_mut().for_each(|f| *f *= scale);
    }

    /// Whether node `i`, of mass `mass`, carries mass (is not empty).
    #[inline]
    pub fn holds(&self, i: usize, mass: f64) -> bool {
        self.holds_on(self.walls[i], mass)
    }

    /// Whether a node on `walls` mirror planes, of mass `mass`, carries mass.
    #[inline]
    pub fn holds_on(&self, walls: u8, mass: f64) -> bool {
        mass > self.floors[usize::from(walls)]
    }

    /// `w_i` of the nodes `range`.
    #[inline]
    pub fn walls_of(&self, range: std::ops::Range<usize>) -> &[u8] {
        &self.walls[range]
    }
}

/// Configuration and buffers of USL MPM.
#[derive(Debug, Clone)]
pub struct MpmSolver<const D: usize> {
    config: MethodConfig,
    options: MpmOptions,
    body: Grid<D>,
    grid: Grid<D>,
    material: LinearElastic,
    model: Model,
    /// Largest wave speed the loads can produce (time step).
    wave_speed: f64,
    loads: Vec<SurfaceLoad<D>>,
    /// Each load's nodes and shares this step (`loads` module).
    load_splits: Vec<loads::LoadSplit<D>>,
    /// Prescribed nodal velocity components `(node, axis, value)` (velocity and symmetry
    /// edges), found once.
    node_constraints: Vec<Constraint>,
    /// Padding nodes beyond velocity and symmetry edges, mirrored from the interior
    /// (`edges` module doc).
    mirror_constraints: Vec<MirrorConstraint>,
    /// The node components the padding fold changes and by how much this step (the
    /// wall's work and impulse, [`grid_update::FoldChange`]).
    fold_changes: Vec<grid_update::FoldChange>,
    /// Prescribed point velocity components (velocity edges).
    point_constraints: Vec<Constraint>,
    nodes: NodeSums<D>,
    /// The points sorted by the layer (along the last axis) of their cell, and where each
    /// layer starts in that order (`layers + 1` entries): the colouring of the scatters.
    layer_order: Vec<usize>,
    layer_start: Vec<usize>,
    /// Whether `layer_order` is the points' own order (then it is not read, and is freed in
    /// the total Lagrangian frame).
    in_layer_order: bool,
    parallel: bool,
    /// Which nodes are empty ([`EmptyNodes`]).
    empty: EmptyNodes,
    /// The shape functions' stencil ([`shape`]).
    stencil: shape::Stencil<D>,
    /// Per point: the linear index of its stencil's base node. Rows of shape values and
    /// gradients (`stencil.nodes` each): point `p`'s row starts at `r · weight_stride`,
    /// `r = point_row[p]` where `point_row` is not empty, else `r = p`.
    point_base: Vec<usize>,
    shape: Vec<f64>,
    shape_gradient: Vec<Vector<D>>,
    /// `stencil.nodes`, or 0 where every point has the same weights (total Lagrangian, one
    /// point at the same place in every cell: one row is stored, 96 B per point less with
    /// 2D hats, and the scatter and gathers read it from cache).
    weight_stride: usize,
    /// Total Lagrangian with several distinct rows (`crate::weights`): each point's row in
    /// the table `shape`/`shape_gradient` of the distinct rows (4 B per point instead of a
    /// row: 216 B with 2D B-splines); empty where each point has its own row (`r = p`) or
    /// all share one.
    point_row: Vec<u32>,
    /// Whether the shape functions at the reference positions are cached (total Lagrangian).
    shapes_ready: bool,
    /// Whether USL runs phases 3 and 5 in one gather ([`MpmSolver::fused_gather`]).
    fuse_gathers: bool,
    /// Where this solver's nodes and points lie in the whole run ([`Place`]).
    place: Place<D>,
}

/// USL MPM as a [`Method`](impact_core::Method).
#[derive(Debug, Clone)]
pub struct Mpm<const D: usize> {
    /// Configuration and buffers.
    pub solver: MpmSolver<D>,
    /// Points.
    pub state: MpmState<D>,
}

impl<const D: usize> Mpm<D> {
    /// Build MPM for `problem`.
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Result<Self, CoreError> {
        Self::build(problem, config, None)
    }
}

impl<const D: usize> MpmSolver<D> {
    /// One step (module doc) from `t` to `t + Δt`. Surface loads act at their step average
    /// `p ḡ`, `ḡ = (I(t + Δt) - I(t))/Δt` (`impact_core::load`: the step's impulse to
    /// round-off); prescribed velocities take their step average too (the velocity that
    /// moves the points over the step: the loaded face's displacement is exact).
    pub fn step(&mut self, state: &mut MpmState<D>, t: f64, dt: f64) {
        let window = (t, t + dt);
        let usl = self.options.stress_update != StressUpdate::Usf;
        self.particles_to_grid(&state.points, &state.affine, usl);
        self.shapes_ready = true;
        if !usl {
            self.update_stress(&mut state.points, dt);
            self.internal_forces(&state.points);
        }
        self.external_forces(&state.points, window);
        for load in self.loads.iter().filter(|l| self.place.owns(l.point)) {
            state.impulse += load.force * (load.history.mean(t, t + dt) * dt);
        }
        let (work, impulse) = self.grid_update(dt, window);
        state.impulse += impulse;
        let fused = self.fused_gather(&state.points);
        if fused {
            self.grid_to_particles_and_stress(&mut state.points, &mut state.affine, dt);
        } else {
            self.grid_to_particles(&mut state.points, &mut state.affine, dt);
        }
        state.work += work + dt * self.load_power(&state.points, window);
        state.impulse += self.impose_point_velocities(&mut state.points, window);
        if self.options.stress_update == StressUpdate::Musl {
            self.remap_momentum(&state.points, &state.affine, window);
        }
        if usl && !fused {
            self.update_stress(&mut state.points, dt);
        }
    }

    /// Whether this step runs phases 3 and 5 in one gather
    /// ([`MpmSolver::grid_to_particles_and_stress`]): USL (nothing between the two phases
    /// touches the nodes), small strain, no CPDI domains; unless switched off
    /// ([`MpmSolver::set_fused_gather`]).
    fn fused_gather(&self, points: &MaterialPoints<D>) -> bool {
        self.fuse_gathers
            && self.options.stress_update == StressUpdate::Usl
            && matches!(self.model, Model::LinearElastic | Model::J2(_))
            && points.domain.is_empty()
    }

    /// The empty-node floor as a fraction of a cell's mass (default `1e-10`,
    /// `EmptyNodes`'s doc): the momentum conservation tests lower it to show that what
    /// APIC loses in the updated frame is what the floor drops (the forces on nodes whose
    /// weights fall below it), not the transfer.
    pub fn set_empty_node_floor(&mut self, fraction: f64) {
        self.empty.rescale(fraction);
    }

    /// Run phases 3 and 5 as separate gathers (`false`; the reference the fused gather is
    /// tested against) or fused where they can be (`true`, the default).
    pub fn set_fused_gather(&mut self, fused: bool) {
        self.fuse_gathers = fused;
    }
}

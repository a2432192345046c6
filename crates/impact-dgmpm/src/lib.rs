//! Discontinuous Galerkin material point method (DGMPM), Renaud & Heuzé, COMPDYN 2017.
//!
//! Material points sit in an Eulerian grid; each cell carries its own multilinear nodal
//! fields (stress `σ_i` and velocity `v_i` on its `2^D` corners), discontinuous across
//! faces. One step (forward Euler) is, one phase per function:
//!
//! 1. [`DgmpmSolver::particles_to_nodes`]: lumped mass `M_i = Σ_α S_iα m_α` and the
//!    mass-weighted map `M_i q_i = Σ_α S_iα m_α q_α` (paper eq. 17).
//! 2. [`DgmpmSolver::interface_fluxes`]: on each face, the left/right states are the
//!    averages of each side's face nodes (paper §4); the exact linear-elastic Riemann
//!    solver ([`riemann`]) gives the Godunov state `(v*, t*)`; boundary faces use ghost
//!    states (LeVeque 2002 §7.3) for free, pressure, velocity and symmetry edges. In 2D and
//!    3D with `--flux ctu`, [`DgmpmSolver::transverse_corrections`] then adds the corner
//!    transport upwind corrections (3D: transverse and transverse-transverse, `ctu3.rs`);
//!    donor-cell (`dcu`) never computes them.
//! 3. [`DgmpmSolver::nodal_rates`]: the semi-discrete system (paper eq. 16) with the volume
//!    term on the points, the nodal field interpolated there (paper eq. 14-15):
//!    `M_i dv_i/dt = -Σ_α V_α σ_h(X_α) ∇S_iα + Σ_f ∫_f S_i t*_out dΓ`,
//!    `(M_i/ρ) dσ_i/dt = C : [-Σ_α V_α sym(v_h(X_α) ⊗ ∇S_iα) + Σ_f ∫_f S_i sym(v* ⊗ n) dΓ]`.
//! 4. [`DgmpmSolver::nodal_update`]: forward Euler, or two-stage RK2 (Heun), repeating 2-3.
//! 5. [`DgmpmSolver::nodes_to_particles`]: see [`PointUpdate`].
//!
//! **Cell path** (one point per cell, forward Euler: the paper's §5 setting). There every
//! node of a cell carries the point's state after phase 1, and phases 3-5 reduce exactly to
//! the cell-centred Godunov update `q ← q - Δt Σ_l (F_l,high - F_l,low)/Δx_l`
//! ([`DgmpmSolver::cell_update`], derivation in its doc). The step is then
//! `interface_fluxes` (face states read from the points), `transverse_corrections` (CTU),
//! `boundary_force`, `cell_update`; the nodal buffers are not allocated. It is tested equal
//! to phases 1-5 to round-off (1D/2D, CTU/donor-cell, linear and SVK), and
//! [`DgmpmSolver::set_step_path`] picks another path for comparison ([`StepPath`]).
//!
//! **Fused path** (the cell path with linear elasticity, the default there): its phases in
//! one sweep over the cell rows (3D: layers), each face solved once, rolling rows (planes)
//! of faces, no face arrays ([`fused`]); tested equal to the cell path (3D: bit for bit).
//!
//! **Fused nodal sweep** (the nodal paths with linear elasticity in 1D or 2D: RK2, several
//! points per cell, the increment update; the default there): phases 2-4 of each stage in
//! the same sweep, the face states read from the DG nodes and each cell's nodal rates and
//! update formed from its four final fluxes (`DgmpmSolver::rates_of_cell`, shared with
//! the phase path), phase 5 in the step's last stage, and with RK2 at one point per cell no
//! phase 1 (the first stage reads the points); no face or rate arrays. With RK2 at one
//! point per cell strictly inside its cell, both stages are cell sweeps: the first forms
//! each cell's side states in closed form from its state and fluxes with fixed weights,
//! the second is a cell update from the fluxes of those states (`fused/heun.rs`; no nodal
//! field). Tested equal to the nodal phases to 1e-13.
//!
//! **Volume weights** (the nodal paths with linear elasticity and `2^D` points per cell or
//! more): phase 3's volume term `-Σ_α V_α σ_h(X_α) ∇S_iα` is `-Σ_b σ_b K_ib` with the
//! cell's weights `K_ib = Σ_α V_α S_bα ∇S_iα`, formed once (`layouts::cell_volume_weights`);
//! they replace the points' gradients, and the last node's row is not stored (`Σ_i K_ib = 0`:
//! its terms are minus the others'). Tested equal to the per-point sums to 1e-13.
//!
//! **Mapping weights** (the nodal paths with several points per cell): phase 1 is
//! `q_i = Σ_α W_αi q_α` with `W_αi = S_iα m_α / M_i` and the lumped masses `M_i` formed
//! once (`layouts::cell_mapping_weights`: the points never move in the grid and their
//! masses are fixed), a small dense product per cell.
//!
//! **Cell layouts** (the nodal paths): the shape values, gradients, volume and mapping
//! weights and lumped masses of a cell depend only on its points' reference local
//! coordinates, masses and volumes, so each distinct set (bit-equal blocks) is stored once
//! and each cell holds a `u32` layout index (`layouts.rs`): a uniform seeding has a few
//! hundred layouts at most, an irregular one up to one per cell. The step reads the same
//! values as per-cell arrays would hold (outputs bit for bit equal). Tested equal to the per-node sums to 1e-13.
//!
//! Choices where the paper is silent, with their reasons:
//! - **Point update** ([`PointUpdate`]): the default is `Nodal` (points take the
//!   interpolated new nodal field, `q_α = Σ_i S_iα q_i^{n+1}`). The point state then stays
//!   in the span of the cell's DG space, so there are no sub-cell modes the grid cannot see
//!   and cannot damp; with one point per cell it makes DGMPM exactly the first-order
//!   Godunov finite-volume scheme (the Courant-1 exactness proven in the tests). `Increment`
//!   (`q_α += Σ_i S_iα (q_i^{n+1} - q_i^n)`, FLIP-like) keeps sub-cell detail but leaves
//!   those modes undamped; it is offered for experiments.
//! - **Points do not move** in the small-strain scenes: the grid is the reference
//!   configuration of a total Lagrangian formulation (paper eq. 11-13), so the shape
//!   function values at the points are computed once (and stored once per distinct cell
//!   layout).
//! - **RK2** is Heun's method (the two-stage SSP Runge-Kutta scheme, TVD under the same
//!   Courant limit as Euler for a TVD spatial operator).
//! - **Face states** are the averages of each side's face nodes (paper §4), so a face has
//!   one Riemann problem and one flux, constant along it. With several points per cell the
//!   volume term sees the nodal field vary along the face while the flux does not, which
//!   leaves a zero-mean sub-cell mode (in a plane wave: opposite `v_y` in a cell's bottom
//!   and top points, about 0.1 % of the impact velocity); cell averages are unaffected.
//! - **CTU at the edges**: cells outside an edge are ghost cells (mirror states through the
//!   edge's condition), so their fluctuations correct the edge fluxes as inside; the
//!   correction on an edge face is then restricted to what the edge's condition leaves
//!   free ([`riemann::constrain_correction`]), so free edges stay exactly traction-free
//!   and a plane wave along a symmetry edge stays plane. In 3D the same, and behind two
//!   edges (the transverse-transverse terms) the ghost's fluctuations are mirrored through
//!   a symmetry edge, copied otherwise (`ctu3.rs`). Stability at one point per cell (von
//!   Neumann): CTU 1 in 1D, 2D and 3D with Euler; donor-cell 0.6517 (2D), 0.4833 (3D). At a corner where both edges
//!   prescribe a traction, the ghost's face towards the diagonal (defined by neither
//!   condition) carries no fluctuation: with it, CTU with all edges free was unstable from
//!   Courant 0.99; without it the limit is 1. With RK2, CTU corrects both stages (limit
//!   about 0.75).
//! - Every cell must hold points (the paper's scenes fill their grid); points are stored
//!   cell by cell, `points_per_cell` each.
//! - Rayon parallelises over cells and faces (disjoint writes) from 4,096 cells on, through
//!   [`impact_core::parallel`] (one serial/parallel dispatch for every loop). Face
//!   and cell loops walk their chunks with a multi-index odometer and plain index
//!   arithmetic: per-face divisions, and multi-index entries written at an axis known only
//!   at run time (a store-forwarding stall), had cost about half of the CTU step.

//!
//! ## Files, one phase each
//! - [`faces`]: face indexing, face states and ghost conditions.
//! - [`mapping`]: phase 1 (particles→nodes) and phase 5 (nodes→particles).
//! - `layouts.rs`: the nodal paths' per-cell weights, formed once and stored once per
//!   distinct cell layout.
//! - [`fluxes`]: phase 2, interface fluxes (linear and SVK) and the boundary force.
//! - [`ctu`]: phase 2b, corner transport upwind corrections (2D; the 3D dispatch).
//! - `ctu3.rs`: phase 2b in 3D, the transverse and transverse-transverse corrections
//!   through per-cell sources (Clawpack's `flux3`, `method(3) = 11`).
//! - [`integrator`]: phases 3-4 and the step (`stage`, once for Euler, twice for RK2).
//! - [`cell_path`]: the cell-centred update of the cell path.
//! - [`fused`]: the cell path's phases in one sweep (linear; 3D in `fused/block.rs`), and
//!   the nodal stages' (linear, 1D and 2D).
//! - `step_path.rs`: [`StepPath`], which of these computations a step runs.
//! - [`wave_correction`]: phase 2c, `order = 2`'s limited wave corrections (1D-3D, limiters
//!   in [`limiter`]); they route the step off the fused paths (to the cell or nodal ones).
//! - [`riemann`]: the Riemann solvers (one file each); a new solver goes there.
//! - [`method`]: the [`Method`](impact_core::Method) impl.

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
pub mod cell_path;
pub mod ctu;
mod ctu3;
pub mod faces;
pub mod fluxes;
pub mod fused;
pub mod integrator;
mod layouts;
pub mod limiter;
pub mod mapping;
pub mod method;
pub mod riemann;
pub mod slab;
mod solver_build;
mod step_path;
#[cfg(test)]
mod test_scenes;
pub mod wave_correction;
pub use step_path::{Fusable, StepPath};

use impact_core::material::Svk;
use impact_core::method::{
    DgmpmOptions, Integrator, MethodConfig, PointUpdate, RiemannSolver, TransverseFlux,
};
use impact_core::parallel::worth_parallel;
use impact_core::points::MaterialPoints;
use impact_core::problem::{Boundary, Model};
use impact_core::{CoreError, Grid, LinearElastic, Problem, Tensor, Vector};
use layouts::{all_inside, shapes};
use riemann::{Conserved, Elastic, Impedances};

/// Which system DGMPM solves.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Physics {
    /// Small-strain linear elasticity, `q = (σ, ρ v)` (paper eq. 7).
    Linear,
    /// Saint-Venant–Kirchhoff, total Lagrangian, `q = (F, ρ₀ v)` (paper eq. 5-6).
    Svk { svk: Svk, riemann: RiemannSolver },
}

/// Most local nodes a cell can have (`2^3`).
const MAX_NODES: usize = 8;
/// Faces or cells per chunk of the face and cell loops (rayon's unit of work).
const CHUNK: usize = 2048;

/// The DGMPM state: material points and the work done on them by the loads.
#[derive(Debug, Clone)]
pub struct DgmpmState<const D: usize> {
    /// Material points (stored cell by cell).
    pub points: MaterialPoints<D>,
    /// Work done by the loads since `t = 0`.
    pub work: f64,
    /// Impulse delivered through the boundary since `t = 0`.
    pub impulse: Vector<D>,
    /// Energy of the state at `t = 0` (J).
    pub initial_energy: f64,
}

/// Nodal buffers of the nodal paths (`cells × 2^D` each; empty on the cell path). The
/// tensor field `q` is the Cauchy stress `σ` in small strain and the deformation gradient
/// `F` under Saint-Venant–Kirchhoff (paper eq. 6-7).
#[derive(Debug, Clone, Default)]
pub(crate) struct NodalFields<const D: usize> {
    /// Lumped mass `M_i` at one point per cell, formed in phase 1 (empty on the fused
    /// sweep's RK2 there, and where the cell layouts hold the masses: several points per
    /// cell).
    pub mass: Vec<f64>,
    /// Tensor field `q_i` (σ or F).
    pub tensor: Vec<Tensor<D>>,
    /// Velocity `v_i`.
    pub velocity: Vec<Vector<D>>,
    /// Tensor field at the start of the step (RK2, increment update; empty otherwise, and
    /// on the fused nodal sweep's RK2 at `2^D` points per cell, `fused/nodal.rs`).
    pub start_tensor: Vec<Tensor<D>>,
    /// Velocity at the start of the step.
    pub start_velocity: Vec<Vector<D>>,
    /// `dq_i/dt` (empty on the fused nodal sweep).
    pub rate_tensor: Vec<Tensor<D>>,
    /// `dv_i/dt`.
    pub rate_velocity: Vec<Vector<D>>,
}

/// Which nodal buffers are allocated, for `nodes` nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NodalLayout {
    nodes: usize,
    /// Lumped masses (not on the fused sweep's RK2 at one point per cell: `S_i m_p`; not
    /// where the cell layouts hold them).
    mass: bool,
    /// Start-of-step fields (RK2, the increment update; not where formed from the points
    /// or where the points' arrays hold RK2's stage fields).
    start: bool,
    /// Rates (the phase paths; the fused sweep updates without them).
    rates: bool,
}

impl<const D: usize> NodalFields<D> {
    /// The buffers `layout` names; the others empty.
    fn new(layout: NodalLayout) -> Self {
        let len = |keep: bool| if keep { layout.nodes } else { 0 };
        Self {
            mass: vec![0.0; len(layout.mass)],
            tensor: vec![Tensor::<D>::zeros(); layout.nodes],
            velocity: vec![Vector::<D>::zeros(); layout.nodes],
            start_tensor: vec![Tensor::<D>::zeros(); len(layout.start)],
            start_velocity: vec![Vector::<D>::zeros(); len(layout.start)],
            rate_tensor: vec![Tensor::<D>::zeros(); len(layout.rates)],
            rate_velocity: vec![Vector::<D>::zeros(); len(layout.rates)],
        }
    }

    /// The layout allocated.
    fn layout(&self) -> NodalLayout {
        NodalLayout {
            nodes: self.tensor.len(),
            mass: !self.mass.is_empty(),
            start: !self.start_tensor.is_empty(),
            rates: !self.rate_tensor.is_empty(),
        }
    }
}

/// Configuration and preallocated buffers of DGMPM.
#[derive(Debug, Clone)]
pub struct DgmpmSolver<const D: usize> {
    pub(crate) config: MethodConfig,
    pub(crate) options: DgmpmOptions,
    pub(crate) grid: Grid<D>,
    pub(crate) material: LinearElastic,
    pub(crate) boundaries: [[Boundary; 2]; D],
    /// The loads' magnitudes averaged over the current step (`set_load_window`).
    pub(crate) load_now: [[f64; 2]; D],
    /// The edges' ghost conditions at those averages, one per edge cell (filled with them,
    /// `faces/edge_table.rs`).
    pub(crate) edge_conditions: faces::EdgeConditions<D>,
    pub(crate) points_per_cell: usize,
    pub(crate) parallel: bool,
    /// The nodal paths' per-cell weights, once per distinct cell layout: the shape values
    /// `S_iα`, and where read the gradients `∇S_iα`, the volume weights
    /// `K_ab = Σ_α V_α S_bα ∇S_aα` (linear elasticity, at least `2^D` points per cell:
    /// `layouts::cell_volume_weights`), phase 1's weights `W_αi = S_iα m_α / M_i` and the
    /// lumped masses `M_i` (several points per cell: `layouts::cell_mapping_weights`);
    /// empty on the cell paths and the Heun cell sweeps (`layouts.rs`).
    pub(crate) layouts: layouts::CellLayouts<D>,
    /// `S_iα` for point α and local node i, `points × 2^D`, and `∇S_iα`: only while the
    /// Heun cell sweeps' weights are formed from them (`fused/heun.rs`; empty otherwise).
    pub(crate) shape: Vec<f64>,
    /// `∇S_iα`, as `shape`.
    pub(crate) shape_gradient: Vec<Vector<D>>,
    /// RK2 at one point per cell strictly inside its cell on the fused nodal path: each
    /// side's state weights `W = Σ_i κ_i G_i` and `K_{m,t}` of its faces (`fused/heun.rs`),
    /// `2D (3D - 1)` values per distinct cell (bit-equal blocks stored once; empty
    /// otherwise; the shape functions are then dropped).
    pub(crate) heun_weights: Vec<f64>,
    /// The same weights scaled for a step of `heun_scaled_dt`, `2D (6D - 2)` rows of lanes
    /// per block (`Δt W_k`, the columns of `Δt ρ M(W)`, `Δt ρ K` and `Δt K`, each weight in
    /// every lane; `fused/heun.rs`).
    pub(crate) heun_scaled: Vec<fused::Lanes<D>>,
    /// The `Δt` of `heun_scaled` (NaN before the first step).
    pub(crate) heun_scaled_dt: f64,
    /// Each cell's block of `heun_weights` (empty where one block serves every cell).
    pub(crate) heun_layout: Vec<u32>,
    /// `1/m_p` of each point where the step takes the fused cell sweeps (the cell path
    /// [`StepPath::Fused`] and the Heun sweeps, one point per cell; empty otherwise): the
    /// cell update's `Δt ρV/m_p` without a division per cell and stage (the masses are
    /// fixed; formed with the weights, `DgmpmSolver::form_weights`).
    pub(crate) inverse_mass: Vec<f64>,
    /// Whether every `S_iα > 0` (every point strictly inside its cell).
    pub(crate) inside: bool,
    pub(crate) nodes: NodalFields<D>,
    /// Per axis `l`: the Godunov flux `F_{e_l}(q*)` on each face.
    pub(crate) face_flux: [Vec<Conserved<D>>; D],
    /// CTU only (empty otherwise): 2D, the transverse corrections of the last axis's faces,
    /// before they are added to its fluxes ([`DgmpmSolver::transverse_corrections`]); 3D,
    /// the sources `V_k` of one axis (`ctu3`).
    pub(crate) correction_scratch: Vec<Conserved<D>>,
    /// 3D CTU only (empty otherwise): per axis `l`, the fluctuations `W_l` entering each
    /// cell, with a ghost layer at each end of the other axes (`ctu3`; the sources `V_k`
    /// then go to `correction_scratch`).
    pub(crate) transverse_sources: [Vec<Conserved<D>>; D],
    /// `order = 2`: the f-waves of every face and of a ghost face beyond each end (empty
    /// otherwise; [`wave_correction`]).
    pub(crate) face_waves: Vec<wave_correction::FaceWaves<D>>,
    /// `order = 2` with CTU: per axis, each face's `F̃`, split once more (else empty; `ctu*`).
    pub(crate) wave_flux: [Vec<Conserved<D>>; D],
    /// The fused path's rolling face rows and next state (empty on the other paths).
    pub(crate) fused: fused::FusedBuffers<D>,
    /// Which fused sweeps apply (linear elasticity without the elastoplastic solver).
    pub(crate) fusable: Fusable,
    pub(crate) elastic: Elastic,
    pub(crate) physics: Physics,
    /// J2 plasticity: the return map corrects the points after each step (phase 6).
    pub(crate) plastic: Option<impact_core::plasticity::J2>,
    /// The elastoplastic Riemann solver (J2, `--riemann elastoplastic`: the rod in 1D, plane
    /// strain in 2D) and its impedances.
    pub(crate) rod_solver: Option<(
        impact_core::plasticity::J2,
        riemann::elastoplastic::RodImpedances,
    )>,
    /// Largest wave speed the loads can produce (time step, guard).
    pub(crate) wave_speed: f64,
    pub(crate) path: StepPath,
    /// Where this grid sits in the whole body (a rank's slab, [`slab`]; the whole grid on
    /// one rank).
    pub(crate) place: GridPlace<D>,
}

/// Where a solver's grid sits in the whole body: the global origin and the global index
/// of its first cell (face coordinates are formed from global indices, so a box's loads
/// see the same bits as the whole grid's), the cells per axis (local indices) whose
/// boundary work and force it owns (a box's halo cells are owned by a neighbour), and the
/// same owned cells as runs of consecutive local cells (rows along axis 0, in order: the
/// cells whose points its diagnostics and samples cover).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GridPlace<const D: usize> {
    pub origin: Vector<D>,
    pub offset: [usize; D],
    pub owned: [std::ops::Range<usize>; D],
    pub owned_cell_runs: Vec<std::ops::Range<usize>>,
}

impl<const D: usize> GridPlace<D> {
    /// The whole grid.
    fn whole(grid: &Grid<D>) -> Self {
        Self {
            origin: grid.origin,
            offset: [0; D],
            owned: std::array::from_fn(|k| 0..grid.cells[k]),
            owned_cell_runs: std::iter::once(0..grid.cell_count()).collect(),
        }
    }

    /// Whether the local cell `idx` (clamped to the grid `cells`: a face index may be one
    /// past the last cell) is owned here.
    #[inline]
    pub fn owns(&self, idx: &[usize; D], cells: &[usize; D]) -> bool {
        (0..D).all(|k| self.owned[k].contains(&idx[k].min(cells[k] - 1)))
    }
}

/// DGMPM as a [`Method`](impact_core::Method): solver plus state.
#[derive(Debug, Clone)]
pub struct Dgmpm<const D: usize> {
    /// Configuration and buffers.
    pub solver: DgmpmSolver<D>,
    /// Points.
    pub state: DgmpmState<D>,
}

/// Unit vector along axis `l`.
#[inline]
pub(crate) fn unit<const D: usize>(l: usize) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| f64::from(u8::from(k == l)))
}

fn unsupported(message: &str) -> CoreError {
    CoreError::Unsupported {
        method: "dgmpm".into(),
        message: message.into(),
    }
}

impl<const D: usize> Dgmpm<D> {
    /// Build DGMPM for `problem` with `config` (a DGMPM configuration).
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Result<Self, CoreError> {
        let options = *config
            .dgmpm()
            .ok_or_else(|| unsupported("not a DGMPM configuration"))?;
        // every option against the model and the dimension (impact_core::config_check)
        problem.check_config(&config)?;
        let points = problem.material_points(&problem.grid, &config)?;
        Self::with_points(problem, config, options, points)
    }

    /// Build on `problem`'s grid with `points` (stored cell by cell).
    fn with_points(
        problem: &Problem<D>,
        config: MethodConfig,
        options: DgmpmOptions,
        mut points: MaterialPoints<D>,
    ) -> Result<Self, CoreError> {
        // DGMPM reads the half-sizes only to sample (before the solver's buffers exist, so
        // the peak holds one copy)
        points.compact_half_sizes();
        let solver = DgmpmSolver::new(problem, config, options, &points)?;
        let mut dgmpm = Self {
            solver,
            state: DgmpmState {
                points,
                work: 0.0,
                impulse: Vector::<D>::zeros(),
                initial_energy: 0.0,
            },
        };
        dgmpm.state.initial_energy = impact_core::Method::energy(&dgmpm);
        Ok(dgmpm)
    }
}

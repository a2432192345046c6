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
//!    states (LeVeque 2002 §7.3) for free, pressure, velocity and symmetry edges. In 2D
//!    with `--flux ctu`, [`DgmpmSolver::transverse_corrections`] then adds the corner
//!    transport upwind corrections; donor-cell (`dcu`) never computes them.
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
//! [`DgmpmSolver::set_cell_path`] switches it off for comparison.
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
//!   function values at the points are computed once.
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
//!   and a plane wave along a symmetry edge stays plane. At a corner where both edges
//!   prescribe a traction, the ghost's face towards the diagonal (defined by neither
//!   condition) carries no fluctuation: with it, CTU with all edges free was unstable from
//!   Courant 0.99; without it the limit is 1. With RK2, CTU corrects both stages (limit
//!   about 0.75).
//! - Every cell must hold points (the paper's scenes fill their grid); points are stored
//!   cell by cell, `points_per_cell` each.
//! - Rayon parallelises over cells and faces (disjoint writes) from 4,096 cells on. Face
//!   and cell loops walk their chunks with a multi-index odometer and plain index
//!   arithmetic: per-face divisions, and multi-index entries written at an axis known only
//!   at run time (a store-forwarding stall), had cost about half of the CTU step.

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
pub mod riemann;

use impact_core::material::Svk;
use impact_core::method::{BadState, Method, MethodConfig, Samples};
use impact_core::points::MaterialPoints;
use impact_core::problem::{
    Boundary, Integrator, Model, PointUpdate, RiemannSolver, TransverseFlux,
};
use impact_core::{CoreError, Grid, LinearElastic, Problem, Tensor, Vector};
use rayon::prelude::*;
use riemann::{
    constrain_correction, fluctuations, ghost_full, linear_elastic_star, normal_flux,
    transverse_into_face, Conserved, Elastic, FullState, GhostCondition, Impedances,
};

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
/// Cell count from which loops run in parallel.
const PARALLEL_CELLS: usize = 4096;
/// Faces or cells per chunk of the cell-path loops (rayon's unit of work).
const CHUNK: usize = 2048;

/// Where face states are read from (see [`DgmpmSolver::interface_fluxes`]).
#[derive(Clone, Copy)]
struct Fields<'a, const D: usize> {
    stress: &'a [Tensor<D>],
    velocity: &'a [Vector<D>],
    /// One value per cell (the cell path) instead of `2^D` nodes per cell.
    per_cell: bool,
}

impl<const D: usize> Fields<'_, D> {
    /// State of cell `c` on its face normal to axis `l` (`high` side or low side): the
    /// average of the cell's nodes on that face (paper §4); on the cell path, the cell's
    /// one state (all its nodes carry it).
    #[inline]
    fn side(&self, c: usize, l: usize, high: bool) -> FullState<D> {
        if self.per_cell {
            return FullState {
                stress: self.stress[c],
                velocity: self.velocity[c],
            };
        }
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut s = Tensor::<D>::zeros();
        let mut v = Vector::<D>::zeros();
        for a in 0..npc {
            if ((a >> l) & 1 == 1) == high {
                s += self.stress[c * npc + a];
                v += self.velocity[c * npc + a];
            }
        }
        let inv = 2.0 / npc as f64;
        FullState {
            stress: s * inv,
            velocity: v * inv,
        }
    }
}

/// The DGMPM state: material points and the work done on them by the loads.
#[derive(Debug, Clone)]
pub struct DgmpmState<const D: usize> {
    /// Material points (stored cell by cell).
    pub points: MaterialPoints<D>,
    /// Work done by the loads since `t = 0`.
    pub work: f64,
    /// Impulse delivered through the boundary since `t = 0`.
    pub impulse: Vector<D>,
}

/// Configuration and preallocated buffers of DGMPM.
#[derive(Debug, Clone)]
pub struct DgmpmSolver<const D: usize> {
    config: MethodConfig,
    grid: Grid<D>,
    material: LinearElastic,
    boundaries: [[Boundary; 2]; D],
    points_per_cell: usize,
    parallel: bool,
    /// `S_iα` for point α and local node i, `points × 2^D`.
    shape: Vec<f64>,
    /// `∇S_iα`, `points × 2^D`.
    shape_gradient: Vec<Vector<D>>,
    node_mass: Vec<f64>,
    node_stress: Vec<Tensor<D>>,
    node_velocity: Vec<Vector<D>>,
    start_stress: Vec<Tensor<D>>,
    start_velocity: Vec<Vector<D>>,
    rate_stress: Vec<Tensor<D>>,
    rate_velocity: Vec<Vector<D>>,
    /// Per axis `l`: the Godunov flux `F_{e_l}(q*)` on each face.
    face_flux: [Vec<Conserved<D>>; D],
    /// Per axis, CTU only (empty otherwise): the transverse correction of each face's flux.
    face_correction: [Vec<Conserved<D>>; D],
    elastic: Elastic,
    physics: Physics,
    /// Largest wave speed the loads can produce (time step, guard).
    wave_speed: f64,
    /// One point per cell: particles→nodes copies the point's state (the mass-weighted map
    /// `Σ S m q / Σ S m` is the identity there) and only weighs the lumped masses.
    single_point_fast_path: bool,
    /// One point per cell with forward Euler: the whole step reduces exactly to the
    /// cell-centred Godunov update ([`DgmpmSolver::cell_update`]); the nodal buffers are
    /// then not allocated.
    cell_path: bool,
}

/// DGMPM as a [`Method`]: solver plus state.
#[derive(Debug, Clone)]
pub struct Dgmpm<const D: usize> {
    /// Configuration and buffers.
    pub solver: DgmpmSolver<D>,
    /// Points.
    pub state: DgmpmState<D>,
}

/// Unit vector along axis `l`.
#[inline]
fn unit<const D: usize>(l: usize) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| f64::from(u8::from(k == l)))
}

fn sym<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> Tensor<D> {
    let outer = a * b.transpose();
    (outer + outer.transpose()) * 0.5
}

impl<const D: usize> Dgmpm<D> {
    /// Build DGMPM for `problem` with `config` (Courant number, points per cell,
    /// integrator, point update).
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Result<Self, CoreError> {
        let per_axis = problem.points_per_axis(config.points_per_cell)?;
        impact_core::scene::check_courant("courant", config.courant)?;
        let grid = problem.grid.clone();
        let mut points = MaterialPoints::regular(&grid, per_axis, problem.material.density);
        if let Model::Svk(_) = problem.model {
            let unsupported = |message: &str| CoreError::Unsupported {
                method: "dgmpm".into(),
                message: message.into(),
            };
            if D > 1 && config.flux == TransverseFlux::Ctu {
                return Err(unsupported(
                    "the CTU transverse solver is implemented for linear elasticity; \
                     use --flux dcu with Saint-Venant-Kirchhoff",
                ));
            }
            if D > 1 && config.riemann == RiemannSolver::Exact {
                return Err(unsupported(
                    "the exact Saint-Venant-Kirchhoff Riemann solver is 1D; use --riemann approximate in 2D",
                ));
            }
            points = points.with_deformation();
        }
        let solver = DgmpmSolver::new(problem, config, &points);
        Ok(Self {
            solver,
            state: DgmpmState {
                points,
                work: 0.0,
                impulse: Vector::<D>::zeros(),
            },
        })
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Allocate every buffer and cache the shape functions at the (fixed) points.
    pub fn new(problem: &Problem<D>, config: MethodConfig, points: &MaterialPoints<D>) -> Self {
        let grid = problem.grid.clone();
        let npc = Grid::<D>::NODES_PER_CELL;
        let nodes = grid.cell_count() * npc;
        let mut shape = vec![0.0; points.len() * npc];
        let mut shape_gradient = vec![Vector::<D>::zeros(); points.len() * npc];
        for (p, x) in points.reference.iter().enumerate() {
            let (_, xi) = grid.locate(x).expect("internal: points lie in the grid");
            grid.shape(
                &xi,
                &mut shape[p * npc..(p + 1) * npc],
                &mut shape_gradient[p * npc..(p + 1) * npc],
            );
        }
        let face_counts: [usize; D] = std::array::from_fn(|l| {
            (0..D)
                .map(|k| grid.cells[k] + usize::from(k == l))
                .product()
        });
        let ctu = D > 1 && config.flux == TransverseFlux::Ctu;
        let correction = || -> [Vec<Conserved<D>>; D] {
            std::array::from_fn(|l| vec![Conserved::zeros(); if ctu { face_counts[l] } else { 0 }])
        };
        let (p, s) = problem.material.impedances::<D>();
        let lame = problem.material.lame;
        let elastic = Elastic {
            lambda: lame.lambda,
            mu: if D == 1 {
                0.5 * problem.material.elastic.young
            } else {
                lame.mu
            },
            density: problem.material.density,
            z: Impedances { p, s },
        };
        // the cell path needs every lumped mass S_a m > 0 (a point strictly inside its cell)
        let cell_path = config.points_per_cell == 1
            && config.integrator == Integrator::Euler
            && shape.iter().all(|&w| w > 0.0);
        let nodes = if cell_path { 0 } else { nodes };
        Self {
            config,
            cell_path,
            parallel: grid.cell_count() >= PARALLEL_CELLS,
            material: problem.material,
            boundaries: problem.boundaries,
            points_per_cell: config.points_per_cell,
            shape,
            shape_gradient,
            node_mass: vec![0.0; nodes],
            node_stress: vec![Tensor::<D>::zeros(); nodes],
            node_velocity: vec![Vector::<D>::zeros(); nodes],
            start_stress: vec![Tensor::<D>::zeros(); nodes],
            start_velocity: vec![Vector::<D>::zeros(); nodes],
            rate_stress: vec![Tensor::<D>::zeros(); nodes],
            rate_velocity: vec![Vector::<D>::zeros(); nodes],
            face_flux: std::array::from_fn(|l| vec![Conserved::zeros(); face_counts[l]]),
            face_correction: correction(),
            elastic,
            physics: match problem.model {
                Model::LinearElastic => Physics::Linear,
                Model::Svk(svk) => Physics::Svk {
                    svk,
                    riemann: config.riemann,
                },
            },
            wave_speed: problem.max_wave_speed(),
            single_point_fast_path: config.points_per_cell == 1,
            grid,
        }
    }

    /// Switch the one-point-per-cell fast path of particles→nodes (on by default at one
    /// point per cell; the general path is kept for comparison).
    pub fn set_single_point_fast_path(&mut self, enabled: bool) {
        self.single_point_fast_path = enabled && self.points_per_cell == 1;
    }

    /// Switch the cell path (on by default where it applies: one point per cell, forward
    /// Euler); off runs the nodal phases 1-5, kept for comparison. Allocates the nodal
    /// buffers when they are first needed (never inside the step loop).
    pub fn set_cell_path(&mut self, enabled: bool) {
        let applies = self.points_per_cell == 1
            && self.config.integrator == Integrator::Euler
            && self.shape.iter().all(|&w| w > 0.0);
        self.cell_path = enabled && applies;
        let nodes = self.grid.cell_count() * Grid::<D>::NODES_PER_CELL;
        if !self.cell_path && self.node_mass.len() != nodes {
            self.node_mass = vec![0.0; nodes];
            self.node_stress = vec![Tensor::<D>::zeros(); nodes];
            self.node_velocity = vec![Vector::<D>::zeros(); nodes];
            self.start_stress = vec![Tensor::<D>::zeros(); nodes];
            self.start_velocity = vec![Vector::<D>::zeros(); nodes];
            self.rate_stress = vec![Tensor::<D>::zeros(); nodes];
            self.rate_velocity = vec![Vector::<D>::zeros(); nodes];
        }
    }

    /// Whether the step takes the cell path.
    pub fn cell_path(&self) -> bool {
        self.cell_path
    }

    /// Phase 1: lumped nodal mass and mass-weighted nodal fields (paper eq. 17).
    pub fn particles_to_nodes(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let ppc = self.points_per_cell;
        let (shape, parallel) = (&self.shape, self.parallel);
        // the tensor field: σ (linear elasticity) or F (SVK)
        let source = match self.physics {
            Physics::Linear => &points.stress,
            Physics::Svk { .. } => &points.deformation,
        };
        let fast = self.single_point_fast_path;
        let kernel =
            |c: usize, mass: &mut [f64], stress: &mut [Tensor<D>], vel: &mut [Vector<D>]| {
                if fast {
                    // one point: M_a = S_a m, q_a = q_p
                    for a in 0..npc {
                        mass[a] = shape[c * npc + a] * points.mass[c];
                        stress[a] = source[c];
                        vel[a] = points.velocity[c];
                    }
                    return;
                }
                for a in 0..npc {
                    let mut m = 0.0;
                    let mut s = Tensor::<D>::zeros();
                    let mut v = Vector::<D>::zeros();
                    for p in c * ppc..(c + 1) * ppc {
                        let w = shape[p * npc + a] * points.mass[p];
                        m += w;
                        s += source[p] * w;
                        v += points.velocity[p] * w;
                    }
                    mass[a] = m;
                    if m > 0.0 {
                        stress[a] = s / m;
                        vel[a] = v / m;
                    } else {
                        stress[a] = Tensor::<D>::zeros();
                        vel[a] = Vector::<D>::zeros();
                    }
                }
            };
        if parallel {
            self.node_mass
                .par_chunks_mut(npc)
                .zip(self.node_stress.par_chunks_mut(npc))
                .zip(self.node_velocity.par_chunks_mut(npc))
                .enumerate()
                .for_each(|(c, ((m, s), v))| kernel(c, m, s, v));
        } else {
            self.node_mass
                .chunks_mut(npc)
                .zip(self.node_stress.chunks_mut(npc))
                .zip(self.node_velocity.chunks_mut(npc))
                .enumerate()
                .for_each(|(c, ((m, s), v))| kernel(c, m, s, v));
        }
    }

    /// Multi-index of entry `f` of an array with dimensions `dims` (first index fastest).
    #[inline]
    fn multi_index(dims: [usize; D], mut f: usize) -> [usize; D] {
        let mut idx = [0; D];
        for k in 0..D {
            idx[k] = f % dims[k];
            f /= dims[k];
        }
        idx
    }

    /// How the face loops of axis `l` are cut (chunks of [`CHUNK`] faces, each walked with
    /// [`Self::advance`] from its first multi-index), and the face array's dimensions.
    fn face_rows(&self, l: usize) -> (usize, [usize; D]) {
        let dims: [usize; D] = std::array::from_fn(|k| self.grid.cells[k] + usize::from(k == l));
        (CHUNK, dims)
    }

    /// Next multi-index in storage order (first index fastest): no division, and entries
    /// other than `idx[0]` are written only at the end of a row.
    #[inline(always)]
    fn advance(idx: &mut [usize; D], dims: &[usize; D]) {
        idx[0] += 1;
        if idx[0] == dims[0] {
            idx[0] = 0;
            for k in 1..D {
                idx[k] += 1;
                if idx[k] < dims[k] {
                    break;
                }
                idx[k] = 0;
            }
        }
    }

    #[inline]
    fn face_index(grid: &Grid<D>, l: usize, idx: [usize; D]) -> usize {
        let mut lin = 0;
        for k in (0..D).rev() {
            lin = lin * (grid.cells[k] + usize::from(k == l)) + idx[k];
        }
        lin
    }

    /// The fields the face states are read from: the cells' DG nodes, or on the cell path
    /// the points themselves (one per cell, stored in cell order).
    #[inline]
    fn fields<'a>(&'a self, points: &'a MaterialPoints<D>) -> Fields<'a, D> {
        if self.cell_path {
            let stress = match self.physics {
                Physics::Linear => &points.stress,
                Physics::Svk { .. } => &points.deformation,
            };
            Fields {
                stress,
                velocity: &points.velocity,
                per_cell: true,
            }
        } else {
            Fields {
                stress: &self.node_stress,
                velocity: &self.node_velocity,
                per_cell: false,
            }
        }
    }

    /// Ghost condition of the boundary at side `side` of axis `l`, at the tangential
    /// coordinate `s` along the edge.
    #[inline]
    fn ghost_condition(&self, l: usize, side: usize, s: f64) -> GhostCondition<D> {
        let outward = unit::<D>(l) * if side == 0 { -1.0 } else { 1.0 };
        match self.boundaries[l][side] {
            Boundary::Free => GhostCondition::Traction(Vector::<D>::zeros()),
            Boundary::Pressure { value, segment } => {
                if Boundary::acts_at(segment, s) {
                    GhostCondition::Traction(outward * (-value))
                } else {
                    GhostCondition::Traction(Vector::<D>::zeros())
                }
            }
            Boundary::Velocity { value, segment } => {
                if Boundary::acts_at(segment, s) {
                    GhostCondition::NormalVelocity(-value)
                } else {
                    GhostCondition::Traction(Vector::<D>::zeros())
                }
            }
            Boundary::Symmetry => GhostCondition::NormalVelocity(0.0),
        }
    }

    /// Both states of a face normal to `e_l`; a missing side (outside the grid) is the ghost
    /// of the other through the boundary condition at tangential coordinate `s`.
    #[inline]
    fn face_pair(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: f64,
    ) -> (FullState<D>, FullState<D>) {
        match (left, right) {
            (Some(a), Some(b)) => (a, b),
            (None, Some(b)) => (
                ghost_full(&b, &(-unit::<D>(l)), self.ghost_condition(l, 0, s)),
                b,
            ),
            (Some(a), None) => (
                a,
                ghost_full(&a, &unit::<D>(l), self.ghost_condition(l, 1, s)),
            ),
            (None, None) => unreachable!("internal: a face has at least one cell"),
        }
    }

    /// The cells on both sides of the face of axis `l` with multi-index `idx` (`None`
    /// outside) and the face's tangential coordinate.
    #[inline]
    fn face_cells(&self, l: usize, idx: [usize; D]) -> (Option<usize>, Option<usize>, f64) {
        let grid = &self.grid;
        // index arithmetic (cell strides), no multi-index entry written at a run-time axis
        let mut cell = 0;
        let mut stride = 1;
        let mut stride_l = 1;
        for m in 0..D {
            cell += idx[m] * stride;
            if m == l {
                stride_l = stride;
            }
            stride *= grid.cells[m];
        }
        let right = (idx[l] < grid.cells[l]).then_some(cell);
        let left = (idx[l] > 0).then(|| cell - stride_l);
        let s = if D > 1 {
            let k = (l + 1) % D;
            grid.origin[k] + (idx[k] as f64 + 0.5) * grid.spacing[k]
        } else {
            0.0
        };
        (left, right, s)
    }

    /// Phase 2: the Godunov flux `F_{e_l}(q*)` on every face (exact Riemann solver, ghost
    /// states on the boundary); returns the power delivered by the boundary conditions,
    /// `Σ_boundary |Γ_f| (σ* n_out)·v*`.
    pub fn interface_fluxes(&mut self, points: &MaterialPoints<D>) -> f64 {
        let mut power = 0.0;
        for l in 0..D {
            let e = unit::<D>(l);
            let area = self.grid.cell_volume() / self.grid.spacing[l];
            let mut fluxes = std::mem::take(&mut self.face_flux[l]);
            let this = &*self;
            let fields = this.fields(points);
            let kernel = |idx: [usize; D], flux: &mut Conserved<D>| -> f64 {
                let (lc, rc, s) = this.face_cells(l, idx);
                let left = lc.map(|c| fields.side(c, l, true));
                let right = rc.map(|c| fields.side(c, l, false));
                let star = match this.physics {
                    Physics::Linear => {
                        let (a, b) = this.face_pair(l, left, right, s);
                        let (fa, fb) = (a.on_face(&e), b.on_face(&e));
                        let star = linear_elastic_star(&fa, &fb, &e, this.elastic.z);
                        *flux = normal_flux(&star, &e, &this.elastic);
                        star
                    }
                    Physics::Svk { svk, riemann } => {
                        let star = this.svk_star(&svk, riemann, l, left, right, s);
                        // F_n(q*) = -(v* ⊗ n, Π* n)
                        *flux = Conserved {
                            stress: -(star.velocity * e.transpose()),
                            momentum: -star.traction,
                        };
                        star
                    }
                };
                match (lc, rc) {
                    // traction on the body σ* n_out, n_out = -e_l at the low boundary
                    (None, _) => -area * star.traction.dot(&star.velocity),
                    (_, None) => area * star.traction.dot(&star.velocity),
                    _ => 0.0,
                }
            };
            let (chunk, dims) = self.face_rows(l);
            let row = |start: usize, q: &mut [Conserved<D>]| -> f64 {
                let mut idx = Self::multi_index(dims, start);
                let mut sum = 0.0;
                for q in q.iter_mut() {
                    sum += kernel(idx, q);
                    Self::advance(&mut idx, &dims);
                }
                sum
            };
            power += if self.parallel {
                fluxes
                    .par_chunks_mut(chunk)
                    .enumerate()
                    .map(|(r, q)| row(r * chunk, q))
                    .sum::<f64>()
            } else {
                fluxes
                    .chunks_mut(chunk)
                    .enumerate()
                    .map(|(r, q)| row(r * chunk, q))
                    .sum::<f64>()
            };
            self.face_flux[l] = fluxes;
        }
        power
    }

    /// Star state of a face for Saint-Venant–Kirchhoff (`FullState::stress` holds `F`),
    /// in the `+e_l` orientation. Boundary faces solve the half problem: exactly in 1D
    /// ([`riemann::svk::exact_boundary_1d`]); with the acoustic solver from the interior's
    /// wave relation ([`riemann::svk::acoustic_boundary`]). A face with no admissible
    /// state (hyperbolicity lost) gets a NaN state, which the guard reports.
    fn svk_star(
        &self,
        svk: &Svk,
        riemann: RiemannSolver,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: f64,
    ) -> riemann::FaceState<D> {
        let e = unit::<D>(l);
        let nan = riemann::FaceState {
            traction: Vector::<D>::from_element(f64::NAN),
            velocity: Vector::<D>::from_element(f64::NAN),
        };
        let one_d = |(v, pi): (f64, f64)| riemann::FaceState {
            traction: e * pi,
            velocity: e * v,
        };
        match (riemann, left, right) {
            (RiemannSolver::Exact, Some(a), Some(b)) if D == 1 => riemann::svk::exact_star_1d(
                svk,
                (a.stress[(0, 0)], a.velocity[0]),
                (b.stress[(0, 0)], b.velocity[0]),
            )
            .map_or(nan, one_d),
            (RiemannSolver::Exact, a, b) if D == 1 => {
                let (inner, side) = match (a, b) {
                    (Some(a), None) => (a, 1),
                    (None, Some(b)) => (b, 0),
                    _ => unreachable!("internal: a face has at least one cell"),
                };
                let outward = if side == 0 { -1.0 } else { 1.0 };
                let cond = match self.ghost_condition(l, side, s) {
                    GhostCondition::Traction(t) => GhostCondition::Traction(Vector::<1>::new(t[0])),
                    GhostCondition::NormalVelocity(v) => GhostCondition::NormalVelocity(v),
                };
                riemann::svk::exact_boundary_1d(
                    svk,
                    (inner.stress[(0, 0)], inner.velocity[0]),
                    outward,
                    cond,
                )
                .map_or(nan, one_d)
            }
            (_, Some(a), Some(b)) => riemann::svk::acoustic_star(
                svk,
                (&a.stress, &a.velocity),
                (&b.stress, &b.velocity),
                &e,
            )
            .unwrap_or(nan),
            (_, a, b) => {
                let (inner, side) = match (a, b) {
                    (Some(a), None) => (a, 1),
                    (None, Some(b)) => (b, 0),
                    _ => unreachable!("internal: a face has at least one cell"),
                };
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let outward = e * sign;
                // solve along the outward normal with the interior on the left
                let interior = riemann::FaceState {
                    traction: svk.piola(&inner.stress) * outward,
                    velocity: inner.velocity,
                };
                let z = riemann::svk::impedance(svk, &inner.stress, &outward);
                riemann::svk::acoustic_boundary(
                    &z,
                    &interior,
                    &outward,
                    self.ghost_condition(l, side, s),
                )
                .map(|st| riemann::FaceState {
                    traction: st.traction * sign,
                    velocity: st.velocity,
                })
                .unwrap_or(nan)
            }
        }
    }

    /// Fluctuations `(A⁻Δq, A⁺Δq)` of the face between `left` and `right` (normal `e_l`).
    #[inline]
    fn face_fluctuations(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: f64,
    ) -> (Conserved<D>, Conserved<D>) {
        let e = unit::<D>(l);
        let (a, b) = self.face_pair(l, left, right, s);
        let (fa, fb) = (a.on_face(&e), b.on_face(&e));
        let star = linear_elastic_star(&fa, &fb, &e, self.elastic.z);
        fluctuations(&fa, &fb, &star, &e, &self.elastic)
    }

    /// Phase 2b (2D, CTU only): corner transport upwind (LeVeque 2002, §21.2). The
    /// fluctuation entering cell `C` through a face normal to `e_l` is split by the
    /// transverse solver ([`riemann::transverse_split`], applied as
    /// [`transverse_into_face`]) along `e_k`, and its up- and down-going parts correct the
    /// fluxes of `C`'s faces normal to `e_k`:
    /// `F_k(C, high) -= Δt/(2Δx_l) B⁺A^±Δq`, `F_k(C, low) -= Δt/(2Δx_l) B⁻A^±Δq`.
    /// Cells outside an edge are ghost cells (mirror states through the edge's condition),
    /// so a plane wave along an edge stays plane.
    ///
    /// The fluctuations entering a cell through its two `l`-faces add up to
    /// `A⁺Δq_low + A⁻Δq_high = F*_high - F*_low + F(q_C,low) - F(q_C,high)` (with `q_C,side`
    /// the cell's state on that face), so they are formed from the stored Godunov fluxes;
    /// on the cell path the last two terms cancel. The corrections go to their own arrays,
    /// so every axis reads uncorrected fluxes.
    pub fn transverse_corrections(&mut self, points: &MaterialPoints<D>, dt: f64) {
        for k in 0..D {
            if self.cell_path {
                self.transverse_corrections_axis::<true>(k, points, dt);
            } else {
                self.transverse_corrections_axis::<false>(k, points, dt);
            }
        }
    }

    /// [`Self::transverse_corrections`] of the faces normal to `e_k`; `PER_CELL`: the
    /// cell path (compiled apart so that its kernel carries no nodal branch).
    fn transverse_corrections_axis<const PER_CELL: bool>(
        &mut self,
        k: usize,
        points: &MaterialPoints<D>,
        dt: f64,
    ) {
        {
            let l = (k + 1) % D;
            let scale = dt / (2.0 * self.grid.spacing[l]);
            let n_k = unit::<D>(k);
            let mut corrections = std::mem::take(&mut self.face_correction[k]);
            let this = &*self;
            let fields = this.fields(points);
            let l_fluxes = &this.face_flux[l];
            // strides of the l-face array: a cell's low l-face is Σ_m c_m stride_m, its high
            // one `stride_l` further (index arithmetic only: writing a multi-index entry
            // picked at run time stalls store forwarding in this loop)
            let stride: [usize; D] = std::array::from_fn(|m| {
                (0..m)
                    .map(|p| this.grid.cells[p] + usize::from(p == l))
                    .product()
            });
            let kernel = |idx: [usize; D], out: &mut Conserved<D>| {
                let base: usize = (0..D).filter(|&m| m != k).map(|m| idx[m] * stride[m]).sum();
                // the fluctuations of the cell below the face (side 0: their B⁺ part counts)
                // and above (side 1: B⁻)
                let mut w_side = [Conserved::<D>::zeros(); 2];
                for side in 0..2 {
                    let j = idx[k] as isize - 1 + side as isize;
                    let inside = j >= 0 && (j as usize) < this.grid.cells[k];
                    let w = if inside {
                        let lo = base + j as usize * stride[k];
                        let w = l_fluxes[lo + stride[l]].add_scaled(&l_fluxes[lo], -1.0);
                        if PER_CELL {
                            w
                        } else {
                            let mut cell = idx;
                            cell[k] = j as usize;
                            w.add_scaled(&this.side_flux_difference(fields, cell, l), 1.0)
                        }
                    } else {
                        // ghost cell behind the edge of axis k on this side
                        let mut cell = idx;
                        cell[k] = j.clamp(0, this.grid.cells[k] as isize - 1) as usize;
                        let (m_in, p_in) = this.ghost_cell_fluctuations(k, side, l, cell, fields);
                        m_in.add_scaled(&p_in, 1.0)
                    };
                    w_side[side] = w;
                }
                let total = transverse_into_face(&w_side[0], &w_side[1], &n_k, &this.elastic);
                let mut correction = Conserved::<D>::zeros().add_scaled(&total, -scale);
                // on an edge, the correction must not undo the edge's condition
                if idx[k] == 0 || idx[k] == this.grid.cells[k] {
                    let side = usize::from(idx[k] != 0);
                    let s = this.grid.origin[l] + (idx[l] as f64 + 0.5) * this.grid.spacing[l];
                    let cond = this.ghost_condition(k, side, s);
                    correction = constrain_correction(&correction, &n_k, cond);
                }
                *out = correction;
            };
            let (chunk, dims) = self.face_rows(k);
            let row = |start: usize, q: &mut [Conserved<D>]| {
                let mut idx = Self::multi_index(dims, start);
                for q in q.iter_mut() {
                    kernel(idx, q);
                    Self::advance(&mut idx, &dims);
                }
            };
            if self.parallel {
                corrections
                    .par_chunks_mut(chunk)
                    .enumerate()
                    .for_each(|(r, q)| row(r * chunk, q));
            } else {
                corrections
                    .chunks_mut(chunk)
                    .enumerate()
                    .for_each(|(r, q)| row(r * chunk, q));
            }
            self.face_correction[k] = corrections;
        }
    }

    /// `F(q_C,low) - F(q_C,high)`: the difference of the normal fluxes (`e_l`) of cell `C`'s
    /// states on its low and high `l`-faces (nodal path only; kept out of line so the
    /// cell path's kernel stays small).
    #[inline(never)]
    fn side_flux_difference(
        &self,
        fields: Fields<'_, D>,
        cell: [usize; D],
        l: usize,
    ) -> Conserved<D> {
        let e_l = unit::<D>(l);
        let c = self.grid.cell_index(cell);
        let flux_of =
            |high: bool| normal_flux(&fields.side(c, l, high).on_face(&e_l), &e_l, &self.elastic);
        flux_of(false).add_scaled(&flux_of(true), -1.0)
    }

    /// `(A⁺Δq` through its low `l`-face, `A⁻Δq` through its high `l`-face) of the ghost
    /// cell mirroring `cell` through the edge of axis `k` at `side`.
    fn ghost_cell_fluctuations(
        &self,
        k: usize,
        side: usize,
        l: usize,
        cell: [usize; D],
        fields: Fields<'_, D>,
    ) -> (Conserved<D>, Conserved<D>) {
        let outward = unit::<D>(k) * if side == 0 { -1.0 } else { 1.0 };
        let grid = &self.grid;
        let ghost_of = |c: [usize; D], high: bool| -> FullState<D> {
            let s_edge = grid.origin[l] + (c[l] as f64 + 0.5) * grid.spacing[l];
            let inner = fields.side(grid.cell_index(c), l, high);
            ghost_full(&inner, &outward, self.ghost_condition(k, side, s_edge))
        };
        // tangential coordinate (along e_k) of the ghost cell, clamped into the edge
        let s_l = grid.origin[k] + (cell[k] as f64 + 0.5) * grid.spacing[k];
        let me_low = ghost_of(cell, false);
        let me_high = ghost_of(cell, true);
        let left = (cell[l] > 0).then(|| {
            let mut c = cell;
            c[l] -= 1;
            ghost_of(c, true)
        });
        let right = (cell[l] + 1 < grid.cells[l]).then(|| {
            let mut c = cell;
            c[l] += 1;
            ghost_of(c, false)
        });
        // a corner where both edges prescribe a traction: the ghost of the ghost cell (the
        // diagonal neighbour) is not defined by either condition alone; its face carries no
        // fluctuation (measured: with it, CTU with free corners is unstable from Courant 0.99)
        let traction_corner = |l_side: usize| {
            matches!(
                self.ghost_condition(k, side, s_l),
                GhostCondition::Traction(_)
            ) && matches!(
                self.ghost_condition(l, l_side, s_l),
                GhostCondition::Traction(_)
            )
        };
        let plus_low = if left.is_none() && traction_corner(0) {
            Conserved::zeros()
        } else {
            self.face_fluctuations(l, left, Some(me_low), s_l).1
        };
        let minus_high = if right.is_none() && traction_corner(1) {
            Conserved::zeros()
        } else {
            self.face_fluctuations(l, Some(me_high), right, s_l).0
        };
        (plus_low, minus_high)
    }

    /// The flux of face `f` of axis `l` as the update uses it: Godunov plus, under CTU,
    /// the transverse correction.
    #[inline]
    fn final_flux(&self, l: usize, f: usize) -> Conserved<D> {
        Self::flux_with_correction(&self.face_flux, &self.face_correction, l, f)
    }

    #[inline]
    fn flux_with_correction(
        flux: &[Vec<Conserved<D>>; D],
        correction: &[Vec<Conserved<D>>; D],
        l: usize,
        f: usize,
    ) -> Conserved<D> {
        match correction[l].get(f) {
            Some(c) => flux[l][f].add_scaled(c, 1.0),
            None => flux[l][f],
        }
    }

    /// Force on the body through the loaded boundary faces (those whose condition is not
    /// traction-free), `Σ -sign |Γ_f| F_{e_l}` (the momentum part of the final face fluxes,
    /// CTU corrections included). Free faces are left out, so momentum equals this impulse
    /// only if they carry no traction.
    pub fn boundary_force(&self) -> Vector<D> {
        let grid = &self.grid;
        let mut force = Vector::<D>::zeros();
        for l in 0..D {
            let area = grid.cell_volume() / grid.spacing[l];
            let layer: usize = (0..D).filter(|&k| k != l).map(|k| grid.cells[k]).product();
            for t in 0..layer {
                let mut idx = [0usize; D];
                let mut rest = t;
                for k in (0..D).filter(|&k| k != l) {
                    idx[k] = rest % grid.cells[k];
                    rest /= grid.cells[k];
                }
                for side in 0..2 {
                    idx[l] = side * grid.cells[l];
                    let sign = if side == 0 { -1.0 } else { 1.0 };
                    let s = if D > 1 {
                        let k = (l + 1) % D;
                        grid.origin[k] + (idx[k] as f64 + 0.5) * grid.spacing[k]
                    } else {
                        0.0
                    };
                    let free = GhostCondition::Traction(Vector::<D>::zeros());
                    if self.ghost_condition(l, side, s) == free {
                        continue;
                    }
                    let f = Self::face_index(grid, l, idx);
                    force -= self.final_flux(l, f).momentum * (sign * area);
                }
            }
        }
        force
    }

    /// Phase 3: nodal rates `dσ_i/dt`, `dv_i/dt` from the volume term on the points and the
    /// face fluxes (module doc).
    pub fn nodal_rates(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let ppc = self.points_per_cell;
        let grid = &self.grid;
        let material = &self.material;
        let density = material.density;
        let (shape, grad) = (&self.shape, &self.shape_gradient);
        let (mass, stress, velocity) = (&self.node_mass, &self.node_stress, &self.node_velocity);
        let (face_flux, face_correction) = (&self.face_flux, &self.face_correction);
        let physics = self.physics;
        let kernel = |c: usize, rs: &mut [Tensor<D>], rv: &mut [Vector<D>]| {
            let mut strain = [Tensor::<D>::zeros(); MAX_NODES];
            let mut force = [Vector::<D>::zeros(); MAX_NODES];
            let ns = &stress[c * npc..(c + 1) * npc];
            let nv = &velocity[c * npc..(c + 1) * npc];
            for p in c * ppc..(c + 1) * ppc {
                let s = &shape[p * npc..(p + 1) * npc];
                let g = &grad[p * npc..(p + 1) * npc];
                let mut sh = Tensor::<D>::zeros();
                let mut vh = Vector::<D>::zeros();
                for b in 0..npc {
                    sh += ns[b] * s[b];
                    vh += nv[b] * s[b];
                }
                let vol = points.volume[p];
                match physics {
                    Physics::Linear => {
                        for a in 0..npc {
                            strain[a] -= sym(&vh, &g[a]) * vol;
                            force[a] -= (sh * g[a]) * vol;
                        }
                    }
                    Physics::Svk { svk, .. } => {
                        // volume term of F: -V v_h ⊗ ∇S; of ρ₀v: -V Π(F_h) ∇S
                        let pi = svk.piola(&sh);
                        for a in 0..npc {
                            strain[a] -= (vh * g[a].transpose()) * vol;
                            force[a] -= (pi * g[a]) * vol;
                        }
                    }
                }
            }
            let idx = grid.cell_multi_index(c);
            let mut stress_flux = [Tensor::<D>::zeros(); MAX_NODES];
            for l in 0..D {
                let weight = grid.cell_volume() / grid.spacing[l] * 2.0 / npc as f64;
                // the high face is one l-stride of the l-face array further (no multi-index
                // entry written at a run-time axis)
                let low = Self::face_index(grid, l, idx);
                let stride: usize = grid.cells[..l].iter().product();
                for side in 0..2 {
                    let f = low + side * stride;
                    // outward flux F_n = sign · F_{e_l}; it leaves the cell
                    let sign = if side == 0 { -1.0 } else { 1.0 };
                    let q = &Self::flux_with_correction(face_flux, face_correction, l, f);
                    for a in 0..npc {
                        if (a >> l) & 1 == side {
                            stress_flux[a] -= q.stress * (sign * weight);
                            force[a] -= q.momentum * (sign * weight);
                        }
                    }
                }
            }
            for a in 0..npc {
                let m = mass[c * npc + a];
                if m > 0.0 {
                    let volume_part = match physics {
                        Physics::Linear => material.stress(&strain[a]),
                        Physics::Svk { .. } => strain[a],
                    };
                    rs[a] = (volume_part + stress_flux[a]) * (density / m);
                    rv[a] = force[a] / m;
                } else {
                    rs[a] = Tensor::<D>::zeros();
                    rv[a] = Vector::<D>::zeros();
                }
            }
        };
        if self.parallel {
            self.rate_stress
                .par_chunks_mut(npc)
                .zip(self.rate_velocity.par_chunks_mut(npc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        } else {
            self.rate_stress
                .chunks_mut(npc)
                .zip(self.rate_velocity.chunks_mut(npc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        }
    }

    /// Phase 4: `q_i ← a q_i^n + b (q_i + dt q̇_i)`: Euler is `(a, b) = (0, 1)`, Heun's second
    /// stage `(½, ½)`.
    pub fn nodal_update(&mut self, dt: f64, start_weight: f64) {
        let b = 1.0 - start_weight;
        let (rs, rv) = (&self.rate_stress, &self.rate_velocity);
        let (s0, v0) = (&self.start_stress, &self.start_velocity);
        let kernel = |i: usize, stress: &mut Tensor<D>, velocity: &mut Vector<D>| {
            let s = *stress + rs[i] * dt;
            let v = *velocity + rv[i] * dt;
            if start_weight == 0.0 {
                *stress = s;
                *velocity = v;
            } else {
                *stress = s0[i] * start_weight + s * b;
                *velocity = v0[i] * start_weight + v * b;
            }
        };
        if self.parallel {
            self.node_stress
                .par_iter_mut()
                .zip(self.node_velocity.par_iter_mut())
                .enumerate()
                .for_each(|(i, (s, v))| kernel(i, s, v));
        } else {
            self.node_stress
                .iter_mut()
                .zip(self.node_velocity.iter_mut())
                .enumerate()
                .for_each(|(i, (s, v))| kernel(i, s, v));
        }
    }

    /// Cell path, phases 3-5 in one (one point per cell, forward Euler): the point update
    /// `q_p ← q_p + Δt Σ_i S_i(X_p) q̇_i` of phases 3-5 with `M_i = S_i m_p` and
    /// `q_i = q_p` on every node reduces exactly to the cell-centred Godunov update
    /// `q_p ← q_p - Δt (ρ V/m_p) Σ_l (F_l(high) - F_l(low))/Δx_l` (momentum part divided
    /// by `ρ`): `Σ_i S_i q̇_i = (ρ/m_p) Σ_i (…)_i`, the volume terms cancel because
    /// `Σ_i ∇S_i = 0`, and each face flux reaches its `2^{D-1}` nodes with weight
    /// `|Γ_f| 2/2^D`. Tested equal to phases 1-5 to round-off.
    pub fn cell_update(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let grid = &self.grid;
        let (face_flux, face_correction) = (&self.face_flux, &self.face_correction);
        let (density, volume) = (self.material.density, grid.cell_volume());
        let mass = &points.mass;
        // stride along l of the l-face array: the high face of a cell is this far on
        let high_offset: [usize; D] = std::array::from_fn(|l| grid.cells[..l].iter().product());
        let kernel = |c: usize, idx: [usize; D], q: &mut Tensor<D>, v: &mut Vector<D>| {
            let mut dq = Tensor::<D>::zeros();
            let mut dm = Vector::<D>::zeros();
            for l in 0..D {
                let lo = Self::face_index(grid, l, idx);
                let hi = lo + high_offset[l];
                let a = Self::flux_with_correction(face_flux, face_correction, l, lo);
                let b = Self::flux_with_correction(face_flux, face_correction, l, hi);
                let inv = 1.0 / grid.spacing[l];
                dq -= (b.stress - a.stress) * inv;
                dm -= (b.momentum - a.momentum) * inv;
            }
            let scale = dt * density * volume / mass[c];
            *q += dq * scale;
            *v += dm * (scale / density);
        };
        let target = match self.physics {
            Physics::Linear => &mut points.stress,
            Physics::Svk { .. } => &mut points.deformation,
        };
        let chunk = CHUNK;
        let row = |start: usize, q: &mut [Tensor<D>], v: &mut [Vector<D>]| {
            let mut idx = Self::multi_index(grid.cells, start);
            for (j, (q, v)) in q.iter_mut().zip(v.iter_mut()).enumerate() {
                kernel(start + j, idx, q, v);
                Self::advance(&mut idx, &grid.cells);
            }
        };
        if self.parallel {
            target
                .par_chunks_mut(chunk)
                .zip(points.velocity.par_chunks_mut(chunk))
                .enumerate()
                .for_each(|(r, (q, v))| row(r * chunk, q, v));
        } else {
            target
                .chunks_mut(chunk)
                .zip(points.velocity.chunks_mut(chunk))
                .enumerate()
                .for_each(|(r, (q, v))| row(r * chunk, q, v));
        }
        self.piola_at_points(points);
    }

    /// Phase 5: points take the new nodal field ([`PointUpdate::Nodal`]) or add its
    /// increment ([`PointUpdate::Increment`]).
    pub fn nodes_to_particles(&self, points: &mut MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let ppc = self.points_per_cell;
        let shape = &self.shape;
        let (ns, nv) = (&self.node_stress, &self.node_velocity);
        let (s0, v0) = (&self.start_stress, &self.start_velocity);
        let increment = self.config.update == PointUpdate::Increment;
        let kernel = |c: usize, ps: &mut [Tensor<D>], pv: &mut [Vector<D>]| {
            for k in 0..ppc {
                let p = c * ppc + k;
                let mut s = Tensor::<D>::zeros();
                let mut v = Vector::<D>::zeros();
                for a in 0..npc {
                    let w = shape[p * npc + a];
                    let i = c * npc + a;
                    if increment {
                        s += (ns[i] - s0[i]) * w;
                        v += (nv[i] - v0[i]) * w;
                    } else {
                        s += ns[i] * w;
                        v += nv[i] * w;
                    }
                }
                if increment {
                    ps[k] += s;
                    pv[k] += v;
                } else {
                    ps[k] = s;
                    pv[k] = v;
                }
            }
        };
        // the tensor field: σ (linear elasticity) or F (SVK)
        let target = match self.physics {
            Physics::Linear => &mut points.stress,
            Physics::Svk { .. } => &mut points.deformation,
        };
        if self.parallel {
            target
                .par_chunks_mut(ppc)
                .zip(points.velocity.par_chunks_mut(ppc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        } else {
            target
                .chunks_mut(ppc)
                .zip(points.velocity.chunks_mut(ppc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        }
        self.piola_at_points(points);
    }

    /// One step: phases 1-5 (module doc); on the cell path `interface_fluxes`,
    /// `transverse_corrections` (CTU), `boundary_force` and [`Self::cell_update`]. Adds the
    /// work and impulse of the loads to the state.
    pub fn step(&mut self, state: &mut DgmpmState<D>, dt: f64) {
        let ctu = D > 1 && self.config.flux == TransverseFlux::Ctu;
        if self.cell_path {
            let power = self.interface_fluxes(&state.points);
            if ctu {
                self.transverse_corrections(&state.points, dt);
            }
            let force = self.boundary_force();
            self.cell_update(&mut state.points, dt);
            state.work += dt * power;
            state.impulse += force * dt;
            self.move_points(&mut state.points, dt);
            return;
        }
        self.particles_to_nodes(&state.points);
        let keep_start = self.config.integrator == Integrator::Rk2
            || self.config.update == PointUpdate::Increment;
        if keep_start {
            self.start_stress.copy_from_slice(&self.node_stress);
            self.start_velocity.copy_from_slice(&self.node_velocity);
        }
        let power = self.interface_fluxes(&state.points);
        if ctu {
            self.transverse_corrections(&state.points, dt);
        }
        let force = self.boundary_force();
        self.nodal_rates(&state.points);
        self.nodal_update(dt, 0.0);
        match self.config.integrator {
            Integrator::Euler => {
                state.work += dt * power;
                state.impulse += force * dt;
            }
            Integrator::Rk2 => {
                let power2 = self.interface_fluxes(&state.points);
                if ctu {
                    self.transverse_corrections(&state.points, dt);
                }
                let force2 = self.boundary_force();
                self.nodal_rates(&state.points);
                self.nodal_update(dt, 0.5);
                state.work += 0.5 * dt * (power + power2);
                state.impulse += (force + force2) * (0.5 * dt);
            }
        }
        self.nodes_to_particles(&mut state.points);
        self.move_points(&mut state.points, dt);
    }

    /// SVK: the points' stress is `Π(F)` of their new deformation gradient.
    fn piola_at_points(&self, points: &mut MaterialPoints<D>) {
        let Physics::Svk { svk, .. } = self.physics else {
            return;
        };
        let kernel = |(s, f): (&mut Tensor<D>, &Tensor<D>)| *s = svk.piola(f);
        if self.parallel {
            points
                .stress
                .par_iter_mut()
                .zip(points.deformation.par_iter())
                .for_each(kernel);
        } else {
            points
                .stress
                .iter_mut()
                .zip(points.deformation.iter())
                .for_each(kernel);
        }
    }

    /// Points move with the velocity solution (output only: the grid is the reference).
    fn move_points(&self, points: &mut MaterialPoints<D>, dt: f64) {
        if self.parallel {
            points
                .position
                .par_iter_mut()
                .zip(points.velocity.par_iter())
                .for_each(|(x, v)| *x += v * dt);
        } else {
            for (x, v) in points.position.iter_mut().zip(&points.velocity) {
                *x += v * dt;
            }
        }
    }
}

impl<const D: usize> Method<D> for Dgmpm<D> {
    fn config(&self) -> &MethodConfig {
        &self.solver.config
    }
    fn stable_dt(&self) -> f64 {
        self.solver.config.courant * self.solver.grid.min_spacing() / self.solver.wave_speed
    }
    fn step(&mut self, _t: f64, dt: f64) {
        self.solver.step(&mut self.state, dt);
    }
    fn sample_into(&self, out: &mut Samples<D>) {
        let p = &self.state.points;
        out.clear();
        out.reference.extend_from_slice(&p.reference);
        out.position.extend_from_slice(&p.position);
        out.half_size.extend_from_slice(&p.half_size);
        out.stress.extend_from_slice(&p.stress);
        out.velocity.extend_from_slice(&p.velocity);
    }
    fn energy(&self) -> f64 {
        let p = &self.state.points;
        let m = &self.solver.material;
        (0..p.len())
            .map(|i| {
                let strain = match self.solver.physics {
                    Physics::Linear => m.energy_density(&p.stress[i]),
                    Physics::Svk { svk, .. } => svk.energy_density(&p.deformation[i]),
                };
                0.5 * p.mass[i] * p.velocity[i].norm_squared() + p.volume[i] * strain
            })
            .sum()
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    fn momentum(&self) -> Vector<D> {
        let p = &self.state.points;
        (0..p.len()).fold(Vector::<D>::zeros(), |m, i| m + p.velocity[i] * p.mass[i])
    }
    fn external_impulse(&self) -> Vector<D> {
        self.state.impulse
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let p = &self.state.points;
        for i in 0..p.len() {
            if !(p.stress[i].iter().all(|x| x.is_finite())
                && p.velocity[i].iter().all(|x| x.is_finite()))
            {
                return Err(BadState {
                    place: p.reference[i],
                    reason: match self.solver.physics {
                        Physics::Linear => "non-finite stress or velocity at a material point".into(),
                        Physics::Svk { .. } => "non-finite state at a material point: no admissible Riemann \
                                                state (Saint-Venant-Kirchhoff hyperbolicity lost at F = 1/√3)"
                            .into(),
                    },
                });
            }
            if let Physics::Svk { svk, .. } = self.solver.physics {
                if !svk.admissible(&p.deformation[i], self.solver.wave_speed) {
                    return Err(BadState {
                        place: p.reference[i],
                        reason: Svk::inadmissible_reason(&p.deformation[i]),
                    });
                }
            }
        }
        Ok(())
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.state.points;
        let i = (0..p.len())
            .max_by(|&a, &b| p.velocity[a].norm().total_cmp(&p.velocity[b].norm()))
            .unwrap_or(0);
        p.reference
            .get(i)
            .copied()
            .unwrap_or_else(Vector::<D>::zeros)
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let p = &mut self.state.points;
        for i in 0..p.len() {
            p.velocity[i] += kick(i, &p.reference[i]);
        }
    }
    fn cells(&self) -> usize {
        self.solver.grid.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.solver.grid.cell_count()
    }
}

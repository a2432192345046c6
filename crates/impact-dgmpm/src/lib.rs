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
//!    states (LeVeque 2002 §7.3) for free, pressure, velocity and symmetry edges.
//! 3. [`DgmpmSolver::nodal_rates`]: the semi-discrete system (paper eq. 16) with the volume
//!    term on the points, the nodal field interpolated there (paper eq. 14-15):
//!    `M_i dv_i/dt = -Σ_α V_α σ_h(X_α) ∇S_iα + Σ_f ∫_f S_i t*_out dΓ`,
//!    `(M_i/ρ) dσ_i/dt = C : [-Σ_α V_α sym(v_h(X_α) ⊗ ∇S_iα) + Σ_f ∫_f S_i sym(v* ⊗ n) dΓ]`.
//! 4. [`DgmpmSolver::nodal_update`]: forward Euler, or two-stage RK2 (Heun), repeating 2-3.
//! 5. [`DgmpmSolver::nodes_to_particles`]: see [`PointUpdate`].
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
//! - Every cell must hold points (the paper's scenes fill their grid); points are stored
//!   cell by cell, `points_per_cell` each.
//! - Rayon parallelises over cells and faces (disjoint writes) from 4,096 cells on.

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
pub mod riemann;

use impact_core::method::{BadState, Method, MethodConfig, Samples};
use impact_core::points::MaterialPoints;
use impact_core::problem::{Boundary, Integrator, PointUpdate};
use impact_core::{CoreError, Grid, LinearElastic, Problem, Tensor, Vector};
use rayon::prelude::*;
use riemann::{ghost_state, linear_elastic_star, FaceState, GhostCondition, Impedances};

/// Most local nodes a cell can have (`2^3`).
const MAX_NODES: usize = 8;
/// Cell count from which loops run in parallel.
const PARALLEL_CELLS: usize = 4096;

/// The DGMPM state: material points and the work done on them by the loads.
#[derive(Debug, Clone)]
pub struct DgmpmState<const D: usize> {
    /// Material points (stored cell by cell).
    pub points: MaterialPoints<D>,
    /// Work done by the loads since `t = 0`.
    pub work: f64,
}

/// Configuration and preallocated buffers of DGMPM.
#[derive(Debug, Clone)]
pub struct DgmpmSolver<const D: usize> {
    config: MethodConfig,
    grid: Grid<D>,
    material: LinearElastic,
    boundaries: [[Boundary; 2]; D],
    impedances: Impedances,
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
    /// Per axis: Godunov traction `σ* e_l` on each face.
    face_traction: [Vec<Vector<D>>; D],
    /// Per axis: Godunov velocity `v*` on each face.
    face_velocity: [Vec<Vector<D>>; D],
}

/// DGMPM as a [`Method`]: solver plus state.
#[derive(Debug, Clone)]
pub struct Dgmpm<const D: usize> {
    /// Configuration and buffers.
    pub solver: DgmpmSolver<D>,
    /// Points.
    pub state: DgmpmState<D>,
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
        let points = MaterialPoints::regular(&grid, per_axis, problem.material.density);
        let solver = DgmpmSolver::new(problem, config, &points);
        Ok(Self {
            solver,
            state: DgmpmState { points, work: 0.0 },
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
        let faces: [Vec<Vector<D>>; D] = std::array::from_fn(|l| {
            let mut count = 1;
            for k in 0..D {
                count *= grid.cells[k] + usize::from(k == l);
            }
            vec![Vector::<D>::zeros(); count]
        });
        let (p, s) = problem.material.impedances::<D>();
        Self {
            config,
            parallel: grid.cell_count() >= PARALLEL_CELLS,
            material: problem.material,
            boundaries: problem.boundaries,
            impedances: Impedances { p, s },
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
            face_velocity: faces.clone(),
            face_traction: faces,
            grid,
        }
    }

    /// Phase 1: lumped nodal mass and mass-weighted nodal fields (paper eq. 17).
    pub fn particles_to_nodes(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let ppc = self.points_per_cell;
        let (shape, parallel) = (&self.shape, self.parallel);
        let kernel =
            |c: usize, mass: &mut [f64], stress: &mut [Tensor<D>], vel: &mut [Vector<D>]| {
                for a in 0..npc {
                    let mut m = 0.0;
                    let mut s = Tensor::<D>::zeros();
                    let mut v = Vector::<D>::zeros();
                    for p in c * ppc..(c + 1) * ppc {
                        let w = shape[p * npc + a] * points.mass[p];
                        m += w;
                        s += points.stress[p] * w;
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

    /// Multi-index of face `f` of axis `l` (`cells + 1` faces along `l`).
    #[inline]
    fn face_multi_index(grid: &Grid<D>, l: usize, mut f: usize) -> [usize; D] {
        let mut idx = [0; D];
        for k in 0..D {
            let n = grid.cells[k] + usize::from(k == l);
            idx[k] = f % n;
            f /= n;
        }
        idx
    }

    #[inline]
    fn face_index(grid: &Grid<D>, l: usize, idx: [usize; D]) -> usize {
        let mut lin = 0;
        for k in (0..D).rev() {
            lin = lin * (grid.cells[k] + usize::from(k == l)) + idx[k];
        }
        lin
    }

    /// State of cell `c` on its face normal to axis `l` (`high` side or low side): the
    /// average of the cell's nodes on that face (paper §4).
    #[inline]
    fn side_state(
        stress: &[Tensor<D>],
        velocity: &[Vector<D>],
        c: usize,
        l: usize,
        high: bool,
    ) -> FaceState<D> {
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut s = Tensor::<D>::zeros();
        let mut v = Vector::<D>::zeros();
        for a in 0..npc {
            if ((a >> l) & 1 == 1) == high {
                s += stress[c * npc + a];
                v += velocity[c * npc + a];
            }
        }
        let inv = 2.0 / npc as f64;
        let e = Vector::<D>::from_fn(|k, _| f64::from(u8::from(k == l)));
        FaceState {
            traction: (s * e) * inv,
            velocity: v * inv,
        }
    }

    /// Ghost condition of a boundary face whose centre has coordinates `centre`.
    #[inline]
    fn ghost_condition(&self, l: usize, side: usize, centre: &Vector<D>) -> GhostCondition<D> {
        let outward = Vector::<D>::from_fn(|k, _| {
            if k == l {
                if side == 0 {
                    -1.0
                } else {
                    1.0
                }
            } else {
                0.0
            }
        });
        // tangential coordinate along the edge (2D: the other axis)
        let s = if D > 1 { centre[(l + 1) % D] } else { 0.0 };
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

    /// Phase 2: Godunov state on every face; returns the power delivered by the boundary
    /// conditions, `Σ_boundary |Γ_f| t*·v*`.
    pub fn interface_fluxes(&mut self) -> f64 {
        let grid = &self.grid;
        let z = self.impedances;
        let (stress, velocity) = (&self.node_stress, &self.node_velocity);
        let mut power = 0.0;
        for l in 0..D {
            let e = Vector::<D>::from_fn(|k, _| f64::from(u8::from(k == l)));
            let kernel = |f: usize, traction: &mut Vector<D>, vel: &mut Vector<D>| {
                let idx = Self::face_multi_index(grid, l, f);
                if idx[l] == 0 || idx[l] == grid.cells[l] {
                    return; // boundary faces below
                }
                let mut left = idx;
                left[l] -= 1;
                let lc = grid.cell_index(left);
                let rc = grid.cell_index(idx);
                let sl = Self::side_state(stress, velocity, lc, l, true);
                let sr = Self::side_state(stress, velocity, rc, l, false);
                let star = linear_elastic_star(&sl, &sr, &e, z);
                *traction = star.traction;
                *vel = star.velocity;
            };
            let (ft, fv) = (&mut self.face_traction[l], &mut self.face_velocity[l]);
            if self.parallel {
                ft.par_iter_mut()
                    .zip(fv.par_iter_mut())
                    .enumerate()
                    .for_each(|(f, (t, v))| kernel(f, t, v));
            } else {
                ft.iter_mut()
                    .zip(fv.iter_mut())
                    .enumerate()
                    .for_each(|(f, (t, v))| kernel(f, t, v));
            }
        }
        // boundary faces: interior state on the left, ghost on the right, normal outward
        for l in 0..D {
            let area = grid.cell_volume() / grid.spacing[l];
            // faces of axis l per layer normal to l
            let layer: usize = (0..D).filter(|&k| k != l).map(|k| grid.cells[k]).product();
            for (transverse, side) in (0..layer).flat_map(|t| [(t, 0), (t, 1)]) {
                let mut idx = [0usize; D];
                let mut rest = transverse;
                for k in (0..D).filter(|&k| k != l) {
                    idx[k] = rest % grid.cells[k];
                    rest /= grid.cells[k];
                }
                idx[l] = side * grid.cells[l];
                let f = Self::face_index(grid, l, idx);
                let mut cell = idx;
                if side == 1 {
                    cell[l] -= 1;
                }
                let c = grid.cell_index(cell);
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let outward = Vector::<D>::from_fn(|k, _| if k == l { sign } else { 0.0 });
                let mut centre = grid.cell_centre(c);
                centre[l] += sign * 0.5 * grid.spacing[l];
                let interior_plus = Self::side_state(stress, velocity, c, l, side == 1);
                // traction with respect to the outward normal
                let interior = FaceState {
                    traction: interior_plus.traction * sign,
                    velocity: interior_plus.velocity,
                };
                let ghost =
                    ghost_state(&interior, &outward, self.ghost_condition(l, side, &centre));
                let star = linear_elastic_star(&interior, &ghost, &outward, z);
                power += area * star.traction.dot(&star.velocity);
                self.face_traction[l][f] = star.traction * sign;
                self.face_velocity[l][f] = star.velocity;
            }
        }
        power
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
        let (face_t, face_v) = (&self.face_traction, &self.face_velocity);
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
                for a in 0..npc {
                    strain[a] -= sym(&vh, &g[a]) * vol;
                    force[a] -= (sh * g[a]) * vol;
                }
            }
            let idx = grid.cell_multi_index(c);
            for l in 0..D {
                let weight = grid.cell_volume() / grid.spacing[l] * 2.0 / npc as f64;
                for side in 0..2 {
                    let mut fidx = idx;
                    fidx[l] += side;
                    let f = Self::face_index(grid, l, fidx);
                    let sign = if side == 0 { -1.0 } else { 1.0 };
                    let normal = Vector::<D>::from_fn(|k, _| if k == l { sign } else { 0.0 });
                    let t_out = face_t[l][f] * sign;
                    let d = sym(&face_v[l][f], &normal) * weight;
                    for a in 0..npc {
                        if (a >> l) & 1 == side {
                            strain[a] += d;
                            force[a] += t_out * weight;
                        }
                    }
                }
            }
            for a in 0..npc {
                let m = mass[c * npc + a];
                if m > 0.0 {
                    rs[a] = material.stress(&strain[a]) * (density / m);
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
        for i in 0..self.node_stress.len() {
            let s = self.node_stress[i] + self.rate_stress[i] * dt;
            let v = self.node_velocity[i] + self.rate_velocity[i] * dt;
            if start_weight == 0.0 {
                self.node_stress[i] = s;
                self.node_velocity[i] = v;
            } else {
                self.node_stress[i] = self.start_stress[i] * start_weight + s * b;
                self.node_velocity[i] = self.start_velocity[i] * start_weight + v * b;
            }
        }
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
        if self.parallel {
            points
                .stress
                .par_chunks_mut(ppc)
                .zip(points.velocity.par_chunks_mut(ppc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        } else {
            points
                .stress
                .chunks_mut(ppc)
                .zip(points.velocity.chunks_mut(ppc))
                .enumerate()
                .for_each(|(c, (s, v))| kernel(c, s, v));
        }
    }

    /// One step: phases 1-5 (module doc). Returns the work done by the loads.
    pub fn step(&mut self, state: &mut DgmpmState<D>, dt: f64) {
        self.particles_to_nodes(&state.points);
        let keep_start = self.config.integrator == Integrator::Rk2
            || self.config.update == PointUpdate::Increment;
        if keep_start {
            self.start_stress.copy_from_slice(&self.node_stress);
            self.start_velocity.copy_from_slice(&self.node_velocity);
        }
        let power = self.interface_fluxes();
        self.nodal_rates(&state.points);
        self.nodal_update(dt, 0.0);
        match self.config.integrator {
            Integrator::Euler => state.work += dt * power,
            Integrator::Rk2 => {
                let power2 = self.interface_fluxes();
                self.nodal_rates(&state.points);
                self.nodal_update(dt, 0.5);
                state.work += 0.5 * dt * (power + power2);
            }
        }
        self.nodes_to_particles(&mut state.points);
    }
}

impl<const D: usize> Method<D> for Dgmpm<D> {
    fn config(&self) -> &MethodConfig {
        &self.solver.config
    }
    fn stable_dt(&self) -> f64 {
        self.solver.config.courant * self.solver.grid.min_spacing()
            / self.solver.material.p_wave_speed::<D>()
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
                0.5 * p.mass[i] * p.velocity[i].norm_squared()
                    + p.volume[i] * m.energy_density(&p.stress[i])
            })
            .sum()
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let p = &self.state.points;
        for i in 0..p.len() {
            if !(p.stress[i].iter().all(|x| x.is_finite())
                && p.velocity[i].iter().all(|x| x.is_finite()))
            {
                return Err(BadState {
                    place: p.reference[i],
                    reason: "non-finite stress or velocity at a material point".into(),
                });
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
    fn cells(&self) -> usize {
        self.solver.grid.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.solver.grid.cell_count()
    }
}

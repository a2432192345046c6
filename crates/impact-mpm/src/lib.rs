//! Update-stress-last material point method (Sulsky, Zhou & Schreyer 1995) with linear
//! (1D) / bilinear (2D) shape functions on a fixed background grid.
//!
//! One step, one phase per function:
//! 1. [`MpmSolver::particles_to_grid`]: nodal mass `m_i = Σ_p N_ip m_p`, momentum
//!    `p_i = Σ_p N_ip m_p v_p`, internal force `f_i = -Σ_p V_p σ_p ∇N_ip`; external forces
//!    (a pressure `p` on a loaded edge is the nodal force `f_i = N_i(x_s) p A` at the
//!    body's surface `x_s`).
//! 2. [`MpmSolver::grid_update`]: `p_i += Δt f_i`; prescribed velocities are imposed on
//!    their nodes; symmetry edges zero the normal component.
//! 3. [`MpmSolver::grid_to_particles`]: `v_p += Δt Σ_i N_ip f_i/m_i` (FLIP) and
//!    `x_p += Δt Σ_i N_ip p_i/m_i`.
//! 4. MUSL only ([`MpmSolver::remap_momentum`]): `p_i = Σ_p N_ip m_p v_p^{n+1}` again.
//! 5. [`MpmSolver::update_stress`]: with the nodal velocity `v_i = p_i/m_i`,
//!    `ε̇_p = sym(Σ_i v_i ⊗ ∇N_ip)`, `σ_p += Δt C:ε̇_p` (and `V_p *= 1 + Δt tr ε̇_p` in the
//!    updated Lagrangian frame).
//!
//! Variants ([`StressUpdate`]): `Usl` (default) takes the grid-updated velocity
//! `v_i + Δt f_i/m_i` for the strain rate; `Musl` remaps it from the updated point
//! velocities first (phase 4; damps, and is stable past Courant 1 here); `Usf` updates
//! the stress before the internal force, from the velocity mapped at the start of the step.
//!
//! Frame ([`MpmFrame`]): the default is the total Lagrangian form the paper uses for its
//! comparisons (§5.3: "MPM, DGMPM (both in total Lagrangian formulation)"): shape
//! functions at the points' reference positions and reference volumes, so the grid is the
//! reference configuration, as for DGMPM and FEM. Positions are still integrated
//! (`x_p += Δt v`) for output. The updated Lagrangian form (points move through the
//! grid) is the option: with linear shape functions it suffers cell-crossing errors that do
//! not shrink under refinement (measured on the bar: L1 error 0.10 at 300 cells, 0.22 at
//! 1200) and, with plain USL, a vanishing nodal mass when a node's last point leaves it.
//!
//! With these defaults (TL, USL, 1 point per cell) the bar is stable at the paper's
//! Courant 0.5 and blows up at 0.8 and above, as the paper reports ("the MPM is unstable
//! with α = 1").
//!
//! Other choices where the paper is silent: the background grid is the body's grid
//! extended by [`PADDING`] cells on every side so points may move in the updated frame;
//! nodes with no mass are skipped; a surface load is spread over the nodes of the
//! surface's cell that carry mass (renormalised shape functions), so the whole load
//! reaches the body when the outer node of that cell has lost its points.

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
use impact_core::method::{
    BadState, Method, MethodConfig, Model, MpmFrame, MpmOptions, Samples, StressUpdate,
};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::{CoreError, Grid, LinearElastic, Problem, Tensor, Vector};

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
}

/// A load acting on a surface point of the body.
#[derive(Debug, Clone, Copy)]
struct SurfaceLoad<const D: usize> {
    point: usize,
    /// Offset from the point to the surface (reference configuration).
    offset: Vector<D>,
    /// Force (pressure × area), constant in time.
    force: Vector<D>,
}

/// A prescribed normal velocity on the nodes and points near an edge.
#[derive(Debug, Clone, Copy)]
struct VelocityEdge {
    axis: usize,
    /// Nodes with this index along `axis` (background-grid numbering).
    node_layer: usize,
    value: f64,
    segment: Option<(f64, f64)>,
    /// Whether it is a symmetry edge (zero normal velocity, points untouched).
    symmetry: bool,
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
    velocity_edges: Vec<VelocityEdge>,
    node_mass: Vec<f64>,
    node_momentum: Vec<Vector<D>>,
    node_force: Vec<Vector<D>>,
    /// Per point: its cell in the background grid, shape values and gradients.
    point_cell: Vec<usize>,
    shape: Vec<f64>,
    shape_gradient: Vec<Vector<D>>,
    /// Whether the shape functions at the reference positions are cached (total Lagrangian).
    shapes_ready: bool,
}

/// USL MPM as a [`Method`].
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
        let options = *config.mpm().ok_or_else(|| CoreError::Unsupported {
            method: "mpm".into(),
            message: "not an MPM configuration".into(),
        })?;
        let per_axis = problem.points_per_axis(config.points_per_cell)?;
        impact_core::scene::check_courant("courant", config.courant)?;
        let body = problem.grid.clone();
        let mut points = MaterialPoints::regular(&body, per_axis, problem.material.density);
        if let Model::Svk(_) = problem.model {
            if options.frame != MpmFrame::TotalLagrangian {
                return Err(CoreError::Unsupported {
                    method: "mpm".into(),
                    message: "Saint-Venant-Kirchhoff is solved in the total Lagrangian frame \
                              (--frame total-lagrangian)"
                        .into(),
                });
            }
            points = points.with_deformation();
        }
        let mut cells = body.cells;
        for c in cells.iter_mut() {
            *c += 2 * PADDING;
        }
        let grid = Grid {
            origin: body.origin - body.spacing * PADDING as f64,
            spacing: body.spacing,
            cells,
        };
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut loads = Vec::new();
        let mut velocity_edges = Vec::new();
        let upper = body.upper();
        for l in 0..D {
            for side in 0..2 {
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let edge = if side == 0 { body.origin[l] } else { upper[l] };
                let outward = Vector::<D>::from_fn(|k, _| if k == l { sign } else { 0.0 });
                let node_layer = PADDING + side * body.cells[l];
                match problem.boundaries[l][side] {
                    Boundary::Free => {}
                    Boundary::Pressure { value, segment } => {
                        // points whose domain touches the edge carry its load
                        for p in 0..points.len() {
                            let x = points.reference[p];
                            let h = points.half_size[p];
                            if ((x[l] + sign * h[l]) - edge).abs() > 1e-9 * body.spacing[l] {
                                continue;
                            }
                            let s = Grid::<D>::segment_axis(l).map_or(0.0, |k| x[k]);
                            if !Boundary::acts_at(segment, s) {
                                continue;
                            }
                            let area: f64 =
                                Grid::<D>::tangent_axes(l).map(|k| 2.0 * h[k]).product();
                            let mut offset = Vector::<D>::zeros();
                            offset[l] = sign * h[l];
                            loads.push(SurfaceLoad {
                                point: p,
                                offset,
                                force: outward * (-value * area),
                            });
                        }
                    }
                    Boundary::Velocity { value, segment } => velocity_edges.push(VelocityEdge {
                        axis: l,
                        node_layer,
                        value: -sign * value,
                        segment,
                        symmetry: false,
                    }),
                    Boundary::Symmetry => velocity_edges.push(VelocityEdge {
                        axis: l,
                        node_layer,
                        value: 0.0,
                        segment: None,
                        symmetry: true,
                    }),
                }
            }
        }
        let nodes = grid.vertex_count();
        let np = points.len();
        let mut mpm = Self {
            solver: MpmSolver {
                config,
                options,
                body,
                material: problem.material,
                model: problem.model,
                wave_speed: problem.max_wave_speed(),
                loads,
                velocity_edges,
                node_mass: vec![0.0; nodes],
                node_momentum: vec![Vector::<D>::zeros(); nodes],
                node_force: vec![Vector::<D>::zeros(); nodes],
                point_cell: vec![0; np],
                shape: vec![0.0; np * npc],
                shape_gradient: vec![Vector::<D>::zeros(); np * npc],
                shapes_ready: false,
                grid,
            },
            state: MpmState {
                points,
                work: 0.0,
                impulse: Vector::<D>::zeros(),
            },
        };
        let kick = mpm.solver.impose_point_velocities(&mut mpm.state.points);
        mpm.state.impulse += kick;
        Ok(mpm)
    }
}

impl<const D: usize> MpmSolver<D> {
    /// Whether vertex `v` lies on velocity edge `e` (and inside its segment).
    fn on_edge(&self, e: &VelocityEdge, v: usize) -> bool {
        let counts = self.grid.vertex_counts();
        let mut rest = v;
        let mut idx = [0usize; D];
        for k in 0..D {
            idx[k] = rest % counts[k];
            rest /= counts[k];
        }
        if idx[e.axis] != e.node_layer {
            return false;
        }
        let s = Grid::<D>::segment_axis(e.axis).map_or(0.0, |k| self.grid.vertex_position(v)[k]);
        Boundary::acts_at(e.segment, s)
    }

    /// Points on a velocity edge take the prescribed normal velocity (as the paper does).
    /// Returns the impulse this gives them, `Σ m_p Δv_p`.
    fn impose_point_velocities(&self, points: &mut MaterialPoints<D>) -> Vector<D> {
        let mut kick = Vector::<D>::zeros();
        for e in self.velocity_edges.iter().filter(|e| !e.symmetry) {
            let side_is_low = e.node_layer == PADDING;
            let edge = if side_is_low {
                self.body.origin[e.axis]
            } else {
                self.body.upper()[e.axis]
            };
            for p in 0..points.len() {
                let x = points.reference[p];
                let h = points.half_size[p];
                let sign = if side_is_low { -1.0 } else { 1.0 };
                if ((x[e.axis] + sign * h[e.axis]) - edge).abs() > 1e-9 * self.body.spacing[e.axis]
                {
                    continue;
                }
                let s = Grid::<D>::segment_axis(e.axis).map_or(0.0, |k| x[k]);
                if Boundary::acts_at(e.segment, s) {
                    kick[e.axis] += points.mass[p] * (e.value - points.velocity[p][e.axis]);
                    points.velocity[p][e.axis] = e.value;
                }
            }
        }
        kick
    }

    /// Phase 1: shape functions at the current positions, then mass, momentum and forces
    /// on the grid.
    pub fn particles_to_grid(&mut self, points: &MaterialPoints<D>, with_internal: bool) {
        let npc = Grid::<D>::NODES_PER_CELL;
        self.node_mass.iter_mut().for_each(|m| *m = 0.0);
        self.node_momentum
            .iter_mut()
            .for_each(|m| *m = Vector::<D>::zeros());
        self.node_force
            .iter_mut()
            .for_each(|m| *m = Vector::<D>::zeros());
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        for p in 0..points.len() {
            if moving || !self.shapes_ready {
                let x = if moving {
                    &points.position[p]
                } else {
                    &points.reference[p]
                };
                // a point outside the padded grid is reported by check_finite
                let (c, xi) = self
                    .grid
                    .locate(x)
                    .unwrap_or((self.point_cell[p], Vector::<D>::from_element(0.5)));
                self.point_cell[p] = c;
                self.grid.shape(
                    &xi,
                    &mut self.shape[p * npc..(p + 1) * npc],
                    &mut self.shape_gradient[p * npc..(p + 1) * npc],
                );
            }
            let c = self.point_cell[p];
            let (s, g) = (
                &self.shape[p * npc..(p + 1) * npc],
                &self.shape_gradient[p * npc..(p + 1) * npc],
            );
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                let w = s[a] * points.mass[p];
                self.node_mass[i] += w;
                self.node_momentum[i] += points.velocity[p] * w;
                if with_internal {
                    self.node_force[i] -= (points.stress[p] * g[a]) * points.volume[p];
                }
            }
        }
    }

    /// Internal forces only (USF computes them after its stress update).
    fn internal_forces(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        for p in 0..points.len() {
            let c = self.point_cell[p];
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                self.node_force[i] -=
                    (points.stress[p] * self.shape_gradient[p * npc + a]) * points.volume[p];
            }
        }
    }

    /// External surface loads as nodal forces at the current surface positions.
    fn external_forces(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut s = [0.0; MAX_NODES];
        let mut g = [Vector::<D>::zeros(); MAX_NODES];
        for k in 0..self.loads.len() {
            let load = self.loads[k];
            let x = match self.options.frame {
                MpmFrame::TotalLagrangian => points.reference[load.point],
                MpmFrame::UpdatedLagrangian => points.position[load.point],
            } + load.offset;
            let Some((c, xi)) = self.grid.locate(&x) else {
                continue;
            };
            self.grid.shape(&xi, &mut s[..npc], &mut g[..npc]);
            // only nodes with mass can take the load: renormalise over them so the
            // whole force reaches the body (momentum is conserved)
            let mut total = 0.0;
            for a in 0..npc {
                if self.node_mass[self.grid.vertex_of(c, a)] > 0.0 {
                    total += s[a];
                }
            }
            if total <= 0.0 {
                continue;
            }
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                if self.node_mass[i] > 0.0 {
                    self.node_force[i] += load.force * (s[a] / total);
                }
            }
        }
    }

    /// Power of the surface loads, `Σ F · v_p` with `v_p` the velocity of the loaded point.
    fn load_power(&self, points: &MaterialPoints<D>) -> f64 {
        self.loads
            .iter()
            .map(|l| l.force.dot(&points.velocity[l.point]))
            .sum()
    }

    /// Phase 2: `p_i += Δt f_i`, then prescribed nodal velocities. Returns the work done
    /// in the step by the velocity constraints, `Δt Σ r · v_d`, and the impulse of the
    /// external and reaction forces, `Δt Σ (f_ext + r)`.
    pub fn grid_update(&mut self, dt: f64) -> (f64, Vector<D>) {
        let mut impulse = Vector::<D>::zeros();
        for i in 0..self.node_mass.len() {
            if self.node_mass[i] > 0.0 {
                self.node_momentum[i] += self.node_force[i] * dt;
            }
        }
        let mut work = 0.0;
        for k in 0..self.velocity_edges.len() {
            let e = self.velocity_edges[k];
            for v in 0..self.node_mass.len() {
                if self.node_mass[v] > 0.0 && self.on_edge(&e, v) {
                    let m = self.node_mass[v];
                    let old = self.node_momentum[v][e.axis];
                    self.node_momentum[v][e.axis] = e.value * m;
                    // reaction force of the constraint, kept in the force for the FLIP update
                    let reaction = (e.value * m - old) / dt;
                    self.node_force[v][e.axis] += reaction;
                    work += dt * reaction * e.value;
                    impulse[e.axis] += dt * reaction;
                }
            }
        }
        (work, impulse)
    }

    /// Phase 3: FLIP velocity update and position update from the nodal velocity.
    pub fn grid_to_particles(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let npc = Grid::<D>::NODES_PER_CELL;
        for p in 0..points.len() {
            let c = self.point_cell[p];
            let mut dv = Vector::<D>::zeros();
            let mut v = Vector::<D>::zeros();
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                let m = self.node_mass[i];
                if m > 0.0 {
                    let s = self.shape[p * npc + a];
                    dv += self.node_force[i] * (s * dt / m);
                    v += self.node_momentum[i] * (s / m);
                }
            }
            points.velocity[p] += dv;
            points.position[p] += v * dt;
        }
    }

    /// Phase 4: nodal momentum mapped again from the updated point velocities (with the
    /// shape functions of the start of the step), then the prescribed nodal velocities.
    pub fn remap_momentum(&mut self, points: &MaterialPoints<D>) {
        let npc = Grid::<D>::NODES_PER_CELL;
        self.node_momentum
            .iter_mut()
            .for_each(|m| *m = Vector::<D>::zeros());
        for p in 0..points.len() {
            let c = self.point_cell[p];
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                self.node_momentum[i] +=
                    points.velocity[p] * (self.shape[p * npc + a] * points.mass[p]);
            }
        }
        for k in 0..self.velocity_edges.len() {
            let e = self.velocity_edges[k];
            for v in 0..self.node_mass.len() {
                if self.node_mass[v] > 0.0 && self.on_edge(&e, v) {
                    self.node_momentum[v][e.axis] = e.value * self.node_mass[v];
                }
            }
        }
    }

    /// Phase 5: stress and volume update from the nodal velocity (linear elasticity), or
    /// `F += Δt ∇_X v`, `Π = Π(F)` (Saint-Venant–Kirchhoff, total Lagrangian).
    pub fn update_stress(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let npc = Grid::<D>::NODES_PER_CELL;
        for p in 0..points.len() {
            let c = self.point_cell[p];
            // velocity gradient ∇v = Σ_i v_i ⊗ ∇N_ip (∇_X in the total Lagrangian frame)
            let mut l = Tensor::<D>::zeros();
            for a in 0..npc {
                let i = self.grid.vertex_of(c, a);
                let m = self.node_mass[i];
                if m > 0.0 {
                    l += (self.node_momentum[i] / m) * self.shape_gradient[p * npc + a].transpose();
                }
            }
            match self.model {
                Model::LinearElastic => {
                    points.stress[p] += self.material.stress(&((l + l.transpose()) * 0.5)) * dt;
                }
                Model::Svk(svk) => {
                    points.deformation[p] += l * dt;
                    points.stress[p] = svk.piola(&points.deformation[p]);
                }
            }
            if self.options.frame == MpmFrame::UpdatedLagrangian {
                points.volume[p] *= 1.0 + dt * l.trace();
            }
        }
    }

    /// One step (module doc).
    pub fn step(&mut self, state: &mut MpmState<D>, dt: f64) {
        let usl = self.options.stress_update != StressUpdate::Usf;
        self.particles_to_grid(&state.points, usl);
        self.shapes_ready = true;
        if !usl {
            self.update_stress(&mut state.points, dt);
            self.internal_forces(&state.points);
        }
        self.external_forces(&state.points);
        let power_start = self.load_power(&state.points);
        for load in &self.loads {
            state.impulse += load.force * dt;
        }
        let (work, impulse) = self.grid_update(dt);
        state.work += work;
        state.impulse += impulse;
        self.grid_to_particles(&mut state.points, dt);
        // trapezoidal work of the loads over the step
        state.work += 0.5 * dt * (power_start + self.load_power(&state.points));
        state.impulse += self.impose_point_velocities(&mut state.points);
        if self.options.stress_update == StressUpdate::Musl {
            self.remap_momentum(&state.points);
        }
        if usl {
            self.update_stress(&mut state.points, dt);
        }
    }
}

impl<const D: usize> Method<D> for Mpm<D> {
    fn config(&self) -> &MethodConfig {
        &self.solver.config
    }
    fn stable_dt(&self) -> f64 {
        self.solver.config.courant * self.solver.body.min_spacing() / self.solver.wave_speed
    }
    fn step(&mut self, _t: f64, dt: f64) {
        self.solver.step(&mut self.state, dt);
    }
    fn sample_into(&self, out: &mut Samples<D>) {
        self.state.points.sample_into(out);
    }
    fn energy(&self) -> f64 {
        let p = &self.state.points;
        let m = &self.solver.material;
        p.energy(|i| match self.solver.model {
            Model::LinearElastic => m.energy_density(&p.stress[i]),
            Model::Svk(svk) => svk.energy_density(&p.deformation[i]),
        })
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    fn momentum(&self) -> Vector<D> {
        self.state.points.momentum()
    }
    fn external_impulse(&self) -> Vector<D> {
        self.state.impulse
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let p = &self.state.points;
        for i in 0..p.len() {
            let finite = p.stress[i].iter().all(|x| x.is_finite())
                && p.velocity[i].iter().all(|x| x.is_finite())
                && p.position[i].iter().all(|x| x.is_finite());
            if !finite {
                return Err(BadState {
                    place: p.reference[i],
                    reason: "non-finite stress, velocity or position at a material point".into(),
                });
            }
            if let Model::Svk(svk) = self.solver.model {
                if !svk.admissible(&p.deformation[i], self.solver.wave_speed) {
                    return Err(BadState {
                        place: p.reference[i],
                        reason: impact_core::material::Svk::inadmissible_reason(&p.deformation[i]),
                    });
                }
            }
            let moving = self.solver.options.frame == MpmFrame::UpdatedLagrangian;
            if moving && self.solver.grid.locate(&p.position[i]).is_none() {
                return Err(BadState {
                    place: p.reference[i],
                    reason: format!(
                        "material point left the background grid (x = {:?})",
                        p.position[i].as_slice()
                    ),
                });
            }
        }
        Ok(())
    }
    fn hottest_place(&self) -> Vector<D> {
        self.state.points.hottest_place()
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        self.state.points.perturb_velocity(kick);
    }
    fn cells(&self) -> usize {
        self.solver.body.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.state.points.len()
    }
}

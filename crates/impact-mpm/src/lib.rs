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
//!
//! Layout: `shape.rs` (the shape functions and their stencils: a new one goes there),
//! `transfer.rs` (phases 1, 3, 4, 5: the scatters, coloured by node layer, and the gathers), `grid_update.rs`
//! (phase 2), `method.rs` (the `Method` impl); this file holds the solver and its buffers.

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
mod grid_update;
mod method;
pub mod shape;
mod transfer;
use impact_core::method::{MethodConfig, Model, MpmFrame, MpmOptions, StressUpdate};
use impact_core::parallel::worth_parallel;
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::{CoreError, Grid, LinearElastic, Problem, Vector};

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
    /// Bonded impactor: the tangential velocity is prescribed (zero) too.
    bonded: bool,
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
    fn new(nodes: usize) -> Self {
        Self {
            mass: vec![0.0; nodes],
            momentum: vec![Vector::<D>::zeros(); nodes],
            force: vec![Vector::<D>::zeros(); nodes],
        }
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
    /// Prescribed nodal velocity components `(node, axis, value)` (velocity and symmetry
    /// edges), found once.
    node_constraints: Vec<(usize, usize, f64)>,
    /// Prescribed point velocity components `(point, axis, value)` (velocity edges).
    point_constraints: Vec<(usize, usize, f64)>,
    nodes: NodeSums<D>,
    /// The points sorted by the layer (along the last axis) of their cell, and where each
    /// layer starts in that order (`layers + 1` entries): the colouring of the scatters.
    layer_order: Vec<usize>,
    layer_start: Vec<usize>,
    parallel: bool,
    /// Nodes holding at most this mass are empty: `1e-10` of the lightest point. A smooth
    /// stencil (GIMP, B-splines) gives round-off weights (~1e-15) to nodes at its edge; with
    /// USL their velocity `p_i/m_i` would be divided by that round-off.
    empty_mass: f64,
    /// The shape functions' stencil ([`shape`]).
    stencil: shape::Stencil<D>,
    /// Per point: the linear index of its stencil's base node, shape values and gradients
    /// (`stencil.nodes` per point).
    point_base: Vec<usize>,
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
        let stencil = shape::Stencil::new(&grid, options.shape, per_axis);
        let npc = stencil.nodes;
        let (loads, velocity_edges) = edge_conditions(problem, &points);
        let nodes = grid.vertex_count();
        let np = points.len();
        let node_constraints = node_constraints(&grid, &velocity_edges);
        let point_constraints = point_constraints(&body, &points, &velocity_edges);
        let parallel = worth_parallel(np);
        let mut mpm = Self {
            solver: MpmSolver {
                config,
                options,
                body,
                material: problem.material,
                model: problem.model,
                wave_speed: problem.max_wave_speed(),
                loads,
                node_constraints,
                point_constraints,
                nodes: NodeSums::new(nodes),
                layer_order: vec![0; np],
                layer_start: vec![0; grid.cells[D - 1] + 2],
                parallel,
                point_base: vec![0; np],
                stencil,
                empty_mass: 1e-10 * points.mass.iter().copied().fold(f64::INFINITY, f64::min),
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

/// The surface loads of the pressure edges (on the points whose domain touches the edge,
/// at the domain's edge midpoint, force `-p A n`) and the velocity and symmetry edges.
fn edge_conditions<const D: usize>(
    problem: &Problem<D>,
    points: &MaterialPoints<D>,
) -> (Vec<SurfaceLoad<D>>, Vec<VelocityEdge>) {
    let body = &problem.grid;
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
                        let area: f64 = Grid::<D>::tangent_axes(l).map(|k| 2.0 * h[k]).product();
                        let mut offset = Vector::<D>::zeros();
                        offset[l] = sign * h[l];
                        loads.push(SurfaceLoad {
                            point: p,
                            offset,
                            force: outward * (-value * area),
                        });
                    }
                }
                Boundary::Velocity {
                    value,
                    segment,
                    bonded,
                } => velocity_edges.push(VelocityEdge {
                    axis: l,
                    node_layer,
                    value: -sign * value,
                    segment,
                    symmetry: false,
                    bonded,
                }),
                Boundary::Symmetry => velocity_edges.push(VelocityEdge {
                    axis: l,
                    node_layer,
                    value: 0.0,
                    segment: None,
                    symmetry: true,
                    bonded: false,
                }),
            }
        }
    }
    (loads, velocity_edges)
}

/// The prescribed nodal velocity components of the velocity and symmetry edges:
/// `(node, axis, value)` for every node of the edge's layer, and of the padding layers
/// beyond it, inside its segment.
fn node_constraints<const D: usize>(
    grid: &Grid<D>,
    edges: &[VelocityEdge],
) -> Vec<(usize, usize, f64)> {
    let counts = grid.vertex_counts();
    let mut out = Vec::new();
    for e in edges {
        for v in 0..grid.vertex_count() {
            let along = (0..e.axis).fold(v, |rest, k| rest / counts[k]) % counts[e.axis];
            let s = Grid::<D>::segment_axis(e.axis).map_or(0.0, |k| grid.vertex_position(v)[k]);
            // the edge layer and the padding beyond it: smooth stencils (GIMP, B-splines)
            // put mass on nodes outside the body, which move with the wall
            let outside = if e.node_layer == PADDING {
                along <= e.node_layer
            } else {
                along >= e.node_layer
            };
            if outside && Boundary::acts_at(e.segment, s) {
                out.push((v, e.axis, e.value));
                if e.bonded {
                    out.extend(Grid::<D>::tangent_axes(e.axis).map(|k| (v, k, 0.0)));
                }
            }
        }
    }
    out
}

/// The prescribed point velocity components (velocity edges, as the paper does): points
/// whose domain touches the edge, inside its segment.
fn point_constraints<const D: usize>(
    body: &Grid<D>,
    points: &MaterialPoints<D>,
    edges: &[VelocityEdge],
) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::new();
    for e in edges.iter().filter(|e| !e.symmetry) {
        let low = e.node_layer == PADDING;
        let (edge, sign) = if low {
            (body.origin[e.axis], -1.0)
        } else {
            (body.upper()[e.axis], 1.0)
        };
        for p in 0..points.len() {
            let (x, h) = (points.reference[p], points.half_size[p]);
            let touches =
                ((x[e.axis] + sign * h[e.axis]) - edge).abs() <= 1e-9 * body.spacing[e.axis];
            let s = Grid::<D>::segment_axis(e.axis).map_or(0.0, |k| x[k]);
            if touches && Boundary::acts_at(e.segment, s) {
                out.push((p, e.axis, e.value));
                if e.bonded {
                    out.extend(Grid::<D>::tangent_axes(e.axis).map(|k| (p, k, 0.0)));
                }
            }
        }
    }
    out
}

impl<const D: usize> MpmSolver<D> {
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

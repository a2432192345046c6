//! Building MPM ([`Mpm::build`]) on the whole body or on one rank's box of it (`slab.rs`),
//! and where the solver lies in the whole run ([`Place`]).
//!
//! **A box's nodes.** A rank stores the cells of its box plus the halo ([`RankBox`]), and
//! the background nodes of those cells plus [`PADDING`] cells on every side (as the whole
//! body's grid is padded): the box `first_node[k] .. first_node[k] + node_counts[k]` of the
//! whole padded grid's nodes per axis, numbered lexicographically (axis 0 fastest) like the
//! whole grid's, so the box keeps the nodes' global relative order. The stencil's node
//! offsets use the box's strides; the shape functions are evaluated on the whole padded grid
//! (the same bits as one rank's: a box's own origin would round `(x − x_0)/h` differently)
//! and their base node `Σ_k b_k s_k` (whole per-axis index `b_k`, box stride `s_k`) is moved
//! to the box by `node_offset = Σ_k first_node_k s_k`, which is the box's number of the node
//! `b − first_node` (linear in `b`). The nodal constraints and the empty-node walls are
//! found on the stored nodes only, each at its place in the whole grid
//! ([`Place::whole_node`]; a mirror node moved back by [`Place::local_node`]).
use crate::edges::{edge_conditions, node_constraints, point_constraints};
use crate::{shape, EmptyNodes, Mpm, MpmSolver, MpmState, NodeSums, PADDING};
use impact_core::comm::RankBox;
use impact_core::method::{MethodConfig, MpmFrame, MpmShape, MpmTransfer};
use impact_core::parallel::worth_parallel;
use impact_core::{CoreError, Grid, Problem, Tensor, Vector};
use std::ops::Range;

/// Where a solver's nodes and points lie in the whole run: on one rank the whole padded
/// grid and every point; on a rank's box (`slab.rs`) the nodes and points of its stored
/// cells (module doc), of which it owns some.
#[derive(Debug, Clone)]
pub(crate) struct Place<const D: usize> {
    /// The padded background grid of the whole body. Shape functions and load positions
    /// are evaluated on it, then moved to the box's nodes (module doc): a box's own origin
    /// would round the grid coordinates `(x − x_0)/h` differently, and its weights would
    /// differ from one rank's in the last bits.
    pub whole: Grid<D>,
    /// Per axis, the node of `whole` that is this solver's first.
    pub first_node: [usize; D],
    /// Per axis, this solver's nodes.
    pub node_counts: [usize; D],
    /// Node layers (along the last axis) of `whole` below this solver's first: the coloured
    /// scatter's blocks follow the whole grid's layers (`transfer.rs`), so a node's sum is
    /// added in one rank's order.
    pub first_layer: usize,
    /// `Σ_k first_node_k s_k` with `s_k` this solver's node strides (module doc).
    pub node_offset: usize,
    /// Per axis, the node indices (this solver's) whose constraint reactions it counts in
    /// the work and impulse: those of its own cells' lower faces, and on the grid's last
    /// (first) own cells those above (below) too.
    pub owned_nodes: [Range<usize>; D],
    /// The points whose loads, prescribed velocities and diagnostics this solver counts, a
    /// run per row of own cells (one run on one rank and on a slab), in order.
    pub owned_runs: Vec<Range<usize>>,
    /// The stored points in the whole run's order (their global numbers' order), which the
    /// scatters keep within a layer (`weights.rs`), so that a node adds its points as one
    /// rank does; empty where that is the stored order (`migrate.rs` fills it).
    pub scatter_order: Vec<usize>,
}

impl<const D: usize> Place<D> {
    /// Whether point `p` is this solver's own.
    #[inline]
    pub fn owns(&self, p: usize) -> bool {
        let runs = &self.owned_runs;
        let k = runs.partition_point(|r| r.end <= p);
        k < runs.len() && runs[k].contains(&p)
    }

    /// Whether this solver counts the reactions of its node `v`.
    pub fn owns_node(&self, v: usize) -> bool {
        let mut rest = v;
        (0..D).all(|k| {
            let along = rest % self.node_counts[k];
            rest /= self.node_counts[k];
            self.owned_nodes[k].contains(&along)
        })
    }

    /// The whole grid's number of this solver's node `local`.
    pub fn whole_node(&self, local: usize) -> usize {
        let counts = self.whole.vertex_counts();
        let (mut rest, mut whole, mut stride) = (local, 0, 1);
        for k in 0..D {
            whole += (self.first_node[k] + rest % self.node_counts[k]) * stride;
            rest /= self.node_counts[k];
            stride *= counts[k];
        }
        whole
    }

    /// This solver's number of the whole grid's node `whole`, if it stores it.
    pub fn local_node(&self, whole: usize) -> Option<usize> {
        let counts = self.whole.vertex_counts();
        let (mut rest, mut local, mut stride) = (whole, 0, 1);
        for k in 0..D {
            let along = (rest % counts[k]).checked_sub(self.first_node[k])?;
            if along >= self.node_counts[k] {
                return None;
            }
            local += along * stride;
            rest /= counts[k];
            stride *= self.node_counts[k];
        }
        Some(local)
    }
}

impl<const D: usize> Mpm<D> {
    /// MPM for `problem` on the stored box of `rank_box` (the whole body without one):
    /// only the stored cells' points, seeded from the whole grid's origin and global cell
    /// indices (the same bits as one rank's, in memory that shrinks with the ranks), the
    /// edge conditions of the whole body's edges only (found on the points by position: a
    /// cut face is no edge), the nodal constraints found on the stored nodes, and the
    /// empty-node floor, the shared row of weights and the serial/parallel choice of the
    /// whole body (`slab.rs`).
    pub(crate) fn build(
        problem: &Problem<D>,
        config: MethodConfig,
        rank_box: Option<&RankBox>,
    ) -> Result<Self, CoreError> {
        let options = *config.mpm().ok_or_else(|| CoreError::Unsupported {
            method: "mpm".into(),
            message: "not an MPM configuration".into(),
        })?;
        let per_axis = problem.points_per_axis(config.points_per_cell)?;
        problem.check_config(&config)?;
        let body = problem.grid.clone();
        let whole = Grid {
            origin: body.origin - body.spacing * PADDING as f64,
            spacing: body.spacing,
            cells: std::array::from_fn(|k| body.cells[k] + 2 * PADDING),
        };
        let every: [Range<usize>; D] = std::array::from_fn(|k| 0..body.cells[k]);
        let (stored, owned) = match rank_box {
            Some(b) => (
                std::array::from_fn(|k| b.stored[k].clone()),
                std::array::from_fn(|k| b.owned[k].clone()),
            ),
            None => (every.clone(), every),
        };
        let cpdi = options.shape == MpmShape::Cpdi;
        let with_domains = |p: impact_core::points::MaterialPoints<D>| {
            if cpdi {
                p.with_domains()
            } else {
                p
            }
        };
        let points = with_domains(problem.material_points_of_box(&body, &config, &stored)?);
        // the serial/parallel choice and the shared weights' point are the whole body's
        // (the same sums and bits on every rank count): its first cell's first point
        let parallel = worth_parallel(body.cell_count() * config.points_per_cell);
        let first_cell: [Range<usize>; D] = std::array::from_fn(|_| 0..1);
        let first = with_domains(problem.material_points_of_box(&body, &config, &first_cell)?);
        let share_from = (
            first.reference.first().copied(),
            first.domain.first().copied(),
        );
        // every point's mass is `ρ V_cell / n` (the seeding's): the box's lightest point is
        // the body's, and so is the empty-node floor
        let lightest = points.mass.iter().copied().fold(f64::INFINITY, f64::min);
        let grid = whole.cut(
            std::array::from_fn(|k| stored[k].start),
            std::array::from_fn(|k| stored[k].len() + 2 * PADDING),
        );
        let stencil = shape::Stencil::new(&grid, options.shape, per_axis);
        let node_count = grid.vertex_count();
        let node_counts = grid.vertex_counts();
        let whole_counts = whole.vertex_counts();
        // per axis: the own cells' lower faces' nodes, the grid's first (last) cells' those
        // below (above) too
        let owned_nodes = std::array::from_fn(|k| {
            let low = if owned[k].start == 0 {
                0
            } else {
                PADDING + owned[k].start
            };
            let high = if owned[k].end == body.cells[k] {
                whole_counts[k]
            } else {
                PADDING + owned[k].end
            };
            low - stored[k].start..high - stored[k].start
        });
        let per_cell = config.points_per_cell;
        let owned_runs = match rank_box {
            Some(b) => (b.owned_runs().into_iter())
                .map(|r| r.start * per_cell..r.end * per_cell)
                .collect(),
            None => std::iter::once(0..points.len()).collect(),
        };
        let place = Place {
            first_node: std::array::from_fn(|k| stored[k].start),
            node_counts,
            first_layer: stored[D - 1].start,
            node_offset: (0..D).map(|k| stored[k].start * stencil.strides[k]).sum(),
            owned_nodes,
            owned_runs,
            scatter_order: Vec::new(),
            whole,
        };
        let (loads, velocity_edges) = edge_conditions(problem, &points);
        let (node_constraints, mirror_constraints, walls) =
            node_constraints(&place, &velocity_edges);
        let empty = EmptyNodes::new(lightest, config.points_per_cell, walls);
        let np = points.len();
        let point_constraints = point_constraints(&body, &points, &velocity_edges);
        let affine = match options.transfer {
            MpmTransfer::Apic => vec![Tensor::<D>::zeros(); np],
            _ => Vec::new(),
        };
        // the weights are fixed: phase 1's mass sums are kept (`NodeSums::point_mass`)
        let fixed_mass = options.frame == MpmFrame::TotalLagrangian;
        let mut mpm = Self {
            solver: MpmSolver {
                config,
                options,
                body,
                material: problem.material,
                model: problem.model,
                wave_speed: problem.max_wave_speed(),
                load_splits: vec![Default::default(); loads.len()],
                loads,
                node_constraints,
                fold_changes: crate::grid_update::FoldChange::of(&mirror_constraints, &place),
                mirror_constraints,
                point_constraints,
                nodes: NodeSums::new(node_count, fixed_mass),
                layer_order: vec![0; np],
                layer_start: vec![0; grid.cells[D - 1] + 2],
                in_layer_order: false,
                parallel,
                point_base: vec![0; np],
                stencil,
                empty,
                shape: Vec::new(),
                shape_gradient: Vec::new(),
                weight_stride: 0,
                point_row: Vec::new(),
                shapes_ready: false,
                fuse_gathers: true,
                grid,
                place,
            },
            state: MpmState {
                points,
                work: 0.0,
                impulse: Vector::<D>::zeros(),
                initial_energy: 0.0,
                affine,
            },
        };
        mpm.solver.weight_stride = mpm.solver.stencil.nodes;
        mpm.solver.allocate_weights(&mpm.state.points, share_from);
        // the scene's initial state (of the owned points); the impactor's kick below is the
        // load's doing (the reference's work counts it)
        mpm.state.initial_energy = impact_core::Method::energy(&mpm);
        let kick = mpm
            .solver
            .impose_point_velocities(&mut mpm.state.points, (0.0, 0.0));
        mpm.state.impulse += kick;
        Ok(mpm)
    }
}

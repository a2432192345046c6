//! The fused nodal sweep ([`StepPath::FusedNodal`]): phases 2-4 of one stage of the nodal
//! paths in one sweep, for linear elasticity in 1D and 2D at any number of points per
//! cell, with forward Euler or Heun's RK2:
//!
//! 1. phase 2, the Godunov flux of each face from the averages of each side's face nodes
//!    (paper §4);
//! 2. phase 2b (2D, CTU), the transverse corrections, a cell's fluctuation being
//!    `w_l = F_l,high - F_l,low + F_l(q_C,low - q_C,high)`
//!    (`DgmpmSolver::transverse_corrections`);
//! 3. the boundary force and power of the loaded faces;
//! 4. phase 3, the nodal rates of each cell from its four final face fluxes
//!    (`DgmpmSolver::rates_of_cell`, paper eq. 14-16), and at once phase 4,
//!    `q_i ← a q_i^n + (1 - a)(q_i + Δt q̇_i)` ([`crate::integrator::stage_update`]);
//! 5. in the step's last stage, phase 5 for the cell's points
//!    ([`crate::mapping::point_from_nodes`]): the new nodal fields are not stored.
//!
//! The 2D sweep is the cell path's ([`super`], `plane.rs`) with the nodal face states; the
//! 1D one walks each chunk of cells. No face array and no rate array is allocated. Between
//! RK2's stages the new nodal fields go to a second buffer, swapped in after the sweep
//! (the old ones become the start-of-step fields, so they are never copied), or at `2^D`
//! points per cell into the points' state arrays (below).
//!
//! **RK2 at one point per cell.** Phase 1 is the identity there (every node of a cell
//! carries its point's state, `StepPath::SinglePoint`) and the lumped masses are
//! `M_i = S_i m_p`, so phase 1 is not run: the first stage reads the points (its face
//! states are then the cells' states and the side terms vanish, as on the cell path) and
//! writes the nodal fields in place; the masses and the start-of-step fields are formed
//! from the point where a stage needs them (the second stage reads a point's state before
//! it writes it). No nodal mass, start or next buffer is allocated.
//!
//! **RK2 at `2^D` points per cell** (the plate at 4, the bar at 2; the update
//! `PointUpdate::Nodal`). The cell's points' state arrays then hold exactly as many
//! entries as its nodes, and after phase 1 nothing reads the points' start-of-step state
//! but phase 1 itself. So the first stage writes `q¹` into the points' stress and
//! velocity arrays (cell `c`'s nodes at entries `2^D c ..`, read back as nodal fields). The
//! second reads `q¹` there and each cell's `q⁰` from the nodes (read by that cell alone),
//! forms `q = ½ q⁰ + ½ (q¹ + Δt q̇¹)` and writes its points' new states (phase 5) over
//! its `q⁰`, in the nodal buffer; the points' and the nodes' arrays are then swapped. Nodal
//! storage: one set of fields, as Euler's (no start and no next buffer: 384 B a cell less
//! at 4 points in 2D), and the bytes moved are the three-buffer stages'. The values are
//! theirs, bit for bit. The increment update keeps the three buffers (it reads the
//! points' start-of-step state in phase 5).
//!
//! With every point strictly inside its cell, RK2 at one point per cell takes the Heun
//! cell sweeps instead (`heun.rs`): side states in closed form, no nodal rate and no
//! nodal field.
//!
//! Tested against the phase-by-phase nodal paths to 1e-13.
use super::{Band, FusedBuffers};
use crate::faces::Fields;
use crate::integrator::stage_update;
use crate::mapping::points_of_cell;
use crate::riemann::Conserved;
use crate::{DgmpmSolver, StepPath, MAX_NODES};
use impact_core::method::{Integrator, PointUpdate};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

mod line;

/// Where one band's stage update goes: the new nodal fields (`2^D` entries per cell), or
/// in the step's last stage the band's points (phase 5 in the sweep) and their positions,
/// moved there with the new velocity (`x ← x + Δt v`, the arithmetic of
/// `DgmpmSolver::move_points`, which the fused nodal path then does not run).
pub(super) enum NodalOut<'a, const D: usize> {
    Nodes {
        tensor: &'a mut [Tensor<D>],
        velocity: &'a mut [Vector<D>],
    },
    Points {
        tensor: &'a mut [Tensor<D>],
        velocity: &'a mut [Vector<D>],
        position: &'a mut [Vector<D>],
    },
}

/// What a stage reads: the points' volumes, the nodal fields it starts from, the lumped
/// masses phase 1 formed (one point per cell; several: in the cell layouts) and the
/// start-of-step fields (RK2's second stage); with one point per cell
/// instead the points' masses (`M_i = S_i m_p`) and, in the first stage, their states.
#[derive(Clone, Copy)]
pub(super) struct NodalIn<'a, const D: usize> {
    volume: &'a [f64],
    tensor: &'a [Tensor<D>],
    velocity: &'a [Vector<D>],
    mass: &'a [f64],
    start: (&'a [Tensor<D>], &'a [Vector<D>]),
    point_mass: &'a [f64],
    points: Option<(&'a [Tensor<D>], &'a [Vector<D>])>,
}

/// The stage's step, start weight `a` (0: Euler and Heun's first stage; ½: Heun's second),
/// whether it is the step's last, and whether the nodes are formed from the points (RK2 at
/// one point per cell: module doc).
#[derive(Clone, Copy)]
pub(super) struct Stage {
    dt: f64,
    start_weight: f64,
    last: bool,
    single: bool,
    /// RK2's fields between its stages live in the points' state arrays (module doc).
    in_points: bool,
}

impl Stage {
    /// Whether the stage reads the points instead of nodal fields (the first stage with
    /// one point per cell).
    fn reads_points(self) -> bool {
        self.single && self.start_weight == 0.0
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Whether the fused nodal path forms its nodes from the points without phase 1 (RK2
    /// at one point per cell; module doc of `fused::nodal`).
    pub(crate) fn fused_nodal_single(&self) -> bool {
        self.points_per_cell == 1 && self.options.integrator == Integrator::Rk2
    }

    /// Whether the fused nodal path keeps RK2's first-stage fields in the points' state
    /// arrays (`2^D` points per cell, the nodal update; module doc of `fused::nodal`).
    pub(crate) fn fused_nodal_in_points(&self) -> bool {
        self.path == StepPath::FusedNodal
            && self.options.integrator == Integrator::Rk2
            && self.points_per_cell == Grid::<D>::NODES_PER_CELL
            && self.options.update == PointUpdate::Nodal
    }

    /// One stage of the fused nodal path (module doc): the new nodal fields replace the
    /// old ones or, in the step's `last` stage, go to the points (phase 5). Returns the
    /// power and the force of the boundary conditions.
    pub(crate) fn fused_nodal_stage(
        &mut self,
        points: &mut MaterialPoints<D>,
        dt: f64,
        start_weight: f64,
        last: bool,
    ) -> (f64, Vector<D>) {
        debug_assert_eq!(self.path, StepPath::FusedNodal);
        debug_assert!(
            !self.heun_on_cells(),
            "internal: the Heun step is heun_step"
        );
        let stage = Stage {
            dt,
            start_weight,
            last,
            single: self.fused_nodal_single(),
            in_points: self.fused_nodal_in_points(),
        };
        self.by_dimension(
            points,
            |_, _| unreachable!("internal: the fused nodal sweep is 1D and 2D (Fusable::All)"),
            |solver, points| solver.nodal_sweep_2d(points, stage),
            |solver, points| solver.nodal_sweep_1d(points, stage),
        )
    }

    /// Run `sweep(band index, band, face fields, inputs, output)` on every band. A stage
    /// before the last writes the new nodal fields: in place when it reads the points,
    /// into the points' state arrays when they hold RK2's stage fields (`in_points`),
    /// otherwise to the next buffer, swapped in after (after a first stage, `a = 0`, the
    /// old fields become the start-of-step fields). The last stage writes the points (with
    /// `in_points` their new states into the nodal buffer, then swapped with the points'
    /// arrays). Returns the bands' power and force, added up.
    fn nodal_bands(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        stage: Stage,
        sweep: impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, NodalIn<'_, D>, &mut NodalOut<'_, D>)
            + Sync,
    ) -> (f64, Vector<D>) {
        self.with_buffers(|this, buffers, nodes| {
            let MaterialPoints {
                stress,
                velocity,
                position,
                volume,
                mass,
                ..
            } = points;
            let bands = &mut buffers.bands;
            let nodal_per_band = cells_per_band * Grid::<D>::NODES_PER_CELL;
            let point_per_band = cells_per_band * this.points_per_cell;
            // the positions' chunks match the bands in every stage (moved in the last)
            let position_chunks = (&mut position[..], point_per_band);
            // what every stage reads (the fields it starts from are set below)
            let base = NodalIn {
                volume,
                tensor: &[],
                velocity: &[],
                mass: &nodes.mass,
                start: (&nodes.start_tensor, &nodes.start_velocity),
                point_mass: mass,
                points: None,
            };
            if stage.reads_points() {
                // RK2's first stage at one point per cell: the points in, the nodes out
                let inputs = NodalIn {
                    points: Some((stress, velocity)),
                    ..base
                };
                let fields = Fields::per_cell(stress, velocity);
                let out = (&mut nodes.tensor[..], &mut nodes.velocity[..]);
                let out = (out, nodal_per_band, false);
                this.run_bands(bands, fields, inputs, out, position_chunks, &sweep);
            } else if stage.in_points && !stage.last {
                // RK2's first stage, q¹ into the points' state arrays (module doc)
                let inputs = NodalIn {
                    tensor: &nodes.tensor,
                    velocity: &nodes.velocity,
                    ..base
                };
                let fields = Fields::nodal(&nodes.tensor, &nodes.velocity);
                let out = ((&mut stress[..], &mut velocity[..]), nodal_per_band, false);
                this.run_bands(bands, fields, inputs, out, position_chunks, &sweep);
            } else if stage.in_points {
                // RK2's second stage: q¹ from the points' arrays, each cell's q⁰ from the
                // nodes, the cell's new point states over its q⁰; the arrays then swapped
                assert_eq!(
                    stress.len(),
                    nodes.tensor.len(),
                    "internal: 2^D points a cell"
                );
                let inputs = NodalIn {
                    tensor: stress,
                    velocity,
                    ..base
                };
                let fields = Fields::nodal(stress, velocity);
                let out = (&mut nodes.tensor[..], &mut nodes.velocity[..]);
                let out = (out, point_per_band, true);
                this.run_bands(bands, fields, inputs, out, position_chunks, &sweep);
                std::mem::swap(stress, &mut nodes.tensor);
                std::mem::swap(velocity, &mut nodes.velocity);
            } else {
                let inputs = NodalIn {
                    tensor: &nodes.tensor,
                    velocity: &nodes.velocity,
                    ..base
                };
                let fields = Fields::nodal(&nodes.tensor, &nodes.velocity);
                let out = match stage.last {
                    true => ((&mut stress[..], &mut velocity[..]), point_per_band, true),
                    false => (
                        (&mut buffers.next_tensor[..], &mut buffers.next_velocity[..]),
                        nodal_per_band,
                        false,
                    ),
                };
                this.run_bands(bands, fields, inputs, out, position_chunks, &sweep);
            }
            if !stage.last && !stage.reads_points() && !stage.in_points {
                if stage.start_weight == 0.0 && !nodes.start_tensor.is_empty() {
                    std::mem::swap(&mut nodes.start_tensor, &mut nodes.tensor);
                    std::mem::swap(&mut nodes.start_velocity, &mut nodes.velocity);
                }
                std::mem::swap(&mut nodes.tensor, &mut buffers.next_tensor);
                std::mem::swap(&mut nodes.velocity, &mut buffers.next_velocity);
            }
        })
    }

    /// [`Self::nodal_bands`]' loop: `sweep` on every band with its chunk of the output
    /// (`per_band` entries; the points' if `to_points`, else nodal fields) and of the
    /// points' positions (`position.1` per band; moved only with the points' output).
    #[allow(clippy::type_complexity)]
    fn run_bands(
        &self,
        bands: &mut [Band<D>],
        fields: Fields<'_, D>,
        inputs: NodalIn<'_, D>,
        ((tensor, velocity), per_band, to_points): (
            (&mut [Tensor<D>], &mut [Vector<D>]),
            usize,
            bool,
        ),
        position: (&mut [Vector<D>], usize),
        sweep: &(impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, NodalIn<'_, D>, &mut NodalOut<'_, D>)
              + Sync),
    ) {
        let parts = (
            chunks(bands, 1),
            (chunks(tensor, per_band), chunks(velocity, per_band)),
            chunks(position.0, position.1),
        );
        for_each_chunk(
            self.parallel,
            1,
            parts,
            |b, (band, (tensor, velocity), position)| {
                let mut out = match to_points {
                    true => NodalOut::Points {
                        tensor,
                        velocity,
                        position,
                    },
                    false => NodalOut::Nodes { tensor, velocity },
                };
                sweep(self, b, &mut band[0], fields, inputs, &mut out);
            },
        );
    }

    /// Phases 3-4 of cell `cell` (entry `local` of its band) from its faces' final fluxes
    /// `[low, high]` per axis: [`Self::rates_of_cell`] and the stage update of its nodes;
    /// in the last stage then phase 5 for the cell's points (`point_from_nodes`, the
    /// step's start being the start-of-step fields for RK2 and this stage's for Euler).
    /// With one point per cell the nodal fields, masses and start-of-step fields are formed
    /// from the point (module doc): the point's state is read before it is written.
    #[inline(always)]
    fn nodal_cell_update<const SINGLE: bool>(
        &self,
        (cell, local): (usize, usize),
        faces: [[&Conserved<D>; 2]; D],
        inputs: NodalIn<'_, D>,
        stage: Stage,
        out: &mut NodalOut<'_, D>,
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let range = cell * nodes_per_cell..(cell + 1) * nodes_per_cell;
        let Stage {
            dt, start_weight, ..
        } = stage;
        debug_assert_eq!(SINGLE, stage.single);
        let single = SINGLE;
        let layouts = &self.layouts;
        let layout = layouts.layout_of(cell);
        // one point per cell: the point's state on every node, M_i = S_i m_p
        let mut point_q = [Tensor::<D>::zeros(); MAX_NODES];
        let mut point_v = [Vector::<D>::zeros(); MAX_NODES];
        let mut point_m = [0.0; MAX_NODES];
        let point_state = match (SINGLE, inputs.points, &*out) {
            (false, ..) => None,
            (true, Some((q, v)), _) => Some((q[cell], v[cell])),
            (
                true,
                None,
                NodalOut::Points {
                    tensor, velocity, ..
                },
            ) => Some((tensor[local], velocity[local])),
            (true, None, NodalOut::Nodes { .. }) => None,
        };
        if let Some((q, v)) = point_state {
            point_q[..nodes_per_cell].fill(q);
            point_v[..nodes_per_cell].fill(v);
        }
        if single {
            let shape = layouts.shape_of(layout);
            for a in 0..nodes_per_cell {
                point_m[a] = shape[a] * inputs.point_mass[cell];
            }
        }
        let (q, v) = match SINGLE && inputs.points.is_some() {
            true => (&point_q[..nodes_per_cell], &point_v[..nodes_per_cell]),
            false => (
                &inputs.tensor[range.clone()],
                &inputs.velocity[range.clone()],
            ),
        };
        let mass = match (single, layouts.has_mapping()) {
            (true, _) => &point_m[..nodes_per_cell],
            (false, true) => layouts.mass_of(layout),
            (false, false) => &inputs.mass[range.clone()],
        };
        let mut rate_tensor = [Tensor::<D>::zeros(); MAX_NODES];
        let mut rate_velocity = [Vector::<D>::zeros(); MAX_NODES];
        let rates = (&mut rate_tensor[..], &mut rate_velocity[..]);
        self.rates_of_cell(cell, inputs.volume, (q, v, mass), faces, rates);
        // RK2's second stage with its fields in the points' arrays: this cell's q⁰ is in
        // the output, updated in place below (module doc)
        let start_in_output = stage.in_points && start_weight != 0.0;
        let starts = (start_weight != 0.0 && !start_in_output).then(|| match single {
            true => (&point_q[..nodes_per_cell], &point_v[..nodes_per_cell]),
            false => (
                &inputs.start.0[range.clone()],
                &inputs.start.1[range.clone()],
            ),
        });
        let mut new_q = [Tensor::<D>::zeros(); MAX_NODES];
        let mut new_v = [Vector::<D>::zeros(); MAX_NODES];
        let rates = (
            &rate_tensor[..nodes_per_cell],
            &rate_velocity[..nodes_per_cell],
        );
        let new = (&mut new_q[..nodes_per_cell], &mut new_v[..nodes_per_cell]);
        if !start_in_output {
            stage_nodes_into((q, v), rates, (dt, starts, start_weight), new);
        }
        match out {
            NodalOut::Nodes { tensor, velocity } => {
                // the band's chunk of the nodal fields (in place) or of the next buffer
                let out = local * nodes_per_cell..(local + 1) * nodes_per_cell;
                tensor[out.clone()].copy_from_slice(&new_q[..nodes_per_cell]);
                velocity[out].copy_from_slice(&new_v[..nodes_per_cell]);
            }
            NodalOut::Points {
                tensor,
                velocity,
                position,
            } => {
                let per_cell = self.points_per_cell;
                if start_in_output {
                    // the cell's q⁰, in the entries its points' new states go to
                    let own = local * per_cell..(local + 1) * per_cell;
                    let starts = Some((&tensor[own.clone()], &velocity[own]));
                    let new = (&mut new_q[..nodes_per_cell], &mut new_v[..nodes_per_cell]);
                    stage_nodes_into((q, v), rates, (dt, starts, start_weight), new);
                }
                let increment = (self.options.update == PointUpdate::Increment)
                    .then(|| starts.unwrap_or((q, v)));
                let new = (&new_q[..nodes_per_cell], &new_v[..nodes_per_cell]);
                let entries = local * per_cell..(local + 1) * per_cell;
                let points = (
                    &mut tensor[entries.clone()],
                    &mut velocity[entries.clone()],
                    &mut position[entries],
                );
                let shapes = layouts.shape_of(layout);
                match per_cell {
                    4 => points_of_cell::<D, 4>(shapes, new, increment, points, dt),
                    2 => points_of_cell::<D, 2>(shapes, new, increment, points, dt),
                    _ => points_of_cell::<D, 0>(shapes, new, increment, points, dt),
                }
            }
        }
    }
}

/// Phase 4 at one cell's nodes ([`stage_update`] at each): `new = q + Δt q̇`, or with the
/// start-of-step fields `starts` and their weight `a`, `a q⁰ + (1 - a)(q + Δt q̇)`.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn stage_nodes_into<const D: usize>(
    (q, v): (&[Tensor<D>], &[Vector<D>]),
    (rate_tensor, rate_velocity): (&[Tensor<D>], &[Vector<D>]),
    (dt, starts, start_weight): (f64, Option<(&[Tensor<D>], &[Vector<D>])>, f64),
    (new_q, new_v): (&mut [Tensor<D>], &mut [Vector<D>]),
) {
    match starts {
        None => {
            for a in 0..new_q.len() {
                new_q[a] = stage_update(q[a], rate_tensor[a], dt, None, 0.0);
                new_v[a] = stage_update(v[a], rate_velocity[a], dt, None, 0.0);
            }
        }
        Some((q0, v0)) => {
            for a in 0..new_q.len() {
                new_q[a] = stage_update(q[a], rate_tensor[a], dt, Some(q0[a]), start_weight);
                new_v[a] = stage_update(v[a], rate_velocity[a], dt, Some(v0[a]), start_weight);
            }
        }
    }
}

impl DgmpmSolver<2> {
    /// The 2D nodal sweep: [`Self::band_2d`] with the nodal update, the face states from
    /// the nodes (or, read from the points, the cells' states).
    fn nodal_sweep_2d(&mut self, points: &mut MaterialPoints<2>, stage: Stage) -> (f64, Vector<2>) {
        let nx = self.grid.cells[0];
        let k = self.sweep_2d_constants(stage.dt);
        let cells_per_band = super::BAND_ROWS * nx;
        self.nodal_bands(
            points,
            cells_per_band,
            stage,
            |this, b, band, fields, inputs, out| {
                // the three kinds of stage, each compiled apart
                match (stage.reads_points(), stage.single) {
                    (true, _) => this.band_2d::<false>(b, band, fields, &k, |c, l, faces| {
                        this.nodal_cell_update::<true>((c, l), faces, inputs, stage, out)
                    }),
                    (false, true) => this.band_2d::<true>(b, band, fields, &k, |c, l, faces| {
                        this.nodal_cell_update::<true>((c, l), faces, inputs, stage, out)
                    }),
                    (false, false) => this.band_2d::<true>(b, band, fields, &k, |c, l, faces| {
                        this.nodal_cell_update::<false>((c, l), faces, inputs, stage, out)
                    }),
                }
            },
        )
    }
}

impl<const D: usize> FusedBuffers<D> {
    /// The bands' power and force, added up.
    pub(super) fn totals(&self) -> (f64, Vector<D>) {
        let power = self.bands.iter().map(|b| b.power).sum::<f64>()
            + self.slabs.iter().map(|s| s.power).sum::<f64>();
        let mut force: Vector<D> = self.bands.iter().map(|b| b.force).sum();
        for slab in &self.slabs {
            force += Vector::<D>::from_fn(|k, _| slab.force[k]);
        }
        (power, force)
    }
}

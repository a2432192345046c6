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
//!    `q_i ← a q_i^n + (1 - a)(q_i + Δt q̇_i)` ([`crate::integrator::stage_update`]).
//!
//! The 2D sweep is the cell path's ([`super`], `plane.rs`) with the nodal face states; the
//! 1D one walks each chunk of cells. No face array and no rate array is allocated: the new
//! nodal fields go to a second buffer, swapped in after the sweep (after Heun's first
//! stage the old fields become the start-of-step fields, so they are never copied).
//! Tested against the phase-by-phase nodal paths to 1e-13.
use super::{Band, FusedBuffers, CHUNK};
use crate::faces::Fields;
use crate::integrator::stage_update;
use crate::mapping::point_from_nodes;
use crate::riemann::axis::{axis_flux_1d, AxisConstants};
use crate::riemann::Conserved;
use crate::{DgmpmSolver, StepPath, MAX_NODES};
use impact_core::method::PointUpdate;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

/// Where one band's stage update goes: the new nodal fields (`2^D` entries per cell), or
/// in the step's last stage the band's points (phase 5 in the sweep; the new nodal fields
/// are not stored).
pub(super) enum NodalOut<'a, const D: usize> {
    Nodes {
        tensor: &'a mut [Tensor<D>],
        velocity: &'a mut [Vector<D>],
    },
    Points {
        tensor: &'a mut [Tensor<D>],
        velocity: &'a mut [Vector<D>],
    },
}

/// The stage's step, start weight `a` (0: Euler and Heun's first stage; ½: Heun's second)
/// and whether it is the step's last.
#[derive(Clone, Copy)]
pub(super) struct Stage {
    dt: f64,
    start_weight: f64,
    last: bool,
}

impl<const D: usize> DgmpmSolver<D> {
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
        let stage = Stage {
            dt,
            start_weight,
            last,
        };
        self.by_dimension(
            points,
            |solver, points| solver.nodal_sweep_2d(points, stage),
            |solver, points| solver.nodal_sweep_1d(points, stage),
        )
    }

    /// Run `sweep(band index, band, face fields, the points' volumes, output)` on every
    /// band. A stage before the last writes the new nodal fields and swaps them in (after
    /// a first stage, `a = 0`, the old ones become the start-of-step fields, kept for
    /// RK2); the last writes the points. Returns the bands' power and force, added up.
    #[allow(clippy::type_complexity)]
    fn nodal_bands(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        stage: Stage,
        sweep: impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, &[f64], &mut NodalOut<'_, D>) + Sync,
    ) -> (f64, Vector<D>) {
        let mut buffers = std::mem::take(&mut self.fused);
        {
            let this = &*self;
            let fields = Fields::nodal(&this.nodes.tensor, &this.nodes.velocity);
            let MaterialPoints {
                stress,
                velocity,
                volume,
                ..
            } = points;
            let volume: &[f64] = volume;
            if stage.last {
                let per_band = cells_per_band * this.points_per_cell;
                let parts = (
                    chunks(&mut buffers.bands, 1),
                    (chunks(stress, per_band), chunks(velocity, per_band)),
                );
                for_each_chunk(this.parallel, 1, parts, |b, (band, (tensor, velocity))| {
                    let mut out = NodalOut::Points { tensor, velocity };
                    sweep(this, b, &mut band[0], fields, volume, &mut out);
                });
            } else {
                let per_band = cells_per_band * Grid::<D>::NODES_PER_CELL;
                let parts = (
                    chunks(&mut buffers.bands, 1),
                    (
                        chunks(&mut buffers.next_tensor, per_band),
                        chunks(&mut buffers.next_velocity, per_band),
                    ),
                );
                for_each_chunk(this.parallel, 1, parts, |b, (band, (tensor, velocity))| {
                    let mut out = NodalOut::Nodes { tensor, velocity };
                    sweep(this, b, &mut band[0], fields, volume, &mut out);
                });
            }
        }
        if !stage.last {
            let nodes = &mut self.nodes;
            if stage.start_weight == 0.0 && !nodes.start_tensor.is_empty() {
                std::mem::swap(&mut nodes.start_tensor, &mut nodes.tensor);
                std::mem::swap(&mut nodes.start_velocity, &mut nodes.velocity);
            }
            std::mem::swap(&mut nodes.tensor, &mut buffers.next_tensor);
            std::mem::swap(&mut nodes.velocity, &mut buffers.next_velocity);
        }
        let totals = buffers.totals();
        self.fused = buffers;
        totals
    }

    /// Phases 3-4 of cell `cell` (entry `local` of its band) from its faces' final fluxes
    /// `[low, high]` per axis: [`Self::rates_of_cell`] and the stage update of its nodes;
    /// in the last stage then phase 5 for the cell's points (`point_from_nodes`, the
    /// step's start being the start-of-step fields for RK2 and this stage's for Euler).
    #[inline(always)]
    fn nodal_cell_update(
        &self,
        (cell, local): (usize, usize),
        faces: [[&Conserved<D>; 2]; D],
        volume: &[f64],
        stage: Stage,
        out: &mut NodalOut<'_, D>,
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let nodes = &self.nodes;
        let range = cell * nodes_per_cell..(cell + 1) * nodes_per_cell;
        let (q, v) = (&nodes.tensor[range.clone()], &nodes.velocity[range.clone()]);
        let mut rate_tensor = [Tensor::<D>::zeros(); MAX_NODES];
        let mut rate_velocity = [Vector::<D>::zeros(); MAX_NODES];
        let nodal = (q, v, &nodes.mass[range.clone()]);
        let rates = (&mut rate_tensor[..], &mut rate_velocity[..]);
        self.rates_of_cell(cell, volume, nodal, faces, rates);
        let Stage {
            dt, start_weight, ..
        } = stage;
        let starts = (start_weight != 0.0).then(|| {
            (
                &nodes.start_tensor[range.clone()],
                &nodes.start_velocity[range.clone()],
            )
        });
        let mut new_q = [Tensor::<D>::zeros(); MAX_NODES];
        let mut new_v = [Vector::<D>::zeros(); MAX_NODES];
        match starts {
            None => {
                for a in 0..nodes_per_cell {
                    new_q[a] = stage_update(q[a], rate_tensor[a], dt, None, 0.0);
                    new_v[a] = stage_update(v[a], rate_velocity[a], dt, None, 0.0);
                }
            }
            Some((q0, v0)) => {
                for a in 0..nodes_per_cell {
                    new_q[a] = stage_update(q[a], rate_tensor[a], dt, Some(q0[a]), start_weight);
                    new_v[a] = stage_update(v[a], rate_velocity[a], dt, Some(v0[a]), start_weight);
                }
            }
        }
        match out {
            NodalOut::Nodes { tensor, velocity } => {
                let out = local * nodes_per_cell..(local + 1) * nodes_per_cell;
                tensor[out.clone()].copy_from_slice(&new_q[..nodes_per_cell]);
                velocity[out].copy_from_slice(&new_v[..nodes_per_cell]);
            }
            NodalOut::Points { tensor, velocity } => {
                let per_cell = self.points_per_cell;
                let increment = (self.options.update == PointUpdate::Increment)
                    .then(|| starts.unwrap_or((q, v)));
                let new = (&new_q[..nodes_per_cell], &new_v[..nodes_per_cell]);
                for k in 0..per_cell {
                    let (point, entry) = (cell * per_cell + k, local * per_cell + k);
                    let s = &self.shape[point * nodes_per_cell..(point + 1) * nodes_per_cell];
                    let (pq, pv) = point_from_nodes(s, new, increment);
                    match increment {
                        Some(_) => {
                            tensor[entry] += pq;
                            velocity[entry] += pv;
                        }
                        None => {
                            tensor[entry] = pq;
                            velocity[entry] = pv;
                        }
                    }
                }
            }
        }
    }
}

impl DgmpmSolver<2> {
    /// The 2D nodal sweep: [`Self::band_2d`] with nodal face states and the nodal update.
    fn nodal_sweep_2d(&mut self, points: &mut MaterialPoints<2>, stage: Stage) -> (f64, Vector<2>) {
        let nx = self.grid.cells[0];
        let k = self.sweep_2d_constants(stage.dt);
        let cells_per_band = super::BAND_ROWS * nx;
        self.nodal_bands(
            points,
            cells_per_band,
            stage,
            |this, b, band, fields, volume, out| {
                this.band_2d::<true>(b, band, fields, &k, |cell, local, faces| {
                    this.nodal_cell_update((cell, local), faces, volume, stage, out);
                });
            },
        )
    }
}

impl DgmpmSolver<1> {
    /// The 1D nodal sweep: each chunk of cells solves its low face (node 1 of the cell
    /// below against its node 0), then per cell its high face and the update.
    fn nodal_sweep_1d(&mut self, points: &mut MaterialPoints<1>, stage: Stage) -> (f64, Vector<1>) {
        let constants = AxisConstants::new(&self.elastic);
        let count = self.grid.cells[0];
        self.nodal_bands(
            points,
            CHUNK,
            stage,
            |this, b, band, fields, volume, out| {
                let start = b * CHUNK;
                let len = CHUNK.min(count - start);
                band.power = 0.0;
                band.force = Vector::<1>::zeros();
                let face = |left: usize| {
                    let (l, r) = (
                        fields.at::<true>(left, 0, true),
                        fields.at::<true>(left + 1, 0, false),
                    );
                    axis_flux_1d(&l, &r, &constants)
                };
                // the chunk's low face is counted by the chunk below it (or here at the bar's end)
                let mut low = match start {
                    0 => this.boundary_flux(0, [0], fields, band),
                    _ => face(start - 1),
                };
                for j in 0..len {
                    let cell = start + j;
                    let high = match cell + 1 < count {
                        true => face(cell),
                        false => this.boundary_flux(0, [count], fields, band),
                    };
                    this.nodal_cell_update((cell, j), [[&low, &high]], volume, stage, out);
                    low = high;
                }
            },
        )
    }
}

impl<const D: usize> FusedBuffers<D> {
    /// The bands' power and force, added up.
    pub(super) fn totals(&self) -> (f64, Vector<D>) {
        let power = self.bands.iter().map(|b| b.power).sum();
        let force = self.bands.iter().map(|b| b.force).sum();
        (power, force)
    }
}

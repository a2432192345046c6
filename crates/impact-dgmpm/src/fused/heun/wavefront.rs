//! Heun's two stages in 2D as one wavefront per band (module doc of [`super`]): stage 2 of
//! cell row `j` reads the side states of rows `j - 1..=j + 1` only (its faces, their CTU
//! corrections and the edges' ghost cells), so each band runs stage 1 a row ahead of
//! stage 2 and keeps the side states in a ring of [`RING_ROWS`] rows (in cache) instead
//! of a whole-grid array.
//!
//! The bands of rows are the fused sweeps' ([`BAND_ROWS`]); a wavefront runs over a group
//! of consecutive bands (as many groups as rayon's threads and rings, one when serial;
//! [`rings`] of them are allocated, one per thread at the build). A group owns
//! their cell rows `j0..j1`: it writes their next state, moves their points and counts
//! the power and force of their boundary faces per band and stage, in the order of the
//! two-sweep form (the totals add the bands up in order). Stage 1 sweeps the rows
//! `j0 - 1..=j1` (those inside the grid): the rows next to the group give only the side
//! states its stage 2 reads (the neighbouring group forms the same values). Stage 1 reads
//! only the points' old state and each value is formed by the same operations whoever
//! forms it, so the result depends neither on the groups nor on the thread count and
//! equals the two-sweep form's bit for bit.
//!
//! The ring: stage 1 writes row `r` to slot `r mod R` (`R` = [`RING_ROWS`]); stage 2 reads
//! it through [`Fields::ring`], which finds a cell's slot from its offset to the window's
//! first row, less the ring's length past its end (a row is overwritten `R` rows later,
//! after the last read of it, two rows later).
//!
//! Each row of a stage is the nodal sweep's row ([`DgmpmSolver::band_row`], CTU a
//! constant) with the stage's cell update holding the row's slices ([`FirstRow`],
//! [`SecondRow`]): 888 → 798 instructions a cell-update against closures indexing the
//! whole arrays (plate-wave 200×150, callgrind), the bounds checks and a call gone.
use super::super::plane::{CellUpdate, Sweep2d};
use super::super::{Band, FusedBuffers, BAND_ROWS};
use super::HeunConstants;
use crate::faces::{Fields, SideState};
use crate::riemann::Conserved;
use crate::DgmpmSolver;
use impact_core::parallel::{chunks, for_each_chunk, threads};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};

/// Cell rows of side states in a ring (module doc; at least 3: stage 2's row `j` reads
/// rows `j - 1..=j + 1` after stage 1 wrote row `j + 1`). Four: a ring of 512 B a cell of
/// a row fits a 1 MB L2 cache up to about 2,000 cells a row. (It held two rows more, a copy
/// of slots 0 and 1 so that the three rows lay in order: about 8 instructions a cell,
/// callgrind.)
const RING_ROWS: usize = 4;

/// Side states of one ring for `nx` cells a row: `RING_ROWS` rows.
pub(crate) fn ring_len(nx: usize) -> usize {
    RING_ROWS * nx * SIDES
}

/// The rings allocated for `bands` bands of rows: one per thread of rayon's pool, at most
/// one per band.
pub(crate) fn rings(bands: usize) -> usize {
    threads().clamp(1, bands.max(1))
}

/// A band's power and force of one Heun stage.
pub(crate) type BandTotals = (f64, Vector<2>);

/// Side states per cell in 2D (`2D`).
const SIDES: usize = 4;

/// Heun's first stage on one cell row of the wavefront ([`DgmpmSolver::heun_first`] per
/// cell): the row's slices (`nx` each, indexed by the cell's place in the row) of side
/// states in the ring, inverse point masses and, where the group owns the row, next state.
/// (A struct, not a closure: [`CellUpdate`].)
struct FirstRow<'a> {
    solver: &'a DgmpmSolver<2>,
    u: &'a HeunConstants<2>,
    fields: Fields<'a, 2>,
    row: usize,
    inverse_mass: &'a [f64],
    sides: &'a mut [[SideState<2>; SIDES]],
    next: Option<(&'a mut [Tensor<2>], &'a mut [Vector<2>])>,
}

impl CellUpdate for FirstRow<'_> {
    #[inline(always)]
    fn update(&mut self, cell: usize, _: usize, faces: [[&Conserved<2>; 2]; 2]) {
        let i = cell - self.row;
        let next = self.next.as_mut().map(|(t, v)| (&mut t[i], &mut v[i]));
        let (fields, inverse_mass) = (self.fields, self.inverse_mass[i]);
        let sides = &mut self.sides[i];
        self.solver
            .heun_first(self.u, cell, faces, (fields, inverse_mass), sides, next);
    }
}

/// Heun's second stage on one cell row of the wavefront ([`DgmpmSolver::heun_second`] per
/// cell): the row's slices (`nx` each) of inverse point masses, next state and positions.
struct SecondRow<'a> {
    u: &'a HeunConstants<2>,
    row: usize,
    inverse_mass: &'a [f64],
    next: (&'a mut [Tensor<2>], &'a mut [Vector<2>]),
    position: &'a mut [Vector<2>],
}

impl CellUpdate for SecondRow<'_> {
    #[inline(always)]
    fn update(&mut self, cell: usize, _: usize, faces: [[&Conserved<2>; 2]; 2]) {
        let i = cell - self.row;
        let (next, inverse_mass) = (
            (&mut self.next.0[i], &mut self.next.1[i]),
            self.inverse_mass[i],
        );
        DgmpmSolver::heun_second(self.u, faces, inverse_mass, next, &mut self.position[i]);
    }
}

/// One group's part of the step's outputs: the next state and the positions of its rows.
struct GroupOut<'a> {
    tensor: &'a mut [Tensor<2>],
    velocity: &'a mut [Vector<2>],
    position: &'a mut [Vector<2>],
}

impl DgmpmSolver<2> {
    /// Both Heun stages on every group of bands (module doc), each group with a ring and
    /// a pair of [`Band`]s (the two stages' rolling rows); each band's power and force per
    /// stage go to the buffers' `heun_totals`. The next state is swapped into the points
    /// after.
    pub(super) fn heun_wavefront_2d(&mut self, points: &mut MaterialPoints<2>, dt: f64) {
        let k = self.sweep_2d_constants(dt);
        let u = self.heun_constants(dt);
        let [nx, ny] = self.grid.cells;
        let bands = ny.div_ceil(BAND_ROWS);
        let ring = ring_len(nx);
        // (never more groups than rings; as many chunks of bands as groups or fewer)
        let groups = match self.parallel {
            true => rings(bands).min(self.fused.bands.len() / 2),
            false => 1,
        };
        let per_group = bands.div_ceil(groups.max(1)).max(1);
        let cells = per_group * BAND_ROWS * nx;
        let mut buffers = std::mem::take(&mut self.fused);
        {
            let this = &*self;
            let FusedBuffers {
                bands: rolling,
                next_tensor,
                next_velocity,
                side_states,
                heun_totals,
                ..
            } = &mut buffers;
            let MaterialPoints {
                stress,
                velocity,
                position,
                ..
            } = &mut *points;
            let inputs = (Fields::per_cell(stress, velocity), &this.inverse_mass[..]);
            let parts = (
                (chunks(heun_totals, 2 * per_group), chunks(rolling, 2)),
                (chunks(next_tensor, cells), chunks(next_velocity, cells)),
                (chunks(side_states, ring), chunks(position, cells)),
            );
            for_each_chunk(
                this.parallel,
                1,
                parts,
                |g, (bands, (tensor, v), (ring, x))| {
                    let out = GroupOut {
                        tensor,
                        velocity: v,
                        position: x,
                    };
                    let first_band = g * per_group;
                    let step = (&k, &u);
                    match k.ctu {
                        true => {
                            this.heun_group_2d::<true>(first_band, bands, inputs, out, ring, step)
                        }
                        false => {
                            this.heun_group_2d::<false>(first_band, bands, inputs, out, ring, step)
                        }
                    }
                },
            );
        }
        std::mem::swap(&mut points.stress, &mut buffers.next_tensor);
        std::mem::swap(&mut points.velocity, &mut buffers.next_velocity);
        self.fused = buffers;
    }

    /// The wavefront of the group of bands from `first_band` (module doc): stage 1 on its
    /// rows `j0 - 1..=j1` (inside the grid) into the ring, stage 2 on row `j` as soon as
    /// row `min(j + 1, ny - 1)` is formed; at each band's end its power and force go to
    /// its pair of `totals` (stage 1, stage 2). `CTU`: `k`'s, a constant of the sweeps.
    fn heun_group_2d<const CTU: bool>(
        &self,
        first_band: usize,
        (totals, rolling): (&mut [BandTotals], &mut [Band<2>]),
        (fields, inverse_mass): (Fields<'_, 2>, &[f64]),
        out: GroupOut<'_>,
        ring: &mut [SideState<2>],
        (k, u): (&Sweep2d, &HeunConstants<2>),
    ) {
        let [nx, ny] = self.grid.cells;
        let band_rows = |b: usize| b * BAND_ROWS..((b + 1) * BAND_ROWS).min(ny);
        let last_band = first_band + totals.len() / 2 - 1;
        let own = band_rows(first_band).start..band_rows(last_band).end;
        let rows = own.start.saturating_sub(1)..(own.end + 1).min(ny);
        let [one, two] = rolling else {
            unreachable!("internal: two rolling bands per group")
        };
        for band in [&mut *one, &mut *two] {
            band.power = 0.0;
            band.force = Vector::<2>::zeros();
        }
        let mut record = |b: usize, stage: usize, band: &mut Band<2>, x_power: f64| {
            totals[2 * (b - first_band) + stage] = (band.power, band.force);
            // the next band's first term: its first row's x-faces
            band.power = 0.0;
            band.power += x_power;
            band.force = Vector::<2>::zeros();
        };
        let GroupOut {
            tensor,
            velocity,
            position,
        } = out;
        let row_len = nx * SIDES;
        // stage 2's next row
        let mut next = own.start;
        let band_of = |j: usize| j.clamp(own.start, own.end - 1) / BAND_ROWS;
        self.band_start::<false>(rows.start, &band_rows(first_band), one, fields, k);
        for r in rows {
            let owned = own.contains(&r);
            let (slot, b) = (r % RING_ROWS, band_of(r));
            // the row's slices (`nx` each, indexed by the cell's place in the row: no
            // index checks per cell): its side states in the ring, inverse masses and
            // (where the group owns the row) next state
            let base = slot * row_len;
            let row = r * nx;
            let ring_row = &mut ring[base..base + row_len].as_chunks_mut::<SIDES>().0[..nx];
            let inverse_mass_row = &inverse_mass[row..row + nx];
            let mut first = FirstRow {
                solver: self,
                u,
                fields,
                row,
                inverse_mass: inverse_mass_row,
                sides: ring_row,
                next: owned.then(|| {
                    let at = row - own.start * nx;
                    (&mut tensor[at..at + nx], &mut velocity[at..at + nx])
                }),
            };
            let x_power = self.band_row::<false, CTU>(r, &band_rows(b), one, fields, k, &mut first);
            if owned && (r + 1 == band_rows(b).end || r + 1 == own.end) {
                record(b, 0, one, x_power);
            }
            while next < own.end && (next + 1).min(ny - 1) <= r {
                // rows next - 1..=next + 1 from the ring
                let sides = Fields::ring(ring, nx, next.saturating_sub(1));
                let b = band_of(next);
                let band = band_rows(b);
                if next == own.start {
                    self.band_start::<true>(next, &band, two, sides, k);
                }
                // the row's slices, indexed by the cell's place in the row
                let row = next * nx;
                let at = row - own.start * nx;
                let (tensor, velocity) = (&mut tensor[at..at + nx], &mut velocity[at..at + nx]);
                let position = &mut position[at..at + nx];
                let inverse_mass = &inverse_mass[row..row + nx];
                let mut second = SecondRow {
                    u,
                    row,
                    inverse_mass,
                    next: (tensor, velocity),
                    position,
                };
                let x_power = self.band_row::<true, CTU>(next, &band, two, sides, k, &mut second);
                if next + 1 == band.end {
                    record(b, 1, two, x_power);
                }
                next += 1;
            }
        }
    }
}

impl<const D: usize> FusedBuffers<D> {
    /// The power and force of Heun's stage `stage` (0 or 1) on the 2D wavefront, added up
    /// over the bands in order (each band's pair in `heun_totals`: stage 1's, stage 2's).
    pub(crate) fn stage_totals(&self, stage: usize) -> (f64, Vector<D>) {
        let bands = || self.heun_totals.iter().skip(stage).step_by(2);
        let power =
            bands().map(|b| b.0).sum::<f64>() + self.slabs.iter().map(|s| s.power).sum::<f64>();
        let force: Vector<2> = bands().map(|b| b.1).sum();
        (power, Vector::<D>::from_fn(|k, _| force[k]))
    }
}

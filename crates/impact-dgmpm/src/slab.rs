//! DGMPM on one rank's slab of the grid (issue 27): the layers of cells along the last axis
//! are split over the ranks ([`Slab`]); each rank steps its own layers plus a halo of
//! its neighbours' layers with the unchanged kernels, and exchanges the halo's point state
//! once per step.
//!
//! **Why the halo makes the owned cells exact.** One stage of DGMPM updates a cell from
//! its faces' fluxes, which read the two cells of the face and, under CTU, their transverse
//! neighbours (the corner cells): a stage reaches one layer (order 2's wave corrections and
//! their transverse parts: up to three). A slab's outer face that is not a physical edge is
//! given a free condition; what it makes wrong travels at most `reach` layers per stage, so
//! with a halo of `stages × reach` layers ([`halo_layers`]) only halo cells are wrong after a
//! step, and the exchange before the next step overwrites them with their owners' values.
//! Every owned cell is then formed by the same operations on the same bits as on one rank
//! (face coordinates come from global indices, `GridPlace`), so the owned fields equal the
//! serial run's bit for bit on the cell and fused paths. On the nodal paths (several points
//! per cell, RK2) the shape functions are formed from the slab's origin, which rounds
//! differently from the whole grid's: equal to round-off there.
//!
//! The exchange per step is one message each way per neighbour of `halo` layers of points
//! ([`SlabDgmpm::bytes_per_step`]); the halo trades extra cells (`2 × halo` layers per
//! rank) for one message per step instead of one per stage.
//!
//! Diagnostics are reduced over the owned points only: the energy and momentum in rank
//! order ([`impact_core::comm`]), so they differ from one rank's sums by round-off
//! (`Σ_r Σ_{i∈r}` against `Σ_i`); the boundary work and impulse of a halo layer's edge
//! faces count on its owner only. [`Method::sample_into`] gathers the samples to every
//! rank in rank order (the global point order), so profiles and error metrics equal the
//! serial ones; [`Method::owned_samples_into`] gives this rank's owned points only (the
//! guard's max norms reduce over them, and each rank writes them as its output piece).
//!
//! **Memory.** Each rank seeds only its stored layers' points
//! ([`Problem::material_points_of_layers`], from the whole grid's origin and global cell
//! indices: the same bits as the whole body's), so a rank's points and solver buffers
//! scale with `1/ranks` (plus the halo).
use crate::{Dgmpm, GridPlace};
use impact_core::comm::{sum_vector, Comm, CommError, Slab};
use impact_core::method::{BadState, DgmpmOptions, Integrator, Method, MethodConfig, Samples};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::{CoreError, Grid, Problem, Vector};
use std::sync::Arc;

/// Halo width (layers) for `options`: stages per step × layers a stage reaches.
pub fn halo_layers(options: &DgmpmOptions) -> usize {
    let stages = match options.integrator {
        Integrator::Euler => 1,
        Integrator::Rk2 => 2,
    };
    let reach = match options.wave_limiter() {
        None => 1,
        Some(_) => 3,
    };
    // (CTU reads the corner cells: still the next layer)
    stages * reach
}

/// DGMPM on one rank's slab, a [`Method`] whose values are global (module doc).
#[derive(Debug)]
pub struct SlabDgmpm<const D: usize> {
    /// The slab's DGMPM (owned layers and halo).
    pub local: Dgmpm<D>,
    comm: Arc<dyn Comm>,
    slab: Slab,
    /// Points per layer of cells.
    per_layer: usize,
    /// Cells of the whole grid.
    global_cells: usize,
    initial_energy: f64,
    buffers: Buffers,
}

#[derive(Debug, Default)]
struct Buffers {
    send_low: Vec<f64>,
    send_high: Vec<f64>,
    receive_low: Vec<f64>,
    receive_high: Vec<f64>,
}

impl<const D: usize> SlabDgmpm<D> {
    /// This rank's slab of DGMPM on `problem` (every rank builds its own; a bad input is
    /// refused on every rank alike, before any communication).
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
    ) -> Result<Self, CoreError> {
        let options = *config.dgmpm().ok_or_else(|| CoreError::Unsupported {
            method: "dgmpm".into(),
            message: "not a DGMPM configuration".into(),
        })?;
        problem.check_config(&config)?;
        let global = &problem.grid;
        let slab = Slab::new(
            global.cells[D - 1],
            comm.size(),
            comm.rank(),
            halo_layers(&options),
        )?;
        let per_layer = global.cell_count() / global.cells[D - 1] * config.points_per_cell;
        // only the stored layers' points, seeded from the whole grid's origin and global
        // cell indices: the same bits as one rank's, in memory that shrinks with the ranks
        let points = problem.material_points_of_layers(global, &config, slab.stored.clone())?;
        let mut part = problem.clone();
        part.grid = slab.grid(global);
        for side in 0..2 {
            if !slab.physical_edge(side) {
                part.boundaries[D - 1][side] = Boundary::Free;
            }
        }
        let mut local = Dgmpm::with_points(&part, config, options, points)?;
        local.solver.place = GridPlace {
            origin: global.origin,
            offset: std::array::from_fn(|k| if k == D - 1 { slab.stored.start } else { 0 }),
            owned_layers: slab.owned_local(),
        };
        // the whole body's wave speed (a slab without the loaded edge has a lower one)
        local.solver.wave_speed = problem.max_wave_speed();
        local.state.initial_energy = local.energy();
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let size = |layers: usize| layers * per_layer * Self::packed_len(&local.state.points);
        let buffers = Buffers {
            send_low: vec![0.0; size(slab.halo_below())],
            send_high: vec![0.0; size(slab.halo_above())],
            receive_low: vec![0.0; size(slab.halo_below())],
            receive_high: vec![0.0; size(slab.halo_above())],
        };
        Ok(Self {
            local,
            comm,
            slab,
            per_layer,
            global_cells: global.cell_count(),
            initial_energy,
            buffers,
        })
    }

    /// The slab this rank stores.
    pub fn slab(&self) -> &Slab {
        &self.slab
    }

    /// Bytes this rank sends per step (the halo's point state, both neighbours).
    pub fn bytes_per_step(&self) -> usize {
        8 * (self.buffers.send_low.len() + self.buffers.send_high.len())
    }

    /// Values per point in the halo messages: position, velocity, the stress, and the
    /// deformation gradient and plastic history where the model has them.
    fn packed_len(p: &MaterialPoints<D>) -> usize {
        let present = |n: usize, v: bool| if v { n } else { 0 };
        2 * D
            + D * D
            + present(D * D, !p.deformation.is_empty())
            + present(3, !p.equivalent_plastic_strain.is_empty())
    }

    /// Copy the state of the local layers `layers` into `out`.
    fn pack(p: &MaterialPoints<D>, points: std::ops::Range<usize>, out: &mut [f64]) {
        let mut k = 0;
        let mut put = |x: &[f64]| {
            out[k..k + x.len()].copy_from_slice(x);
            k += x.len();
        };
        for i in points {
            put(p.position[i].as_slice());
            put(p.velocity[i].as_slice());
            put(p.stress[i].as_slice());
            if !p.deformation.is_empty() {
                put(p.deformation[i].as_slice());
            }
            if !p.equivalent_plastic_strain.is_empty() {
                put(&[
                    p.equivalent_plastic_strain[i],
                    p.plastic_strain_zz[i],
                    p.plastic_work[i],
                ]);
            }
        }
    }

    /// The inverse of [`Self::pack`].
    fn unpack(p: &mut MaterialPoints<D>, points: std::ops::Range<usize>, data: &[f64]) {
        let mut k = 0;
        let mut take = |n: usize| {
            k += n;
            &data[k - n..k]
        };
        for i in points {
            p.position[i].copy_from_slice(take(D));
            p.velocity[i].copy_from_slice(take(D));
            p.stress[i].copy_from_slice(take(D * D));
            if !p.deformation.is_empty() {
                p.deformation[i].copy_from_slice(take(D * D));
            }
            if !p.equivalent_plastic_strain.is_empty() {
                let h = take(3);
                p.equivalent_plastic_strain[i] = h[0];
                p.plastic_strain_zz[i] = h[1];
                p.plastic_work[i] = h[2];
            }
        }
    }

    /// Send the owned edge layers to the neighbours and take theirs into the halo.
    fn exchange_halo(&mut self) {
        let (below, above) = (self.slab.halo_below(), self.slab.halo_above());
        let stored = self.slab.stored.len();
        let own = self.slab.owned_local();
        let n = self.per_layer;
        let b = &mut self.buffers;
        let p = &mut self.local.state.points;
        Self::pack(p, own.start * n..(own.start + below) * n, &mut b.send_low);
        Self::pack(p, (own.end - above) * n..own.end * n, &mut b.send_high);
        self.comm.exchange(
            &b.send_low,
            &b.send_high,
            &mut b.receive_low,
            &mut b.receive_high,
        );
        Self::unpack(p, 0..below * n, &b.receive_low);
        Self::unpack(p, (stored - above) * n..stored * n, &b.receive_high);
    }

    /// The first failure over the ranks, as a [`BadState`] at its global place.
    fn first_bad(&self, local: Result<(), BadState<D>>) -> Result<(), BadState<D>> {
        let reason = local.as_ref().err().map(|b| b.reason.clone());
        let Some(CommError::Rank { rank, message }) = self.comm.first_error(reason.as_deref())
        else {
            return Ok(());
        };
        let place = local.err().map_or_else(Vector::<D>::zeros, |b| b.place);
        let all = self.comm.all_gather(place.as_slice());
        Err(BadState {
            place: Vector::<D>::from_fn(|k, _| all[rank * D + k]),
            reason: message,
        })
    }
}

impl<const D: usize> Dgmpm<D> {
    /// The points this solver owns (all of them on one rank; a slab's own layers).
    pub fn owned_points(&self) -> std::ops::Range<usize> {
        let layers = &self.solver.place.owned_layers;
        let grid = &self.solver.grid;
        let per_layer = grid.cell_count() / grid.cells[D - 1] * self.solver.points_per_cell;
        layers.start * per_layer..layers.end * per_layer
    }
}

impl<const D: usize> Method<D> for SlabDgmpm<D> {
    fn config(&self) -> &MethodConfig {
        self.local.config()
    }
    fn stable_dt(&self) -> f64 {
        self.comm.all_reduce_min(self.local.stable_dt())
    }
    fn step(&mut self, t: f64, dt: f64) {
        self.exchange_halo();
        self.local.step(t, dt);
    }
    fn sample_into(&self, out: &mut Samples<D>) {
        // (outputs and the guard's max-norm test only: the buffers are the caller's)
        let mut mine = Samples::<D>::default();
        self.local.sample_into(&mut mine);
        let (plastic, zz) = (!mine.plastic_strain.is_empty(), !mine.stress_zz.is_empty());
        let width = 4 * D + D * D + usize::from(plastic) + usize::from(zz);
        let mut packed = Vec::with_capacity(mine.len() * width);
        for i in 0..mine.len() {
            packed.extend_from_slice(mine.reference[i].as_slice());
            packed.extend_from_slice(mine.position[i].as_slice());
            packed.extend_from_slice(mine.half_size[i].as_slice());
            packed.extend_from_slice(mine.stress[i].as_slice());
            packed.extend_from_slice(mine.velocity[i].as_slice());
            if plastic {
                packed.push(mine.plastic_strain[i]);
            }
            if zz {
                packed.push(mine.stress_zz[i]);
            }
        }
        let all = self.comm.all_gather(&packed);
        out.clear();
        for s in all.chunks_exact(width) {
            let v = |k: usize| Vector::<D>::from_column_slice(&s[k * D..(k + 1) * D]);
            out.reference.push(v(0));
            out.position.push(v(1));
            out.half_size.push(v(2));
            out.stress.push(impact_core::Tensor::<D>::from_column_slice(
                &s[3 * D..3 * D + D * D],
            ));
            out.velocity.push(Vector::<D>::from_column_slice(
                &s[3 * D + D * D..4 * D + D * D],
            ));
            let mut k = 4 * D + D * D;
            if plastic {
                out.plastic_strain.push(s[k]);
                k += 1;
            }
            if zz {
                out.stress_zz.push(s[k]);
            }
        }
    }
    fn owned_samples_into(&self, out: &mut Samples<D>) {
        self.local.sample_into(out);
    }
    fn comm(&self) -> &dyn Comm {
        self.comm.as_ref()
    }
    fn bytes_exchanged_per_step(&self) -> usize {
        self.bytes_per_step()
    }
    fn energy(&self) -> f64 {
        self.comm.all_reduce_sum(self.local.energy())
    }
    fn external_work(&self) -> f64 {
        self.comm.all_reduce_sum(self.local.external_work())
    }
    fn initial_energy(&self) -> f64 {
        self.initial_energy
    }
    fn momentum(&self) -> Vector<D> {
        sum_vector(self.comm.as_ref(), self.local.momentum())
    }
    fn external_impulse(&self) -> Vector<D> {
        sum_vector(self.comm.as_ref(), self.local.external_impulse())
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        self.first_bad(self.local.check_finite())
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.local.state.points;
        let mine = p
            .hottest_in(self.local.owned_points())
            .map_or((f64::NEG_INFINITY, Vector::<D>::zeros()), |i| {
                (p.velocity[i].norm(), p.reference[i])
            });
        let mut entry = vec![mine.0];
        entry.extend_from_slice(mine.1.as_slice());
        let all = self.comm.all_gather(&entry);
        // the last rank of the largest speed (one rank's `max_by` keeps the last of equals)
        let best = (0..self.comm.size())
            .max_by(|&a, &b| all[a * (D + 1)].total_cmp(&all[b * (D + 1)]))
            .unwrap_or(0);
        Vector::<D>::from_column_slice(&all[best * (D + 1) + 1..(best + 1) * (D + 1)])
    }
    fn cells(&self) -> usize {
        self.global_cells
    }
    fn updates_per_step(&self) -> usize {
        self.global_cells
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let first = self.slab.stored.start * self.per_layer;
        self.local
            .state
            .points
            .perturb_velocity(&mut |i, x| kick(first + i, x));
    }
}

/// What a run on `ranks` ranks is split into, for summaries.
pub fn describe<const D: usize>(grid: &Grid<D>, options: &DgmpmOptions, ranks: usize) -> String {
    format!(
        "{ranks} slabs along axis {} ({} layers of cells, halo {} layers, exchanged once per step)",
        D - 1,
        grid.cells[D - 1],
        halo_layers(options)
    )
}

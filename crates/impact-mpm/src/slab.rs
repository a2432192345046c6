//! MPM on one rank's slab of the grid (issue 27): the layers of cells along the last axis
//! are split over the ranks ([`Slab`]); each rank steps the points of its own layers plus a
//! halo of its neighbours' layers with the unchanged kernels on the background nodes of
//! those layers, and exchanges the halo's point state once per step. Total Lagrangian
//! frame only (the default): a point never changes cell, so a layer's points stay on their
//! rank. The updated Lagrangian frame (points migrating between ranks) is refused on more
//! than one rank ([`CommError::Unsupported`]).
//!
//! **Why the halo makes the own points exact.** A node's sums read the points whose
//! stencil covers it, and a point's update reads the nodes of its stencil. A point of cell
//! layer `j` has its stencil's nodes within layers `j − 1 .. j + 2` (hats: `j .. j + 1`;
//! CPDI's domains at rest lie in their cell). Beyond a cut face (no physical edge: no load,
//! no prescribed velocity, no mirrored padding there) the points are missing, so the nodes
//! of the first layers miss some sums, and the points reading them go wrong: one scatter
//! and gather spoil `reach` layers next to the cut (1 with hats, 3 with the wider
//! stencils), and a step has one such round under USL and two under MUSL (the remap) and
//! USF (the stress update before the internal force). With a halo of `rounds × reach`
//! layers ([`halo_layers`]) only halo points are wrong after a step, and the exchange before
//! the next one overwrites them with their owners' values.
//!
//! Every own point is then formed by the same operations on the same bits as on one rank:
//! the points are the whole body's cut to the stored layers; the shape functions and load
//! positions are evaluated on the whole padded grid and shifted to the slab's nodes (a
//! slab's own origin would round the grid coordinates differently); the shared row of
//! weights is the body's first point's; the empty-node floor and the serial or parallel
//! scatter are the whole body's; and the coloured scatter's blocks follow the whole grid's
//! layers, so each node adds its points in one rank's order (`transfer.rs`). So the own
//! points' fields equal the serial run's bit for bit, for every transfer, stress update,
//! shape and model (`tests/slab.rs`).
//!
//! The exchange per step is one message each way per neighbour of `halo` layers of points
//! ([`SlabMpm::bytes_per_step`]): position, velocity and stress, and where present the
//! deformation gradient (Saint-Venant–Kirchhoff), the plastic history (J2) and APIC's
//! affine velocity. The volumes and the CPDI domains never change in the total Lagrangian
//! frame and are not sent.
//!
//! Diagnostics are over the own points and nodes only, reduced in rank order
//! ([`impact_core::comm`]): the energy and momentum differ from one rank's sums by
//! round-off (`Σ_r Σ_{i∈r}` against `Σ_i`); the loads' work and impulse count on the rank
//! owning the loaded point, the velocity constraints' reactions on the rank owning the node
//! (the node layers at a rank's own cell layers' lower faces; the padding's on the first and
//! last ranks). Samples are gathered in rank order (the global point order), so outputs and
//! error metrics equal the serial ones.
use crate::Mpm;
use impact_core::comm::{sum_vector, Comm, CommError, Slab};
use impact_core::comm_gather;
use impact_core::method::{
    BadState, Method, MethodConfig, MpmFrame, MpmOptions, MpmShape, Samples, StressUpdate,
};
use impact_core::points::MaterialPoints;
use impact_core::{CoreError, Grid, Problem, Tensor, Vector};
use std::sync::Arc;

/// Halo width (layers) for `options`: scatter–gather rounds per step × layers a round
/// spoils next to a cut face (module doc).
pub fn halo_layers(options: &MpmOptions) -> usize {
    let rounds = match options.stress_update {
        StressUpdate::Usl => 1,
        StressUpdate::Musl | StressUpdate::Usf => 2,
    };
    let reach = match options.shape {
        MpmShape::Linear => 1,
        _ => 3,
    };
    rounds * reach
}

/// MPM on one rank's slab, a [`Method`] whose values are global (module doc).
#[derive(Debug)]
pub struct SlabMpm<const D: usize> {
    /// The slab's MPM (own layers and halo).
    pub local: Mpm<D>,
    comm: Arc<dyn Comm>,
    slab: Slab,
    /// Points per layer of cells.
    per_layer: usize,
    /// Points of the whole body.
    global_points: usize,
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

impl<const D: usize> SlabMpm<D> {
    /// This rank's slab of MPM on `problem` (every rank builds its own; a bad input is
    /// refused on every rank alike, before any communication).
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
    ) -> Result<Self, CoreError> {
        let options = *config.mpm().ok_or_else(|| CoreError::Unsupported {
            method: "mpm".into(),
            message: "not an MPM configuration".into(),
        })?;
        if options.frame == MpmFrame::UpdatedLagrangian && comm.size() > 1 {
            return Err(CommError::Unsupported {
                what: "MPM in the updated Lagrangian frame (frame = updated)".into(),
                ranks: comm.size(),
                allowed: "points do not migrate between ranks yet; run it on one rank, or \
                          the total Lagrangian frame (the default) on several"
                    .into(),
            }
            .into());
        }
        problem.check_config(&config)?;
        let global = &problem.grid;
        let layers = global.cells[D - 1];
        let slab = Slab::new(layers, comm.size(), comm.rank(), halo_layers(&options))?;
        let local = Mpm::build(problem, config, Some(&slab))?;
        let per_layer = local.state.points.len() / slab.stored.len();
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let size = |layers: usize| layers * per_layer * Self::packed_len(&local);
        let buffers = Buffers {
            send_low: vec![0.0; size(slab.halo_below())],
            send_high: vec![0.0; size(slab.halo_above())],
            receive_low: vec![0.0; size(slab.halo_below())],
            receive_high: vec![0.0; size(slab.halo_above())],
        };
        Ok(Self {
            local,
            comm,
            per_layer,
            global_points: per_layer * layers,
            slab,
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

    /// Values per point in the halo messages (module doc).
    fn packed_len(m: &Mpm<D>) -> usize {
        let p = &m.state.points;
        let present = |n: usize, v: bool| if v { n } else { 0 };
        2 * D
            + D * D
            + present(D * D, !p.deformation.is_empty())
            + present(3, !p.equivalent_plastic_strain.is_empty())
            + present(D * D, !m.state.affine.is_empty())
    }

    /// Copy the state of the local points `points` into `out`.
    fn pack(
        p: &MaterialPoints<D>,
        affine: &[Tensor<D>],
        points: std::ops::Range<usize>,
        out: &mut [f64],
    ) {
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
            if !affine.is_empty() {
                put(affine[i].as_slice());
            }
        }
    }

    /// The inverse of [`Self::pack`].
    fn unpack(
        p: &mut MaterialPoints<D>,
        affine: &mut [Tensor<D>],
        points: std::ops::Range<usize>,
        data: &[f64],
    ) {
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
            if !affine.is_empty() {
                affine[i].copy_from_slice(take(D * D));
            }
        }
    }

    /// Send the own edge layers to the neighbours and take theirs into the halo.
    fn exchange_halo(&mut self) {
        let (below, above) = (self.slab.halo_below(), self.slab.halo_above());
        let stored = self.slab.stored.len();
        let own = self.slab.owned_local();
        let n = self.per_layer;
        let b = &mut self.buffers;
        let state = &mut self.local.state;
        let (p, affine) = (&mut state.points, &mut state.affine);
        let low = own.start * n..(own.start + below) * n;
        let high = (own.end - above) * n..own.end * n;
        Self::pack(p, affine, low, &mut b.send_low);
        Self::pack(p, affine, high, &mut b.send_high);
        self.comm.exchange(
            &b.send_low,
            &b.send_high,
            &mut b.receive_low,
            &mut b.receive_high,
        );
        Self::unpack(p, affine, 0..below * n, &b.receive_low);
        Self::unpack(p, affine, (stored - above) * n..stored * n, &b.receive_high);
    }
}

impl<const D: usize> Method<D> for SlabMpm<D> {
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
        let mut mine = Samples::<D>::default();
        self.local.sample_into(&mut mine);
        comm_gather::gather_samples(self.comm.as_ref(), &mine, out);
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
        comm_gather::first_bad(self.comm.as_ref(), self.local.check_finite())
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.local.state.points;
        let mine = p
            .hottest_in(self.local.owned_points())
            .map(|i| (p.velocity[i].norm(), p.reference[i]));
        comm_gather::hottest_place(self.comm.as_ref(), mine)
    }
    fn cells(&self) -> usize {
        self.local.cells()
    }
    fn updates_per_step(&self) -> usize {
        self.global_points
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
pub fn describe<const D: usize>(grid: &Grid<D>, options: &MpmOptions, ranks: usize) -> String {
    format!(
        "{ranks} slabs along axis {} ({} layers of cells, halo {} layers of points, \
         exchanged once per step)",
        D - 1,
        grid.cells[D - 1],
        halo_layers(options)
    )
}

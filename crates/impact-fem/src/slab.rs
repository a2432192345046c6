//! FEM on one rank's slab of the mesh (issue 27): the element layers along the last axis
//! are split over the ranks ([`RankBox`], the slab `1 × … × 1 × N`: boxes are
//! refused); each rank stores its own layers plus one layer of
//! each neighbour's, steps them with the unchanged kernels (stencil or Gauss-point path,
//! fused or not), and after each step (and once when built) receives the halo's nodal
//! state (`u^n`, `v^{n-1/2}`, `a^n`) from the nodes' owners.
//!
//! **Design: the DGMPM one (a halo), not "shared nodes' forces summed".** Summing the
//! partial forces of a shared node layer over two ranks adds its elements' contributions
//! in another association than one rank does (the colour passes, the stencil's pairs), so
//! the fields would agree to round-off only; with a halo every owned node is formed by the
//! same operations on the same bits as on one rank, so the owned fields equal the serial
//! run's bit for bit, at the price of one extra element layer per neighbour.
//!
//! **Ownership.** A rank owns its element layers `[a, b)` and the node layers `[a, b)`
//! (their lower faces; the last rank also the mesh's top face `L`). It stores the element
//! layers `[a − 1, b + 1)` (clamped to the mesh), so the node layers `[a − 1, b + 1]`. A
//! face of the stored layers inside the mesh (a cut) is free: loads, prescribed velocities
//! and symmetry are found on the whole mesh by global index (`place.rs`), so a cut never
//! carries one, while a halo node on a physical edge keeps its own.
//!
//! **Why one layer of halo makes the owned nodes exact.** One step is pointwise at the
//! nodes (`v += Δt_avg a`, `u += Δt v`, the held velocities) and then forms `a^{n+1}` at a
//! node from the elements around it, which read `u^{n+1}` one node layer away (the Gauss
//! stresses of an element read its own nodes and its own history). So an owned node
//! `k ∈ [a, b)` needs `u^{n+1}` on node layers `[a − 1, b]`, which the pointwise update
//! forms exactly from the state at `t^n` received for layers `a − 1` and `b` (their owners'
//! bits) and held for the owned ones. Only the cut nodes' `a^{n+1}` is wrong (half the
//! mass, half the elements), and layer `b`'s, which reads the top cut node; both are
//! received at the end of the step, so that the owned elements' samples (whose nodes
//! include layer `b`) and the next step read their owners' values. J2's Gauss-point history needs no exchange: the
//! halo element layer `a − 1` reads node layers `a − 1` and `a` only, exact every step, so
//! its history stays exact; that of element layer `b` may drift from the top cut node, but
//! it reaches node layers `b` and `b + 1` only, which are not owned. The Gauss path adds a
//! node's element forces in colour passes; they run with the layers of even global index
//! first on every slab (`lib.rs`), the order one rank uses.
//!
//! The exchange per step is one message each way per neighbour of one node layer, `3 D`
//! values per node ([`SlabFem::bytes_per_step`]).
//!
//! Diagnostics are reduced over the owned nodes and elements only: energy, work, momentum
//! and impulse per rank, then added in rank order ([`impact_core::comm`]), so they differ
//! from one rank's sums by round-off (`Σ_r Σ_{i∈r}` against `Σ_i`). Samples and the nodal
//! fields of the mesh are gathered to every rank in rank order (the owned elements and
//! nodes are consecutive runs of the global order), so outputs equal the serial ones.
use crate::Fem;
use impact_core::comm::{Comm, RankBox, RankGrid};
use impact_core::comm_gather::hottest_place;
use impact_core::comm_method::gather_vectors;
use impact_core::comm_method::HaloBuffers;
use impact_core::method::{Method, MethodConfig};
use impact_core::{CoreError, Grid, Problem, Vector};
use std::sync::Arc;

/// Element layers of halo each side (module doc).
pub const HALO_LAYERS: usize = 1;

/// FEM on one rank's slab, a [`Method`] whose values are global (module doc).
#[derive(Debug)]
pub struct SlabFem<const D: usize> {
    /// The slab's FEM (owned layers and halo).
    pub local: Fem<D>,
    comm: Arc<dyn Comm>,
    slab: RankBox,
    /// Nodes per layer along the last axis.
    layer_nodes: usize,
    /// Elements of the whole mesh.
    global_cells: usize,
    initial_energy: f64,
    buffers: HaloBuffers,
}

/// Values per node in the halo messages: `u`, `v^{n-1/2}`, `a`.
const fn packed_len(dim: usize) -> usize {
    3 * dim
}

impl<const D: usize> SlabFem<D> {
    /// This rank's slab of the FEM on `problem` (every rank builds its own; a bad input is
    /// refused on every rank alike, before any communication).
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
    ) -> Result<Self, CoreError> {
        Self::on_grid(problem, config, comm, &RankGrid::automatic())
    }

    /// [`Self::new`] split as `rank_grid` says: slabs along the last axis only (the FEM's
    /// halo is not on boxes yet); another rank grid is refused with the slab one to use.
    pub fn on_grid(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
        rank_grid: &RankGrid,
    ) -> Result<Self, CoreError> {
        problem.check_config(&config)?;
        rank_grid.slabs_only("FEM", D, comm.size())?;
        let global = &problem.grid;
        let slab = RankBox::for_rank(&global.cells, rank_grid, comm.as_ref(), HALO_LAYERS)?;
        let (stored, owned) = (&slab.stored[D - 1], &slab.owned[D - 1]);
        let local = Fem::on_layers(problem, config, stored, owned)?;
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let layer_nodes = global.vertex_count() / (global.cells[D - 1] + 1);
        let size = |layers: usize| layers * layer_nodes * packed_len(D);
        let buffers = HaloBuffers::new(
            slab.neighbours(D - 1),
            size(slab.halo_width(D - 1, 0)),
            size(slab.halo_width(D - 1, 1)),
        );
        let mut slab_fem = Self {
            local,
            comm,
            slab,
            layer_nodes,
            global_cells: global.cell_count(),
            initial_energy,
            buffers,
        };
        // `a^0` of the halo's nodes next to the cut faces from their owners
        slab_fem.exchange_halo();
        Ok(slab_fem)
    }

    /// The slab this rank stores.
    pub fn slab(&self) -> &RankBox {
        &self.slab
    }

    /// The samples' global order: the rank order (empty, `reduced_over_ranks!`).
    pub fn sample_order(&self) -> &[usize] {
        &[]
    }

    /// Bytes this rank sends per step (one node layer's `u`, `v`, `a` per neighbour).
    pub fn bytes_per_step(&self) -> usize {
        self.buffers.bytes_sent()
    }

    /// Copy the nodal state of `nodes` into `out`.
    fn pack(local: &Fem<D>, nodes: std::ops::Range<usize>, out: &mut [f64]) {
        let s = &local.state;
        let fields = [&s.displacement, &s.velocity_half, &s.acceleration];
        for (k, i) in nodes.enumerate() {
            for (f, field) in fields.iter().enumerate() {
                let at = (packed_len(D) * k) + f * D;
                out[at..at + D].copy_from_slice(field[i].as_slice());
            }
        }
    }

    /// The inverse of [`Self::pack`].
    fn unpack(local: &mut Fem<D>, nodes: std::ops::Range<usize>, data: &[f64]) {
        let s = &mut local.state;
        let fields = [
            &mut s.displacement,
            &mut s.velocity_half,
            &mut s.acceleration,
        ];
        for (f, field) in fields.into_iter().enumerate() {
            for (k, i) in nodes.clone().enumerate() {
                let at = (packed_len(D) * k) + f * D;
                field[i].copy_from_slice(&data[at..at + D]);
            }
        }
    }

    /// Send the owned edge node layers to the neighbours and take theirs into the halo:
    /// the node layers below the owned ones, and those from the upper neighbour's first
    /// owned layer up to (not including) the top cut face.
    fn exchange_halo(&mut self) {
        let (below, above) = (
            self.slab.halo_width(D - 1, 0),
            self.slab.halo_width(D - 1, 1),
        );
        let own = self.slab.owned_local(D - 1);
        let n = self.layer_nodes;
        let b = &mut self.buffers;
        Self::pack(
            &self.local,
            own.start * n..(own.start + below) * n,
            &mut b.send_low,
        );
        Self::pack(
            &self.local,
            (own.end - above) * n..own.end * n,
            &mut b.send_high,
        );
        b.exchange(self.comm.as_ref());
        Self::unpack(&mut self.local, 0..below * n, &b.receive_low);
        let high = own.end * n..(own.end + above) * n;
        Self::unpack(&mut self.local, high, &b.receive_high);
    }
}

impl<const D: usize> Method<D> for SlabFem<D> {
    impact_core::reduced_over_ranks!();
    fn cells(&self) -> usize {
        self.global_cells
    }
    fn updates_per_step(&self) -> usize {
        self.global_cells
    }
    fn step(&mut self, t: f64, dt: f64) {
        self.local.step(t, dt);
        self.exchange_halo();
    }
    fn hottest_place(&self) -> Vector<D> {
        hottest_place(self.comm.as_ref(), self.local.hottest_owned())
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        self.local.perturb_velocity(kick);
    }
    fn mesh_nodal_fields(&self) -> Option<(Vec<Vector<D>>, Vec<Vector<D>>)> {
        let (velocity, displacement) = self.local.mesh_nodal_fields()?;
        let comm = self.comm.as_ref();
        Some((
            gather_vectors(comm, &velocity),
            gather_vectors(comm, &displacement),
        ))
    }
}

/// What a run on `ranks` ranks is split into, for summaries.
pub fn describe<const D: usize>(grid: &Grid<D>, ranks: usize) -> String {
    format!(
        "{ranks} slabs along axis {} ({} layers of elements, halo {HALO_LAYERS} layer, \
         nodal state exchanged once per step)",
        D - 1,
        grid.cells[D - 1],
    )
}

//! FEM on one rank's box of the mesh (issue 27): the elements are split over a grid of
//! ranks along every axis ([`RankBox`], `--ranks-grid px,py[,pz]`; the automatic choice,
//! slabs along the last axis, is the box `1 × … × 1 × N`); each rank stores its own
//! elements plus one element layer of each neighbour's along every split axis (the faces,
//! edges and corners of its box), steps them with the unchanged kernels (stencil or
//! Gauss-point path, fused or not), and after each step (and once when built) receives the
//! halo's nodal state (`u^n`, `v^{n-1/2}`, `a^n`) from the nodes' owners, axis by axis
//! (`node_halo.rs`, which fills the edges and corners with no extra message).
//!
//! **Design: the DGMPM one (a halo), not "shared nodes' forces summed".** Summing the
//! partial forces of a shared node layer over two ranks adds its elements' contributions
//! in another association than one rank does (the colour passes, the stencil's pairs), so
//! the fields would agree to round-off only; with a halo every owned node is formed by the
//! same operations on the same bits as on one rank, so the owned fields equal the serial
//! run's bit for bit, at the price of one extra element layer per neighbour.
//!
//! **Ownership.** Along each axis a rank owns its element layers `[a, b)` and the node
//! layers `[a, b)` (their lower faces; where `b` is the mesh's end `L`, the top face `L`
//! too); it owns the elements and nodes owned along every axis. It stores the element
//! layers `[a − 1, b + 1)` (clamped to the mesh), so the node layers `[a − 1, b + 1]`. A
//! face of the stored box inside the mesh (a cut) is free: loads, prescribed velocities
//! and symmetry are found on the whole mesh by global index (`place.rs`), so a cut never
//! carries one, while a halo node on a physical edge keeps its own; every stored node has
//! its whole-mesh lumped mass (`build.rs`).
//!
//! **Why one layer of halo makes the owned nodes exact.** One step is pointwise at the
//! nodes (`v += Δt_avg a`, `u += Δt v`, the held velocities) and then forms `a^{n+1}` at a
//! node from the elements around it, which read `u^{n+1}` one node away along every axis
//! (the Gauss stresses of an element read its own nodes and its own history). So an owned
//! node needs `u^{n+1}` on the node box `[a − 1, b]` along every axis, which the pointwise
//! update forms exactly from the state at `t^n` received for the halo layers `a − 1` and
//! `b` (their owners' bits, corners included) and held for the owned ones. Only the halo
//! nodes' `a^{n+1}` is wrong (those on a cut face miss the elements outside the box; layer
//! `b` reads the never-received `b + 1`); they are received at the end of the step, so the
//! owned elements' samples (whose nodes reach layer `b`) and the next step read their
//! owners' values. J2's Gauss-point history needs no exchange: a halo element of layer
//! `a − 1` reads node layers `a − 1` and `a` only, exact every step, so its history stays
//! exact; that of layer `b` may drift from the node `b + 1`, but it reaches nodes `b` and
//! `b + 1` only, which are not owned.
//!
//! **Node classes and colours.** The stencil path classifies each node as low edge,
//! interior or high edge per axis by its place in the stored box (`stencil.rs`). That is
//! its class in the whole mesh for every node that matters: an owned node is never on a
//! cut face (the cut nodes `a − 1` and `b + 1` are halo nodes), so it is on a face of the
//! box exactly where it is on the mesh's, and its blocks, its row path (paired interior
//! blocks or the general sum) and so its bits are one rank's; a cut node classed as
//! interior would instead read nodes past the stored box. The Gauss path adds a node's
//! element forces in colour passes over the element layers along the last axis; they run
//! with the layers of even global index first on every box (`lib.rs`), the order one rank
//! uses; along the other axes there is no colouring, and a box keeps the global relative
//! order of its elements within a layer, so each node adds its elements in one rank's
//! order.
//!
//! The exchange per step is one message each way per neighbour along each split axis,
//! `3 D` values per node of one node layer of the box ([`SlabFem::bytes_per_step`]).
//!
//! Diagnostics are reduced over the owned nodes and elements only: energy, work, momentum
//! and impulse per rank, then added in rank order ([`impact_core::comm`]), so they differ
//! from one rank's sums by round-off (`Σ_r Σ_{i∈r}` against `Σ_i`). Samples are gathered to
//! every rank (`Method::sample_into`) and put in the global order (on slabs the rank order
//! already is); the mesh's nodal fields are never gathered: each rank gives those of its
//! owned elements' nodes (`Method::piece_nodal_fields`, the halo layer above a cut
//! included, whose state is its owner's), its piece of the grid file.
use crate::node_halo::NodeHalo;
use crate::Fem;
use impact_core::comm::{Comm, RankBox, RankGrid};
use impact_core::comm_gather::hottest_place;
use impact_core::method::{Method, MethodConfig};
use impact_core::{CoreError, Grid, Problem, Vector};
use std::ops::Range;
use std::sync::Arc;

/// Element layers of halo each side along every split axis (module doc).
pub const HALO_LAYERS: usize = 1;

/// FEM on one rank's box, a [`Method`] whose values are global (module doc).
#[derive(Debug)]
pub struct SlabFem<const D: usize> {
    /// The box's FEM (owned elements and halo).
    pub local: Fem<D>,
    comm: Arc<dyn Comm>,
    rank_box: RankBox,
    /// Elements of the whole mesh.
    global_cells: usize,
    initial_energy: f64,
    halo: NodeHalo,
    /// The global index of each own sample (owned element), in order; empty on slabs,
    /// whose rank order is the global order.
    sample_order: Vec<usize>,
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

    /// [`Self::new`] split as `rank_grid` says (a grid that does not fit the rank count or
    /// the mesh is refused on every rank alike, `RankBox::new`).
    pub fn on_grid(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
        rank_grid: &RankGrid,
    ) -> Result<Self, CoreError> {
        problem.check_config(&config)?;
        let global = &problem.grid;
        let rank_box = RankBox::for_rank(&global.cells, rank_grid, comm.as_ref(), HALO_LAYERS)?;
        let stored: [Range<usize>; D] = std::array::from_fn(|k| rank_box.stored[k].clone());
        let owned: [Range<usize>; D] = std::array::from_fn(|k| rank_box.owned[k].clone());
        let local = Fem::on_box(problem, config, &stored, &owned)?;
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let sample_order = if rank_box.is_slabs() {
            Vec::new()
        } else {
            let place = &local.solver.place;
            let elements = place.owned_element_iter().map(|c| place.global_element(c));
            elements.collect()
        };
        let mut on_box = Self {
            local,
            comm,
            halo: NodeHalo::new(&rank_box, D),
            rank_box,
            global_cells: global.cell_count(),
            initial_energy,
            sample_order,
        };
        // `a^0` of the halo's nodes next to the cut faces from their owners
        on_box.exchange_halo();
        Ok(on_box)
    }

    /// The box this rank stores.
    pub fn rank_box(&self) -> &RankBox {
        &self.rank_box
    }

    /// The global index of each own sample (empty: rank order is the global order).
    pub fn sample_order(&self) -> &[usize] {
        &self.sample_order
    }

    /// Bytes this rank sends per step (one node layer's `u`, `v`, `a` per neighbour).
    pub fn bytes_per_step(&self) -> usize {
        self.halo.bytes_per_step()
    }

    /// Take the halo nodes' state from their owners (`node_halo.rs`).
    fn exchange_halo(&mut self) {
        self.halo
            .exchange(self.comm.as_ref(), &mut self.local.state);
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
    /// This rank's piece: its owned elements' nodes (no communication).
    fn piece_nodal_fields(&self) -> Option<(Vec<Vector<D>>, Vec<Vector<D>>)> {
        self.local.piece_nodal_fields()
    }
}

/// What a run on `ranks` ranks split as `rank_grid` says is split into, for summaries.
pub fn describe<const D: usize>(grid: &Grid<D>, ranks: usize, rank_grid: &RankGrid) -> String {
    match RankBox::new(&grid.cells, rank_grid, ranks, 0, HALO_LAYERS) {
        Ok(b) => format!(
            "{} (halo elements, nodal state exchanged once per step)",
            b.describe()
        ),
        Err(e) => e.to_string(),
    }
}

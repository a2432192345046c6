//! MPM on one rank's slab of the grid (issue 27): the layers of cells along the last axis
//! are split over the ranks ([`RankBox`], the slab `1 × … × 1 × N`: boxes are
//! refused); each rank steps the points of its own layers plus a
//! halo of its neighbours' layers with the unchanged kernels on the background nodes of
//! those layers, and exchanges the halo's point state once per step. Total Lagrangian
//! frame only (the default): a point never changes cell, so a layer's points stay on their
//! rank. The updated Lagrangian frame, whose points migrate between ranks, is
//! [`crate::migrate::MigratingMpm`]'s; this wrapper refuses it on more than one rank
//! ([`CommError::Unsupported`]).
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
//! ([`OnSlab::bytes_per_step`], `impact_core::comm_halo`): position, velocity and stress, and where
//! present the deformation gradient (Saint-Venant–Kirchhoff), the plastic history (J2) and
//! APIC's affine velocity. The volumes and the CPDI domains never change in the total
//! Lagrangian frame and are not sent.
//!
//! The wrapper ([`OnSlab`]) is DGMPM's too (`impact_core::slab_method`). Diagnostics are
//! over the own points and nodes only, reduced in rank order ([`impact_core::comm`]): the energy and momentum differ from one rank's sums by
//! round-off (`Σ_r Σ_{i∈r}` against `Σ_i`); the loads' work and impulse count on the rank
//! owning the loaded point, the velocity constraints' reactions on the rank owning the node
//! (the node layers at a rank's own cell layers' lower faces; the padding's on the first and
//! last ranks). Samples are gathered in rank order (the global point order), so outputs and
//! error metrics equal the serial ones.
use crate::Mpm;
use impact_core::comm::{Comm, CommError, RankBox, RankGrid};
use impact_core::method::{MethodConfig, MpmFrame, MpmOptions, MpmShape, StressUpdate};
use impact_core::points::MaterialPoints;
use impact_core::slab_method::{OnSlab, SlabBuild, SlabLocal, SlabParts};
use impact_core::{CoreError, Grid, Problem, Tensor};

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

/// MPM on one rank's slab, a [`Method`](impact_core::Method) whose values are global (module doc).
pub type SlabMpm<const D: usize> = OnSlab<D, Mpm<D>>;

impl<const D: usize> SlabBuild<D> for Mpm<D> {
    fn on_slab(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: &dyn Comm,
        rank_grid: &RankGrid,
    ) -> Result<SlabParts<Self>, CoreError> {
        let options = *config.mpm().ok_or_else(|| CoreError::Unsupported {
            method: "mpm".into(),
            message: "not an MPM configuration".into(),
        })?;
        if options.frame == MpmFrame::UpdatedLagrangian && comm.size() > 1 {
            return Err(CommError::Unsupported {
                what: "MPM in the updated Lagrangian frame (frame = updated)".into(),
                ranks: comm.size(),
                allowed: "this slab's halo holds fixed points; the migrating slab \
                          (impact_mpm::migrate::MigratingMpm) runs it"
                    .into(),
            }
            .into());
        }
        problem.check_config(&config)?;
        let global = &problem.grid;
        let layers = global.cells[D - 1];
        rank_grid.slabs_only("MPM", D, comm.size())?;
        let rank_box = RankBox::for_rank(&global.cells, rank_grid, comm, halo_layers(&options))?;
        let local = Mpm::build(problem, config, Some(&rank_box))?;
        let per_layer = local.state.points.len() / rank_box.stored[D - 1].len();
        Ok(SlabParts {
            local,
            per_cell: per_layer * layers / global.cell_count(),
            rank_box,
            cells: global.cell_count(),
            updates_per_step: per_layer * layers,
        })
    }
}

impl<const D: usize> SlabLocal<D> for Mpm<D> {
    fn points(&self) -> &MaterialPoints<D> {
        &self.state.points
    }
    fn halo_state(&mut self) -> (&mut MaterialPoints<D>, &mut [Tensor<D>]) {
        (&mut self.state.points, &mut self.state.affine)
    }
    fn owned_runs(&self) -> Vec<std::ops::Range<usize>> {
        std::iter::once(Mpm::owned_points(self)).collect()
    }
}

/// What a run on `ranks` ranks is split into, for summaries.
pub fn describe<const D: usize>(grid: &Grid<D>, options: &MpmOptions, ranks: usize) -> String {
    format!(
        "{ranks} slabs along axis {} ({} layers of cells, halo {} layers of points, \
         exchanged once per step{})",
        D - 1,
        grid.cells[D - 1],
        halo_layers(options),
        match options.frame {
            MpmFrame::TotalLagrangian => "",
            MpmFrame::UpdatedLagrangian => "; points migrate to the rank owning their cell",
        }
    )
}

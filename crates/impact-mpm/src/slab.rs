//! MPM on one rank's box of the grid (issue 27): the cells are split over a grid of ranks
//! along every axis ([`RankBox`]; `--ranks-grid px,py[,pz]`, the automatic choice being
//! slabs along the last axis, the box `1 × … × 1 × N`); each rank steps the points of its
//! own cells plus a halo of its neighbours' cells along every axis with the unchanged
//! kernels on the background nodes of those cells, and exchanges the halo's point state
//! once per step (axis by axis, which also fills the halo's edges and corners:
//! `impact_core::comm_box`). Total Lagrangian frame only (the default): a point never
//! changes cell, so a cell's points stay on their rank. The updated Lagrangian frame, whose
//! points migrate between ranks, is [`crate::migrate::MigratingMpm`]'s (on slabs and
//! boxes); this wrapper refuses it on more than one rank ([`CommError::Unsupported`]).
//!
//! **Why the halo makes the own points exact.** A node's sums read the points whose
//! stencil covers it, and a point's update reads the nodes of its stencil. A point of cell
//! `j` (along any axis) has its stencil's nodes within `j − 1 .. j + 2` (hats: `j .. j + 1`;
//! CPDI's domains at rest lie in their cell). Beyond a cut face (no physical edge: no load,
//! no prescribed velocity, no mirrored padding there) the points are missing, so the nodes
//! next to it miss some sums, and the points reading them go wrong: one scatter and gather
//! spoil `reach` cells next to the cut along its axis (diagonally too, at a box's edges and
//! corners; 1 with hats, 3 with the wider stencils), and a step has one such round under
//! USL and two under MUSL (the remap) and USF (the stress update before the internal
//! force). With a halo of `rounds × reach` cells along every axis ([`halo_layers`]) only
//! halo points are wrong after a step, and the exchange before the next one overwrites
//! them with their owners' values.
//!
//! Every own point is then formed by the same operations on the same bits as on one rank:
//! the points are the whole body's seeding of the stored cells (the same bits, in the
//! box's lexicographic cell order, which keeps the global relative order); the box's nodes
//! are numbered in the whole grid's relative order; the shape functions and load positions
//! are evaluated on the whole padded grid and moved to the box's nodes (`build.rs`: a box's
//! own origin would round the grid coordinates differently); the shared row of weights is
//! the body's first point's; the empty-node floor and the serial or parallel scatter are
//! the whole body's; and the coloured scatter's blocks follow the whole grid's layers along
//! the last axis, so each node adds its points in one rank's order (`transfer.rs`: within a
//! layer the box's points are a subsequence of the whole layer's, in the same order). The
//! edge conditions are found on the stored points by position, so only a box reaching an
//! edge of the body loads or holds its points there. So the own points' fields equal the
//! serial run's bit for bit, for every transfer, stress update, shape (CPDI included) and
//! model, on slabs (`tests/slab.rs`) and boxes (`tests/boxes.rs`).
//!
//! The exchange per step is one message each way per neighbour along each split axis of
//! `halo` cells' points ([`OnSlab::bytes_per_step`], `impact_core::comm_halo`): position,
//! velocity and stress, and where present the deformation gradient (Saint-Venant–Kirchhoff),
//! the plastic history (J2) and APIC's affine velocity. The volumes and the CPDI domains
//! never change in the total Lagrangian frame and are not sent.
//!
//! The wrapper ([`OnSlab`]) is DGMPM's too (`impact_core::slab_method`). Diagnostics are
//! over the own points (a run per row of own cells) and nodes only, reduced in rank order
//! ([`impact_core::comm`]): the energy and momentum differ from one rank's sums by
//! round-off (`Σ_r Σ_{i∈r}` against `Σ_i`); the loads' work and impulse count on the rank
//! owning the loaded point, the velocity constraints' reactions on the rank owning the node
//! (per axis, the nodes of a rank's own cells' lower faces; the padding's on the ranks at
//! the grid's ends). Samples are gathered in the global point order, so outputs and error
//! metrics equal the serial ones.
use crate::Mpm;
use impact_core::comm::{Comm, CommError, RankBox, RankGrid};
use impact_core::method::{MethodConfig, MpmFrame, MpmOptions, MpmShape, StressUpdate};
use impact_core::points::MaterialPoints;
use impact_core::slab_method::{OnSlab, SlabBuild, SlabLocal, SlabParts};
use impact_core::{CoreError, Grid, Problem, Tensor};

/// Cells by which a CPDI domain's stencil may start below its point's cell along an axis
/// in the updated Lagrangian frame, which the halo covers (`migrate.rs`: a domain stretched
/// or sheared about one cell beyond its rest size; a point whose stencil starts lower fails
/// the run).
pub const CPDI_DOMAIN_REACH: usize = 1;

/// Halo width (cells, along every axis) for `options`: scatter–gather rounds per step ×
/// cells a round spoils next to a cut face (module doc; CPDI in the updated frame:
/// `3 + CPDI_DOMAIN_REACH`, `migrate.rs`).
pub fn halo_layers(options: &MpmOptions) -> usize {
    let rounds = match options.stress_update {
        StressUpdate::Usl => 1,
        StressUpdate::Musl | StressUpdate::Usf => 2,
    };
    let reach = match (options.shape, options.frame) {
        (MpmShape::Linear, _) => 1,
        (MpmShape::Cpdi, MpmFrame::UpdatedLagrangian) => 3 + CPDI_DOMAIN_REACH,
        _ => 3,
    };
    rounds * reach
}

/// MPM on one rank's box (or slab), a [`Method`](impact_core::Method) whose values are global (module doc).
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
        let rank_box = RankBox::for_rank(&global.cells, rank_grid, comm, halo_layers(&options))?;
        let local = Mpm::build(problem, config, Some(&rank_box))?;
        let per_cell = config.points_per_cell;
        Ok(SlabParts {
            local,
            per_cell,
            rank_box,
            cells: global.cell_count(),
            updates_per_step: per_cell * global.cell_count(),
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
        self.owned_point_runs().to_vec()
    }
}

/// What a run on `ranks` ranks split as `rank_grid` says is split into, for summaries: the
/// rank grid, the cells and the halo ([`RankBox::describe`]).
pub fn describe<const D: usize>(
    grid: &Grid<D>,
    options: &MpmOptions,
    ranks: usize,
    rank_grid: &RankGrid,
) -> String {
    match RankBox::new(&grid.cells, rank_grid, ranks, 0, halo_layers(options)) {
        Ok(b) => format!(
            "{} (the halo cells' points, exchanged once per step{})",
            b.describe(),
            match options.frame {
                MpmFrame::TotalLagrangian => "",
                MpmFrame::UpdatedLagrangian => "; points migrate to the rank owning their cell",
            }
        ),
        Err(e) => e.to_string(),
    }
}

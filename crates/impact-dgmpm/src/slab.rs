//! DGMPM on one rank's box of the grid (issue 27): the cells are split over a grid of ranks
//! along every axis ([`RankBox`]; the automatic choice, slabs along the last axis, is the
//! box `1 × … × 1 × N`); each rank steps its own cells plus a halo of its neighbours' cells
//! along every axis with the unchanged kernels, and exchanges the halo's point state once
//! per step (axis by axis, which also fills the halo's edges and corners:
//! `impact_core::comm_box`).
//!
//! **Why the halo makes the owned cells exact.** One stage of DGMPM updates a cell from
//! its faces' fluxes, which read the two cells of the face and, under CTU, their transverse
//! neighbours (the edge and corner cells): a stage reaches one cell (order 2's wave
//! corrections and their transverse parts: up to three). A box's outer face that is not a
//! physical edge is given a free condition; what it makes wrong travels at most `reach`
//! cells per stage along any axis (diagonally too), so with a halo of `stages × reach`
//! cells ([`halo_layers`]) along every axis only halo cells are wrong after a step, and the
//! exchange before the next step overwrites them with their owners' values. Every owned
//! cell is then formed by the same operations on the same bits as on one rank (the box's
//! cells keep the global relative order; face coordinates come from global indices,
//! `GridPlace`), so the owned fields equal the serial run's bit for bit on the cell and
//! fused paths. On the nodal paths (several points per cell, RK2) the shape functions are
//! formed from the box's origin, which rounds differently from the whole grid's: equal to
//! round-off there.
//!
//! The exchange per step is one message each way per neighbour along each split axis
//! ([`OnSlab::bytes_per_step`]; the wrapper is shared with MPM, `impact_core::slab_method`);
//! the halo trades extra cells (`2 × halo` per split axis) for one exchange per step
//! instead of one per stage.
//!
//! Diagnostics are reduced over the owned points only (a run per row of own cells,
//! `GridPlace`): the energy and momentum in rank order ([`impact_core::comm`]), so they
//! differ from one rank's sums by round-off (`Σ_r Σ_{i∈r}` against `Σ_i`); the boundary
//! work and impulse of a halo cell's edge faces count on its owner only. Samples are
//! gathered to every rank in the global point order, so outputs and error metrics equal
//! the serial ones.
use crate::{Dgmpm, GridPlace};
use impact_core::comm::{Comm, RankBox, RankGrid};
use impact_core::method::{DgmpmOptions, Integrator, Method, MethodConfig};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::slab_method::{OnSlab, SlabBuild, SlabLocal, SlabParts};
use impact_core::{CoreError, Grid, Problem, Tensor};
use std::ops::Range;

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
pub type SlabDgmpm<const D: usize> = OnSlab<D, Dgmpm<D>>;

impl<const D: usize> SlabBuild<D> for Dgmpm<D> {
    fn on_slab(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: &dyn Comm,
        rank_grid: &RankGrid,
    ) -> Result<SlabParts<Self>, CoreError> {
        let options = *config.dgmpm().ok_or_else(|| CoreError::Unsupported {
            method: "dgmpm".into(),
            message: "not a DGMPM configuration".into(),
        })?;
        problem.check_config(&config)?;
        let global = &problem.grid;
        let rank_box = RankBox::for_rank(&global.cells, rank_grid, comm, halo_layers(&options))?;
        let stored: [Range<usize>; D] = std::array::from_fn(|k| rank_box.stored[k].clone());
        // only the stored cells' points, seeded from the whole grid's origin and global
        // cell indices: the same bits as one rank's, in memory that shrinks with the ranks
        let points = problem.material_points_of_box(global, &config, &stored)?;
        let mut part = problem.clone();
        part.grid = global.cut(
            stored.clone().map(|r| r.start),
            stored.clone().map(|r| r.len()),
        );
        for axis in 0..D {
            for side in 0..2 {
                if !rank_box.physical_edge(axis, side) {
                    part.boundaries[axis][side] = Boundary::Free;
                }
            }
        }
        let mut local = Dgmpm::with_points(&part, config, options, points)?;
        local.solver.place = GridPlace {
            origin: global.origin,
            offset: stored.clone().map(|r| r.start),
            owned: std::array::from_fn(|k| rank_box.owned_local(k)),
            owned_cell_runs: rank_box.owned_runs(),
        };
        // (the edges' conditions at the box's global coordinates)
        local.solver.fill_edge_conditions();
        // the whole body's wave speed (a box without the loaded edge has a lower one)
        local.solver.wave_speed = problem.max_wave_speed();
        local.state.initial_energy = local.energy();
        Ok(SlabParts {
            local,
            rank_box,
            per_cell: config.points_per_cell,
            cells: global.cell_count(),
            updates_per_step: global.cell_count(),
        })
    }
}

impl<const D: usize> SlabLocal<D> for Dgmpm<D> {
    fn points(&self) -> &MaterialPoints<D> {
        &self.state.points
    }
    fn halo_state(&mut self) -> (&mut MaterialPoints<D>, &mut [Tensor<D>]) {
        (&mut self.state.points, &mut [])
    }
    fn owned_runs(&self) -> Vec<Range<usize>> {
        self.owned_point_runs().collect()
    }
}

impl<const D: usize> Dgmpm<D> {
    /// The points this solver owns, a run per row of own cells in order (one run on one
    /// rank; one per slab).
    pub fn owned_point_runs(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        let n = self.solver.points_per_cell;
        (self.solver.place.owned_cell_runs.iter()).map(move |r| r.start * n..r.end * n)
    }
}

/// What a run on `ranks` ranks split as `rank_grid` says is split into, for summaries.
pub fn describe<const D: usize>(
    grid: &Grid<D>,
    options: &DgmpmOptions,
    ranks: usize,
    rank_grid: &RankGrid,
) -> String {
    match RankBox::new(&grid.cells, rank_grid, ranks, 0, halo_layers(options)) {
        Ok(b) => format!("{} (halo cells, exchanged once per step)", b.describe()),
        Err(e) => e.to_string(),
    }
}

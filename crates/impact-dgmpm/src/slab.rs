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
//! ([`OnSlab::bytes_per_step`]; the wrapper is shared with MPM, `impact_core::slab_method`);
//! the halo trades extra cells (`2 × halo` layers per
//! rank) for one message per step instead of one per stage.
//!
//! Diagnostics are reduced over the owned points only: the energy and momentum in rank
//! order ([`impact_core::comm`]), so they differ from one rank's sums by round-off
//! (`Σ_r Σ_{i∈r}` against `Σ_i`); the boundary work and impulse of a halo layer's edge
//! faces count on its owner only. Samples are gathered to every rank in rank order (the
//! global point order), so outputs and error metrics equal the serial ones.
use crate::{Dgmpm, GridPlace};
use impact_core::comm::{Comm, Slab};
use impact_core::method::{DgmpmOptions, Integrator, Method, MethodConfig};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::slab_method::{OnSlab, SlabBuild, SlabLocal, SlabParts};
use impact_core::{CoreError, Grid, Problem, Tensor};

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
    ) -> Result<SlabParts<Self>, CoreError> {
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
        Ok(SlabParts {
            local,
            slab,
            per_layer,
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
    fn owned_points(&self) -> std::ops::Range<usize> {
        Dgmpm::owned_points(self)
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

/// What a run on `ranks` ranks is split into, for summaries.
pub fn describe<const D: usize>(grid: &Grid<D>, options: &DgmpmOptions, ranks: usize) -> String {
    format!(
        "{ranks} slabs along axis {} ({} layers of cells, halo {} layers, exchanged once per step)",
        D - 1,
        grid.cells[D - 1],
        halo_layers(options)
    )
}

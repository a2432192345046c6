//! The fused sweeps in 1D: the nodal sweep's stage over chunks of cells and the walk of
//! one chunk, which the Heun sweeps share (module docs of `fused::nodal` and `fused::heun`).
use super::super::{Band, CHUNK};
use super::Stage;
use crate::faces::Fields;
use crate::riemann::axis::{axis_flux_1d, AxisConstants};
use crate::riemann::Conserved;
use crate::DgmpmSolver;
use impact_core::points::MaterialPoints;
use impact_core::Vector;

impl DgmpmSolver<1> {
    /// The 1D nodal sweep: [`Self::walk_1d`] with the nodal update, the face states from
    /// the nodes (or, read from the points, the cells' states).
    pub(super) fn nodal_sweep_1d(
        &mut self,
        points: &mut MaterialPoints<1>,
        stage: Stage,
    ) -> (f64, Vector<1>) {
        let constants = AxisConstants::new(&self.elastic);
        self.nodal_bands(
            points,
            CHUNK,
            stage,
            |this, b, band, fields, inputs, out| {
                let c = &constants;
                match (stage.reads_points(), stage.single) {
                    (true, _) => this.walk_1d::<false>(b, band, fields, c, |cell, j, faces| {
                        this.nodal_cell_update::<true>((cell, j), faces, inputs, stage, out)
                    }),
                    (false, true) => this.walk_1d::<true>(b, band, fields, c, |cell, j, faces| {
                        this.nodal_cell_update::<true>((cell, j), faces, inputs, stage, out)
                    }),
                    (false, false) => this.walk_1d::<true>(b, band, fields, c, |cell, j, faces| {
                        this.nodal_cell_update::<false>((cell, j), faces, inputs, stage, out)
                    }),
                }
            },
        )
    }

    /// The 1D sweep of chunk `b` (the 1D nodal sweep's and the Heun sweeps'): it solves
    /// its low face (`NODAL`: node 1 of the cell below against its node 0, or side
    /// states; otherwise the two cells' states), then per cell its high face and
    /// `update(cell, index in the chunk, [[low, high]])`. Boundary faces add their power
    /// and force to the band's.
    pub(in crate::fused) fn walk_1d<const NODAL: bool>(
        &self,
        b: usize,
        band: &mut Band<1>,
        fields: Fields<'_, 1>,
        constants: &AxisConstants,
        mut update: impl FnMut(usize, usize, [[&Conserved<1>; 2]; 1]),
    ) {
        let count = self.grid.cells[0];
        let start = b * CHUNK;
        let len = CHUNK.min(count - start);
        band.power = 0.0;
        band.force = Vector::<1>::zeros();
        let face = |left: usize| {
            let l = fields.at::<NODAL>(left, 0, true);
            let r = fields.at::<NODAL>(left + 1, 0, false);
            axis_flux_1d(&l, &r, constants)
        };
        // the chunk's low face is counted by the chunk below it (or here at the bar's end)
        let mut low = match start {
            0 => self.boundary_flux(0, [0], fields, band),
            _ => face(start - 1),
        };
        for j in 0..len {
            let cell = start + j;
            let high = match cell + 1 < count {
                true => face(cell),
                false => self.boundary_flux(0, [count], fields, band),
            };
            update(cell, j, [[&low, &high]]);
            low = high;
        }
    }
}

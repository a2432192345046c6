//! The 2D sweep's steps one at a time (module doc of [`super`], [`DgmpmSolver::band_2d`]):
//! the start at a cell row and one row, with the power and force of the boundary faces
//! counted only on the rows a band owns; the Heun wavefront (`fused/heun/wavefront.rs`)
//! runs its two stages' sweeps row by row through them.
use super::{difference_flux, for_row_sides, Sweep2d};
use crate::faces::Fields;
use crate::fused::Band;
use crate::riemann::axis::axis_transverse_2d;
use crate::riemann::Conserved;
use crate::DgmpmSolver;
use impact_core::Vector;
use std::ops::Range;

/// What a row sweep ([`DgmpmSolver::band_row`]) does with each cell from its faces' final
/// fluxes: `update(cell, index in the band, [[x low, x high], [y low, y high]])`. A closure
/// is one; a struct holding a row's slices (Heun's first stage, `heun/wavefront.rs`) is
/// another, whose method is always inlined and whose slices' lengths the optimizer then
/// knows (no index checks per cell; a closure holding them was not inlined).
pub(in crate::fused) trait CellUpdate {
    /// Update `cell` from its faces' final fluxes.
    fn update(&mut self, cell: usize, local: usize, faces: [[&Conserved<2>; 2]; 2]);
}

impl<F: FnMut(usize, usize, [[&Conserved<2>; 2]; 2])> CellUpdate for F {
    #[inline(always)]
    fn update(&mut self, cell: usize, local: usize, faces: [[&Conserved<2>; 2]; 2]) {
        self(cell, local, faces)
    }
}

impl DgmpmSolver<2> {
    /// The start of a sweep at cell row `j0` ([`Self::band_2d`]): face row `j0` (its
    /// Godunov fluxes, [`Self::y_godunov_row`], and under CTU the x-fluxes of row `j0 - 1`
    /// for its final fluxes, [`Self::y_final_row`]) and the x-fluxes of row `j0`
    /// ([`Self::x_godunov_row`]). The power and force of its boundary faces count where
    /// the band owns their row (`own`: the Heun wavefront also sweeps the rows next to its
    /// band, `heun.rs`).
    pub(in crate::fused) fn band_start<const NODAL: bool>(
        &self,
        j0: usize,
        own: &Range<usize>,
        band: &mut Band<2>,
        fields: Fields<'_, 2>,
        k: &Sweep2d,
    ) {
        let nx = self.grid.cells[0];
        let c = &k.constants;
        band.edge_carry = [None, None];
        let (x_row, x_fluctuation) = (&mut band.x_godunov[0], &mut band.x_fluctuation[0]);
        let power = self.x_godunov_row::<NODAL>(j0, fields, c, x_row, x_fluctuation);
        if own.contains(&j0) {
            band.power += power;
        }
        let power = self.y_godunov_row::<NODAL>(j0, fields, c, &mut band.y_godunov[0]);
        let bottom = j0 == 0 && own.contains(&0);
        if bottom {
            band.power += power;
        }
        if k.ctu && j0 > 0 {
            // the row below: its x-fluxes, recomputed here
            let (x_row, x_fluctuation) = (&mut band.x_godunov[1], &mut band.x_fluctuation[1]);
            self.x_godunov_row::<NODAL>(j0 - 1, fields, c, x_row, x_fluctuation);
        }
        let below = (j0 > 0).then_some(&band.x_fluctuation[1][..]);
        let here = Some(&band.x_fluctuation[0][..]);
        let godunov = &band.y_godunov[0];
        let finals = &mut band.y_final[0];
        self.y_final_row::<NODAL>(j0, godunov, [below, here], fields, k, finals);
        if bottom {
            for i in 0..nx {
                band.force += self.boundary_face_force(1, [i, 0], &band.y_final[0][i]);
            }
        }
    }

    /// Row `j` of a sweep ([`Self::band_2d`], steps 1-4), after [`Self::band_start`] or row
    /// `j - 1`; `update`'s index in the band counts from row `own.start`. The power and
    /// force of its boundary faces count where `own` holds their row; returns the power of
    /// row `j + 1`'s x-faces (counted or not).
    ///
    /// `CTU`: whether CTU corrects (`k`'s, a constant here: no test of it per cell).
    #[inline(always)]
    pub(in crate::fused) fn band_row<const NODAL: bool, const CTU: bool>(
        &self,
        j: usize,
        own: &Range<usize>,
        band: &mut Band<2>,
        fields: Fields<'_, 2>,
        k: &Sweep2d,
        update: &mut impl CellUpdate,
    ) -> f64 {
        let [nx, ny] = self.grid.cells;
        debug_assert_eq!(k.ctu, CTU, "internal: the sweep's CTU");
        let (c, ctu, scale) = (&k.constants, CTU, k.scale);
        let counted = own.contains(&j);
        let mut x_power = 0.0;
        let top = j + 1 == ny;
        let power = self.y_godunov_row::<NODAL>(j + 1, fields, c, &mut band.y_godunov[1]);
        if top && counted {
            band.power += power;
        }
        if !top {
            let (x_row, x_fluctuation) = (&mut band.x_godunov[1], &mut band.x_fluctuation[1]);
            x_power = self.x_godunov_row::<NODAL>(j + 1, fields, c, x_row, x_fluctuation);
            if own.contains(&(j + 1)) {
                band.power += x_power;
            }
        }
        let here = Some(&band.x_fluctuation[0][..]);
        let above = (!top).then_some(&band.x_fluctuation[1][..]);
        let godunov = &band.y_godunov[1];
        let finals = &mut band.y_final[1];
        self.y_final_row::<NODAL>(j + 1, godunov, [here, above], fields, k, finals);
        if top && counted {
            for i in 0..nx {
                band.force += self.boundary_face_force(1, [i, ny], &band.y_final[1][i]);
            }
        }
        // the x-faces' final fluxes, rolling along the row, and the cell updates
        let row = j * nx;
        let (y_low, y_high) = (&band.y_godunov[0], &band.y_godunov[1]);
        if NODAL && ctu {
            // (sliced to the row: no index checks on the y-fluxes)
            let (w_y, y_low, y_high) = (&mut band.w_y[..nx], &y_low[..nx], &y_high[..nx]);
            for_row_sides!(fields, row, nx, 1, |i, low, high| {
                let w_flux = y_high[i].add_scaled(&y_low[i], -1.0);
                w_y[i] = w_flux.add_scaled(&difference_flux::<1>(&low, &high, c), 1.0);
            });
        }
        let ghosts = self.x_edge_ghosts(j, fields, ctu, &mut band.edge_carry);
        // (sliced to the row: no index checks per cell)
        let (y_low, y_high) = (&band.y_godunov[0][..nx], &band.y_godunov[1][..nx]);
        let w_row = &band.w_y[..if NODAL && ctu { nx } else { 0 }];
        let x_godunov = &band.x_godunov[0][..nx + 1];
        // (`move`: the closures hold the slices themselves, whose lengths the optimizer then
        // knows, rather than references to them: no index checks per cell)
        let w_y = move |i: usize| match NODAL {
            true => w_row[i],
            false => y_high[i].add_scaled(&y_low[i], -1.0),
        };
        // the edge faces (ghost cells; their force) out of line, the interior ones in the
        // loop with each cell's y-fluctuation formed once
        let x_edge = move |i: usize, band_force: &mut Vector<2>| {
            let w = ctu.then(|| {
                let inside = [(i > 0).then(|| w_y(i - 1)), (i < nx).then(|| w_y(i))];
                [inside[0].or(ghosts[0]), inside[1].or(ghosts[1])]
            });
            self.x_edge_flux([i, j], x_godunov[i], w, (fields, k), band_force)
        };
        let x_interior = move |i: usize, w_left: &Conserved<2>, w_right: &Conserved<2>| {
            let godunov = x_godunov[i];
            if !ctu {
                return godunov;
            }
            let total = axis_transverse_2d::<0>(w_left, w_right, c);
            godunov.add_scaled(&Conserved::zeros().add_scaled(&total, -scale[0]), 1.0)
        };
        let mut force = Vector::<2>::zeros();
        let mut low = x_edge(0, &mut force);
        let mut w_left = match ctu {
            true => w_y(0),
            false => Conserved::zeros(),
        };
        // (rows below `own` are the Heun wavefront's, whose update ignores the index)
        let local = row.wrapping_sub(own.start * nx);
        // (sliced to the row: no index checks on the final y-fluxes)
        let (y_below, y_above) = (&band.y_final[0][..nx], &band.y_final[1][..nx]);
        for i in 0..nx {
            let high = match i + 1 < nx {
                true => {
                    let w_right = match ctu {
                        true => w_y(i + 1),
                        false => Conserved::zeros(),
                    };
                    let flux = x_interior(i + 1, &w_left, &w_right);
                    w_left = w_right;
                    flux
                }
                false => x_edge(nx, &mut force),
            };
            let faces = [[&low, &high], [&y_below[i], &y_above[i]]];
            update.update(row + i, local.wrapping_add(i), faces);
            low = high;
        }
        if counted {
            band.force += force;
        }
        band.x_godunov.swap(0, 1);
        band.x_fluctuation.swap(0, 1);
        band.y_godunov.swap(0, 1);
        band.y_final.swap(0, 1);
        x_power
    }
}

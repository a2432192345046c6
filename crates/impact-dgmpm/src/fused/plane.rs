//! The fused sweeps in 2D (module doc of [`super`]): the sweep of one band of rows with
//! its rolling face rows, and the rows of Godunov and final fluxes; the cell path's and the
//! nodal sweep's, one generic function.
use super::{Band, Next, BAND_ROWS};
use crate::faces::Fields;
use crate::riemann::axis::{axis_flux_2d, axis_normal_flux_2d, axis_transverse_2d, AxisConstants};
use crate::riemann::{Conserved, FullState};
use crate::DgmpmSolver;
use impact_core::method::TransverseFlux;
use impact_core::points::MaterialPoints;
use impact_core::Vector;

mod edges;
mod rows;
pub(super) use rows::CellUpdate;
#[cfg(test)]
mod tests;

/// `for_row_sides!(fields, first, n, L, |i, low, high| body)`: the body with the two
/// `L`-side states of each cell `first + i` of a row (`i < n`; nodal or side fields), from
/// the row's slice where the fields are side states ([`Fields::side_row`], Heun's second
/// stage: no index check per cell), else through [`Fields::at`]; the same states either
/// way. A macro so that the body is written once and compiled into both loops (as a
/// closure called from two loops it was not inlined: 78 instructions a cell more,
/// callgrind).
macro_rules! for_row_sides {
    ($fields:expr, $first:expr, $n:expr, $axis:literal, |$i:ident, $low:ident, $high:ident| $body:block) => {
        match $fields.side_row($first, $n) {
            Some(sides) => {
                for ($i, cell) in sides.as_chunks::<4>().0.iter().enumerate() {
                    let ($low, $high) =
                        (cell[2 * $axis].full($axis), cell[2 * $axis + 1].full($axis));
                    $body
                }
            }
            None => {
                for $i in 0..$n {
                    let cell = $first + $i;
                    let ($low, $high) = (
                        $fields.at::<true>(cell, $axis, false),
                        $fields.at::<true>(cell, $axis, true),
                    );
                    $body
                }
            }
        }
    };
}
use for_row_sides;

/// The constants of one 2D sweep: the axis solvers', whether CTU corrects, and the
/// corrections' scales (x-faces by the y-fluctuations, `Δt/2Δy`; y-faces by the x ones).
pub(super) struct Sweep2d {
    constants: AxisConstants,
    pub(super) ctu: bool,
    scale: [f64; 2],
}

/// The x-fluctuations of one cell row's cells (`Band::x_fluctuation`).
type XRow<'a> = &'a [Conserved<2>];

impl DgmpmSolver<2> {
    /// The constants of a 2D sweep with step `dt`.
    pub(super) fn sweep_2d_constants(&self, dt: f64) -> Sweep2d {
        Sweep2d {
            constants: AxisConstants::new(&self.elastic),
            ctu: self.options.flux == TransverseFlux::Ctu,
            scale: [
                dt / (2.0 * self.grid.spacing[1]),
                dt / (2.0 * self.grid.spacing[0]),
            ],
        }
    }

    /// The 2D sweep of the cell path: [`Self::band_2d`] with the cell update.
    pub(super) fn sweep_2d(&mut self, points: &mut MaterialPoints<2>, dt: f64) -> (f64, Vector<2>) {
        let nx = self.grid.cells[0];
        let k = self.sweep_2d_constants(dt);
        let u = self.update_constants(dt);
        self.sweep_bands(
            points,
            BAND_ROWS * nx,
            |this, b, band, fields, inverse_mass, next| {
                let Next {
                    tensor,
                    velocity,
                    position,
                } = next;
                this.band_2d::<false>(b, band, fields, &k, |cell, local, faces| {
                    let state = fields.cell(cell);
                    let old = (&state.tensor, &state.velocity, inverse_mass[cell]);
                    let out = (
                        &mut tensor[local],
                        &mut velocity[local],
                        &mut position[local],
                    );
                    Self::update_cell(&u, faces, old, out);
                });
            },
        )
    }

    /// The 2D sweep of band `b` (module doc of [`super`]): its rows `j0..j1`. It first
    /// forms face row `j0` (its Godunov fluxes, [`Self::y_godunov_row`], and under CTU the
    /// x-fluxes of row `j0 - 1` for its final fluxes, [`Self::y_final_row`]) and the
    /// x-fluxes of row `j0` ([`Self::x_godunov_row`]); then for each row `j`:
    /// 1. the Godunov fluxes of face row `j + 1` and of the x-faces of row `j + 1`;
    /// 2. the final fluxes of face row `j + 1` (corrections from the x-fluctuations of
    ///    rows `j` and `j + 1`);
    /// 3. along the row, the final x-fluxes (corrections from the y-fluctuations of the
    ///    cells on either side) and `update(cell, index in the band, [[x low, x high],
    ///    [y low, y high]])` of each cell;
    /// 4. the rolling rows shift by one.
    ///
    /// `NODAL`: face states are the averages of each side's DG nodes, and a cell's
    /// fluctuation `w_l` adds `F_l(q_C,low - q_C,high)` to its flux difference (the cell
    /// path's states are one per cell, where that term vanishes). Boundary faces add their
    /// power and force to the band's.
    ///
    /// (The same steps as [`Self::band_start`] and [`Self::band_row`], which the Heun
    /// wavefront runs row by row, `heun/wavefront.rs`; kept in one piece here: through
    /// them the Euler sweep took 9 instructions a cell more, callgrind.)
    pub(super) fn band_2d<const NODAL: bool>(
        &self,
        b: usize,
        band: &mut Band<2>,
        fields: Fields<'_, 2>,
        k: &Sweep2d,
        mut update: impl FnMut(usize, usize, [[&Conserved<2>; 2]; 2]),
    ) {
        let [nx, ny] = self.grid.cells;
        let (c, ctu, scale) = (&k.constants, k.ctu, k.scale);
        let rows = b * BAND_ROWS..((b + 1) * BAND_ROWS).min(ny);
        band.power = 0.0;
        band.force = Vector::<2>::zeros();
        band.edge_carry = [None, None];
        let j0 = rows.start;
        // prologue: face row j0 (Godunov and final) and the x-fluxes of cell row j0
        let (x_row, x_fluctuation) = (&mut band.x_godunov[0], &mut band.x_fluctuation[0]);
        band.power += self.x_godunov_row::<NODAL>(j0, fields, c, x_row, x_fluctuation);
        let power = self.y_godunov_row::<NODAL>(j0, fields, c, &mut band.y_godunov[0]);
        if j0 == 0 {
            band.power += power;
        }
        if ctu && j0 > 0 {
            // the row below the band: its x-fluxes, recomputed here
            let (x_row, x_fluctuation) = (&mut band.x_godunov[1], &mut band.x_fluctuation[1]);
            self.x_godunov_row::<NODAL>(j0 - 1, fields, c, x_row, x_fluctuation);
        }
        let below = (j0 > 0).then_some(&band.x_fluctuation[1][..]);
        let here = Some(&band.x_fluctuation[0][..]);
        let godunov = &band.y_godunov[0];
        let finals = &mut band.y_final[0];
        self.y_final_row::<NODAL>(j0, godunov, [below, here], fields, k, finals);
        if j0 == 0 {
            for i in 0..nx {
                band.force += self.boundary_face_force(1, [i, 0], &band.y_final[0][i]);
            }
        }
        for j in rows.clone() {
            let top = j + 1 == ny;
            let power = self.y_godunov_row::<NODAL>(j + 1, fields, c, &mut band.y_godunov[1]);
            if top {
                band.power += power;
            }
            if !top {
                let (x_row, x_fluctuation) = (&mut band.x_godunov[1], &mut band.x_fluctuation[1]);
                let power = self.x_godunov_row::<NODAL>(j + 1, fields, c, x_row, x_fluctuation);
                if j + 1 < rows.end {
                    band.power += power;
                }
            }
            let here = Some(&band.x_fluctuation[0][..]);
            let above = (!top).then_some(&band.x_fluctuation[1][..]);
            let godunov = &band.y_godunov[1];
            let finals = &mut band.y_final[1];
            self.y_final_row::<NODAL>(j + 1, godunov, [here, above], fields, k, finals);
            if top {
                for i in 0..nx {
                    band.force += self.boundary_face_force(1, [i, ny], &band.y_final[1][i]);
                }
            }
            // the x-faces' final fluxes, rolling along the row, and the cell updates
            let row = j * nx;
            let (y_low, y_high) = (&band.y_godunov[0], &band.y_godunov[1]);
            if NODAL && ctu {
                for (i, w) in band.w_y.iter_mut().enumerate() {
                    let (low, high) = (
                        fields.at::<true>(row + i, 1, false),
                        fields.at::<true>(row + i, 1, true),
                    );
                    let w_flux = y_high[i].add_scaled(&y_low[i], -1.0);
                    *w = w_flux.add_scaled(&difference_flux::<1>(&low, &high, c), 1.0);
                }
            }
            let ghosts = self.x_edge_ghosts(j, fields, ctu, &mut band.edge_carry);
            // (sliced to the row and held by `move` closures, the slices' lengths known to
            // the optimizer: no index checks per cell, as in `band_row`)
            let (y_low, y_high) = (&band.y_godunov[0][..nx], &band.y_godunov[1][..nx]);
            let w_row = &band.w_y[..if NODAL && ctu { nx } else { 0 }];
            let x_godunov = &band.x_godunov[0][..nx + 1];
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
            let local = (j - j0) * nx;
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
                update(row + i, local + i, faces);
                low = high;
            }
            band.force += force;
            band.x_godunov.swap(0, 1);
            band.x_fluctuation.swap(0, 1);
            band.y_godunov.swap(0, 1);
            band.y_final.swap(0, 1);
        }
    }

    /// Godunov fluxes of the x-faces of cell row `j` into `out` (`nx + 1`); under CTU
    /// (`w` not empty, [`super::Band`]'s `x_fluctuation`) also each cell's x-fluctuation
    /// into `w` (`nx`), `w_x = F_x,high - F_x,low` (`NODAL`: `+ F_x(q_C,low - q_C,high)`):
    /// the side terms in the flux loop, the flux differences in a pass of their own (inside
    /// the flux loop they took more instructions, callgrind). Returns the power of its two
    /// boundary faces.
    fn x_godunov_row<const NODAL: bool>(
        &self,
        j: usize,
        fields: Fields<'_, 2>,
        c: &AxisConstants,
        out: &mut [Conserved<2>],
        w: &mut [Conserved<2>],
    ) -> f64 {
        let nx = self.grid.cells[0];
        let row = j * nx;
        let with_fluctuations = !w.is_empty();
        if NODAL {
            // each cell's two x-side states, formed once: its high side is the next face's left
            let (out, w) = (
                &mut out[..nx + 1],
                &mut w[..if with_fluctuations { nx } else { 0 }],
            );
            let mut previous_high = None;
            for_row_sides!(fields, row, nx, 0, |i, low, high| {
                if let Some(left) = &previous_high {
                    out[i] = axis_flux_2d::<0>(left, &low, c);
                }
                if with_fluctuations {
                    w[i] = difference_flux::<0>(&low, &high, c);
                }
                previous_high = Some(high);
            });
        } else {
            for i in 1..nx {
                out[i] = axis_flux_2d::<0>(&fields.cell(row + i - 1), &fields.cell(row + i), c);
            }
        }
        let mut power = 0.0;
        for i in [0, nx] {
            let (flux, p) = self.linear_face_flux(0, [i, j], fields);
            out[i] = flux;
            power += p;
        }
        if with_fluctuations {
            for (w, faces) in w.iter_mut().zip(out.windows(2)) {
                let difference = faces[1].add_scaled(&faces[0], -1.0);
                *w = match NODAL {
                    true => difference.add_scaled(w, 1.0),
                    false => difference,
                };
            }
        }
        power
    }

    /// Godunov fluxes of face row `j` (the y-faces between cell rows `j - 1` and `j`) into
    /// `out` (`nx`); returns the power of the row if it is a boundary.
    fn y_godunov_row<const NODAL: bool>(
        &self,
        j: usize,
        fields: Fields<'_, 2>,
        c: &AxisConstants,
        out: &mut [Conserved<2>],
    ) -> f64 {
        let [nx, ny] = self.grid.cells;
        if j == 0 || j == ny {
            let mut power = 0.0;
            for (i, out) in out.iter_mut().enumerate() {
                let (flux, p) = self.linear_face_flux(1, [i, j], fields);
                *out = flux;
                power += p;
            }
            return power;
        }
        let (below, above) = ((j - 1) * nx, j * nx);
        if NODAL {
            if let (Some(lower), Some(upper)) =
                (fields.side_row(below, nx), fields.side_row(above, nx))
            {
                // side fields: both rows' slices, no index check per cell
                let rows = lower
                    .as_chunks::<4>()
                    .0
                    .iter()
                    .zip(upper.as_chunks::<4>().0);
                for (out, (lower, upper)) in out.iter_mut().zip(rows) {
                    *out = axis_flux_2d::<1>(&lower[3].full(1), &upper[2].full(1), c);
                }
                return 0.0;
            }
        }
        for (i, out) in out.iter_mut().enumerate() {
            let lower = fields.at::<NODAL>(below + i, 1, true);
            let upper = fields.at::<NODAL>(above + i, 1, false);
            *out = axis_flux_2d::<1>(&lower, &upper, c);
        }
        0.0
    }

    /// Final fluxes of face row `j` into `out`: its Godunov fluxes plus, under CTU, the
    /// corrections from the x-fluctuations of the cell rows below and above it (formed
    /// once per row by [`Self::x_godunov_row`], [`XRow`]; `None` behind an edge: ghost cells,
    /// whose row of fluctuations is formed once for the face row,
    /// [`Self::ghost_row_fluctuations`], the values `face_correction` forms per face).
    fn y_final_row<const NODAL: bool>(
        &self,
        j: usize,
        godunov: &[Conserved<2>],
        [below, above]: [Option<XRow<'_>>; 2],
        fields: Fields<'_, 2>,
        k: &Sweep2d,
        out: &mut [Conserved<2>],
    ) {
        if !k.ctu {
            out.copy_from_slice(godunov);
            return;
        }
        let (c, scale) = (&k.constants, k.scale[1]);
        let w = |fluctuations: XRow<'_>, i: usize| fluctuations[i];
        match (below, above) {
            (Some(below), Some(above)) => {
                for (i, out) in out.iter_mut().enumerate() {
                    let total = axis_transverse_2d::<1>(&w(below, i), &w(above, i), c);
                    let correction = Conserved::zeros().add_scaled(&total, -scale);
                    *out = godunov[i].add_scaled(&correction, 1.0);
                }
            }
            (below, above) => {
                // an edge row: the ghost row's fluctuations formed once for the row, in
                // `out` until each face's final flux replaces its entry
                let ghost = match (below, above) {
                    (None, Some(_)) => Some(0),
                    (Some(_), None) => Some(1),
                    _ => None,
                };
                let ghost = ghost.filter(|_| self.wave_flux[0].is_empty());
                if let Some(side) = ghost {
                    let row = [0, j.min(self.grid.cells[1] - 1)];
                    self.ghost_row_fluctuations(1, side, 0, row, fields, out);
                }
                for (i, out) in out.iter_mut().enumerate() {
                    let formed = ghost.map(|_| *out);
                    let sides = [
                        below.map(|r| w(r, i)).or(formed),
                        above.map(|r| w(r, i)).or(formed),
                    ];
                    let correction = match sides {
                        [Some(low), Some(high)] => {
                            self.edge_correction::<1>([i, j], [low, high], k)
                        }
                        sides => self.face_correction(1, [i, j], sides, fields, scale),
                    };
                    *out = godunov[i].add_scaled(&correction, 1.0);
                }
            }
        }
    }
}

/// `F_{e_L}(q_low - q_high)` of a cell's two `L`-side states (the flux is linear): the
/// part of the cell's fluctuation `w_L` its face fluxes miss on the nodal sweep
/// (`DgmpmSolver::transverse_corrections`).
#[inline(always)]
fn difference_flux<const L: usize>(
    low: &FullState<2>,
    high: &FullState<2>,
    c: &AxisConstants,
) -> Conserved<2> {
    let difference = FullState {
        tensor: low.tensor - high.tensor,
        velocity: low.velocity - high.velocity,
    };
    axis_normal_flux_2d::<L>(&difference, c)
}

//! The fused path in 2D (module doc of [`super`]): the sweep of one band of rows with its
//! rolling face rows, and the rows of Godunov and final fluxes.
use super::BAND_ROWS;
use crate::faces::Fields;
use crate::riemann::axis::{axis_flux_2d, axis_transverse_2d, AxisConstants};
use crate::riemann::Conserved;
use crate::DgmpmSolver;
use impact_core::method::TransverseFlux;
use impact_core::points::MaterialPoints;
use impact_core::Vector;

impl DgmpmSolver<2> {
    /// The 2D sweep (module doc of [`super`]), band by band. A band of rows `j0..j1`
    /// first forms face row `j0` (its Godunov fluxes, [`Self::y_godunov_row`], and under
    /// CTU the x-fluxes of row `j0 - 1` for its final fluxes, [`Self::y_final_row`]) and
    /// the x-fluxes of row `j0` ([`Self::x_godunov_row`]); then for each row `j`:
    /// 1. the Godunov fluxes of face row `j + 1` and of the x-faces of row `j + 1`;
    /// 2. the final fluxes of face row `j + 1` (corrections from the x-fluctuations of
    ///    rows `j` and `j + 1`);
    /// 3. along the row, the final x-fluxes (corrections from the y-fluctuations of the
    ///    cells on either side) and the cell updates;
    /// 4. the rolling rows shift by one.
    ///
    /// Boundary faces add their power and force to the band's.
    pub(super) fn sweep_2d(&mut self, points: &mut MaterialPoints<2>, dt: f64) -> (f64, Vector<2>) {
        let [nx, ny] = self.grid.cells;
        let constants = AxisConstants::new(&self.elastic);
        let ctu = self.options.flux == TransverseFlux::Ctu;
        let u = self.update_constants(dt);
        // x-faces are corrected by the y-fluctuations (Δt/2Δy), y-faces by the x ones
        let scale = [
            dt / (2.0 * self.grid.spacing[1]),
            dt / (2.0 * self.grid.spacing[0]),
        ];
        self.sweep_bands(
            points,
            BAND_ROWS * nx,
            |this, b, band, fields, mass, next| {
                let rows = b * BAND_ROWS..((b + 1) * BAND_ROWS).min(ny);
                let c = &constants;
                band.power = 0.0;
                band.force = Vector::<2>::zeros();
                let j0 = rows.start;
                // prologue: face row j0 (Godunov and final) and the x-fluxes of cell row j0
                let power = this.x_godunov_row(j0, fields, c, &mut band.x_godunov[0]);
                band.power += power;
                let power = this.y_godunov_row(j0, fields, c, &mut band.y_godunov[0]);
                if j0 == 0 {
                    band.power += power;
                }
                if ctu && j0 > 0 {
                    // the row below the band: its x-fluxes, recomputed here
                    this.x_godunov_row(j0 - 1, fields, c, &mut band.x_godunov[1]);
                }
                let [x_row, x_below] = &band.x_godunov;
                let below = (j0 > 0).then_some(&x_below[..]);
                let finals = &mut band.y_final[0];
                this.y_final_row(
                    j0,
                    &band.y_godunov[0],
                    below,
                    Some(x_row),
                    fields,
                    ctu,
                    c,
                    scale[1],
                    finals,
                );
                if j0 == 0 {
                    for i in 0..nx {
                        band.force += this.boundary_face_force(1, [i, 0], &band.y_final[0][i]);
                    }
                }
                for j in rows.clone() {
                    let top = j + 1 == ny;
                    let power = this.y_godunov_row(j + 1, fields, c, &mut band.y_godunov[1]);
                    if top {
                        band.power += power;
                    }
                    if !top {
                        let power = this.x_godunov_row(j + 1, fields, c, &mut band.x_godunov[1]);
                        if j + 1 < rows.end {
                            band.power += power;
                        }
                    }
                    let [x_row, x_above] = &band.x_godunov;
                    let above = (!top).then_some(&x_above[..]);
                    let finals = &mut band.y_final[1];
                    this.y_final_row(
                        j + 1,
                        &band.y_godunov[1],
                        Some(x_row),
                        above,
                        fields,
                        ctu,
                        c,
                        scale[1],
                        finals,
                    );
                    if top {
                        for i in 0..nx {
                            band.force += this.boundary_face_force(1, [i, ny], &band.y_final[1][i]);
                        }
                    }
                    // the x-faces' final fluxes, rolling along the row, and the cell updates
                    let row = j * nx;
                    let (y_low, y_high) = (&band.y_godunov[0], &band.y_godunov[1]);
                    let w_y = |i: usize| y_high[i].add_scaled(&y_low[i], -1.0);
                    let x_final = |i: usize, band_force: &mut Vector<2>| -> Conserved<2> {
                        let godunov = band.x_godunov[0][i];
                        if !ctu {
                            if i == 0 || i == nx {
                                *band_force += this.boundary_face_force(0, [i, j], &godunov);
                            }
                            return godunov;
                        }
                        if i == 0 || i == nx {
                            let w = [(i > 0).then(|| w_y(i - 1)), (i < nx).then(|| w_y(i))];
                            let correction = this.face_correction(0, [i, j], w, fields, scale[0]);
                            let flux = godunov.add_scaled(&correction, 1.0);
                            *band_force += this.boundary_face_force(0, [i, j], &flux);
                            return flux;
                        }
                        let total = axis_transverse_2d::<0>(&w_y(i - 1), &w_y(i), c);
                        godunov.add_scaled(&Conserved::zeros().add_scaled(&total, -scale[0]), 1.0)
                    };
                    let mut force = Vector::<2>::zeros();
                    let mut low = x_final(0, &mut force);
                    let local = (j - j0) * nx;
                    for i in 0..nx {
                        let high = x_final(i + 1, &mut force);
                        let state = fields.cell(row + i);
                        let faces = [[&low, &high], [&band.y_final[0][i], &band.y_final[1][i]]];
                        let old = (&state.tensor, &state.velocity, mass[row + i]);
                        let k = local + i;
                        let out = (
                            &mut next.tensor[k],
                            &mut next.velocity[k],
                            &mut next.position[k],
                        );
                        Self::update_cell(&u, faces, old, out);
                        low = high;
                    }
                    band.force += force;
                    band.x_godunov.swap(0, 1);
                    band.y_godunov.swap(0, 1);
                    band.y_final.swap(0, 1);
                }
            },
        )
    }

    /// Godunov fluxes of the x-faces of cell row `j` into `out` (`nx + 1`); returns the
    /// power of its two boundary faces.
    fn x_godunov_row(
        &self,
        j: usize,
        fields: Fields<'_, 2>,
        c: &AxisConstants,
        out: &mut [Conserved<2>],
    ) -> f64 {
        let nx = self.grid.cells[0];
        let row = j * nx;
        for i in 1..nx {
            out[i] = axis_flux_2d::<0>(&fields.cell(row + i - 1), &fields.cell(row + i), c);
        }
        let mut power = 0.0;
        for i in [0, nx] {
            let (flux, p) = self.linear_face_flux(0, [i, j], fields);
            out[i] = flux;
            power += p;
        }
        power
    }

    /// Godunov fluxes of face row `j` (the y-faces between cell rows `j - 1` and `j`) into
    /// `out` (`nx`); returns the power of the row if it is a boundary.
    fn y_godunov_row(
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
        for (i, out) in out.iter_mut().enumerate() {
            *out = axis_flux_2d::<1>(&fields.cell(below + i), &fields.cell(above + i), c);
        }
        0.0
    }

    /// Final fluxes of face row `j` into `out`: its Godunov fluxes plus, under CTU, the
    /// corrections from the x-fluctuations of the cell rows below and above it (their
    /// x-fluxes `below` and `above`; `None` behind an edge: ghost cells).
    #[allow(clippy::too_many_arguments)]
    fn y_final_row(
        &self,
        j: usize,
        godunov: &[Conserved<2>],
        below: Option<&[Conserved<2>]>,
        above: Option<&[Conserved<2>]>,
        fields: Fields<'_, 2>,
        ctu: bool,
        c: &AxisConstants,
        scale: f64,
        out: &mut [Conserved<2>],
    ) {
        if !ctu {
            out.copy_from_slice(godunov);
            return;
        }
        let w = |row: &[Conserved<2>], i: usize| row[i + 1].add_scaled(&row[i], -1.0);
        match (below, above) {
            (Some(below), Some(above)) => {
                for (i, out) in out.iter_mut().enumerate() {
                    let total = axis_transverse_2d::<1>(&w(below, i), &w(above, i), c);
                    let correction = Conserved::zeros().add_scaled(&total, -scale);
                    *out = godunov[i].add_scaled(&correction, 1.0);
                }
            }
            _ => {
                for (i, out) in out.iter_mut().enumerate() {
                    let sides = [below.map(|r| w(r, i)), above.map(|r| w(r, i))];
                    let correction = self.face_correction(1, [i, j], sides, fields, scale);
                    *out = godunov[i].add_scaled(&correction, 1.0);
                }
            }
        }
    }
}

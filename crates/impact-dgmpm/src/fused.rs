//! The fused cell path ([`StepPath::Fused`]): one point per cell, forward Euler, linear
//! elasticity, 1D or 2D. The phases of the cell path ([`crate::cell_path`]) in one sweep:
//!
//! 1. phase 2, the Godunov flux `F_{e_l}(q*)` of each face (paper §4, eqs. 18-21);
//! 2. phase 2b (2D, CTU), the transverse corrections
//!    `F_k -= Δt/(2Δx_l) (B⁺ w_below + B⁻ w_above)` (LeVeque 2002, §21.2), `w` the flux
//!    difference `F_l,high - F_l,low` of the cells on either side;
//! 3. the boundary force and power of the loaded faces;
//! 4. the cell update `q ← q - Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l` and the point's
//!    move `x ← x + Δt v`.
//!
//! The 2D sweep walks the cell rows `j` upwards and keeps only rolling rows of faces: the
//! Godunov x-fluxes of cell rows `j` and `j+1`, the Godunov and the final y-fluxes of face
//! rows `j` and `j+1` (the low and high faces of row `j`). Each face is solved once, the
//! face arrays of the phase-by-phase path (144 B per cell) are not allocated, and the step
//! reads each point's state once and writes it once (the cell path moves 776-920 B per
//! cell and step, this one about 130). Interior faces call the axis solvers
//! ([`crate::riemann::axis`]); boundary faces and the corrections that need ghost cells
//! call the same functions as the phase path (`DgmpmSolver::linear_face_flux`,
//! `DgmpmSolver::face_correction`). The new states go to a second buffer, swapped with
//! the points' at the end, so every face reads the old states (48 B per cell).
//!
//! Parallel: bands of `BAND_ROWS` (32) cell rows (1D: chunks of cells), each band with its
//! own rolling rows; a band recomputes the Godunov fluxes of the row below it (one row in
//! `BAND_ROWS` computed twice). The bands are fixed by the grid, so results do not depend
//! on the thread count. Tested equal to the phase-by-phase cell path to 1e-13.
use crate::faces::Fields;
use crate::riemann::axis::{axis_flux_1d, axis_flux_2d, axis_transverse_2d, AxisConstants};
use crate::riemann::{Conserved, FullState};
use crate::{DgmpmSolver, StepPath, CHUNK};
use impact_core::method::TransverseFlux;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};
use std::any::Any;

/// Cell rows per band of the 2D sweep (the unit of parallel work).
pub(crate) const BAND_ROWS: usize = 32;

/// The rolling face rows of one band (2D) and the boundary power and force of its faces.
#[derive(Debug, Clone)]
pub(crate) struct Band<const D: usize> {
    /// Godunov fluxes of the x-faces of cell rows `j` and `j+1` (`nx + 1` each).
    x_godunov: [Vec<Conserved<D>>; 2],
    /// Godunov fluxes of the y-faces of face rows `j` and `j+1` (`nx` each).
    y_godunov: [Vec<Conserved<D>>; 2],
    /// Final (CTU-corrected) fluxes of face rows `j` and `j+1`.
    y_final: [Vec<Conserved<D>>; 2],
    /// Power of the boundary conditions on the band's faces.
    power: f64,
    /// Force on the body through the band's loaded boundary faces.
    force: Vector<D>,
}

impl<const D: usize> Default for Band<D> {
    fn default() -> Self {
        Self {
            x_godunov: Default::default(),
            y_godunov: Default::default(),
            y_final: Default::default(),
            power: 0.0,
            force: Vector::<D>::zeros(),
        }
    }
}

/// The buffers of the fused path: one [`Band`] per band and the points' next state.
#[derive(Debug, Clone, Default)]
pub(crate) struct FusedBuffers<const D: usize> {
    bands: Vec<Band<D>>,
    next_tensor: Vec<Tensor<D>>,
    next_velocity: Vec<Vector<D>>,
}

impl<const D: usize> FusedBuffers<D> {
    /// Whether the buffers are not allocated.
    pub(crate) fn is_empty(&self) -> bool {
        self.bands.is_empty()
    }

    /// Buffers for `grid`'s cells: in 2D bands of [`BAND_ROWS`] rows, each with its face
    /// rows; in 1D one (empty) band per chunk of [`CHUNK`] cells.
    pub(crate) fn new(cells: [usize; D]) -> Self {
        let count: usize = cells.iter().product();
        let bands = match D {
            2 => {
                let nx = cells[0];
                let band = Band {
                    x_godunov: [
                        vec![Conserved::zeros(); nx + 1],
                        vec![Conserved::zeros(); nx + 1],
                    ],
                    y_godunov: [vec![Conserved::zeros(); nx], vec![Conserved::zeros(); nx]],
                    y_final: [vec![Conserved::zeros(); nx], vec![Conserved::zeros(); nx]],
                    ..Band::default()
                };
                vec![band; cells[1].div_ceil(BAND_ROWS)]
            }
            _ => vec![Band::default(); count.div_ceil(CHUNK)],
        };
        Self {
            bands,
            next_tensor: vec![Tensor::<D>::zeros(); count],
            next_velocity: vec![Vector::<D>::zeros(); count],
        }
    }
}

/// The points' next state of one band or chunk, and their positions (moved in place).
struct Next<'a, const D: usize> {
    tensor: &'a mut [Tensor<D>],
    velocity: &'a mut [Vector<D>],
    position: &'a mut [Vector<D>],
}

impl<const D: usize> DgmpmSolver<D> {
    /// One step of the fused path: the module doc's phases 1-4 in one sweep. Returns the
    /// power and the force of the boundary conditions.
    pub(crate) fn fused_step(
        &mut self,
        points: &mut MaterialPoints<D>,
        dt: f64,
    ) -> (f64, Vector<D>) {
        debug_assert_eq!(self.path, StepPath::Fused);
        let solver: &mut dyn Any = self;
        let points: &mut dyn Any = points;
        let mut force = [0.0; 2];
        let power = if let Some(solver) = solver.downcast_mut::<DgmpmSolver<2>>() {
            let points = points.downcast_mut::<MaterialPoints<2>>();
            let (power, f) = solver.sweep_2d(points.expect("internal: same D"), dt);
            force = [f[0], f[1]];
            power
        } else if let Some(solver) = solver.downcast_mut::<DgmpmSolver<1>>() {
            let points = points.downcast_mut::<MaterialPoints<1>>();
            let (power, f) = solver.sweep_1d(points.expect("internal: same D"), dt);
            force[0] = f[0];
            power
        } else {
            unreachable!("internal: the fused path is refused beyond 2D")
        };
        (power, Vector::<D>::from_fn(|k, _| force[k]))
    }

    /// Run `sweep` on every band with the points' old state and the band's part of the
    /// next state, swap the next state in and add up the bands' power and force.
    fn sweep_bands(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        sweep: impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, &[f64], Next<'_, D>) + Sync,
    ) -> (f64, Vector<D>) {
        let mut buffers = std::mem::take(&mut self.fused);
        {
            let this = &*self;
            let MaterialPoints {
                stress,
                velocity,
                position,
                mass,
                ..
            } = &mut *points;
            let fields = Fields::per_cell(stress, velocity);
            let mass: &[f64] = mass;
            let parts = (
                chunks(&mut buffers.bands, 1),
                chunks(&mut buffers.next_tensor, cells_per_band),
                (
                    chunks(&mut buffers.next_velocity, cells_per_band),
                    chunks(position, cells_per_band),
                ),
            );
            for_each_chunk(this.parallel, 1, parts, |b, (band, tensor, (v, x))| {
                let next = Next {
                    tensor,
                    velocity: v,
                    position: x,
                };
                sweep(this, b, &mut band[0], fields, mass, next);
            });
        }
        std::mem::swap(&mut points.stress, &mut buffers.next_tensor);
        std::mem::swap(&mut points.velocity, &mut buffers.next_velocity);
        let power = buffers.bands.iter().map(|b| b.power).sum();
        let force = buffers.bands.iter().map(|b| b.force).sum();
        self.fused = buffers;
        (power, force)
    }

    /// Phase 4 for one cell: `q ← q - Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l` (momentum
    /// part: `v ← v - Δt (V/m) Σ_l …`) from its faces' final fluxes `[low, high]` per axis, and the
    /// move `x ← x + Δt v`; the same arithmetic as [`Self::cell_update`], with the
    /// step's constants `u` formed once.
    #[inline(always)]
    fn update_cell(
        u: &UpdateConstants<D>,
        faces: [[&Conserved<D>; 2]; D],
        (q, v, mass): (&Tensor<D>, &Vector<D>, f64),
        next: (&mut Tensor<D>, &mut Vector<D>, &mut Vector<D>),
    ) {
        let mut dq = Tensor::<D>::zeros();
        let mut dm = Vector::<D>::zeros();
        for (l, [low, high]) in faces.iter().enumerate() {
            dq -= (high.tensor - low.tensor) * u.inv_spacing[l];
            dm -= (high.momentum - low.momentum) * u.inv_spacing[l];
        }
        let inv_mass = 1.0 / mass;
        *next.0 = q + dq * (u.tensor_scale * inv_mass);
        *next.1 = v + dm * (u.velocity_scale * inv_mass);
        *next.2 += *next.1 * u.dt;
    }

    /// The constants of [`Self::update_cell`] for a step of `dt`.
    fn update_constants(&self, dt: f64) -> UpdateConstants<D> {
        let (density, volume) = (self.material.density, self.grid.cell_volume());
        UpdateConstants {
            inv_spacing: std::array::from_fn(|l| 1.0 / self.grid.spacing[l]),
            tensor_scale: dt * density * volume,
            velocity_scale: dt * volume,
            dt,
        }
    }
}

/// The constants of the cell update: `1/Δx_l`, `Δt ρ V`, `Δt V` and `Δt`.
struct UpdateConstants<const D: usize> {
    inv_spacing: [f64; D],
    tensor_scale: f64,
    velocity_scale: f64,
    dt: f64,
}

impl DgmpmSolver<1> {
    /// The 1D sweep: each chunk of cells solves its low face, then per cell its high face
    /// and the update.
    fn sweep_1d(&mut self, points: &mut MaterialPoints<1>, dt: f64) -> (f64, Vector<1>) {
        let constants = AxisConstants::new(&self.elastic);
        let count = self.grid.cells[0];
        let u = self.update_constants(dt);
        self.sweep_bands(points, CHUNK, |this, b, band, fields, mass, next| {
            let start = b * CHUNK;
            let len = next.tensor.len();
            band.power = 0.0;
            band.force = Vector::<1>::zeros();
            // the chunk's low face is counted by the chunk below it (or here at i = 0)
            let mut low = match start {
                0 => this.boundary_flux(0, [0], fields, band),
                _ => axis_flux_1d(&fields.cell(start - 1), &fields.cell(start), &constants),
            };
            // cells whose high face is interior: all but the bar's last
            let interior = if start + len == count { len - 1 } else { len };
            // slices of equal, known lengths: the loop indexes them without bounds checks
            let (tensor, velocity) = fields.slices();
            let (q, v) = (&tensor[start..start + len], &velocity[start..start + len]);
            let (q_right, v_right) = (
                &tensor[start + 1..start + 1 + interior],
                &velocity[start + 1..start + 1 + interior],
            );
            let mass = &mass[start..start + len];
            let Next {
                tensor: next_q,
                velocity: next_v,
                position,
            } = next;
            let (next_q, next_v, position) =
                (&mut next_q[..len], &mut next_v[..len], &mut position[..len]);
            let mut state = fields.cell(start);
            for j in 0..interior {
                let right = FullState {
                    tensor: q_right[j],
                    velocity: v_right[j],
                };
                let high = axis_flux_1d(&state, &right, &constants);
                let old = (&q[j], &v[j], mass[j]);
                let out = (&mut next_q[j], &mut next_v[j], &mut position[j]);
                Self::update_cell(&u, [[&low, &high]], old, out);
                (low, state) = (high, right);
            }
            if interior < len {
                // the bar's last cell: its high face is the boundary
                let j = interior;
                let high = this.boundary_flux(0, [count], fields, band);
                let out = (&mut next_q[j], &mut next_v[j], &mut position[j]);
                Self::update_cell(&u, [[&low, &high]], (&q[j], &v[j], mass[j]), out);
            }
        })
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// The Godunov flux of a boundary face ([`Self::linear_face_flux`]), its power and
    /// force added to `band`'s (kept out of the sweeps' inner loops).
    #[inline(never)]
    fn boundary_flux(
        &self,
        l: usize,
        idx: [usize; D],
        fields: Fields<'_, D>,
        band: &mut Band<D>,
    ) -> Conserved<D> {
        let (flux, power) = self.linear_face_flux(l, idx, fields);
        band.power += power;
        band.force += self.boundary_face_force(l, idx, &flux);
        flux
    }
}

impl DgmpmSolver<2> {
    /// The 2D sweep of one band of rows (module doc).
    fn sweep_2d(&mut self, points: &mut MaterialPoints<2>, dt: f64) -> (f64, Vector<2>) {
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

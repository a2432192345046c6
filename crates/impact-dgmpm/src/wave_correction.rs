//! Phase 2c (`order = 2`, 1D): the limited second-order wave corrections of the face fluxes
//! (LeVeque 2002, §6.8-6.15, and §15.4 for systems; Clawpack classic `step1` with
//! `order = 2`), added to the Godunov fluxes of phase 2 before the flux balance.
//!
//! Each face `i−½` has the Riemann problem of its two states (each side's face-node average,
//! paper §4: the corrections act on the cells' nodal face states, at any points per cell;
//! on the cell path, the points). The linear solver's star state `q*` splits the jump into
//! the left-going P wave `W¹ = q* − q_L` (speed `s¹ = −c_p`) and the right-going one
//! `W² = q_R − q*` (`s² = +c_p`), with `q = (σ, ρ v)`. They are used as f-waves
//! `Z^p = s^p W^p` (LeVeque 2002, §15.5): `Z¹ = F(q*) − F(q_L)`, `Z² = F(q_R) − F(q*)`, the
//! fluctuations, so the correction flux
//!
//! `F̃_{i−½} = ½ Σ_p |s^p| (1 − Δt|s^p|/Δx) φ(θ^p) W^p = ½ Σ_p sign(s^p) (1 − Δt|s^p|/Δx) φ(θ^p) Z^p`
//!
//! is Clawpack's to round-off (for one family `θ` is the same ratio of `W` or of `Z`;
//! [`crate::limiter`] gives `θ` and `φ`). It is added to the face's flux `F_{i−½}`, so the
//! cell update takes `−Δt (F̃_{i+½} − F̃_{i−½})/Δx` on top of the Godunov update: on the
//! cell path exactly Clawpack's `q_i −= Δt/Δx (A⁺ΔQ_{i−½} + A⁻ΔQ_{i+½}) + Δt/Δx (F̃_{i+½} −
//! F̃_{i−½})`; on the nodal paths the face flux reaches the face's nodes as before.
//!
//! **Ghost faces.** The limiter of a boundary face reads the wave of the face beyond it.
//! As Clawpack with two ghost cells, the ghost cells are mirror images through the edge's
//! condition ([`crate::riemann::ghost_full`], the rule of the boundary face): the first ghost
//! mirrors the first interior cell, the second mirrors the second (Clawpack's `wall`
//! pattern); so the face beyond the edge has as left state the mirror of the second cell's
//! face state towards the first, and as right state the mirror of the first cell's face
//! state towards the second (the mirror image of the first interior face). A one-cell grid
//! mirrors its one cell twice. A free end's corrections then carry no traction and a
//! velocity end's no velocity: the edge conditions hold exactly.
//!
//! **Δt.** Euler uses the step's `Δt`. Each stage of Heun's RK2 is a forward Euler step of
//! the full `Δt` (`q¹ = q⁰ + Δt L(q⁰)`, `q² = q¹ + Δt L(q¹)`, averaged), so each stage's
//! corrections use `(1 − Δt|s|/Δx)` with that `Δt`: each stage is then the Lax-Wendroff-type
//! step it replaces (with RK2 the time accuracy is then both the stage's and the
//! Runge-Kutta's; the corrections are not re-derived for the method of lines).
//!
//! Implemented for the linear-elastic solver (linear elasticity, and J2 with the elastic
//! solver and the return map after the step) in 1D; `Problem::check_config` refuses the
//! others. The buffers are allocated once (`face_count + 2` faces); the step allocates
//! nothing.
use crate::limiter::{limiter_phi, wave_ratio};
use crate::riemann::{ghost_full, linear_elastic_star, normal_flux, Conserved, FullState};
use crate::{unit, DgmpmSolver};
use impact_core::points::MaterialPoints;

/// Wave families of a 1D face: the left-going and the right-going P wave.
pub(crate) const WAVES: usize = 2;

/// The f-waves `Z^p` of one face and their speeds `s^p`, in family order (module doc).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceWaves<const D: usize> {
    pub wave: [Conserved<D>; WAVES],
    pub speed: [f64; WAVES],
}

impl<const D: usize> Default for FaceWaves<D> {
    fn default() -> Self {
        Self {
            wave: [Conserved::zeros(); WAVES],
            speed: [0.0; WAVES],
        }
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 2c: add the limited second-order corrections `F̃` (module doc) to the face
    /// fluxes of phase 2, for a stage of length `dt`; returns the change of the power the
    /// boundary conditions deliver (the loaded ends' flux changes). Nothing at order 1.
    pub fn wave_corrections(&mut self, points: &MaterialPoints<D>, dt: f64) -> f64 {
        let Some(limiter) = self.options.wave_limiter() else {
            return 0.0;
        };
        let mut waves = std::mem::take(&mut self.face_waves);
        self.face_waves_into(points, &mut waves);
        let mut fluxes = std::mem::take(&mut self.face_flux[0]);
        let dtdx = dt / self.grid.spacing[0];
        let mut power = 0.0;
        let last = fluxes.len() - 1;
        for (f, flux) in fluxes.iter_mut().enumerate() {
            // the face's waves at f + 1 in the padded array (a ghost face at each end)
            let here = &waves[f + 1];
            let mut correction = Conserved::<D>::zeros();
            for p in 0..WAVES {
                let s = here.speed[p];
                let upwind = if s > 0.0 { &waves[f] } else { &waves[f + 2] };
                let Some(theta) = wave_ratio(&upwind.wave[p], &here.wave[p]) else {
                    continue;
                };
                let weight =
                    0.5 * s.signum() * (1.0 - dtdx * s.abs()) * limiter_phi(limiter, theta);
                correction = correction.add_scaled(&here.wave[p], weight);
            }
            if f == 0 || f == last {
                power -= self.end_power(f, flux);
                *flux = flux.add_scaled(&correction, 1.0);
                power += self.end_power(f, flux);
            } else {
                *flux = flux.add_scaled(&correction, 1.0);
            }
        }
        self.face_flux[0] = fluxes;
        self.face_waves = waves;
        power
    }

    /// The power the condition of the end face `f` delivers with face flux `flux`,
    /// `sign (σ n)·v` per unit area times the area, from `F = −(E v, σ)` (0 on a free end,
    /// as `boundary_power`).
    fn end_power(&self, f: usize, flux: &Conserved<D>) -> f64 {
        let side = usize::from(f != 0);
        let mut idx = [0usize; D];
        idx[0] = f;
        let s = self.edge_coordinate(0, &idx);
        if self.ghost_condition(0, side, s) == crate::riemann::GhostCondition::free() {
            return 0.0;
        }
        let sign = if side == 0 { -1.0 } else { 1.0 };
        let area = self.grid.cell_volume() / self.grid.spacing[0];
        let traction = -flux.momentum[0];
        let velocity = -flux.tensor[(0, 0)] / (2.0 * self.elastic.mu);
        sign * area * traction * velocity
    }

    /// The f-waves of every face of the 1D grid and of the ghost face beyond each end
    /// (module doc), into `waves` (`face_count + 2`, the ghost faces first and last).
    fn face_waves_into(&self, points: &MaterialPoints<D>, waves: &mut [FaceWaves<D>]) {
        let fields = self.fields(points);
        let n = self.grid.cells[0];
        let e = unit::<D>(0);
        let side = |c: usize, high: bool| fields.side(c, 0, high);
        // the ends' conditions and the mirror through them
        let condition = |end: usize| {
            let mut idx = [0usize; D];
            idx[0] = end * n;
            self.ghost_condition(0, end, self.edge_coordinate(0, &idx))
        };
        let (low, high) = (condition(0), condition(1));
        let mirror_low = |q: FullState<D>| ghost_full(&q, &(-e), low);
        let mirror_high = |q: FullState<D>| ghost_full(&q, &e, high);
        let second = |c: usize| if n > 1 { c } else { 0 };
        for (j, slot) in waves.iter_mut().enumerate() {
            // padded face j is face f = j - 1, between cells f - 1 and f
            let (left, right) = match j {
                0 => (
                    mirror_low(side(second(1), false)),
                    mirror_low(side(0, true)),
                ),
                j if j == n + 2 => (
                    mirror_high(side(n - 1, false)),
                    mirror_high(side(n - 1 - second(1), true)),
                ),
                1 => (mirror_low(side(0, false)), side(0, false)),
                j if j == n + 1 => (side(n - 1, true), mirror_high(side(n - 1, true))),
                j => (side(j - 2, true), side(j - 1, false)),
            };
            *slot = self.linear_waves(&left, &right);
        }
    }

    /// The f-waves of the linear-elastic Riemann problem `(left, right)` normal to `e_0`:
    /// `Z¹ = F(q*) − F(q_L)` at `−c_p`, `Z² = F(q_R) − F(q*)` at `+c_p`.
    #[inline]
    fn linear_waves(&self, left: &FullState<D>, right: &FullState<D>) -> FaceWaves<D> {
        let e = unit::<D>(0);
        let (a, b) = (left.on_face(&e), right.on_face(&e));
        let star = linear_elastic_star(&a, &b, &e, self.elastic.z);
        let (fl, fs, fr) = (
            normal_flux(&a, &e, &self.elastic),
            normal_flux(&star, &e, &self.elastic),
            normal_flux(&b, &e, &self.elastic),
        );
        let c = self.elastic.z.p / self.elastic.density;
        FaceWaves {
            wave: [fs.add_scaled(&fl, -1.0), fr.add_scaled(&fs, -1.0)],
            speed: [-c, c],
        }
    }
}

//! Order 2 with the approximate Saint-Venant–Kirchhoff solver (1D, `riemann =
//! "approximate"`; [`crate::riemann::svk_approximate`]). The solver links each side to the
//! star state `q*` by one acoustic wave linearised about that side (Toro 2009, §9.3):
//! `t* − t_L = Z_L (v* − v_L)` at `s¹ = −c_L`, `t* − t_R = −Z_R (v* − v_R)` at
//! `s² = +c_R`, `c = Z/ρ₀`, `Z = sqrt(ρ₀ A(F, n))`. With `q = (F, ρ₀ v)` and the flux
//! `F_n(q) = −(v ⊗ n, Π n)` its f-waves are `Z¹ = F_n(q*) − F_n(q_L)` and
//! `Z² = F_n(q_R) − F_n(q*)` (LeVeque 2002, §15.5: they sum to the flux jump, and the
//! Godunov flux `F_n(q*)` is `F_n(q_L) + Z¹`), limited and weighted as the linear ones
//! (`F̃ = ½ Σ sign(s) (1 − Δt|s|/Δx) φ(θ) Z`, the parent module).
//!
//! **Ends.** The boundary face's star state is the flux's own half problem (the
//! interior's wave relation with the end's condition, `acoustic_boundary`); its wave into
//! the body is `F_n(q_0) − F_n(q*)` (left end), and the wave into the ghost cell its mirror
//! image `M Z`: through a traction condition the velocity part of a wave flips
//! (`(Z_F, Z_p) ↦ (−Z_F, Z_p)`), through a velocity condition the traction part
//! (`↦ (Z_F, −Z_p)`), at the same speed. The face beyond the end is the mirror of the first
//! interior face (its left- and right-going waves swapped through `M`). For linear
//! elasticity these are the waves the mirror ghost cells give (the parent module), so a
//! free end's correction carries no traction and a velocity end's no velocity: the end's
//! condition holds at order 2 as at order 1.
use super::{FaceWaves, LAST};
use crate::faces::Fields;
use crate::riemann::{Conserved, FaceState, FullState, GhostCondition};
use crate::{unit, DgmpmSolver};
use impact_core::material::Svk;

impl<const D: usize> DgmpmSolver<D> {
    /// The f-waves of padded face `j` of the 1D row (the parent module's numbering: the
    /// ghost faces `0` and `n + 2`, the end faces `1` and `n + 1`) under the approximate
    /// SVK solver (module doc).
    pub(crate) fn svk_padded_waves(
        &self,
        svk: &Svk,
        j: usize,
        fields: Fields<'_, D>,
    ) -> FaceWaves<D> {
        let n = self.grid.cells[0];
        let e = unit::<D>(0);
        let state = |c: usize, high: bool| fields.side(c, 0, high);
        let mirror_of = |end: usize| -> fn(&Conserved<D>) -> Conserved<D> {
            let idx = [end * n; D];
            match self.ghost_condition(0, end, self.edge_coordinate(0, &idx)) {
                GhostCondition::Traction(_) => |w| Conserved {
                    tensor: -w.tensor,
                    momentum: w.momentum,
                },
                _ => |w| Conserved {
                    tensor: w.tensor,
                    momentum: -w.momentum,
                },
            }
        };
        match j {
            j if j == 0 || j == n + 2 => {
                // the mirror of the first interior face (of the end face on a one-cell grid)
                let (end, inner) = if j == 0 { (0, 2) } else { (1, n) };
                let m = mirror_of(end);
                let w = self.svk_padded_waves(svk, inner, fields);
                let mut out = FaceWaves::default();
                (out.wave[0], out.speed[0]) = (m(&w.wave[LAST]), -w.speed[LAST]);
                (out.wave[LAST], out.speed[LAST]) = (m(&w.wave[0]), -w.speed[0]);
                out
            }
            1 => {
                let inner = state(0, false);
                let star = self.svk_end_star(0, None, Some(inner));
                let (c, flux) = self.svk_side(svk, &inner);
                let wave = flux.add_scaled(&svk_flux(&star, &e), -1.0);
                let mut out = FaceWaves::default();
                (out.wave[LAST], out.speed[LAST]) = (wave, c);
                (out.wave[0], out.speed[0]) = (mirror_of(0)(&wave), -c);
                out
            }
            _ if j == n + 1 => {
                let inner = state(n - 1, true);
                let star = self.svk_end_star(n, Some(inner), None);
                let (c, flux) = self.svk_side(svk, &inner);
                let wave = svk_flux(&star, &e).add_scaled(&flux, -1.0);
                let mut out = FaceWaves::default();
                (out.wave[0], out.speed[0]) = (wave, -c);
                (out.wave[LAST], out.speed[LAST]) = (mirror_of(1)(&wave), c);
                out
            }
            _ => {
                let (left, right) = (state(j - 2, true), state(j - 1, false));
                let star = self.svk_end_star(j - 1, Some(left), Some(right));
                let ((cl, fl), (cr, fr)) = (self.svk_side(svk, &left), self.svk_side(svk, &right));
                let fs = svk_flux(&star, &e);
                let mut out = FaceWaves::default();
                (out.wave[0], out.speed[0]) = (fs.add_scaled(&fl, -1.0), -cl);
                (out.wave[LAST], out.speed[LAST]) = (fr.add_scaled(&fs, -1.0), cr);
                out
            }
        }
    }

    /// The star state of 1D face `f` between `left` and `right` (`None` beyond an end):
    /// the Godunov flux's own (`svk_star`).
    fn svk_end_star(
        &self,
        f: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
    ) -> FaceState<D> {
        let crate::Physics::Svk { svk, riemann } = self.physics else {
            unreachable!("internal: the SVK waves without SVK")
        };
        let s = self.edge_coordinate(0, &[f; D]);
        self.svk_star(&svk, riemann, 0, left, right, s)
    }

    /// A side's acoustic wave speed `c = Z/ρ₀`, `Z = sqrt(ρ₀ A(F, e_x))`, and its flux.
    fn svk_side(&self, svk: &Svk, side: &FullState<D>) -> (f64, Conserved<D>) {
        let e = unit::<D>(0);
        let z = crate::riemann::svk::impedance(svk, &side.tensor, &e);
        let face = FaceState {
            traction: svk.piola(&side.tensor) * e,
            velocity: side.velocity,
        };
        (z[(0, 0)] / svk.linear.density, svk_flux(&face, &e))
    }
}

/// `F_n(q) = −(v ⊗ n, Π n)` of a face state (traction `Π n`, velocity `v`).
#[inline]
fn svk_flux<const D: usize>(q: &FaceState<D>, n: &impact_core::Vector<D>) -> Conserved<D> {
    Conserved {
        tensor: -(q.velocity * n.transpose()),
        momentum: -q.traction,
    }
}

//! Order 2 with the elastoplastic face solver (`riemann = "elastoplastic"`, J2; the rod in
//! 1D, plane strain in 2D; [`crate::riemann::elastoplastic`]). The face problem's normal
//! part follows each side's wave curve: elastic (impedance `Z_0 = ρ c_0`) up to the bound
//! `b` of the side's elastic range `[lower, upper]` that the star stress `σ*` lies beyond,
//! then plastic (`Z_t = ρ c_t`); its tangential part is the linear solver's (shear waves at
//! `c_s`, 2D). With the states between the waves
//!
//! - `q_L`, then `e_L = (b_L, v_L + (b_L − σ_L)/Z_0)` in the normal components (tangential
//!   ones of `q_L`) where the left elastic wave ends (`e_L = m_L` when `σ*` lies in the
//!   left range: no plastic wave),
//! - `m_L = (σ*, v*)` normal, tangential of `q_L`; `q*` = `(σ*, v*)` normal, the linear
//!   star's tangential; `m_R`, `e_R` the mirror on the right, then `q_R`,
//!
//! the six f-waves `Z = F(next) − F(previous)` (LeVeque 2002, §15.5) in the order
//! `q_L → e_L → m_L → q* → m_R → e_R → q_R` are the families of
//! [`WAVES`](super::WAVES): elastic at `−c_0`, plastic at `−c_t`, shear at `−c_s`, then
//! `+c_s`, `+c_t`, `+c_0`. They sum to `F(q_R) − F(q_L)`, and the left-going ones to
//! `F(q*) − F(q_L)`: the Godunov flux of the order-1 solver is `F(q_L) + Z¹ + Z² + Z³`.
//! Each is limited against the upwind face's wave of its own family (parent module).
//!
//! The rod (1D): `c_0 = sqrt(E/ρ)`, `c_t = sqrt(E_t/ρ)`, range `[−Y, Y]`, no shear waves
//! (`m_L = q* = m_R`, the two middle waves vanish). Plane strain (2D): `c_0 = c_p`,
//! `c_t = sqrt(M_p/ρ)` and the range of `σ_nn` along the uniaxial-strain path from the
//! side's 3D state ([`uniaxial_strain_bounds`]): exact for a plane wave, where the scheme
//! reduces to the rod's with `E = λ + 2μ`, `σ_y = σ_HEL`, `E_t = M_p`.
//!
//! **Ghost sides.** A side mirrored through a traction condition takes the mirrored range
//! (`σ ↦ k − σ` turns it over), through a velocity condition the same range, so the
//! ghost face's star state is the boundary half problem of the order-1 flux; through a
//! partly covered face (whose Godunov flux is the linear solver's) the linear waves.
use super::FaceWaves;
use crate::riemann::elastoplastic::{elastoplastic_star_1d, uniaxial_strain_bounds, PlasticSide};
use crate::riemann::{linear_elastic_star, normal_flux, FaceState, FullState};
use crate::{unit, DgmpmSolver};
use impact_core::plasticity::{PlasticState, J2};
use impact_core::points::MaterialPoints;

/// The elastic range `[lower, upper]` of the normal stress `σ_ll` of cell `c`'s face state
/// `state` (module doc): the rod's `[−Y, Y]`, `Y = σ_y + H ε̄`; in plane strain the
/// uniaxial-strain bounds of the 3D state (`σ_zz` from the point's `ε^p_zz`), as the
/// order-1 flux (`fluxes.rs`) takes them.
pub(super) fn elastic_range<const D: usize>(
    j2: &J2,
    l: usize,
    c: usize,
    state: &FullState<D>,
    points: &MaterialPoints<D>,
) -> (f64, f64) {
    let y = j2.current_yield(&PlasticState {
        equivalent_plastic_strain: points.equivalent_plastic_strain[c],
    });
    if D == 1 {
        return (-y, y);
    }
    let full = j2.stress3(&state.tensor, points.plastic_strain_zz[c]);
    let n = nalgebra::Vector3::from_fn(|k, _| if k == l { 1.0 } else { 0.0 });
    let lame = (j2.elastic.lame.lambda, j2.elastic.lame.mu);
    uniaxial_strain_bounds(&full, &n, y, lame)
}

impl<const D: usize> DgmpmSolver<D> {
    /// The six f-waves of the elastoplastic face problem normal to `e_l` between `left` and
    /// `right`, each with its elastic range `[lower, upper]` of `σ_ll` (module doc).
    pub(super) fn elastoplastic_waves(
        &self,
        l: usize,
        (left, (ll, lu)): (&FullState<D>, (f64, f64)),
        (right, (rl, ru)): (&FullState<D>, (f64, f64)),
    ) -> FaceWaves<D> {
        let (_, z) = self.rod_solver.expect("internal: the elastoplastic solver");
        let e = unit::<D>(l);
        let (a, b) = (left.on_face(&e), right.on_face(&e));
        let (sl, vl) = (a.traction[l], a.velocity[l]);
        let (sr, vr) = (b.traction[l], b.velocity[l]);
        let sides = (
            PlasticSide {
                stress: sl,
                velocity: vl,
                lower: ll,
                upper: lu,
            },
            PlasticSide {
                stress: sr,
                velocity: vr,
                lower: rl,
                upper: ru,
            },
        );
        let (ss, vs) = elastoplastic_star_1d(&sides.0, &sides.1, z);
        // `outer` with the normal traction and velocity `(sigma, v)`
        let with_normal = |outer: &FaceState<D>, sigma: f64, v: f64| {
            let mut q = *outer;
            q.traction[l] = sigma;
            q.velocity[l] = v;
            q
        };
        let flux = |q: &FaceState<D>| normal_flux(q, &e, &self.elastic);
        // the state where a side's elastic wave ends (`direction` +1 left, −1 right)
        let bound = |outer: &FaceState<D>, (sigma, v, lower, upper), direction: f64| {
            let b = if ss > upper {
                upper
            } else if ss < lower {
                lower
            } else {
                return None;
            };
            Some(with_normal(
                outer,
                b,
                v + direction * (b - sigma) / z.elastic,
            ))
        };
        let (m_l, m_r) = (with_normal(&a, ss, vs), with_normal(&b, ss, vs));
        // the tangential part: the linear solver's star (none on the rod)
        let star = if D == 1 {
            m_l
        } else {
            with_normal(&linear_elastic_star(&a, &b, &e, self.elastic.z), ss, vs)
        };
        let (fl, fml, fs, fmr, fr) = (flux(&a), flux(&m_l), flux(&star), flux(&m_r), flux(&b));
        let left_mid = bound(&a, (sl, vl, ll, lu), 1.0).map_or(fml, |q| flux(&q));
        let right_mid = bound(&b, (sr, vr, rl, ru), -1.0).map_or(fmr, |q| flux(&q));
        let rho = self.elastic.density;
        let (c0, ct, cs) = (z.elastic / rho, z.plastic / rho, self.elastic.z.s / rho);
        FaceWaves {
            wave: [
                left_mid.add_scaled(&fl, -1.0),
                fml.add_scaled(&left_mid, -1.0),
                fs.add_scaled(&fml, -1.0),
                fmr.add_scaled(&fs, -1.0),
                right_mid.add_scaled(&fmr, -1.0),
                fr.add_scaled(&right_mid, -1.0),
            ],
            speed: [-c0, -ct, -cs, cs, ct, c0],
        }
    }
}

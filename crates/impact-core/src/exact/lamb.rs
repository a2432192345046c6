//! Lamb's problem (issue 24): a vertical point force `F g(t)` on the free surface of an
//! elastic half-space with Poisson's ratio `ν = 1/4` (`λ = μ`), surface displacements at
//! distance `r` from the load.
//!
//! **Convention.** `F > 0` pushes *into* the body (for a block whose free surface is its
//! high-`z` face, a positive pressure on the face: force along `−z`). [`Lamb::vertical`] is
//! the surface displacement *along the load* (into the body, `−u_z` on the high-`z` face);
//! [`Lamb::radial`] is the horizontal displacement *away from the load* (along
//! `(x − x_F)/r`). Statically (Boussinesq) a push moves the surface in and towards the load:
//! `w = F(1−ν)/(2πμr) = 3F/(8πμr)`, `u_r = −F(1−2ν)/(4πμr) = −F/(8πμr)`.
//!
//! **Step responses** (`g = H(t)`), with `τ = c_s t/r`, `c_p = √3 c_s`, Rayleigh speed
//! `c_R = c_s √(2 − 2/√3)`, `γ = c_s/c_R = √(3+√3)/2`, arrivals `τ_P = 1/√3`, `τ_S = 1`,
//! `τ_R = γ`; both vanish for `τ < τ_P`. Vertical, Pekeris (1955, "The seismic surface
//! pulse", PNAS 41, 469–480, the closed form for `ν = 1/4`, restated by Mooney 1974, BSSA
//! 64, 473–491, the kernel of SW4's `lamb_exact.m`, and by Kausel 2013, "Lamb's problem at
//! its simplest", Proc. R. Soc. A 469, 20120462, as partial fractions over the roots of the
//! Rayleigh cubic, which `lamb_tests.rs` checks equal to 1e-13):
//!
//! ```text
//! w = F/(πμr) · 1/32 [6 − √3/√(τ²−1/4) + √(3√3−5)/√(τ²−(3−√3)/4) − √(3√3+5)/√(γ²−τ²)]  τ_P<τ<1
//! w = F/(πμr) · 1/16 [6 − √(3√3+5)/√(γ²−τ²)]                                           1<τ<γ
//! w = F/(πμr) · 3/8                                                                     τ>γ
//! ```
//!
//! Radial (Kausel 2013, `u_rz` in complete elliptic integrals of the first and third kind,
//! as in his MATLAB companion `Lamb_3D`, v3.3, with the correction below), with the roots `x₁ = 1/4`, `x₂ = (3−√3)/4`, `x₃ = γ²` of
//! the Rayleigh cubic `4x³ − 7x² + 3x − 3/8 = 0`, `a² = 1/3`, `b² = 2/3`,
//! `c_i = (1−2x_i)(1−x_i)/∏_{j≠i}(x_i−x_j)`, `n_i = b²/(a²−x_i)` and
//! `Π̃(N|m) = ∫_0^{π/2} dθ/((1+N sin²θ)√(1−m sin²θ))` (`lamb_quadrature.rs`):
//!
//! ```text
//! u_r = −F τ/(8π²μr b³)      [2K(m) − Σ c_i Π̃(n_i m | m)],  m = (τ²−a²)/b²   τ_P<τ<1
//! u_r = −F τ√m'/(8π²μr b³)   [2K(m') − Σ c_i Π̃(n_i | m')],  m' = b²/(τ²−a²)   τ>1
//!     − F τ/(8πμr √(τ²−γ²))  (the Rayleigh pole)                                  τ>γ
//! ```
//!
//! The elliptic term (`τ > 1`) holds after the Rayleigh arrival too (it decays as `τ⁻²`):
//! Kausel's MATLAB `Lamb_3D` (v3.3) keeps only the pole's term after `γ`, which breaks the
//! low-frequency identity below by 1.8e-3 (in units of `F/(μ c_s)`); with the elliptic
//! term continued it holds to 1e-15 (checked with mpmath, and in `lamb_tests.rs`). The
//! identity: at order `ω` the surface response is a rigid translation (vertical for a
//! vertical load), so `∫_0^∞ (U∞ − U_r) dτ = 0`; the same identity holds to 1e-11 for
//! Kausel's closed forms of a horizontal load (`∫(U∞ − U_rx) = ∫(U∞ − U_tx)`).
//!
//! The vertical step response has a one-sided singularity `∝ −(γ−τ)^{−1/2}` just before the
//! Rayleigh arrival and jumps to the static value; the radial one is finite before and
//! `∝ −(τ−γ)^{−1/2}` after. At `τ = γ` exactly the functions return the finite one-sided
//! limit (vertical: the static value; radial: the value from before).
//!
//! **Any load history** by Duhamel: `u(t) = Σ_k J_k U(t−t_k) + ∫_0^t U(t−s) g'(s) ds` with
//! `U` the step response and `J_k` the jumps of `g` (a step's at 0, a pulse's at 0 and `T`).
//! The integral is taken in `τ`, split at `τ_P`, 1, `γ` and at the kinks of `g`, each piece
//! by adaptive Gauss–Kronrod on a cubic substitution that smooths the inverse square roots
//! at `γ` (`lamb_quadrature.rs`), to 1e-10 of the result's scale (`|U_static| ∫|g'|`).
//!
//! **Patch loads.** [`Lamb::patch_vertical`] and [`Lamb::patch_radial`] average the point
//! solution over a square patch of half-side `h` centred on the load point (uniform
//! pressure `p = F/(4h²)`), by a 6×6 Gauss–Legendre rule; the receiver at `(r, 0)`. Against
//! the point load the difference is, statically, `(1/r)(1 + h²/(6r²) + O(h⁴/r⁴))` for the
//! vertical (the surface Laplacian of `1/ρ` is `1/ρ³`), i.e. `+(a/r)²/24` with side `a = 2h`:
//! `+4.2e-4` at `r = 10a`; for a disc of radius `a`, `+(a/r)²/8`. The radial `(x−x')/ρ²`
//! is harmonic in the plane: zero at order `(a/r)²` (`O((a/r)⁴)` for a square). Under a
//! smooth ramp with `c_s T = 2r` the largest dynamic difference of the vertical over the
//! history is 1.2e-3 of the peak at `r = 10a` and falls as `(a/r)²` (tested), larger than
//! the static 4.2e-4 because the Rayleigh pulse curves `u(r)` more than `1/r`.
use super::lamb_quadrature::{adaptive_smoothed, elliptic_k, elliptic_pi_plus, GAUSS6};
use crate::load::LoadHistory;
use crate::material::LinearElastic;
use std::f64::consts::PI;

/// Why a Lamb solution cannot be built or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LambError {
    /// The closed forms hold for `ν = 1/4` only.
    #[error(
        "Lamb's problem: poisson = {0}: the closed forms hold for 0.25 only (λ = μ), within 1e-9"
    )]
    Poisson(f64),
    /// A parameter out of its range.
    #[error("Lamb's problem: {field} = {value}: {allowed}")]
    Invalid {
        /// The parameter's name.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

fn check(
    field: &'static str,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), LambError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(LambError::Invalid {
            field,
            value,
            allowed,
        })
    }
}

/// The Rayleigh arrival in `τ = c_s t/r`: `γ = c_s/c_R = √(3+√3)/2`.
pub(crate) fn gamma() -> f64 {
    (0.75 + 0.25 * 3f64.sqrt()).sqrt()
}

/// Wave arrival times at a distance (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arrivals {
    /// P wave, `r/c_p`.
    pub p: f64,
    /// S wave, `r/c_s`.
    pub s: f64,
    /// Rayleigh wave, `r/c_R`.
    pub rayleigh: f64,
}

/// A vertical point force on a `ν = 1/4` half-space (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lamb {
    /// Shear modulus `μ` (Pa).
    pub shear_modulus: f64,
    /// Density `ρ` (kg/m³).
    pub density: f64,
    /// Force `F` (N), positive into the body.
    pub force: f64,
}

impl Lamb {
    /// From `μ`, `ρ` and `F` (`ν = 1/4` implied).
    pub fn new(shear_modulus: f64, density: f64, force: f64) -> Result<Self, LambError> {
        check(
            "shear_modulus",
            shear_modulus,
            shear_modulus > 0.0,
            "a positive finite modulus in Pa",
        )?;
        check(
            "density",
            density,
            density > 0.0,
            "a positive finite density in kg/m³",
        )?;
        check("force", force, true, "a finite force in N")?;
        Ok(Self {
            shear_modulus,
            density,
            force,
        })
    }

    /// From a material, which must have `|ν − 1/4| ≤ 1e-9`.
    pub fn from_material(material: &LinearElastic, force: f64) -> Result<Self, LambError> {
        let nu = material.elastic.poisson;
        let quarter = (nu - 0.25).abs() <= 1e-9;
        if !quarter {
            return Err(LambError::Poisson(nu));
        }
        check(
            "young",
            material.elastic.young,
            material.elastic.young > 0.0,
            "a positive finite modulus in Pa",
        )?;
        Self::new(material.elastic.young / 2.5, material.density, force)
    }

    /// `c_s = √(μ/ρ)`.
    pub fn shear_speed(&self) -> f64 {
        (self.shear_modulus / self.density).sqrt()
    }

    /// `c_p = √3 c_s` (`λ = μ`).
    pub fn pressure_speed(&self) -> f64 {
        3f64.sqrt() * self.shear_speed()
    }

    /// `c_R = c_s √(2 − 2/√3)`, the root of the Rayleigh equation
    /// `(2 − ξ)² = 4√(1 − ξ/3)√(1 − ξ)`, `ξ = c²/c_s²`.
    pub fn rayleigh_speed(&self) -> f64 {
        self.shear_speed() / gamma()
    }

    /// Arrival times at distance `r > 0`.
    pub fn arrivals(&self, r: f64) -> Result<Arrivals, LambError> {
        check_distance(r)?;
        Ok(Arrivals {
            p: r / self.pressure_speed(),
            s: r / self.shear_speed(),
            rayleigh: r / self.rayleigh_speed(),
        })
    }

    /// Boussinesq: `w = 3F/(8πμr)` (along the load).
    pub fn static_vertical(&self, r: f64) -> Result<f64, LambError> {
        check_distance(r)?;
        Ok(self.scale(r) * 3.0 / (8.0 * PI))
    }

    /// Boussinesq: `u_r = −F/(8πμr)` (towards the load for a push).
    pub fn static_radial(&self, r: f64) -> Result<f64, LambError> {
        check_distance(r)?;
        Ok(-self.scale(r) / (8.0 * PI))
    }

    /// Vertical surface displacement under `F H(t)` (module doc, Pekeris 1955).
    pub fn step_vertical(&self, r: f64, t: f64) -> Result<f64, LambError> {
        check_distance(r)?;
        check("t", t, true, "a finite time in s")?;
        Ok(self.scale(r) * vertical_kernel(self.shear_speed() * t / r))
    }

    /// Radial surface displacement under `F H(t)` (module doc, Kausel 2013).
    pub fn step_radial(&self, r: f64, t: f64) -> Result<f64, LambError> {
        check_distance(r)?;
        check("t", t, true, "a finite time in s")?;
        Ok(self.scale(r) * radial_kernel(self.shear_speed() * t / r))
    }

    /// Vertical surface displacement under `F g(t)` (Duhamel, module doc).
    pub fn vertical(&self, r: f64, t: f64, history: &LoadHistory) -> Result<f64, LambError> {
        self.duhamel(r, t, history, vertical_kernel, 3.0 / (8.0 * PI))
    }

    /// Radial surface displacement under `F g(t)` (Duhamel, module doc).
    pub fn radial(&self, r: f64, t: f64, history: &LoadHistory) -> Result<f64, LambError> {
        self.duhamel(r, t, history, radial_kernel, 1.0 / (8.0 * PI))
    }

    /// [`Lamb::vertical`] averaged over a square patch of half-side `h`, `0 < h < r/2`,
    /// centred on the load point (module doc).
    pub fn patch_vertical(
        &self,
        r: f64,
        t: f64,
        history: &LoadHistory,
        half_side: f64,
    ) -> Result<f64, LambError> {
        self.patch(r, half_side, |rho, _| self.vertical(rho, t, history))
    }

    /// [`Lamb::radial`] averaged over a square patch, the component along the line from the
    /// patch's centre to the receiver (module doc).
    pub fn patch_radial(
        &self,
        r: f64,
        t: f64,
        history: &LoadHistory,
        half_side: f64,
    ) -> Result<f64, LambError> {
        self.patch(r, half_side, |rho, cos| {
            Ok(cos * self.radial(rho, t, history)?)
        })
    }

    /// `F/(μr)`.
    fn scale(&self, r: f64) -> f64 {
        self.force / (self.shear_modulus * r)
    }

    /// 6×6 Gauss–Legendre average over `[−h, h]²` of `f(ρ, cos)` with `ρ` the distance from
    /// the source point to the receiver `(r, 0)` and `cos` the cosine of that direction
    /// with the `x` axis.
    fn patch(
        &self,
        r: f64,
        half_side: f64,
        mut f: impl FnMut(f64, f64) -> Result<f64, LambError>,
    ) -> Result<f64, LambError> {
        check_distance(r)?;
        check(
            "half_side",
            half_side,
            half_side > 0.0 && half_side < 0.5 * r,
            "a positive half-side below r/2 (m)",
        )?;
        let mut sum = 0.0;
        for &(x, wx) in &GAUSS6 {
            for &(y, wy) in &GAUSS6 {
                let (dx, dy) = (r - half_side * x, -half_side * y);
                let rho = dx.hypot(dy);
                sum += 0.25 * wx * wy * f(rho, dx / rho)?;
            }
        }
        Ok(sum)
    }

    /// `Σ_k J_k U(t−t_k) + ∫ U(t−s) g'(s) ds` in `τ` (module doc); `static_size` is
    /// `|U(∞)|` in units of `F/(μr)`, the tolerance's scale.
    fn duhamel(
        &self,
        r: f64,
        t: f64,
        history: &LoadHistory,
        kernel: fn(f64) -> f64,
        static_size: f64,
    ) -> Result<f64, LambError> {
        check_distance(r)?;
        check("t", t, true, "a finite time in s")?;
        let (_, time_scale) = history.shape();
        if !history.is_step() {
            check(
                "history duration",
                time_scale,
                time_scale > 0.0,
                "a positive finite time in s",
            )?;
        }
        let speed = self.shear_speed();
        let tau_t = speed * t / r;
        let tau_p = 1.0 / 3f64.sqrt();
        if tau_t <= tau_p {
            return Ok(0.0);
        }
        // jumps of g: a step's at 0, a pulse's at 0 and T
        let mut total = match *history {
            LoadHistory::Step => kernel(tau_t),
            LoadHistory::Pulse { duration } => kernel(tau_t) - kernel(speed * (t - duration) / r),
            LoadHistory::Ramp { .. }
            | LoadHistory::SmoothRamp { .. }
            | LoadHistory::Sine { .. } => 0.0,
        };
        // s = t − τ r/c_s; ds = −(r/c_s) dτ; the kinks of g' at s = T
        let dt_dtau = r / speed;
        let mut integrand = |tau: f64| kernel(tau) * history.rate(t - tau * dt_dtau) * dt_dtau;
        let mut breaks = vec![tau_p, 1.0, gamma(), tau_t];
        if let Some(b) = history.breakpoint() {
            breaks.push(tau_t - b / dt_dtau);
        }
        breaks.retain(|&b| (tau_p..=tau_t).contains(&b));
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        // the result's scale: |U(∞)| times the total variation of g (≥ its peak)
        let n = 256;
        let variation: f64 = (0..n)
            .map(|k| {
                (history.factor(t * (k + 1) as f64 / n as f64)
                    - history.factor(t * k as f64 / n as f64))
                .abs()
            })
            .sum();
        let tol = 1e-10 * static_size * variation.max(1e-300) / breaks.len() as f64;
        for w in breaks.windows(2) {
            total += adaptive_smoothed(&mut integrand, w[0], w[1], tol);
        }
        Ok(self.scale(r) * total)
    }
}

fn check_distance(r: f64) -> Result<(), LambError> {
    check(
        "r",
        r,
        r > 0.0,
        "a positive finite distance from the load in m",
    )
}

/// Vertical step response in units of `F/(μr)` (module doc, Pekeris 1955).
pub(crate) fn vertical_kernel(tau: f64) -> f64 {
    let g = gamma();
    let s3 = 3f64.sqrt();
    if tau <= 1.0 / s3 {
        return 0.0;
    }
    if tau >= g {
        return 3.0 / (8.0 * PI);
    }
    let t2 = tau * tau;
    let rayleigh = (3.0 * s3 + 5.0).sqrt() / ((g - tau) * (g + tau)).sqrt();
    if tau < 1.0 {
        let p1 = s3 / (t2 - 0.25).sqrt();
        let p2 = (3.0 * s3 - 5.0).sqrt() / (t2 - 0.25 * (3.0 - s3)).sqrt();
        (6.0 - p1 + p2 - rayleigh) / (32.0 * PI)
    } else {
        (6.0 - rayleigh) / (16.0 * PI)
    }
}

/// The roots `x_i` of the Rayleigh cubic, `c_i` and `n_i` (module doc).
fn radial_terms() -> [(f64, f64); 3] {
    let s3 = 3f64.sqrt();
    let x = [0.25, 0.25 * (3.0 - s3), 0.25 * (3.0 + s3)];
    let (a2, b2) = (1.0 / 3.0, 2.0 / 3.0);
    let mut terms = [(0.0, 0.0); 3];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let c = (1.0 - 2.0 * x[i]) * (1.0 - x[i]) / ((x[i] - x[j]) * (x[i] - x[k]));
        terms[i] = (c, b2 / (a2 - x[i]));
    }
    terms
}

/// Radial step response in units of `F/(μr)`, positive away from the load (module doc,
/// Kausel 2013): the elliptic part plus, after `γ`, the Rayleigh pole's term.
pub(crate) fn radial_kernel(tau: f64) -> f64 {
    let g = gamma();
    let elliptic = radial_elliptic(tau);
    if tau > g {
        elliptic - tau / (8.0 * PI * ((tau - g) * (tau + g)).sqrt())
    } else {
        elliptic
    }
}

/// The elliptic part of the radial step response (module doc), for all `τ`.
pub(crate) fn radial_elliptic(tau: f64) -> f64 {
    let (a2, b2): (f64, f64) = (1.0 / 3.0, 2.0 / 3.0);
    if tau <= a2.sqrt() {
        return 0.0;
    }
    let front = -tau / (8.0 * PI * PI * b2 * b2.sqrt());
    let terms = radial_terms();
    if tau < 1.0 {
        let m = (tau * tau - a2) / b2;
        let sum: f64 = terms
            .iter()
            .map(|&(c, n)| c * elliptic_pi_plus(n * m, m))
            .sum();
        front * (2.0 * elliptic_k(m) - sum)
    } else {
        let m = b2 / (tau * tau - a2);
        if m >= 1.0 {
            // τ = 1: the limit of both branches, by continuity (K and Π̃ diverge, their
            // combination does not)
            return radial_elliptic(1.0 - 1e-9);
        }
        let sum: f64 = terms.iter().map(|&(c, n)| c * elliptic_pi_plus(n, m)).sum();
        front * m.sqrt() * (2.0 * elliptic_k(m) - sum)
    }
}

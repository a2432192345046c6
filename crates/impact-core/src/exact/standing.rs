//! A smooth exact solution: the standing P mode of a box with roller (symmetry) edges.
//!
//! In plane strain (2D) the displacement `u = ∇φ` of a potential with
//! `φ_tt = c_p² Δφ` solves Navier's equations (an irrotational field: Achenbach 1973,
//! §5.1). With `φ = A cos(a x) cos(b y) sin(ω t)`, `a = m π/L_x`, `b = n π/L_y`,
//! `k = sqrt(a² + b²)` and `ω = c_p k`:
//!
//! - `v = ∂u/∂t = -(U/k) cos(ω t) (a sin(a x) cos(b y), b cos(a x) sin(b y))`,
//!   with `U = A ω k` (m/s);
//! - `ε_xx = -A a² C_x C_y s_t`, `ε_yy = -A b² C_x C_y s_t`, `ε_xy = A a b S_x S_y s_t`
//!   (`C_x = cos(a x)`, `S_x = sin(a x)`, `s_t = sin(ω t)`);
//! - `σ = λ tr(ε) I + 2μ ε`.
//!
//! On every edge the normal velocity and the shear stress vanish (`S_x = 0` at
//! `x = 0, L_x`; `S_y = 0` at `y = 0, L_y`), so the mode is exact for `symmetry` edges. It
//! is a superposition of four oblique plane waves (`m, n ≥ 1`) and at `t = 0` it is all
//! velocity, no stress. In 1D (uniaxial stress, `b = 0`, `c = sqrt(E/ρ)`) it is the
//! standing wave of a bar with fixed ends, `σ = E ε_xx`. The energy is constant:
//! `ρ U² |Ω| / 8` (`m, n ≥ 1`), `ρ U² |Ω| / 4` when `n = 0`.
use crate::LinearElastic;

/// The standing P mode (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandingWave {
    /// Peak speed `U` (m/s).
    pub amplitude: f64,
    /// `a = m π/L_x`, `b = n π/L_y` (`b = 0` in 1D).
    pub wavenumber: [f64; 2],
    /// `ω = c k`.
    pub frequency: f64,
    /// `λ` (0 in 1D, where the bar is in uniaxial stress).
    pub lambda: f64,
    /// `2μ` in 2D; `E` in 1D.
    pub stiffness: f64,
    /// Density `ρ`.
    pub density: f64,
}

/// Average of `cos(a x)` (`sine = false`) or `sin(a x)` over `[x0, x1]`.
fn average(a: f64, x0: f64, x1: f64, sine: bool) -> f64 {
    if a == 0.0 {
        return if sine { 0.0 } else { 1.0 };
    }
    let span = a * (x1 - x0);
    if sine {
        ((a * x0).cos() - (a * x1).cos()) / span
    } else {
        ((a * x1).sin() - (a * x0).sin()) / span
    }
}

impl StandingWave {
    /// The mode `(m, n)` of the box `lengths` of a material in dimension `dim` with peak
    /// speed `amplitude`.
    pub fn new(
        material: &LinearElastic,
        dim: usize,
        lengths: [f64; 2],
        modes: [u32; 2],
        amplitude: f64,
    ) -> Self {
        let pi = std::f64::consts::PI;
        let a = f64::from(modes[0]) * pi / lengths[0];
        let b = if dim == 1 {
            0.0
        } else {
            f64::from(modes[1]) * pi / lengths[1]
        };
        let k = a.hypot(b);
        let (lambda, stiffness, modulus) = if dim == 1 {
            let young = material.elastic.young;
            (0.0, young, young)
        } else {
            let lame = material.lame;
            (lame.lambda, 2.0 * lame.mu, lame.lambda + 2.0 * lame.mu)
        };
        Self {
            amplitude,
            wavenumber: [a, b],
            frequency: (modulus / material.density).sqrt() * k,
            lambda,
            stiffness,
            density: material.density,
        }
    }

    fn k(&self) -> f64 {
        self.wavenumber[0].hypot(self.wavenumber[1])
    }

    /// Velocity `(v_x, v_y)` at `(x, y)` and `t`.
    pub fn velocity(&self, x: f64, y: f64, t: f64) -> [f64; 2] {
        let [a, b] = self.wavenumber;
        let scale = -self.amplitude / self.k() * (self.frequency * t).cos();
        [
            scale * a * (a * x).sin() * (b * y).cos(),
            scale * b * (a * x).cos() * (b * y).sin(),
        ]
    }

    /// Strain `(ε_xx, ε_yy, ε_xy)` scaled by `C_x C_y`-type factors `(cc, ss)`.
    fn strain(&self, t: f64, cc: f64, ss: f64) -> [f64; 3] {
        let [a, b] = self.wavenumber;
        // A = U / (ω k)
        let scale = self.amplitude / (self.frequency * self.k()) * (self.frequency * t).sin();
        [-scale * a * a * cc, -scale * b * b * cc, scale * a * b * ss]
    }

    fn stress_of(&self, e: [f64; 3]) -> [f64; 3] {
        let trace = e[0] + e[1];
        [
            self.lambda * trace + self.stiffness * e[0],
            self.lambda * trace + self.stiffness * e[1],
            self.stiffness * e[2],
        ]
    }

    /// Stress `(σ_xx, σ_yy, σ_xy)` at `(x, y)` and `t` (1D: `σ_xx = E ε_xx`).
    pub fn stress(&self, x: f64, y: f64, t: f64) -> [f64; 3] {
        let [a, b] = self.wavenumber;
        let cc = (a * x).cos() * (b * y).cos();
        let ss = (a * x).sin() * (b * y).sin();
        self.stress_of(self.strain(t, cc, ss))
    }

    /// Averages of `σ_xx` and `v_x` over the box `[lo, hi]` (exact integrals of the
    /// products of sines and cosines).
    pub fn averages(&self, lo: [f64; 2], hi: [f64; 2], t: f64) -> (f64, f64) {
        let [a, b] = self.wavenumber;
        let (cx, sx) = (
            average(a, lo[0], hi[0], false),
            average(a, lo[0], hi[0], true),
        );
        let cy = average(b, lo[1], hi[1], false);
        let sy = average(b, lo[1], hi[1], true);
        let stress = self.stress_of(self.strain(t, cx * cy, sx * sy))[0];
        let velocity = -self.amplitude / self.k() * (self.frequency * t).cos() * a * sx * cy;
        (stress, velocity)
    }

    /// Largest `|σ_xx|` over space and time: `A (λ k² + s a²)` with `A = U/(ω k)` and `s`
    /// = `2μ` (2D) or `E` (1D).
    pub fn peak_stress_xx(&self) -> f64 {
        let [a, _] = self.wavenumber;
        let k = self.k();
        self.amplitude / (self.frequency * k) * (self.lambda * k * k + self.stiffness * a * a)
    }

    /// Kinetic plus strain energy of the box of volume `volume` (constant in time).
    pub fn energy(&self, volume: f64) -> f64 {
        let both = self.wavenumber.iter().all(|&w| w > 0.0);
        let share = if both { 0.125 } else { 0.25 };
        share * self.density * self.amplitude * self.amplitude * volume
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn material() -> LinearElastic {
        LinearElastic::new(2e11, 0.3, 7800.0)
    }

    /// The mode solves `ρ v_t = div σ` and `σ_t = C : sym ∇v` (central differences of the
    /// closed forms) and vanishes normal velocity and shear on the edges.
    #[test]
    fn mode_solves_the_equations_and_the_edge_conditions() {
        let m = material();
        let w = StandingWave::new(&m, 2, [4.0, 3.0], [2, 1], 0.7);
        let (x, y, t, h, dt) = (1.3, 0.7, 2.1e-4, 1e-5, 1e-9);
        let v = |x, y, t| w.velocity(x, y, t);
        let s = |x, y, t| w.stress(x, y, t);
        let rho = m.density;
        let v_t = [
            (v(x, y, t + dt)[0] - v(x, y, t - dt)[0]) / (2.0 * dt),
            (v(x, y, t + dt)[1] - v(x, y, t - dt)[1]) / (2.0 * dt),
        ];
        let div = [
            (s(x + h, y, t)[0] - s(x - h, y, t)[0]) / (2.0 * h)
                + (s(x, y + h, t)[2] - s(x, y - h, t)[2]) / (2.0 * h),
            (s(x + h, y, t)[2] - s(x - h, y, t)[2]) / (2.0 * h)
                + (s(x, y + h, t)[1] - s(x, y - h, t)[1]) / (2.0 * h),
        ];
        for k in 0..2 {
            assert_relative_eq!(rho * v_t[k], div[k], max_relative = 1e-5);
        }
        let lame = m.lame;
        let dvx_dx = (v(x + h, y, t)[0] - v(x - h, y, t)[0]) / (2.0 * h);
        let dvy_dy = (v(x, y + h, t)[1] - v(x, y - h, t)[1]) / (2.0 * h);
        let s_t = (s(x, y, t + dt)[0] - s(x, y, t - dt)[0]) / (2.0 * dt);
        let expected = lame.lambda * (dvx_dx + dvy_dy) + 2.0 * lame.mu * dvx_dx;
        assert_relative_eq!(s_t, expected, max_relative = 1e-5);
        for t in [0.0, 1e-4, 3e-4] {
            assert!(v(0.0, 1.1, t)[0].abs() < 1e-12 && v(4.0, 1.1, t)[0].abs() < 1e-12);
            assert!(v(2.2, 0.0, t)[1].abs() < 1e-12 && v(2.2, 3.0, t)[1].abs() < 1e-12);
            assert!(s(0.0, 1.1, t)[2].abs() < 1e-3 && s(2.2, 3.0, t)[2].abs() < 1e-3);
        }
    }

    /// Box averages equal a fine midpoint rule; the energy is the integral of the kinetic
    /// energy at `t = 0`.
    #[test]
    fn averages_and_energy_match_quadrature() {
        let m = material();
        for (dim, modes) in [(2, [2, 1]), (2, [1, 0]), (1, [3, 0])] {
            let w = StandingWave::new(&m, dim, [4.0, 3.0], modes, 0.7);
            let (lo, hi, t) = ([0.5, 0.2], [0.9, 0.5], 1.7e-4);
            let n = 400;
            let (mut s, mut v) = (0.0, 0.0);
            for i in 0..n {
                for j in 0..n {
                    let x = lo[0] + (i as f64 + 0.5) * (hi[0] - lo[0]) / n as f64;
                    let y = lo[1] + (j as f64 + 0.5) * (hi[1] - lo[1]) / n as f64;
                    s += w.stress(x, y, t)[0] / (n * n) as f64;
                    v += w.velocity(x, y, t)[0] / (n * n) as f64;
                }
            }
            let (sa, va) = w.averages(lo, hi, t);
            assert_relative_eq!(sa, s, max_relative = 1e-4);
            assert_relative_eq!(va, v, max_relative = 1e-4);
            let mut kinetic = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let x = (i as f64 + 0.5) * 4.0 / n as f64;
                    let y = (j as f64 + 0.5) * 3.0 / n as f64;
                    let [vx, vy] = w.velocity(x, y, 0.0);
                    kinetic += 0.5 * m.density * (vx * vx + vy * vy) * 12.0 / (n * n) as f64;
                }
            }
            assert_relative_eq!(kinetic, w.energy(12.0), max_relative = 1e-6);
        }
    }
}

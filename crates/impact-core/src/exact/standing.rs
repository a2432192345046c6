//! A smooth exact solution: the standing P mode of a box with roller (symmetry) edges.
//!
//! In plane strain (2D) and in 3D the displacement `u = ∇φ` of a potential with
//! `φ_tt = c_p² Δφ` solves Navier's equations (an irrotational field: Achenbach 1973,
//! §5.1). With `φ = A cos(a x) cos(b y) cos(c z) sin(ω t)`, `a = m π/L_x`, `b = n π/L_y`,
//! `c = q π/L_z` (`b = 0` in 1D, `c = 0` in 1D and 2D), `k = sqrt(a² + b² + c²)` and
//! `ω = c_p k`:
//!
//! - `v = ∂u/∂t = -(U/k) cos(ω t) (a S_x C_y C_z, b C_x S_y C_z, c C_x C_y S_z)`, with
//!   `U = A ω k` (m/s), `C_x = cos(a x)`, `S_x = sin(a x)`, ...;
//! - `ε_ii = -A k_i² C_x C_y C_z s_t`, `ε_xy = A a b S_x S_y C_z s_t`,
//!   `ε_yz = A b c C_x S_y S_z s_t`, `ε_xz = A a c S_x C_y S_z s_t` (`s_t = sin(ω t)`);
//! - `σ = λ tr(ε) I + 2μ ε`.
//!
//! On every face the normal velocity and the shear stresses vanish (`S_x = 0` at
//! `x = 0, L_x`, ...), so the mode is exact for `symmetry` edges. With two or three
//! non-zero wavenumbers it is a superposition of oblique plane waves (4 in 2D, 8 in 3D:
//! every CTU transverse and transverse-transverse term is exercised); at `t = 0` it is
//! all velocity, no stress. In 1D (uniaxial stress, `c = sqrt(E/ρ)`) it is the standing
//! wave of a bar with fixed ends, `σ = E ε_xx`. The energy is constant,
//! `ρ U² |Ω| / 2^(N+1)` with `N` the number of non-zero wavenumbers.
use crate::LinearElastic;

/// The standing P mode (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandingWave {
    /// Peak speed `U` (m/s).
    pub amplitude: f64,
    /// `(a, b, c) = (m π/L_x, n π/L_y, q π/L_z)` (zero beyond the scene's dimension).
    pub wavenumber: [f64; 3],
    /// `ω = c k`.
    pub frequency: f64,
    /// `λ` (0 in 1D, where the bar is in uniaxial stress).
    pub lambda: f64,
    /// `2μ` in 2D and 3D; `E` in 1D.
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
    /// The mode `(m, n, q)` of the box `lengths` of a material in dimension `dim` with
    /// peak speed `amplitude` (entries beyond `dim` are ignored).
    pub fn new(
        material: &LinearElastic,
        dim: usize,
        lengths: [f64; 3],
        modes: [u32; 3],
        amplitude: f64,
    ) -> Self {
        let pi = std::f64::consts::PI;
        let wavenumber: [f64; 3] = std::array::from_fn(|l| {
            if l < dim {
                f64::from(modes[l]) * pi / lengths[l]
            } else {
                0.0
            }
        });
        let k = wavenumber.iter().map(|w| w * w).sum::<f64>().sqrt();
        let (lambda, stiffness, modulus) = if dim == 1 {
            let young = material.elastic.young;
            (0.0, young, young)
        } else {
            let lame = material.lame;
            (lame.lambda, 2.0 * lame.mu, lame.lambda + 2.0 * lame.mu)
        };
        Self {
            amplitude,
            wavenumber,
            frequency: (modulus / material.density).sqrt() * k,
            lambda,
            stiffness,
            density: material.density,
        }
    }

    fn k(&self) -> f64 {
        self.wavenumber.iter().map(|w| w * w).sum::<f64>().sqrt()
    }

    /// `(cos, sin)` of `k_l x_l` per axis.
    fn trig(&self, x: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let c = std::array::from_fn(|l| (self.wavenumber[l] * x[l]).cos());
        let s = std::array::from_fn(|l| (self.wavenumber[l] * x[l]).sin());
        (c, s)
    }

    /// Velocity `(v_x, v_y, v_z)` at `x` and `t`.
    pub fn velocity(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let [a, b, c] = self.wavenumber;
        let scale = -self.amplitude / self.k() * (self.frequency * t).cos();
        let (cs, sn) = self.trig(x);
        [
            scale * a * sn[0] * cs[1] * cs[2],
            scale * b * cs[0] * sn[1] * cs[2],
            scale * c * cs[0] * cs[1] * sn[2],
        ]
    }

    /// Strain `(ε_xx, ε_yy, ε_zz, ε_yz, ε_xz, ε_xy)` from the products of the trig
    /// factors `ccc = C_x C_y C_z` and `(S_y S_z C_x, S_x S_z C_y, S_x S_y C_z)`.
    fn strain(&self, t: f64, ccc: f64, shear: [f64; 3]) -> [f64; 6] {
        let [a, b, c] = self.wavenumber;
        // A = U / (ω k)
        let scale = self.amplitude / (self.frequency * self.k()) * (self.frequency * t).sin();
        [
            -scale * a * a * ccc,
            -scale * b * b * ccc,
            -scale * c * c * ccc,
            scale * b * c * shear[0],
            scale * a * c * shear[1],
            scale * a * b * shear[2],
        ]
    }

    fn stress_of(&self, e: [f64; 6]) -> [f64; 6] {
        let trace = e[0] + e[1] + e[2];
        std::array::from_fn(|i| {
            if i < 3 {
                self.lambda * trace + self.stiffness * e[i]
            } else {
                self.stiffness * e[i]
            }
        })
    }

    /// Stress `(σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy)` at `x` and `t` (1D: `σ_xx = E ε_xx`).
    pub fn stress(&self, x: [f64; 3], t: f64) -> [f64; 6] {
        let (c, s) = self.trig(x);
        let shear = [c[0] * s[1] * s[2], s[0] * c[1] * s[2], s[0] * s[1] * c[2]];
        self.stress_of(self.strain(t, c[0] * c[1] * c[2], shear))
    }

    /// Averages of `σ_xx` and `v_x` over the box `[lo, hi]` (exact integrals of the
    /// products of sines and cosines).
    pub fn averages(&self, lo: [f64; 3], hi: [f64; 3], t: f64) -> (f64, f64) {
        let w = self.wavenumber;
        let c: [f64; 3] = std::array::from_fn(|l| average(w[l], lo[l], hi[l], false));
        let sx = average(w[0], lo[0], hi[0], true);
        let stress = self.stress_of(self.strain(t, c[0] * c[1] * c[2], [0.0; 3]))[0];
        let velocity =
            -self.amplitude / self.k() * (self.frequency * t).cos() * w[0] * sx * c[1] * c[2];
        (stress, velocity)
    }

    /// Largest `|σ_xx|` over space and time: `A (λ k² + s a²)` with `A = U/(ω k)` and `s`
    /// = `2μ` (2D, 3D) or `E` (1D).
    pub fn peak_stress_xx(&self) -> f64 {
        let a = self.wavenumber[0];
        let k = self.k();
        self.amplitude / (self.frequency * k) * (self.lambda * k * k + self.stiffness * a * a)
    }

    /// Kinetic plus strain energy of the box of volume `volume` (constant in time):
    /// `ρ U² |Ω| / 2^(N+1)`, `N` the number of non-zero wavenumbers.
    pub fn energy(&self, volume: f64) -> f64 {
        let nonzero = self.wavenumber.iter().filter(|&&w| w > 0.0).count() as i32;
        0.5f64.powi(nonzero + 1) * self.density * self.amplitude * self.amplitude * volume
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
        let w = StandingWave::new(&m, 2, [4.0, 3.0, 1.0], [2, 1, 0], 0.7);
        let (x, y, t, h, dt) = (1.3, 0.7, 2.1e-4, 1e-5, 1e-9);
        let v = |x, y, t| w.velocity([x, y, 0.0], t);
        let s = |x, y, t| {
            let full = w.stress([x, y, 0.0], t);
            [full[0], full[1], full[5]]
        };
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
        for (dim, modes) in [(2, [2, 1, 0]), (2, [1, 0, 0]), (1, [3, 0, 0])] {
            let w = StandingWave::new(&m, dim, [4.0, 3.0, 1.0], modes, 0.7);
            let (lo, hi, t) = ([0.5, 0.2, 0.0], [0.9, 0.5, 1.0], 1.7e-4);
            let n = 400;
            let (mut s, mut v) = (0.0, 0.0);
            for i in 0..n {
                for j in 0..n {
                    let x = lo[0] + (i as f64 + 0.5) * (hi[0] - lo[0]) / n as f64;
                    let y = lo[1] + (j as f64 + 0.5) * (hi[1] - lo[1]) / n as f64;
                    s += w.stress([x, y, 0.5], t)[0] / (n * n) as f64;
                    v += w.velocity([x, y, 0.5], t)[0] / (n * n) as f64;
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
                    let [vx, vy, _] = w.velocity([x, y, 0.0], 0.0);
                    kinetic += 0.5 * m.density * (vx * vx + vy * vy) * 12.0 / (n * n) as f64;
                }
            }
            assert_relative_eq!(kinetic, w.energy(12.0), max_relative = 1e-6);
        }
    }

    /// In 3D the mode (1, 2, 1) solves `ρ v_t = div σ` and `σ_t = C : sym ∇v` (central
    /// differences of the closed forms), and its energy is `ρ U² |Ω| / 16`.
    #[test]
    fn mode_solves_the_equations_in_3d() {
        let m = material();
        let lengths = [1.0, 1.5, 0.8];
        let w = StandingWave::new(&m, 3, lengths, [1, 2, 1], 0.7);
        let (p, t, h, dt) = ([0.31, 0.52, 0.23], 2.1e-4, 1e-5, 1e-9);
        let shifted = |l: usize, d: f64| {
            let mut q = p;
            q[l] += d;
            q
        };
        // Voigt index of σ_{ij}
        let voigt = |i: usize, j: usize| if i == j { i } else { 6 - i - j };
        let lame = m.lame;
        let mut grad_v = [[0.0; 3]; 3];
        for j in 0..3 {
            let (vp, vm) = (w.velocity(shifted(j, h), t), w.velocity(shifted(j, -h), t));
            for i in 0..3 {
                grad_v[i][j] = (vp[i] - vm[i]) / (2.0 * h);
            }
        }
        let divergence = grad_v[0][0] + grad_v[1][1] + grad_v[2][2];
        for i in 0..3 {
            let v_t = (w.velocity(p, t + dt)[i] - w.velocity(p, t - dt)[i]) / (2.0 * dt);
            let div: f64 = (0..3)
                .map(|j| {
                    let sp = w.stress(shifted(j, h), t)[voigt(i, j)];
                    let sm = w.stress(shifted(j, -h), t)[voigt(i, j)];
                    (sp - sm) / (2.0 * h)
                })
                .sum();
            assert_relative_eq!(m.density * v_t, div, max_relative = 1e-5);
            for j in 0..3 {
                let s_t = (w.stress(p, t + dt)[voigt(i, j)] - w.stress(p, t - dt)[voigt(i, j)])
                    / (2.0 * dt);
                let strain_rate = 0.5 * (grad_v[i][j] + grad_v[j][i]);
                let expected = 2.0 * lame.mu * strain_rate
                    + if i == j {
                        lame.lambda * divergence
                    } else {
                        0.0
                    };
                assert_relative_eq!(s_t, expected, max_relative = 1e-4, epsilon = 1e-3);
            }
        }
        let n = 40;
        let volume: f64 = lengths.iter().product();
        let mut kinetic = 0.0;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let x = [i, j, k].map(|c| c as f64 + 0.5);
                    let x = [0, 1, 2].map(|l| x[l] * lengths[l] / n as f64);
                    let v = w.velocity(x, 0.0);
                    kinetic += 0.5 * m.density * v.iter().map(|c| c * c).sum::<f64>();
                }
            }
        }
        kinetic *= volume / (n * n * n) as f64;
        assert_relative_eq!(kinetic, w.energy(volume), max_relative = 1e-9);
    }
}

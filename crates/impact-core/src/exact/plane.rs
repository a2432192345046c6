//! A smooth travelling plane wave in any direction (issue 24): a P or S pulse in an
//! unbounded linear elastic body, exact wherever no boundary has acted yet.
//!
//! With a unit direction `n`, a unit polarisation `a` (`a = n` for a P wave, `a ⟂ n` for
//! an S wave), the speed `c` (`c_p = sqrt((λ+2μ)/ρ)` or `c_s = sqrt(μ/ρ)`) and a profile
//! `f(s) = U g((s − s₀)/w)`, `g(r) = cos⁴(π r / 2)` for `|r| < 1` and 0 outside (C³,
//! compact support of width `2w`):
//!
//! - `v(x, t) = a f(n·x − c t)`;
//! - `σ(x, t) = −(f/c) [λ (a·n) I + μ (n⊗a + a⊗n)]`, i.e. `−(f/c)(λ I + 2μ n⊗n)` for P and
//!   `−(μ f/c)(n⊗a + a⊗n)` for S;
//! - `u(x, t) = (a U w / c) G(r)`, `G(r) = ∫_r^1 g = 3/8 − 3r/8 − sin(πr)/(2π) −
//!   sin(2πr)/(16π)` (`G = 3/4` behind the pulse, 0 ahead of it: the material not yet
//!   reached is at rest and undisplaced).
//!
//! They solve `ρ v_t = div σ` and `σ_t = C : sym ∇v` (Achenbach 1973, §4.7): with `s = n·x −
//! c t`, `ρ v_t = −ρ c a f'` and `div σ = −(f'/c)[λ (a·n) n + μ (n (a·n) + a)]`, equal for
//! `a = n` since `ρ c_p² = λ + 2μ` and for `a·n = 0` since `ρ c_s² = μ`; `σ = C : sym ∇u`
//! with `∇u = −(U/c) g a⊗n`. In 1D (uniaxial stress) `λ = 0`, `2μ = E` and `c = sqrt(E/ρ)`;
//! in 2D, plane strain. Components beyond the scene's dimension are zero.
use crate::LinearElastic;

/// The travelling pulse of the module doc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneWave {
    /// Peak speed `U` (m/s).
    pub amplitude: f64,
    /// Unit direction of travel `n` (zero beyond the scene's dimension).
    pub direction: [f64; 3],
    /// Unit polarisation `a` (`n` for P, `⟂ n` for S).
    pub polarisation: [f64; 3],
    /// `s₀ = n·x₀`: where the pulse's centre is along `n` at `t = 0`.
    pub centre: f64,
    /// Half-width `w` of the pulse along `n` (m).
    pub half_width: f64,
    /// Speed `c` (m/s).
    pub speed: f64,
    /// `λ` (0 in 1D).
    pub lambda: f64,
    /// `μ` (`E/2` in 1D).
    pub mu: f64,
    /// Density `ρ`.
    pub density: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `g(r) = cos⁴(π r / 2)` on `|r| < 1`, 0 outside.
fn bump(r: f64) -> f64 {
    if r.abs() >= 1.0 {
        return 0.0;
    }
    let c = (0.5 * std::f64::consts::PI * r).cos();
    let c2 = c * c;
    c2 * c2
}

/// `G(r) = ∫_r^1 g` (module doc).
fn bump_tail(r: f64) -> f64 {
    let pi = std::f64::consts::PI;
    if r >= 1.0 {
        return 0.0;
    }
    if r <= -1.0 {
        return 0.75;
    }
    0.375 - 0.375 * r - (pi * r).sin() / (2.0 * pi) - (2.0 * pi * r).sin() / (16.0 * pi)
}

/// Gauss–Legendre nodes (on `[-1, 1]`) and weights, 3 points: exact for degree 5.
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

impl PlaneWave {
    /// A P (`shear = false`, `polarisation` ignored) or S wave of `material` in dimension
    /// `dim`, travelling along `direction` (normalised here), polarised along the part of
    /// `polarisation` normal to it (S), centred on the point `centre` at `t = 0`. The caller
    /// checks that the direction is not zero and that an S polarisation has a part normal
    /// to it.
    pub fn new(
        material: &LinearElastic,
        dim: usize,
        (direction, polarisation): ([f64; 3], [f64; 3]),
        shear: bool,
        (centre, half_width): ([f64; 3], f64),
        amplitude: f64,
    ) -> Self {
        let clip = |v: [f64; 3]| std::array::from_fn(|l| if l < dim { v[l] } else { 0.0 });
        let unit = |v: [f64; 3]| {
            let norm = dot(v, v).sqrt();
            v.map(|c| c / norm)
        };
        let n = unit(clip(direction));
        let a = if shear {
            let p = clip(polarisation);
            let along = dot(p, n);
            unit(std::array::from_fn(|l| p[l] - along * n[l]))
        } else {
            n
        };
        let (lambda, mu) = if dim == 1 {
            (0.0, 0.5 * material.elastic.young)
        } else {
            (material.lame.lambda, material.lame.mu)
        };
        let modulus = if shear { mu } else { lambda + 2.0 * mu };
        Self {
            amplitude,
            direction: n,
            polarisation: a,
            centre: dot(n, clip(centre)),
            half_width,
            speed: (modulus / material.density).sqrt(),
            lambda,
            mu,
            density: material.density,
        }
    }

    /// `r = (n·x − c t − s₀)/w`.
    fn phase(&self, x: [f64; 3], t: f64) -> f64 {
        (dot(self.direction, x) - self.speed * t - self.centre) / self.half_width
    }

    /// Velocity `a f` at `x` and `t`.
    pub fn velocity(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let f = self.amplitude * bump(self.phase(x, t));
        self.polarisation.map(|a| a * f)
    }

    /// Stress `(σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy)` at `x` and `t`.
    pub fn stress(&self, x: [f64; 3], t: f64) -> [f64; 6] {
        let scale = -self.amplitude * bump(self.phase(x, t)) / self.speed;
        let (n, a) = (self.direction, self.polarisation);
        let normal = self.lambda * dot(a, n);
        let pair = |i: usize, j: usize| self.mu * (n[i] * a[j] + a[i] * n[j]);
        [
            scale * (normal + pair(0, 0)),
            scale * (normal + pair(1, 1)),
            scale * (normal + pair(2, 2)),
            scale * pair(1, 2),
            scale * pair(0, 2),
            scale * pair(0, 1),
        ]
    }

    /// Displacement `(a U w / c) G(r)` at `x` and `t`.
    pub fn displacement(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let u = self.amplitude * self.half_width / self.speed * bump_tail(self.phase(x, t));
        self.polarisation.map(|a| a * u)
    }

    /// Averages of `σ_xx` and `v_x` over the box `[lo, hi]` (a degenerate axis, `lo = hi`,
    /// is not averaged), by 3-point Gauss–Legendre per axis on each of 2 sub-boxes per axis
    /// (the pulse is C³: the quadrature error is far below any method's).
    pub fn averages(&self, lo: [f64; 3], hi: [f64; 3], t: f64) -> (f64, f64) {
        let (mut stress, mut velocity) = (0.0, 0.0);
        // 6 nodes per axis: 2 halves × 3 Gauss points, weights summing to 1
        let nodes: [(f64, f64); 6] = std::array::from_fn(|k| {
            let (xi, w) = GAUSS3[k % 3];
            (0.5 * (k / 3) as f64 + 0.25 * (1.0 + xi), 0.25 * w)
        });
        for &(sx, wx) in &nodes {
            for &(sy, wy) in &nodes {
                for &(sz, wz) in &nodes {
                    let s = [sx, sy, sz];
                    let x: [f64; 3] = std::array::from_fn(|l| lo[l] + s[l] * (hi[l] - lo[l]));
                    let w = wx * wy * wz;
                    stress += w * self.stress(x, t)[0];
                    velocity += w * self.velocity(x, t)[0];
                }
            }
        }
        (stress, velocity)
    }

    /// Scale of the stress for relative errors where the exact `σ_xx` vanishes: `ρ c U`,
    /// the peak of the traction on the wave front (`|σ n| = ρ c |v|`).
    pub fn stress_scale(&self) -> f64 {
        self.density * self.speed * self.amplitude
    }

    /// Kinetic plus strain energy of the whole pulse per unit area of its front:
    /// `ρ U² ∫g² w = ρ U² w · 35/64` (equal parts; `∫_{-1}^{1} cos⁸(πr/2) dr = 35/64`).
    pub fn energy_per_area(&self) -> f64 {
        self.density * self.amplitude * self.amplitude * self.half_width * 35.0 / 64.0
    }

    /// Whether this is an S wave.
    pub fn is_shear(&self) -> bool {
        dot(self.direction, self.polarisation).abs() < 0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn material() -> LinearElastic {
        LinearElastic::new(2e11, 0.3, 7800.0)
    }

    /// Voigt index of `σ_ij`.
    fn voigt(i: usize, j: usize) -> usize {
        if i == j {
            i
        } else {
            6 - i - j
        }
    }

    /// Central differences of the closed forms: `ρ v_t = div σ`, `σ_t = C : sym ∇v` and
    /// `u_t = v`, at points inside and at the edge of the pulse, for P and S in 3D and P in
    /// 2D and 1D.
    fn check_equations(w: &PlaneWave, dim: usize, points: &[[f64; 3]], t: f64) {
        let (h, dt) = (1e-6, 1e-10);
        let (lambda, mu, rho) = (w.lambda, w.mu, w.density);
        let vmax = w.amplitude;
        let smax = w.stress_scale() * 2.0;
        for &p in points {
            let shifted = |l: usize, d: f64| {
                let mut q = p;
                q[l] += d;
                q
            };
            let mut grad_v = [[0.0; 3]; 3];
            for j in 0..dim {
                let (vp, vm) = (w.velocity(shifted(j, h), t), w.velocity(shifted(j, -h), t));
                for i in 0..3 {
                    grad_v[i][j] = (vp[i] - vm[i]) / (2.0 * h);
                }
            }
            let divergence: f64 = (0..dim).map(|k| grad_v[k][k]).sum();
            for i in 0..dim {
                let v_t = (w.velocity(p, t + dt)[i] - w.velocity(p, t - dt)[i]) / (2.0 * dt);
                let div: f64 = (0..dim)
                    .map(|j| {
                        let sp = w.stress(shifted(j, h), t)[voigt(i, j)];
                        let sm = w.stress(shifted(j, -h), t)[voigt(i, j)];
                        (sp - sm) / (2.0 * h)
                    })
                    .sum();
                let rate = rho * vmax * w.speed / w.half_width;
                assert!((rho * v_t - div).abs() < 1e-6 * rate, "{p:?} {i}");
                let u_t =
                    (w.displacement(p, t + dt)[i] - w.displacement(p, t - dt)[i]) / (2.0 * dt);
                assert!((u_t - w.velocity(p, t)[i]).abs() < 1e-6 * vmax, "{p:?} {i}");
                for j in 0..dim {
                    let s_t = (w.stress(p, t + dt)[voigt(i, j)] - w.stress(p, t - dt)[voigt(i, j)])
                        / (2.0 * dt);
                    let strain_rate = 0.5 * (grad_v[i][j] + grad_v[j][i]);
                    let expected =
                        2.0 * mu * strain_rate + if i == j { lambda * divergence } else { 0.0 };
                    let rate = smax * w.speed / w.half_width;
                    assert!((s_t - expected).abs() < 1e-6 * rate, "{p:?} {i}{j}");
                }
            }
        }
    }

    #[test]
    fn p_and_s_pulses_solve_the_equations() {
        let m = material();
        let points = [[0.31, 0.52, 0.23], [0.4, 0.45, 0.5], [0.2, 0.6, 0.41]];
        let p = PlaneWave::new(
            &m,
            3,
            ([1.0, 2.0, 2.0], [0.0; 3]),
            false,
            ([0.3, 0.4, 0.4], 0.2),
            1.5,
        );
        assert_relative_eq!(p.speed, m.p_wave_speed::<3>(), max_relative = 1e-14);
        assert_relative_eq!(p.direction[1], 2.0 / 3.0, max_relative = 1e-15);
        check_equations(&p, 3, &points, 1.3e-5);
        let s = PlaneWave::new(
            &m,
            3,
            ([1.0, 2.0, 2.0], [1.0, 0.0, 0.0]),
            true,
            ([0.3, 0.4, 0.4], 0.2),
            1.5,
        );
        assert!(dot(s.direction, s.polarisation).abs() < 1e-15 && s.is_shear());
        assert_relative_eq!(s.speed, m.s_wave_speed::<3>(), max_relative = 1e-14);
        check_equations(&s, 3, &points, 2.1e-5);
        let plate = PlaneWave::new(
            &m,
            2,
            ([3.0, 4.0, 9.0], [0.0; 3]),
            false,
            ([0.3, 0.4, 0.0], 0.2),
            1.0,
        );
        assert_eq!(plate.direction, [0.6, 0.8, 0.0]);
        check_equations(&plate, 2, &points, 1.0e-5);
        let bar = PlaneWave::new(
            &m,
            1,
            ([1.0, 0.0, 0.0], [0.0; 3]),
            false,
            ([0.3, 0.0, 0.0], 0.2),
            1.0,
        );
        assert_relative_eq!(bar.speed, m.p_wave_speed::<1>(), max_relative = 1e-14);
        check_equations(&bar, 1, &points, 1.0e-5);
    }

    /// `σ = −ρ c v` along `n` for P (the impedance relation), the pulse is carried unchanged
    /// at `c`, the displacement vanishes ahead of it and is `(a U w / c)(3/4)` behind it,
    /// the averages match a fine midpoint rule, and the energy per area is `ρ U² w 35/64`.
    #[test]
    fn pulse_is_carried_and_averages_match_quadrature() {
        let m = material();
        let w = PlaneWave::new(
            &m,
            3,
            ([1.0, 2.0, 2.0], [0.0; 3]),
            false,
            ([0.3, 0.4, 0.4], 0.2),
            1.5,
        );
        let (x, t) = ([0.35, 0.41, 0.43], 1.1e-5);
        let v = w.velocity(x, 0.0);
        let moved: [f64; 3] = std::array::from_fn(|l| x[l] + w.direction[l] * w.speed * t);
        for (moved, v) in w.velocity(moved, t).iter().zip(v) {
            assert_relative_eq!(*moved, v, max_relative = 1e-12);
        }
        let along = dot(v, w.direction);
        let sigma = w.stress(x, 0.0);
        let n = w.direction;
        let normal: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| n[i] * sigma[voigt(i, j)] * n[j])
            .sum();
        assert_relative_eq!(normal, -m.density * w.speed * along, max_relative = 1e-12);
        assert_eq!(w.displacement([2.0, 2.0, 2.0], 0.0), [0.0; 3]);
        let behind = w.displacement([0.0; 3], 0.0);
        assert_relative_eq!(
            behind[0],
            w.direction[0] * 1.5 * 0.2 / w.speed * 0.75,
            max_relative = 1e-12
        );
        let (lo, hi) = ([0.3, 0.35, 0.4], [0.34, 0.41, 0.43]);
        let nq = 60;
        let (mut s, mut u) = (0.0, 0.0);
        for i in 0..nq {
            for j in 0..nq {
                for k in 0..nq {
                    let c = [i, j, k].map(|q| (q as f64 + 0.5) / nq as f64);
                    let p: [f64; 3] = std::array::from_fn(|l| lo[l] + c[l] * (hi[l] - lo[l]));
                    s += w.stress(p, t)[0];
                    u += w.velocity(p, t)[0];
                }
            }
        }
        let count = (nq * nq * nq) as f64;
        let (sa, va) = w.averages(lo, hi, t);
        assert_relative_eq!(sa, s / count, max_relative = 1e-5);
        assert_relative_eq!(va, u / count, max_relative = 1e-5);
        // energy along a line through the pulse: ∫ (ρ|v|²/2 + σ:ε/2) ds = ρ U² ∫ g² w
        let ns = 30_000;
        let mut energy = 0.0;
        for i in 0..ns {
            let s = 1.5 * (i as f64 + 0.5) / ns as f64;
            let p = n.map(|c| c * s);
            let v = w.velocity(p, 0.0);
            energy += 1.5 * m.density * dot(v, v) / ns as f64;
        }
        assert_relative_eq!(energy, w.energy_per_area(), max_relative = 1e-6);
    }
}

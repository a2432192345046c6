//! Saint-Venant–Kirchhoff hyperelasticity ([`Svk`], paper eq. 22).
use super::LinearElastic;
use crate::{Tensor, Vector};

/// Saint-Venant–Kirchhoff hyperelasticity (paper eq. 22), total Lagrangian.
///
/// `E = ½(FᵀF - 1)`, `S = λ tr(E) 1 + 2μ E`, `Π = F S = 2μ F·E + λ tr(E) F`,
/// `ψ = μ E:E + λ/2 (tr E)²`. In 1D (the bar, uniaxial) `Π = E_Y/2 · F (F² - 1)`,
/// `ψ = E_Y/8 (F² - 1)²`, `Π' = E_Y/2 (3F² - 1)` and the wave speed is
/// `c(F) = sqrt(Π'(F)/ρ₀)`. Uniaxial compression loses hyperbolicity at `F = 1/√3`, where
/// `Π' = 0` and `Π = -E_Y/(3√3)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Svk {
    /// The small-strain parameters (`E`, `ν`, `ρ₀`) it reduces to.
    pub linear: LinearElastic,
}

impl Svk {
    /// SVK with the moduli of `linear`.
    pub fn new(linear: LinearElastic) -> Self {
        Self { linear }
    }

    fn lame<const D: usize>(&self) -> (f64, f64) {
        if D == 1 {
            // uniaxial: S = E_Y · E_GL
            (0.0, 0.5 * self.linear.elastic.young)
        } else {
            (self.linear.lame.lambda, self.linear.lame.mu)
        }
    }

    /// First Piola–Kirchhoff stress `Π(F)` (paper eq. 22).
    #[inline]
    pub fn piola<const D: usize>(&self, f: &Tensor<D>) -> Tensor<D> {
        let (lambda, mu) = self.lame::<D>();
        let green = (f.transpose() * f - Tensor::<D>::identity()) * 0.5;
        let s = Tensor::<D>::identity() * (lambda * green.trace()) + green * (2.0 * mu);
        f * s
    }

    /// Directional derivative `dΠ = dF S + F dS`, `dS = λ tr(dE) 1 + 2μ dE`,
    /// `dE = sym(Fᵀ dF)`.
    #[inline]
    pub fn tangent_apply<const D: usize>(&self, f: &Tensor<D>, df: &Tensor<D>) -> Tensor<D> {
        let (lambda, mu) = self.lame::<D>();
        let green = (f.transpose() * f - Tensor::<D>::identity()) * 0.5;
        let s = Tensor::<D>::identity() * (lambda * green.trace()) + green * (2.0 * mu);
        let ftdf = f.transpose() * df;
        let de = (ftdf + ftdf.transpose()) * 0.5;
        let ds = Tensor::<D>::identity() * (lambda * de.trace()) + de * (2.0 * mu);
        df * s + f * ds
    }

    /// Strain energy density `ψ(F)` per reference volume.
    #[inline]
    pub fn energy_density<const D: usize>(&self, f: &Tensor<D>) -> f64 {
        let (lambda, mu) = self.lame::<D>();
        let green = (f.transpose() * f - Tensor::<D>::identity()) * 0.5;
        mu * green.component_mul(&green).sum() + 0.5 * lambda * green.trace().powi(2)
    }

    /// Acoustic tensor `A_ik(F, n) = ∂Π_ij/∂F_kl n_j n_l`.
    pub fn acoustic_tensor<const D: usize>(&self, f: &Tensor<D>, n: &Vector<D>) -> Tensor<D> {
        let mut a = Tensor::<D>::zeros();
        for k in 0..D {
            let mut e = Vector::<D>::zeros();
            e[k] = 1.0;
            let col = self.tangent_apply(f, &(e * n.transpose())) * n;
            a.set_column(k, &col);
        }
        a
    }

    /// Largest wave speed `sqrt(λ_max(A(F, n))/ρ₀)` over the axis directions `n = e_l`
    /// (`NaN` once hyperbolicity is lost).
    pub fn max_wave_speed<const D: usize>(&self, f: &Tensor<D>) -> f64 {
        let mut c2: f64 = 0.0;
        for l in 0..D {
            let mut n = Vector::<D>::zeros();
            n[l] = 1.0;
            let a = self.acoustic_tensor(f, &n);
            let (lo, hi) = symmetric_eigen_range(&((a + a.transpose()) * 0.5));
            if lo <= 0.0 {
                return f64::NAN;
            }
            c2 = c2.max(hi);
        }
        (c2 / self.linear.density).sqrt()
    }

    /// Whether `F` is hyperbolic with wave speeds within 5 % of `max_speed` (the speed the
    /// time step was chosen for); the guard stops a run whose points fail this.
    pub fn admissible<const D: usize>(&self, f: &Tensor<D>, max_speed: f64) -> bool {
        let c = self.max_wave_speed(f);
        c.is_finite() && c <= 1.05 * max_speed
    }

    /// The guard's message for a deformation gradient that fails [`Self::admissible`].
    pub fn inadmissible_reason<const D: usize>(f: &Tensor<D>) -> String {
        format!(
            "deformation gradient {:?} lost hyperbolicity (uniaxial limit F = 1/√3) or outruns \
             the wave speed the time step was chosen for",
            f.as_slice()
        )
    }

    /// 1D: `Π(F) = E/2 F (F² - 1)`.
    pub fn piola_1d(&self, f: f64) -> f64 {
        0.5 * self.linear.elastic.young * f * (f * f - 1.0)
    }

    /// 1D: `Π'(F) = E/2 (3F² - 1)`.
    pub fn tangent_1d(&self, f: f64) -> f64 {
        0.5 * self.linear.elastic.young * (3.0 * f * f - 1.0)
    }

    /// 1D wave speed `c(F) = sqrt(Π'(F)/ρ₀)`.
    pub fn wave_speed_1d(&self, f: f64) -> f64 {
        (self.tangent_1d(f) / self.linear.density).sqrt()
    }

    /// 1D hyperbolicity limit: `F = 1/√3` and `Π = -E/(3√3)`.
    pub fn hyperbolicity_limit_1d(&self) -> (f64, f64) {
        let f = 1.0 / 3f64.sqrt();
        (f, self.piola_1d(f))
    }

    /// 1D: the stretch `F > 1/√3` with `Π(F) = pi` (Newton from the small-strain guess);
    /// `None` at or beyond the hyperbolicity limit.
    pub fn stretch_for_1d(&self, pi: f64) -> Option<f64> {
        let (_, pi_min) = self.hyperbolicity_limit_1d();
        if pi <= pi_min || !pi.is_finite() {
            return None;
        }
        let mut f = (1.0 + pi / self.linear.elastic.young).max(0.6);
        for _ in 0..100 {
            let r = self.piola_1d(f) - pi;
            let d = self.tangent_1d(f);
            let step = r / d;
            f -= step;
            if f <= 1.0 / 3f64.sqrt() {
                f = 0.5 * (f + step + 1.0 / 3f64.sqrt()); // back off towards the limit
            }
            if step.abs() <= 1e-15 * f.abs() {
                break;
            }
        }
        Some(f)
    }

    /// `φ(F) = ∫_1^F c(s) ds` (1D), with `∫ sqrt(3s² - 1) ds =
    /// s/2 sqrt(3s² - 1) - ln(√3 s + sqrt(3s² - 1))/(2√3)`.
    pub fn riemann_phi_1d(&self, f: f64) -> f64 {
        let a = (0.5 * self.linear.elastic.young / self.linear.density).sqrt();
        let g = |s: f64| {
            let r = (3.0 * s * s - 1.0).max(0.0).sqrt();
            0.5 * s * r - (3f64.sqrt() * s + r).ln() / (2.0 * 3f64.sqrt())
        };
        a * (g(f) - g(1.0))
    }
}

/// Smallest and largest eigenvalue of a symmetric `D×D` tensor: closed form in 1D, 2D and
/// 3D (the trigonometric solution of the characteristic cubic, Smith 1961, "Eigenvalues
/// of a symmetric 3 × 3 matrix", Commun. ACM 4(4) 168: no allocation, for the guard's
/// checks inside the step loop), nalgebra's symmetric eigen-decomposition (of a dynamic
/// copy: it allocates) beyond.
fn symmetric_eigen_range<const D: usize>(a: &Tensor<D>) -> (f64, f64) {
    match D {
        1 => (a[(0, 0)], a[(0, 0)]),
        3 => {
            // A = q I + p B, det B = 2 cos 3φ; eigenvalues q + 2p cos(φ + 2πk/3)
            let q = a.trace() / 3.0;
            let off = a[(0, 1)].powi(2) + a[(0, 2)].powi(2) + a[(1, 2)].powi(2);
            let diagonal: f64 = (0..3).map(|i| (a[(i, i)] - q).powi(2)).sum();
            let p = ((diagonal + 2.0 * off) / 6.0).sqrt();
            if p <= 1e-300 || p <= 1e-15 * q.abs() {
                return (q, q);
            }
            let b = (a - Tensor::<D>::identity() * q) / p;
            let m = |i: usize, j: usize| b[(i, j)];
            let det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
                - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
                + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
            let half_det: f64 = 0.5 * det;
            let phi = half_det.clamp(-1.0, 1.0).acos() / 3.0;
            let largest = q + 2.0 * p * phi.cos();
            let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
            (smallest, largest)
        }
        4.. => {
            let dynamic = nalgebra::DMatrix::from_iterator(D, D, a.iter().copied());
            let values = dynamic.symmetric_eigenvalues();
            (values.min(), values.max())
        }
        _ => {
            let (p, q, r) = (a[(0, 0)], a[(1, 1)], a[(0, 1)]);
            let mean = 0.5 * (p + q);
            let radius = (0.25 * (p - q) * (p - q) + r * r).sqrt();
            (mean - radius, mean + radius)
        }
    }
}

#[cfg(test)]
mod svk_tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The 3D closed form gives nalgebra's extreme eigenvalues (to 1e-12 of the spectral
    /// radius) on symmetric matrices with distinct, double and triple eigenvalues.
    #[test]
    fn closed_form_3d_eigenvalues_match_the_decomposition() {
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut cases: Vec<Tensor<3>> = (0..200)
            .map(|_| {
                let m = Tensor::<3>::from_fn(|_, _| next() * 1e11);
                m + m.transpose()
            })
            .collect();
        cases.push(Tensor::<3>::identity() * 3e10);
        cases.push(Tensor::<3>::from_diagonal(&Vector::<3>::new(
            2.0, 2.0, -1.0,
        )));
        cases.push(Tensor::<3>::zeros());
        for a in cases {
            let values =
                nalgebra::DMatrix::from_iterator(3, 3, a.iter().copied()).symmetric_eigenvalues();
            let (lo, hi) = symmetric_eigen_range(&a);
            let scale = values.amax().max(1e-300);
            assert!(
                (lo - values.min()).abs() <= 1e-12 * scale,
                "{lo} vs {values}"
            );
            assert!(
                (hi - values.max()).abs() <= 1e-12 * scale,
                "{hi} vs {values}"
            );
        }
    }

    fn svk() -> Svk {
        Svk::new(LinearElastic::new(2e11, 0.3, 7800.0))
    }

    fn check_piola_is_energy_gradient<const D: usize>(f: Tensor<D>) {
        let m = svk();
        let p = m.piola(&f);
        let h = 1e-7;
        for i in 0..D {
            for j in 0..D {
                let mut fp = f;
                fp[(i, j)] += h;
                let mut fm = f;
                fm[(i, j)] -= h;
                let fd = (m.energy_density(&fp) - m.energy_density(&fm)) / (2.0 * h);
                assert_relative_eq!(p[(i, j)], fd, max_relative = 1e-6, epsilon = 1e-3);
            }
        }
        // the tangent is the derivative of Π
        let df = Tensor::<D>::from_fn(|i, j| 0.3 + 0.1 * i as f64 - 0.2 * j as f64);
        let fd = (m.piola(&(f + df * h)) - m.piola(&(f - df * h))) / (2.0 * h);
        assert_relative_eq!(
            m.tangent_apply(&f, &df),
            fd,
            max_relative = 1e-6,
            epsilon = 1e-2
        );
    }

    #[test]
    fn piola_is_the_derivative_of_the_energy_1d_and_2d() {
        check_piola_is_energy_gradient(Tensor::<1>::new(0.93));
        check_piola_is_energy_gradient(Tensor::<1>::new(1.08));
        check_piola_is_energy_gradient(Tensor::<2>::new(1.02, 0.05, -0.03, 0.97));
        check_piola_is_energy_gradient(Tensor::<2>::new(0.9, 0.2, 0.1, 1.1));
    }

    #[test]
    fn one_dimensional_form_is_the_paper_s() {
        let m = svk();
        for f in [0.8, 0.99, 1.0, 1.2] {
            let p = m.piola(&Tensor::<1>::new(f))[(0, 0)];
            assert_relative_eq!(
                p,
                1e11 * f * (f * f - 1.0),
                max_relative = 1e-14,
                epsilon = 1e-6
            );
            assert_relative_eq!(m.piola_1d(f), p, max_relative = 1e-14, epsilon = 1e-6);
        }
        let (f, p) = m.hyperbolicity_limit_1d();
        assert!(m.tangent_1d(f).abs() < 1e-3);
        assert_relative_eq!(p, -2e11 / (3.0 * 3f64.sqrt()), max_relative = 1e-12);
        let f = m.stretch_for_1d(-8e8).unwrap();
        assert_relative_eq!(m.piola_1d(f), -8e8, max_relative = 1e-12);
        assert!(m.stretch_for_1d(p * 1.01).is_none());
        // φ' = c
        let h = 1e-6;
        let d = (m.riemann_phi_1d(0.95 + h) - m.riemann_phi_1d(0.95 - h)) / (2.0 * h);
        assert_relative_eq!(d, m.wave_speed_1d(0.95), max_relative = 1e-6);
    }

    /// SVK tends to linear elasticity at small strain: the difference shrinks linearly with
    /// the load (it is quadratic in the strain).
    #[test]
    fn svk_tends_to_linear_elasticity_at_small_strain() {
        let m = svk();
        let lin = m.linear;
        let dir = Tensor::<2>::new(1.0, 0.4, 0.4, -0.6);
        let mut previous = f64::MAX;
        for k in 0..6 {
            let eps = 1e-2 / 4f64.powi(k);
            let f = Tensor::<2>::identity() + dir * eps;
            let sigma = lin.stress(&(dir * eps));
            let rel = (m.piola(&f) - sigma).norm() / sigma.norm();
            if k > 0 {
                assert_relative_eq!(previous / rel, 4.0, max_relative = 0.05);
            }
            previous = rel;
        }
        assert!(previous < 1e-4);
        // and the acoustic tensor at F = 1 gives the linear wave speeds
        let a = m.acoustic_tensor(&Tensor::<2>::identity(), &Vector::<2>::new(1.0, 0.0));
        assert_relative_eq!(
            a[(0, 0)],
            lin.lame.lambda + 2.0 * lin.lame.mu,
            max_relative = 1e-12
        );
        assert_relative_eq!(a[(1, 1)], lin.lame.mu, max_relative = 1e-12);
    }
}

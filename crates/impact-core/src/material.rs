//! Stateless material models with separate parameters.
//!
//! [`LinearElastic`] is Hooke's law. In 1D (a bar in uniaxial stress) `σ = E ε` and the
//! wave speed is `c = sqrt(E/ρ)` (paper §5.1). In 2D (plane strain)
//! `σ = λ tr(ε) 1 + 2μ ε` (paper eq. 7), with P- and S-wave speeds
//! `c_p = sqrt((λ+2μ)/ρ)`, `c_s = sqrt(μ/ρ)` (paper §5.2).
//! [`Svk`] (in `svk.rs`) is Saint-Venant–Kirchhoff hyperelasticity (paper eq. 22).
use crate::Tensor;

/// Young's modulus and Poisson's ratio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YoungPoisson {
    /// Young's modulus `E` (Pa).
    pub young: f64,
    /// Poisson's ratio `ν`.
    pub poisson: f64,
}

/// Lamé coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    /// First Lamé coefficient `λ = Eν/((1+ν)(1-2ν))`.
    pub lambda: f64,
    /// Shear modulus `μ = E/(2(1+ν))`.
    pub mu: f64,
}

impl From<YoungPoisson> for Lame {
    fn from(p: YoungPoisson) -> Self {
        let YoungPoisson { young, poisson } = p;
        Lame {
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            mu: young / (2.0 * (1.0 + poisson)),
        }
    }
}

/// Isotropic linear elasticity (small strain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearElastic {
    /// Young's modulus and Poisson's ratio.
    pub elastic: YoungPoisson,
    /// Lamé coefficients derived from `elastic`.
    pub lame: Lame,
    /// Mass density `ρ` (kg/m³).
    pub density: f64,
}

impl LinearElastic {
    /// Build from Young's modulus, Poisson's ratio and density.
    pub fn new(young: f64, poisson: f64, density: f64) -> Self {
        let elastic = YoungPoisson { young, poisson };
        Self {
            elastic,
            lame: elastic.into(),
            density,
        }
    }

    /// Modulus of a longitudinal wave: `E` for the 1D bar, `λ + 2μ` in plane strain.
    pub fn p_modulus<const D: usize>(&self) -> f64 {
        if D == 1 {
            self.elastic.young
        } else {
            self.lame.lambda + 2.0 * self.lame.mu
        }
    }

    /// Longitudinal wave speed `c_p = sqrt(M/ρ)` with `M` from [`Self::p_modulus`].
    pub fn p_wave_speed<const D: usize>(&self) -> f64 {
        (self.p_modulus::<D>() / self.density).sqrt()
    }

    /// Shear wave speed `c_s = sqrt(μ/ρ)` (no shear wave in the 1D bar: returns 0).
    pub fn s_wave_speed<const D: usize>(&self) -> f64 {
        if D == 1 {
            0.0
        } else {
            (self.lame.mu / self.density).sqrt()
        }
    }

    /// Stress from a (symmetric) strain: `σ = E ε` in 1D, `σ = λ tr(ε) 1 + 2μ ε` in 2D.
    /// Formed as `2μ ε` with `λ tr(ε)` added to the diagonal, and the trace as the sum of the
    /// diagonal from its first entry: the values of `λ tr(ε) 1 + 2μ ε` (the diagonal's
    /// additions are the same, commuted), without the products by the identity's zeros and
    /// the trace's `+0` start, which the compiler must keep (they can only turn a `-0`
    /// into `+0`, or a non-finite trace into a NaN off the diagonal).
    #[inline]
    pub fn stress<const D: usize>(&self, strain: &Tensor<D>) -> Tensor<D> {
        if D == 1 {
            strain * self.elastic.young
        } else {
            let Lame { lambda, mu } = self.lame;
            let trace = (1..D).fold(strain[(0, 0)], |sum, k| sum + strain[(k, k)]);
            let mut stress = strain * (2.0 * mu);
            for k in 0..D {
                stress[(k, k)] += lambda * trace;
            }
            stress
        }
    }

    /// Strain from stress (the inverse of [`Self::stress`]):
    /// `ε = σ/E` in 1D, `ε = (σ - λ tr(σ)/(2(λ+μ)) 1) / (2μ)` in plane strain (the
    /// in-plane trace; `ε_zz = 0`), `ε = (σ - λ tr(σ)/(3λ+2μ) 1) / (2μ)` in 3D.
    #[inline]
    pub fn strain<const D: usize>(&self, stress: &Tensor<D>) -> Tensor<D> {
        if D == 1 {
            stress / self.elastic.young
        } else {
            let Lame { lambda, mu } = self.lame;
            let tr = stress.trace();
            // the trace of 1 over the dimensions that strain: 2 (plane strain) or 3
            let denominator = if D == 2 {
                2.0 * (lambda + mu)
            } else {
                3.0 * lambda + 2.0 * mu
            };
            (stress - Tensor::<D>::identity() * (lambda * tr / denominator)) / (2.0 * mu)
        }
    }

    /// Out-of-plane stress of plane strain (`ε_zz = 0`):
    /// `σ_zz = λ tr(ε) = λ/(2(λ+μ)) (σ_xx + σ_yy)`; 0 for the 1D bar (uniaxial stress);
    /// 2D only (a 3D stress has its own `σ_zz`).
    pub fn out_of_plane_stress<const D: usize>(&self, stress: &Tensor<D>) -> f64 {
        if D == 1 {
            0.0
        } else {
            let Lame { lambda, mu } = self.lame;
            lambda / (2.0 * (lambda + mu)) * stress.trace()
        }
    }

    /// Strain energy density `ψ = ½ σ:ε` with `ε` from [`Self::strain`].
    #[inline]
    pub fn energy_density<const D: usize>(&self, stress: &Tensor<D>) -> f64 {
        0.5 * stress.component_mul(&self.strain(stress)).sum()
    }

    /// Acoustic impedances `(Z_p, Z_s) = (ρ c_p, ρ c_s)`.
    pub fn impedances<const D: usize>(&self) -> (f64, f64) {
        (
            self.density * self.p_wave_speed::<D>(),
            self.density * self.s_wave_speed::<D>(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn lame_from_young_poisson() {
        let lame: Lame = YoungPoisson {
            young: 2e11,
            poisson: 0.3,
        }
        .into();
        assert_relative_eq!(lame.mu, 2e11 / 2.6, max_relative = 1e-14);
        assert_relative_eq!(lame.lambda, 2e11 * 0.3 / (1.3 * 0.4), max_relative = 1e-14);
    }

    /// In 3D the compliance inverts the stiffness, and `ψ = ½ σ:ε` of a uniaxial strain
    /// is `½ M ε²`.
    #[test]
    fn strain_inverts_stress_in_3d() {
        let m = LinearElastic::new(2e11, 0.3, 7800.0);
        let eps = Tensor::<3>::new(1e-3, 2e-4, -1e-4, 2e-4, -5e-4, 3e-4, -1e-4, 3e-4, 7e-4);
        let back = m.strain(&m.stress(&eps));
        assert_relative_eq!(back, eps, max_relative = 1e-12);
        let mut uniaxial = Tensor::<3>::zeros();
        uniaxial[(0, 0)] = 1e-3;
        assert_relative_eq!(
            m.energy_density(&m.stress(&uniaxial)),
            0.5 * m.p_modulus::<3>() * 1e-6,
            max_relative = 1e-12
        );
    }

    #[test]
    fn strain_inverts_stress_in_plane_strain() {
        let m = LinearElastic::new(2e11, 0.3, 7800.0);
        let eps = Tensor::<2>::new(1e-3, 2e-4, 2e-4, -5e-4);
        let back = m.strain(&m.stress(&eps));
        assert_relative_eq!(back, eps, max_relative = 1e-12);
        // energy ½σ:ε is the same written both ways
        let sigma = m.stress(&eps);
        assert_relative_eq!(
            m.energy_density(&sigma),
            0.5 * sigma.component_mul(&eps).sum(),
            max_relative = 1e-12
        );
    }

    #[test]
    fn out_of_plane_stress_is_lambda_times_the_trace_of_strain() {
        let m = LinearElastic::new(2e11, 0.3, 7800.0);
        let eps = Tensor::<2>::new(1e-3, 2e-4, 2e-4, -5e-4);
        let sigma = m.stress(&eps);
        assert_relative_eq!(
            m.out_of_plane_stress(&sigma),
            m.lame.lambda * eps.trace(),
            max_relative = 1e-12
        );
    }

    #[test]
    fn wave_speeds() {
        let m = LinearElastic::new(2e11, 0.3, 7800.0);
        assert_relative_eq!(m.p_wave_speed::<1>(), (2e11f64 / 7800.0).sqrt());
        let cp = m.p_wave_speed::<2>();
        let cs = m.s_wave_speed::<2>();
        // cp/cs = sqrt(2(1-ν)/(1-2ν))
        assert_relative_eq!(cp / cs, (2.0 * 0.7f64 / 0.4).sqrt(), max_relative = 1e-12);
    }
}

mod svk;
pub use svk::Svk;

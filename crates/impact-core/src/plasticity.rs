//! Small-strain J2 (von Mises) plasticity with linear isotropic hardening: the return
//! mappings that DGMPM, MPM and FEM apply at their points or Gauss points (issue 12). The
//! material is stateless: [`J2`] holds the parameters, [`PlasticState`] the history each
//! point carries.
//!
//! **Yield function** (Simo & Hughes 1998, §2.3 and Box 3.2; de Souza Neto, Perić & Owen
//! 2008, Box 7.3), with the equivalent stress `q = sqrt(3/2) |s|`, `s = dev σ`, and the
//! accumulated (equivalent) plastic strain `ε̄ = ∫ sqrt(2/3) |ε̇_p| dt`:
//!
//! `f(σ, ε̄) = q − (σ_y + H ε̄) ≤ 0`.
//!
//! `H` is the hardening modulus of the equivalent stress against `ε̄`, so in uniaxial stress
//! the tangent modulus is `E_t = E H / (E + H)` and in uniaxial strain
//! `M_p = K + 4μH / (3(H + 3μ))` (`K = λ + 2μ/3`, the bulk modulus).
//!
//! **Radial return** (3D; plane strain with `ε_zz = 0` tracks `σ_zz`): from the trial
//! stress `σ_tr = σ_n + C : Δε`, with `q_tr = sqrt(3/2) |s_tr|` and
//! `f_tr = q_tr − (σ_y + H ε̄_n)`; if `f_tr ≤ 0` the step is elastic; otherwise
//!
//! `Δε̄ = f_tr / (3μ + H)`,  `s = (1 − 3μ Δε̄ / q_tr) s_tr`,  `p = p_tr`,
//! `ε_p += Δε̄ sqrt(3/2) n̂`, `n̂ = s_tr / |s_tr|`,
//!
//! with the consistent tangent (de Souza Neto et al. 2008, eq. 7.120)
//! `C_ep = 2μ (1 − 3μΔε̄/q_tr) I_dev + 6μ² (Δε̄/q_tr − 1/(3μ + H)) n̂⊗n̂ + K 1⊗1`.
//!
//! **Uniaxial stress** (the 1D rod; Simo & Hughes 1998, Box 1.4 with isotropic hardening):
//! `σ_tr = σ_n + E Δε`, `f_tr = |σ_tr| − (σ_y + H ε̄_n)`;
//! plastic: `Δε̄ = f_tr/(E + H)`, `σ = σ_tr − E Δε̄ sign(σ_tr)`, tangent `E H/(E + H)`.
//!
//! As `σ_y → ∞` both reduce to linear elasticity (tested to round-off). Kinematic
//! hardening is not offered: the impact scenes load monotonically up to the first
//! reflection, where it and isotropic hardening coincide.
use crate::parallel::{chunks, for_each_chunk};
use crate::points::MaterialPoints;
use crate::{LinearElastic, Tensor};
use nalgebra::Matrix3;

/// Points per chunk of the parallel return maps.
const CHUNK: usize = 4096;

/// A 3×3 symmetric tensor (stress or strain) as a full matrix.
pub type Tensor3 = Matrix3<f64>;

/// J2 parameters (the elastic ones come from [`LinearElastic`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct J2 {
    /// Elastic part.
    pub elastic: LinearElastic,
    /// Initial yield stress `σ_y` (Pa, > 0).
    pub yield_stress: f64,
    /// Hardening modulus `H` (Pa, ≥ 0) of the equivalent stress against `ε̄`.
    pub hardening: f64,
}

/// What a point carries between steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlasticState {
    /// Accumulated plastic strain `ε̄`.
    pub equivalent_plastic_strain: f64,
}

/// The result of one return mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Returned<T> {
    /// The stress after the return.
    pub stress: T,
    /// The plastic multiplier `Δε̄` of the step (0: elastic).
    pub increment: f64,
}

impl J2 {
    /// Current yield stress `σ_y + H ε̄`.
    #[inline]
    pub fn current_yield(&self, state: &PlasticState) -> f64 {
        self.yield_stress + self.hardening * state.equivalent_plastic_strain
    }

    /// Bulk modulus `K = λ + 2μ/3`.
    pub fn bulk(&self) -> f64 {
        self.elastic.lame.lambda + 2.0 * self.elastic.lame.mu / 3.0
    }

    /// Tangent modulus in uniaxial stress, `E_t = E H / (E + H)`.
    pub fn uniaxial_stress_tangent(&self) -> f64 {
        let e = self.elastic.elastic.young;
        e * self.hardening / (e + self.hardening)
    }

    /// Plastic modulus in uniaxial strain, `M_p = K + 4μH / (3(H + 3μ))`.
    pub fn uniaxial_strain_tangent(&self) -> f64 {
        let mu = self.elastic.lame.mu;
        self.bulk() + 4.0 * mu * self.hardening / (3.0 * (self.hardening + 3.0 * mu))
    }

    /// `σ_xx` at first yield in uniaxial strain (the Hugoniot elastic limit),
    /// `σ_y (λ + 2μ) / (2μ)`.
    pub fn hugoniot_elastic_limit(&self) -> f64 {
        let l = self.elastic.lame;
        self.yield_stress * (l.lambda + 2.0 * l.mu) / (2.0 * l.mu)
    }

    /// Radial return (module doc) of the trial stress `trial` (3D), updating `state`.
    pub fn return_map(&self, trial: &Tensor3, state: &mut PlasticState) -> Returned<Tensor3> {
        let mu = self.elastic.lame.mu;
        let pressure = trial.trace() / 3.0;
        let deviator = trial - Tensor3::identity() * pressure;
        let q_trial = (1.5 * deviator.norm_squared()).sqrt();
        let f_trial = q_trial - self.current_yield(state);
        if f_trial <= 0.0 || q_trial == 0.0 {
            return Returned {
                stress: *trial,
                increment: 0.0,
            };
        }
        let increment = f_trial / (3.0 * mu + self.hardening);
        state.equivalent_plastic_strain += increment;
        let scale = 1.0 - 3.0 * mu * increment / q_trial;
        Returned {
            stress: deviator * scale + Tensor3::identity() * pressure,
            increment,
        }
    }

    /// The consistent tangent `C_ep` (module doc) of a return from `trial` with multiplier
    /// `increment`, applied to a strain increment `strain` (`C_ep : strain`).
    pub fn tangent_apply(&self, trial: &Tensor3, increment: f64, strain: &Tensor3) -> Tensor3 {
        let (lambda, mu) = (self.elastic.lame.lambda, self.elastic.lame.mu);
        let volumetric = strain.trace();
        let strain_dev = strain - Tensor3::identity() * (volumetric / 3.0);
        let bulk = lambda + 2.0 * mu / 3.0;
        if increment == 0.0 {
            return strain_dev * (2.0 * mu) + Tensor3::identity() * (bulk * volumetric);
        }
        let deviator = trial - Tensor3::identity() * (trial.trace() / 3.0);
        let q_trial = (1.5 * deviator.norm_squared()).sqrt();
        let n = deviator / deviator.norm();
        let a = 2.0 * mu * (1.0 - 3.0 * mu * increment / q_trial);
        let b = 6.0 * mu * mu * (increment / q_trial - 1.0 / (3.0 * mu + self.hardening));
        strain_dev * a + n * (b * n.dot(strain)) + Tensor3::identity() * (bulk * volumetric)
    }

    /// The uniaxial-stress return (the 1D rod) of `trial`, updating `state`.
    pub fn return_map_1d(&self, trial: f64, state: &mut PlasticState) -> Returned<f64> {
        let young = self.elastic.elastic.young;
        let f_trial = trial.abs() - self.current_yield(state);
        if f_trial <= 0.0 {
            return Returned {
                stress: trial,
                increment: 0.0,
            };
        }
        let increment = f_trial / (young + self.hardening);
        state.equivalent_plastic_strain += increment;
        Returned {
            stress: trial - young * increment * trial.signum(),
            increment,
        }
    }

    /// Elastic trial stress `σ_n + C : Δε` (3D isotropic).
    pub fn trial(&self, stress: &Tensor3, strain_increment: &Tensor3) -> Tensor3 {
        let l = self.elastic.lame;
        stress
            + strain_increment * (2.0 * l.mu)
            + Tensor3::identity() * (l.lambda * strain_increment.trace())
    }

    /// Plane strain (`ε_zz = 0`): `σ_zz` from the in-plane trace `σ_xx + σ_yy` and the
    /// plastic strain `ε^p_zz`. With `e = −ε^p_zz` the elastic `ε_zz`,
    /// `tr ε^e = (σ_xx + σ_yy + 2μ e)/(2(λ + μ))` and `σ_zz = λ tr ε^e + 2μ e`.
    #[inline]
    pub fn out_of_plane(&self, in_plane_trace: f64, plastic_zz: f64) -> f64 {
        let (lambda, mu) = (self.elastic.lame.lambda, self.elastic.lame.mu);
        let e = -plastic_zz;
        lambda * (in_plane_trace + 2.0 * mu * e) / (2.0 * (lambda + mu)) + 2.0 * mu * e
    }

    /// The 3D stress of a point: in 1D `σ_xx` alone (uniaxial stress); in 2D the in-plane
    /// stress with [`Self::out_of_plane`].
    pub fn stress3<const D: usize>(&self, stress: &Tensor<D>, plastic_zz: f64) -> Tensor3 {
        let mut s = Tensor3::zeros();
        for i in 0..D {
            for j in 0..D {
                s[(i, j)] = stress[(i, j)];
            }
        }
        if D == 2 {
            s[(2, 2)] = self.out_of_plane(stress.trace(), plastic_zz);
        }
        s
    }

    /// Elastic strain energy density `½ σ : C⁻¹ : σ` = `|dev σ|²/(4μ) + p²/(2K)` (3D
    /// stress), `σ²/(2E)` in uniaxial stress.
    pub fn elastic_energy_density<const D: usize>(
        &self,
        stress: &Tensor<D>,
        plastic_zz: f64,
    ) -> f64 {
        if D == 1 {
            return 0.5 * stress[(0, 0)] * stress[(0, 0)] / self.elastic.elastic.young;
        }
        let s = self.stress3(stress, plastic_zz);
        let p = s.trace() / 3.0;
        let dev = s - Tensor3::identity() * p;
        dev.norm_squared() / (4.0 * self.elastic.lame.mu) + p * p / (2.0 * self.bulk())
    }

    /// The return map at every point (phase "plastic correction" of DGMPM and MPM): each
    /// point's stress after the elastic update is the trial; the returned stress replaces
    /// it, and `ε̄`, `ε^p_zz` (from `Δε_p = (σ_tr − σ)/(2μ)`, deviatoric) and the plastic
    /// work `∫ q dε̄ = Σ (σ_y + H ε̄_n + ½ H Δε̄) Δε̄` are updated. In parallel over disjoint chunks when `parallel`.
    pub fn correct_points<const D: usize>(&self, points: &mut MaterialPoints<D>, parallel: bool) {
        let two_mu = 2.0 * self.elastic.lame.mu;
        let parts = (
            (
                chunks(&mut points.stress, CHUNK),
                chunks(&mut points.equivalent_plastic_strain, CHUNK),
            ),
            (
                chunks(&mut points.plastic_strain_zz, CHUNK),
                chunks(&mut points.plastic_work, CHUNK),
            ),
        );
        for_each_chunk(parallel, 1, parts, |_, ((stress, eqv), (zz, work))| {
            for (((sigma, eqv), zz), work) in stress.iter_mut().zip(eqv).zip(zz).zip(work) {
                let mut state = PlasticState {
                    equivalent_plastic_strain: *eqv,
                };
                let increment = if D == 1 {
                    let r = self.return_map_1d(sigma[(0, 0)], &mut state);
                    sigma[(0, 0)] = r.stress;
                    r.increment
                } else {
                    let trial = self.stress3(sigma, *zz);
                    let r = self.return_map(&trial, &mut state);
                    if r.increment > 0.0 {
                        *zz += (trial[(2, 2)] - r.stress[(2, 2)]) / two_mu;
                        for i in 0..D {
                            for j in 0..D {
                                sigma[(i, j)] = r.stress[(i, j)];
                            }
                        }
                    }
                    r.increment
                };
                // ∫ q dε̄ over the step, exact for linear hardening:
                // (σ_y + H ε̄_n) Δε̄ + ½ H Δε̄²
                *work +=
                    (self.current_yield(&state) - 0.5 * self.hardening * increment) * increment;
                *eqv = state.equivalent_plastic_strain;
            }
        });
    }

    /// `σ_zz` of every sample into `samples.stress_zz` (plane strain), from the in-plane
    /// stress and `ε^p_zz` of each carrier.
    pub fn samples_zz<const D: usize>(&self, samples: &mut crate::Samples<D>, plastic_zz: &[f64]) {
        if D == 2 {
            samples.stress_zz.extend(
                samples
                    .stress
                    .iter()
                    .zip(plastic_zz)
                    .map(|(s, zz)| self.out_of_plane(s.trace(), *zz)),
            );
        }
    }

    /// Equivalent stress `q = sqrt(3/2) |dev σ|`.
    pub fn equivalent_stress(stress: &Tensor3) -> f64 {
        let deviator = stress - Tensor3::identity() * (stress.trace() / 3.0);
        (1.5 * deviator.norm_squared()).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn steel(yield_stress: f64) -> J2 {
        J2 {
            elastic: LinearElastic::new(2e11, 0.3, 7800.0),
            yield_stress,
            hardening: 2e10,
        }
    }

    fn sym(a: [[f64; 3]; 3]) -> Tensor3 {
        let m = Tensor3::from_fn(|i, j| a[i][j]);
        (m + m.transpose()) * 0.5
    }

    /// After a plastic return the stress lies on the (hardened) yield surface, the return
    /// is radial (the deviator keeps its direction) and the pressure is unchanged.
    #[test]
    fn return_lands_on_the_yield_surface_radially() {
        let m = steel(4e8);
        let stress = sym([[1e8, 3e7, 0.0], [3e7, -2e8, 5e7], [0.0, 5e7, 4e7]]);
        let strain = sym([[2e-3, 1e-3, 0.0], [1e-3, -1.5e-3, 4e-4], [0.0, 4e-4, 0.0]]);
        let trial = m.trial(&stress, &strain);
        let mut state = PlasticState {
            equivalent_plastic_strain: 1e-3,
        };
        let r = m.return_map(&trial, &mut state);
        assert!(r.increment > 0.0);
        let q = J2::equivalent_stress(&r.stress);
        assert_relative_eq!(q, m.current_yield(&state), max_relative = 1e-12);
        assert_relative_eq!(r.stress.trace(), trial.trace(), max_relative = 1e-12);
        let dev = |t: &Tensor3| t - Tensor3::identity() * (t.trace() / 3.0);
        let (a, b) = (dev(&r.stress), dev(&trial));
        assert_relative_eq!(a.dot(&b), a.norm() * b.norm(), max_relative = 1e-12);
    }

    /// The consistent tangent equals central differences of the return map in the strain
    /// increment, for elastic and plastic steps.
    #[test]
    fn consistent_tangent_matches_finite_differences() {
        let m = steel(4e8);
        let stress = sym([[1e8, 3e7, 0.0], [3e7, -2e8, 5e7], [0.0, 5e7, 4e7]]);
        for scale in [1e-5, 2e-3] {
            let strain = sym([[2.0, 1.0, 0.0], [1.0, -1.5, 0.4], [0.0, 0.4, 0.3]]) * scale;
            let stress_of = |e: &Tensor3| {
                let mut state = PlasticState::default();
                m.return_map(&m.trial(&stress, e), &mut state).stress
            };
            let trial = m.trial(&stress, &strain);
            let increment = m.return_map(&trial, &mut PlasticState::default()).increment;
            assert_eq!(increment > 0.0, scale > 1e-4);
            for (i, j) in [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2)] {
                let mut d = Tensor3::zeros();
                d[(i, j)] = 0.5;
                d[(j, i)] += 0.5;
                let h = 1e-9;
                let numeric =
                    (stress_of(&(strain + d * h)) - stress_of(&(strain - d * h))) / (2.0 * h);
                let analytic = m.tangent_apply(&trial, increment, &d);
                assert!(
                    (numeric - analytic).norm() <= 1e-5 * analytic.norm(),
                    "({i},{j}) at {scale}: {numeric} vs {analytic}"
                );
            }
        }
    }

    /// Driven in uniaxial strain past yield the slope `dσ_xx/dε_xx` is `M_p`; in uniaxial
    /// stress (1D return) it is `E_t`; first yield in uniaxial strain is at the Hugoniot
    /// elastic limit.
    #[test]
    fn uniaxial_tangents_equal_their_closed_forms() {
        let m = steel(4e8);
        let mut state = PlasticState::default();
        let mut stress = Tensor3::zeros();
        let step = 1e-5;
        let mut first_yield = None;
        let mut history = Vec::new();
        for _ in 0..600 {
            let mut d = Tensor3::zeros();
            d[(0, 0)] = -step;
            let r = m.return_map(&m.trial(&stress, &d), &mut state);
            if r.increment > 0.0 && first_yield.is_none() {
                first_yield = Some(-stress[(0, 0)]);
            }
            stress = r.stress;
            history.push(stress[(0, 0)]);
        }
        let hel = m.hugoniot_elastic_limit();
        let seen = first_yield.unwrap();
        assert!(
            seen <= hel && seen > hel - 2.0 * m.elastic.p_modulus::<2>() * step,
            "{seen} vs {hel}"
        );
        let slope = (history[590] - history[580]) / (-10.0 * step);
        assert_relative_eq!(slope, m.uniaxial_strain_tangent(), max_relative = 1e-9);

        let mut state = PlasticState::default();
        let mut sigma = 0.0;
        let mut values = Vec::new();
        for _ in 0..600 {
            sigma = m.return_map_1d(sigma + 2e11 * step, &mut state).stress;
            values.push(sigma);
        }
        let slope = (values[590] - values[580]) / (10.0 * step);
        assert_relative_eq!(slope, m.uniaxial_stress_tangent(), max_relative = 1e-9);
    }

    /// `σ_y → ∞`: the return maps are the identity and the tangent is `C`, to round-off.
    #[test]
    fn infinite_yield_stress_is_linear_elasticity() {
        let m = steel(f64::INFINITY);
        let stress = sym([[1e9, 3e8, 0.0], [3e8, -2e9, 5e8], [0.0, 5e8, 4e8]]);
        let strain = sym([[2e-2, 1e-2, 0.0], [1e-2, -1.5e-2, 4e-3], [0.0, 4e-3, 0.0]]);
        let trial = m.trial(&stress, &strain);
        let mut state = PlasticState::default();
        let r = m.return_map(&trial, &mut state);
        assert_eq!(r.stress, trial);
        assert_eq!(state.equivalent_plastic_strain, 0.0);
        let l = m.elastic.lame;
        let elastic = strain * (2.0 * l.mu) + Tensor3::identity() * (l.lambda * strain.trace());
        assert!((m.tangent_apply(&trial, 0.0, &strain) - elastic).norm() <= 1e-15 * elastic.norm());
        assert_eq!(m.return_map_1d(-7e9, &mut state).stress, -7e9);
    }
}

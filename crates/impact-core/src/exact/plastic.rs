//! Exact elastic-plastic waves of a half-space at rest under a step load (valid until the
//! precursor reaches the far end), for the J2 material of [`crate::plasticity`] with linear
//! isotropic hardening `H` (Wang 2011, ch. 3 and 5; Meyers 1994, §7.3-7.4).
//!
//! **Rod** (uniaxial stress), a step pressure `p` at `X = 0` (`σ(0, t) = −p`). If
//! `p ≤ σ_y` it is the elastic bar. Otherwise two shocks run into the rod: the elastic
//! precursor at `c_0 = sqrt(E/ρ)` carrying `(Δσ, Δv) = (−σ_y, σ_y/(ρ c_0))`, and the plastic
//! wave at `c_t = sqrt(E_t/ρ)`, `E_t = E H/(E + H)`, carrying
//! `(−(p − σ_y), (p − σ_y)/(ρ c_t))` (each jump obeys `ρ c [v] = −[σ]`; the tangent is
//! constant, so the plastic wave is a shock, not a fan). Behind it `ε̄ = (p − σ_y)/H`.
//!
//! **Plane wave** (uniaxial strain), an impactor at velocity `V` into `X = 0`: the
//! precursor at `c_L = sqrt((λ + 2μ)/ρ)` reaches the Hugoniot elastic limit
//! `σ_H = σ_y (λ + 2μ)/(2μ)` (`v_H = σ_H/(ρ c_L)`), the plastic wave at
//! `c_p = sqrt(M_p/ρ)`, `M_p = K + 4μH/(3(H + 3μ))`, brings the velocity to `V` and
//! `σ_xx = −σ_H − ρ c_p (V − v_H)`; behind it `ε̄ = 2μ |Δε_xx| / (3μ + H)` with
//! `Δε_xx = (V − v_H)/c_p` the strain jump of the plastic wave. If `V ≤ v_H` it is the
//! elastic plane wave.
//!
//! Stress is compression-negative (`σ_xx < 0` behind the waves). The rod needs `H > 0` for
//! a plastic wave that moves (`H = 0` makes `c_t = 0`); the plane wave allows `H = 0`
//! (`c_p = sqrt(K/ρ)`, `ε̄ = 2|Δε_xx|/3`).
use super::Front;
use crate::plasticity::J2;

/// The two-wave solution (module doc) along `X ≥ 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElastoplasticWave {
    /// Precursor speed (`c_0` or `c_L`).
    pub elastic_speed: f64,
    /// Plastic wave speed (`c_t` or `c_p`); equal to the elastic speed when the load stays
    /// elastic.
    pub plastic_speed: f64,
    /// `(σ_xx, v_x)` between the waves.
    pub precursor: (f64, f64),
    /// `(σ_xx, v_x)` behind the plastic wave.
    pub behind: (f64, f64),
    /// `ε̄` behind the plastic wave (0 if elastic).
    pub plastic_strain: f64,
    /// Time until which it is valid (the precursor reaches `X = length`).
    pub valid_until: f64,
}

impl ElastoplasticWave {
    /// The rod of `length` under a step pressure `pressure` (> 0: compression).
    pub fn rod(material: &J2, length: f64, pressure: f64) -> Self {
        let rho = material.elastic.density;
        let young = material.elastic.elastic.young;
        let c0 = (young / rho).sqrt();
        let p = pressure.abs();
        let sign = pressure.signum();
        if p <= material.yield_stress {
            let state = (-pressure, pressure / (rho * c0));
            return Self::elastic(c0, state, length);
        }
        let ct = (material.uniaxial_stress_tangent() / rho).sqrt();
        let sy = material.yield_stress;
        let v_precursor = sy / (rho * c0);
        Self {
            elastic_speed: c0,
            plastic_speed: ct,
            precursor: (-sign * sy, sign * v_precursor),
            behind: (-pressure, sign * (v_precursor + (p - sy) / (rho * ct))),
            plastic_strain: (p - sy) / material.hardening,
            valid_until: length / c0,
        }
    }

    /// The plane wave in a plate of `length` under an impactor at `velocity` (> 0: into
    /// the plate).
    pub fn plane(material: &J2, length: f64, velocity: f64) -> Self {
        let rho = material.elastic.density;
        let l = material.elastic.lame;
        let cl = ((l.lambda + 2.0 * l.mu) / rho).sqrt();
        let v = velocity.abs();
        let sign = velocity.signum();
        let hel = material.hugoniot_elastic_limit();
        let v_hel = hel / (rho * cl);
        if v <= v_hel {
            return Self::elastic(cl, (-rho * cl * velocity, velocity), length);
        }
        let cp = (material.uniaxial_strain_tangent() / rho).sqrt();
        let strain_jump = (v - v_hel) / cp;
        Self {
            elastic_speed: cl,
            plastic_speed: cp,
            precursor: (-sign * hel, sign * v_hel),
            behind: (-sign * (hel + rho * cp * (v - v_hel)), velocity),
            plastic_strain: 2.0 * l.mu * strain_jump / (3.0 * l.mu + material.hardening),
            valid_until: length / cl,
        }
    }

    fn elastic(speed: f64, state: (f64, f64), length: f64) -> Self {
        Self {
            elastic_speed: speed,
            plastic_speed: speed,
            precursor: state,
            behind: state,
            plastic_strain: 0.0,
            valid_until: length / speed,
        }
    }

    /// Whether the load yields the material (two waves).
    pub fn is_plastic(&self) -> bool {
        self.plastic_strain > 0.0
    }

    /// `(σ_xx, v_x, ε̄)` at `X` and `t`.
    pub fn at(&self, x: f64, t: f64) -> (f64, f64, f64) {
        if x < self.plastic_speed * t {
            (self.behind.0, self.behind.1, self.plastic_strain)
        } else if x < self.elastic_speed * t {
            (self.precursor.0, self.precursor.1, 0.0)
        } else {
            (0.0, 0.0, 0.0)
        }
    }

    /// Averages of `σ_xx` and `v_x` over `[x0, x1]` at `t` (exact: piecewise constant).
    pub fn averages(&self, x0: f64, x1: f64, t: f64) -> (f64, f64) {
        let len = x1 - x0;
        let share = |front: f64| ((front - x0) / len).clamp(0.0, 1.0);
        let (behind, between) = (
            share(self.plastic_speed * t),
            share(self.elastic_speed * t) - share(self.plastic_speed * t),
        );
        (
            behind * self.behind.0 + between * self.precursor.0,
            behind * self.behind.1 + between * self.precursor.1,
        )
    }

    /// The precursor and (if plastic) the plastic wave at `t`, leading first. Each front's
    /// window ends halfway to the other, so the smeared plastic wave does not count as the
    /// precursor's overshoot, nor the precursor as the plastic wave's.
    pub fn fronts(&self, t: f64) -> Vec<Front> {
        let length = self.elastic_speed * self.valid_until;
        let middle = 0.5 * (self.plastic_speed + self.elastic_speed) * t;
        let mut out = vec![Front {
            position: self.elastic_speed * t,
            direction: 1.0,
            ahead: 0.0,
            behind: self.precursor.0,
            window: (if self.is_plastic() { middle } else { 0.0 }, length),
        }];
        if self.is_plastic() {
            out.push(Front {
                position: self.plastic_speed * t,
                direction: 1.0,
                ahead: self.precursor.0,
                behind: self.behind.0,
                window: (0.0, middle),
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plasticity::{PlasticState, Tensor3};
    use crate::LinearElastic;
    use approx::assert_relative_eq;

    fn steel() -> J2 {
        J2 {
            elastic: LinearElastic::new(2e11, 0.3, 7800.0),
            yield_stress: 4e8,
            hardening: 2e10,
        }
    }

    /// Each wave obeys the jump condition `ρ c [v] = −[σ]`, and the state behind the plastic
    /// wave is what the return map gives when driven along the path (uniaxial stress to the
    /// rod's strain, uniaxial strain to the plane wave's).
    #[test]
    fn jumps_and_states_agree_with_the_return_map() {
        let m = steel();
        let rho = m.elastic.density;
        let rod = ElastoplasticWave::rod(&m, 6.0, 8e8);
        let plane = ElastoplasticWave::plane(&m, 4.0, 20.0);
        for w in [rod, plane] {
            assert!(w.is_plastic() && w.plastic_speed < w.elastic_speed);
            let (s1, v1) = w.precursor;
            assert_relative_eq!(rho * w.elastic_speed * v1, -s1, max_relative = 1e-12);
            let (s2, v2) = w.behind;
            assert_relative_eq!(
                rho * w.plastic_speed * (v2 - v1),
                -(s2 - s1),
                max_relative = 1e-12
            );
        }
        // rod: total strain behind = −σ_y/E − (p − σ_y)/E_t, driven in 1e4 steps
        let strain = -4e8 / 2e11 - 4e8 / m.uniaxial_stress_tangent();
        let mut state = PlasticState::default();
        let mut sigma = 0.0;
        for _ in 0..10_000 {
            sigma = m
                .return_map_1d(sigma + 2e11 * strain / 1e4, &mut state)
                .stress;
        }
        assert_relative_eq!(sigma, rod.behind.0, max_relative = 1e-9);
        assert_relative_eq!(
            state.equivalent_plastic_strain,
            rod.plastic_strain,
            max_relative = 1e-9
        );
        // plane wave: strain behind = −(σ_H/M + (V − v_H)/c_p)
        let (_, v_h) = plane.precursor;
        let total = -(m.hugoniot_elastic_limit() / m.elastic.p_modulus::<2>()
            + (20.0 - v_h) / plane.plastic_speed);
        let mut state = PlasticState::default();
        let mut stress = Tensor3::zeros();
        for _ in 0..10_000 {
            let mut d = Tensor3::zeros();
            d[(0, 0)] = total / 1e4;
            stress = m.return_map(&m.trial(&stress, &d), &mut state).stress;
        }
        assert_relative_eq!(stress[(0, 0)], plane.behind.0, max_relative = 1e-9);
        assert_relative_eq!(
            state.equivalent_plastic_strain,
            plane.plastic_strain,
            max_relative = 1e-9
        );
    }

    /// Loads below yield give the elastic solutions; averages integrate the two steps.
    #[test]
    fn elastic_loads_and_averages() {
        let m = steel();
        let rod = ElastoplasticWave::rod(&m, 6.0, 3e8);
        assert!(!rod.is_plastic());
        assert_eq!(
            rod.behind,
            (-3e8, 3e8 / (7800.0 * (2e11f64 / 7800.0).sqrt()))
        );
        assert_eq!(rod.fronts(1e-4).len(), 1);
        let plane = ElastoplasticWave::plane(&m, 4.0, 1.0);
        assert!(!plane.is_plastic());
        let w = ElastoplasticWave::rod(&m, 6.0, 8e8);
        let t = 5e-4;
        let (x_p, x_e) = (w.plastic_speed * t, w.elastic_speed * t);
        let (lo, hi) = (x_p - 0.1, x_e + 0.1);
        let (s, _) = w.averages(lo, hi, t);
        let expected = (0.1 * w.behind.0 + (x_e - x_p) * w.precursor.0) / (hi - lo);
        assert_relative_eq!(s, expected, max_relative = 1e-12);
        assert_eq!(w.at(x_p - 1e-6, t).2, w.plastic_strain);
        assert_eq!(w.fronts(t)[1].ahead, w.precursor.0);
    }
}

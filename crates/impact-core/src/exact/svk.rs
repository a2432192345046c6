//! The Saint-Venant–Kirchhoff bar of paper §5.3 before the first reflection.
use super::{Front, NoFront};

/// Exact solution of the Saint-Venant–Kirchhoff bar of paper §5.3 before the wave reaches
/// the free end: at rest (`F = 1`), loaded at `X = 0` from `t = 0` by a step pressure `p`
/// (`Π(0,t) = -p`). With `F*` from `Π(F*) = -p`, `c(F) = sqrt(Π'(F)/ρ₀)` and
/// `φ(F) = ∫_1^F c`:
/// - compression (`p > 0`, `F* < 1`): a centred fan, `F = F*` for `X < c(F*) t`,
///   `c(F) = X/t` for `c(F*) t < X < c(1) t`, `F = 1` beyond; `v = -φ(F)` (the left-going
///   Riemann invariant `v + φ(F)` is 0 ahead);
/// - tension (`p < 0`, `F* > 1`): a shock at the Rankine–Hugoniot speed
///   `s = sqrt((Π(F*) - Π(1)) / (ρ₀ (F* - 1)))` with `v* = -s (F* - 1)` behind it.
#[derive(Debug, Clone, Copy)]
pub struct SvkBarExact {
    /// The material.
    pub material: crate::material::Svk,
    /// Bar length.
    pub length: f64,
    /// Pressure at `X = 0` (compression positive).
    pub pressure: f64,
    /// `F*` behind the wave.
    pub stretch: f64,
    /// `v*` behind the wave.
    pub velocity_behind: f64,
}

impl SvkBarExact {
    /// The solution for `pressure` (`None` at or beyond the hyperbolicity limit).
    pub fn new(material: crate::material::Svk, length: f64, pressure: f64) -> Option<Self> {
        let stretch = material.stretch_for_1d(-pressure)?;
        let velocity_behind = if stretch <= 1.0 {
            -material.riemann_phi_1d(stretch)
        } else {
            -Self::shock_speed_of(&material, stretch) * (stretch - 1.0)
        };
        Some(Self {
            material,
            length,
            pressure,
            stretch,
            velocity_behind,
        })
    }

    fn shock_speed_of(m: &crate::material::Svk, stretch: f64) -> f64 {
        (m.piola_1d(stretch) / (m.linear.density * (stretch - 1.0))).sqrt()
    }

    /// Whether the wave is a shock (tension).
    pub fn is_shock(&self) -> bool {
        self.stretch > 1.0
    }

    /// Rankine–Hugoniot speed of the tension shock.
    pub fn shock_speed(&self) -> f64 {
        Self::shock_speed_of(&self.material, self.stretch)
    }

    /// Speed of the leading edge of the wave (`c(1)` for the fan, `s` for the shock).
    pub fn leading_speed(&self) -> f64 {
        if self.is_shock() {
            self.shock_speed()
        } else {
            self.material.wave_speed_1d(1.0)
        }
    }

    /// Last time the solution holds (the wave reaches the free end).
    pub fn valid_until(&self) -> f64 {
        self.length / self.leading_speed()
    }

    /// `(F, v)` at `(X, t)`.
    pub fn state(&self, x: f64, t: f64) -> (f64, f64) {
        if t <= 0.0 {
            return (1.0, 0.0);
        }
        let xi = x / t;
        let m = &self.material;
        if self.is_shock() {
            if xi < self.shock_speed() {
                (self.stretch, self.velocity_behind)
            } else {
                (1.0, 0.0)
            }
        } else if xi <= m.wave_speed_1d(self.stretch) {
            (self.stretch, self.velocity_behind)
        } else if xi >= m.wave_speed_1d(1.0) {
            (1.0, 0.0)
        } else {
            // c(F) = ξ: F = sqrt((2ρ₀ ξ²/E + 1)/3)
            let f =
                ((2.0 * m.linear.density * xi * xi / m.linear.elastic.young + 1.0) / 3.0).sqrt();
            (f, -m.riemann_phi_1d(f))
        }
    }

    /// `Π(X, t)`.
    pub fn piola(&self, x: f64, t: f64) -> f64 {
        self.material.piola_1d(self.state(x, t).0)
    }

    /// Averages of `Π` and `v` over `[x0, x1]`: exact off the fan, 8-point Gauss–Legendre
    /// on the part of the interval inside it.
    pub fn averages(&self, x0: f64, x1: f64, t: f64) -> (f64, f64) {
        const G: [(f64, f64); 4] = [
            (0.183_434_642_495_649_8, 0.362_683_783_378_362),
            (0.525_532_409_916_329, 0.313_706_645_877_887_3),
            (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
            (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
        ];
        let m = &self.material;
        let mut cuts = vec![x0, x1];
        if !self.is_shock() && t > 0.0 {
            for edge in [m.wave_speed_1d(self.stretch) * t, m.wave_speed_1d(1.0) * t] {
                if edge > x0 && edge < x1 {
                    cuts.push(edge);
                }
            }
        } else if t > 0.0 {
            let edge = self.shock_speed() * t;
            if edge > x0 && edge < x1 {
                cuts.push(edge);
            }
        }
        cuts.sort_by(f64::total_cmp);
        let (mut p, mut v) = (0.0, 0.0);
        for w in cuts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for &(node, weight) in &G {
                for x in [mid - half * node, mid + half * node] {
                    let (f, vel) = self.state(x, t);
                    p += weight * half * m.piola_1d(f);
                    v += weight * half * vel;
                }
            }
        }
        (p / (x1 - x0), v / (x1 - x0))
    }

    /// Work of the load, `p v* t` (the end moves at `v*` from the start).
    pub fn work(&self, t: f64) -> f64 {
        self.pressure * self.velocity_behind * t
    }

    /// The leading front at `t` (while the solution holds).
    pub fn leading_front(&self, t: f64) -> Result<Front, NoFront> {
        let position = self.leading_speed() * t;
        if position <= 0.0 {
            return Err(NoFront::NotYetFormed);
        }
        if position >= self.length {
            return Err(NoFront::LeftTheBody);
        }
        Ok(Front {
            position,
            direction: 1.0,
            ahead: 0.0,
            behind: -self.pressure,
            window: (0.0, self.length),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{LinearElastic, Svk};
    use approx::assert_relative_eq;

    fn svk() -> Svk {
        Svk::new(LinearElastic::new(2e11, 0.3, 7800.0))
    }

    #[test]
    fn compression_fan_is_continuous_and_keeps_the_riemann_invariant() {
        let e = SvkBarExact::new(svk(), 6.0, 8e8).unwrap();
        assert!(!e.is_shock() && e.stretch < 1.0);
        assert_relative_eq!(svk().piola_1d(e.stretch), -8e8, max_relative = 1e-12);
        let t = 5e-4;
        let (c_star, c0) = (svk().wave_speed_1d(e.stretch), svk().wave_speed_1d(1.0));
        // continuous at both edges of the fan
        let (f_in, _) = e.state(c_star * t * (1.0 + 1e-9), t);
        assert_relative_eq!(f_in, e.stretch, max_relative = 1e-6);
        let (f_out, _) = e.state(c0 * t * (1.0 - 1e-9), t);
        assert_relative_eq!(f_out, 1.0, max_relative = 1e-6);
        // v + φ(F) = 0 everywhere
        for k in 0..20 {
            let x = (c_star + (c0 - c_star) * k as f64 / 19.0) * t;
            let (f, v) = e.state(x, t);
            assert!((v + svk().riemann_phi_1d(f)).abs() < 1e-9);
        }
        // energy balance: kinetic + strain energy = p v* t
        let n = 200_000;
        let dx = c0 * t * 1.2 / n as f64;
        let mut energy = 0.0;
        for i in 0..n {
            let (f, v) = e.state((i as f64 + 0.5) * dx, t);
            energy += dx * (0.5 * 7800.0 * v * v + 2e11 / 8.0 * (f * f - 1.0).powi(2));
        }
        assert_relative_eq!(energy, e.work(t), max_relative = 1e-4);
    }

    #[test]
    fn tension_shock_satisfies_rankine_hugoniot_and_lax() {
        let m = svk();
        let e = SvkBarExact::new(m, 6.0, -8e8).unwrap();
        assert!(e.is_shock() && e.stretch > 1.0);
        let s = e.shock_speed();
        // [Π] = ρ₀ s² [F] and [v] = -s [F]
        assert_relative_eq!(
            m.piola_1d(e.stretch),
            7800.0 * s * s * (e.stretch - 1.0),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            -e.velocity_behind,
            s * (e.stretch - 1.0),
            max_relative = 1e-12
        );
        assert!(m.wave_speed_1d(1.0) < s && s < m.wave_speed_1d(e.stretch));
        let t = 5e-4;
        assert_eq!(e.state(s * t * 0.999, t).0, e.stretch);
        assert_eq!(e.state(s * t * 1.001, t).0, 1.0);
        let (p, _) = e.averages(s * t - 0.01, s * t + 0.03, t);
        assert_relative_eq!(p, 0.25 * m.piola_1d(e.stretch), max_relative = 1e-9);
    }

    #[test]
    fn loads_beyond_the_hyperbolicity_limit_have_no_solution() {
        let (_, pi_min) = svk().hyperbolicity_limit_1d();
        assert!(SvkBarExact::new(svk(), 6.0, -pi_min).is_none());
        assert!(SvkBarExact::new(svk(), 6.0, -pi_min * 0.99).is_some());
    }
}

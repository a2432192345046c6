//! Exact solutions.
//!
//! [`BarExact`]: the elastic bar `0 < X < L` of §5.1, at rest, loaded at `X = 0` from
//! `t = 0` by a step pressure `p` (traction `σ(0,t) = -p`) or a step velocity `v_d`, free
//! at `X = L`. By d'Alembert with images (Wang 2011, ch. 2), with `c = sqrt(M/ρ)`
//! (`M = E` for the bar, `λ + 2μ` for a plane wave in plane strain), `Z = ρ c` and `H` the
//! Heaviside step, the solution is a sum of step waves. The first right-going wave carries
//! `(Δσ, Δv) = (-p, p/Z)` (pressure) or `(-Z v_d, v_d)` (velocity); the free end reflects
//! `(Δσ, Δv) → (-Δσ, Δv)`; the loaded end reflects `(Δσ, Δv) → (-Δσ, Δv)` under a
//! pressure and `(Δσ, -Δv)` under a velocity. For the pressure load:
//!
//! `σ(X,t) = -p Σ_k H(ct - 2kL - X) + p Σ_k H(ct - 2(k+1)L + X)`,
//! `v(X,t) = p/Z [Σ_k H(ct - 2kL - X) + Σ_k H(ct - 2(k+1)L + X)]`, `k = 0, 1, ...`
//!
//! Cell averages integrate each Heaviside exactly, and the displacement
//! `u = ∫ v dt` uses `∫_0^t H(cs - a) ds = max(0, t - a/c)`.
//!
//! A load with a time history `p g(t)` ([`crate::load`]) superposes the same waves with
//! `H(ct - a)` replaced by `g(t - a/c)` (the problem is linear). Averages and the
//! displacement then use `I(τ) = ∫_0^τ g`: the average of `g(t - (off + slope X)/c)` over
//! `[x0, x1]` is `c |I(τ(x0)) - I(τ(x1))| / (x1 - x0)`, and `u` uses `I(t - a/c)`; for a
//! step `I(τ) = max(τ, 0)` gives back the Heaviside formulas. The work of a history load
//! is integrated numerically (composite Simpson between the returns of the wave).
//!
//! [`SvkBarExact`] (file `svk.rs`): the Saint-Venant–Kirchhoff bar of §5.3.
//!
//! [`ElastoplasticWave`] (file `plastic.rs`): the elastic precursor and plastic wave of a
//! J2 rod or plane wave under a step load (issue 12).
//!
//! [`StandingWave`] (file `standing.rs`): a smooth standing P mode with roller edges, the
//! exact solution of the convergence suite.
mod plastic;
mod standing;
mod svk;
use crate::load::LoadHistory;
pub use plastic::ElastoplasticWave;
pub use standing::StandingWave;
pub use svk::SvkBarExact;

/// Load at `X = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EndLoad {
    /// Step pressure (positive in compression).
    Pressure(f64),
    /// Step velocity into the bar.
    Velocity(f64),
}

/// Exact solution of the loaded bar (see the module doc).
#[derive(Debug, Clone, Copy)]
pub struct BarExact {
    /// Bar length `L`.
    pub length: f64,
    /// Wave speed `c`.
    pub speed: f64,
    /// Impedance `Z = ρ c`.
    pub impedance: f64,
    /// Magnitude of the stress jump of the first wave, `p` or `Z v_d` (compression
    /// positive).
    pub pressure: f64,
    /// The load.
    pub load: EndLoad,
    /// The load's time history `g(t)` (a step in the paper).
    pub history: LoadHistory,
}

/// A discontinuity of the exact solution at time `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Front {
    /// Position.
    pub position: f64,
    /// `+1` if the front moves towards larger `X` (the undisturbed side is at larger `X`).
    pub direction: f64,
    /// Value just ahead of the front (not yet reached).
    pub ahead: f64,
    /// Value just behind the front.
    pub behind: f64,
    /// Interval in which this front is the only discontinuity.
    pub window: (f64, f64),
}

/// Why a reference has no measurable front at some time: the front metrics (width,
/// overshoot, position) and the gate report this reason instead of a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum NoFront {
    /// The load is not a step (a ramp or sine starts with a kink, not a jump; a smooth
    /// initial state has no discontinuity).
    NotAStep,
    /// The front has not yet moved far enough from the loaded face to be resolved.
    NotYetFormed,
    /// The front has reached the far side of the body (or left the measured line).
    LeftTheBody,
    /// Another discontinuity lies within the measuring window (fronts merged or crossing).
    Merged,
    /// The jump across the front is too small against the load's stress scale to measure
    /// a width or an overshoot relative to it.
    JumpTooSmall,
    /// The reference behind the front is not a plateau (it varies by more than the jump
    /// within the window), so width and overshoot relative to the jump are meaningless.
    NoPlateau,
    /// The run has no reference solution.
    NoReference,
    /// The reference is past the time it holds for.
    PastValidity,
}

impl NoFront {
    /// A sentence for tables and reports.
    pub fn describe(self) -> &'static str {
        match self {
            NoFront::NotAStep => "no front: the load is not a step (no jump to measure)",
            NoFront::NotYetFormed => "no front yet: it is within 1.5 cells of the loaded face",
            NoFront::LeftTheBody => "no front: it has reached the far side of the body",
            NoFront::Merged => "no front: another discontinuity lies within the measuring window",
            NoFront::JumpTooSmall => {
                "no front: the jump across it is under 5 % of the load's stress scale"
            }
            NoFront::NoPlateau => {
                "no front: the reference behind it is not a plateau (varies by more than the jump)"
            }
            NoFront::NoReference => "no front: the run has no reference solution",
            NoFront::PastValidity => "no front: past the time the reference holds for",
        }
    }
}

impl BarExact {
    /// Build from bar length, density, modulus and pressure.
    pub fn new(length: f64, density: f64, young: f64, pressure: f64) -> Self {
        Self::with_load(length, density, young, EndLoad::Pressure(pressure))
    }

    /// Build from length, density, longitudinal modulus `M` and the end load.
    pub fn with_load(length: f64, density: f64, modulus: f64, load: EndLoad) -> Self {
        let speed = (modulus / density).sqrt();
        let impedance = density * speed;
        let pressure = match load {
            EndLoad::Pressure(p) => p,
            EndLoad::Velocity(v) => impedance * v,
        };
        Self {
            length,
            speed,
            impedance,
            pressure,
            load,
            history: LoadHistory::Step,
        }
    }

    /// The same bar under the load `p g(t)`.
    pub fn with_history(mut self, history: LoadHistory) -> Self {
        self.history = history;
        self
    }

    /// `g` of the wave that reaches `X` when `c t = offset + slope X`.
    #[inline]
    fn arrival_factor(&self, t: f64, offset: f64, slope: f64, x: f64) -> f64 {
        let tau = t - (offset + slope * x) / self.speed;
        if tau <= 0.0 {
            0.0
        } else {
            self.history.factor(tau)
        }
    }

    /// Average over `[x0, x1]` of the wave's `g` (module doc).
    fn covered_history(&self, t: f64, off: f64, slope: f64, x0: f64, x1: f64) -> f64 {
        if self.history.is_step() {
            return Self::covered(self.speed * t, off, slope, x0, x1);
        }
        let tau = |x: f64| t - (off + slope * x) / self.speed;
        let span = (self.history.integral(tau(x0)) - self.history.integral(tau(x1))) * slope;
        span * self.speed / (x1 - x0)
    }

    /// Signs `(s_σ, s_v)` of wave `n` (0, 1, 2, ... in order of creation: right, left,
    /// right, ...) relative to `(-p, p/Z)`.
    fn signs(&self, n: usize) -> (f64, f64) {
        let (mut ss, mut sv) = (1.0, 1.0);
        for k in 0..n {
            if k % 2 == 0 {
                ss = -ss; // free end
            } else {
                match self.load {
                    EndLoad::Pressure(_) => ss = -ss,
                    EndLoad::Velocity(_) => sv = -sv,
                }
            }
        }
        (ss, sv)
    }

    /// Call `f(offset, slope, s_σ, s_v)` for each wave that has started: it reaches `X`
    /// when `c t > offset + slope X` (right-going `2kL + X`, left-going `2(k+1)L - X`) and
    /// carries `(Δσ, Δv) = (-s_σ p, s_v p/Z)`.
    fn waves(&self, t: f64, mut f: impl FnMut(f64, f64, f64, f64)) {
        let travelled = self.speed * t;
        let mut k = 0usize;
        loop {
            let right = 2.0 * k as f64 * self.length;
            let left = 2.0 * (k + 1) as f64 * self.length;
            if right > travelled {
                break;
            }
            let (ss, sv) = self.signs(2 * k);
            f(right, 1.0, ss, sv);
            if left - self.length <= travelled {
                let (ss, sv) = self.signs(2 * k + 1);
                f(left, -1.0, ss, sv);
            }
            k += 1;
        }
    }

    /// Point value of `σ(X,t)`.
    pub fn stress(&self, x: f64, t: f64) -> f64 {
        let mut s = 0.0;
        self.waves(t, |off, slope, ss, _| {
            s -= ss * self.pressure * self.arrival_factor(t, off, slope, x);
        });
        s
    }

    /// Point value of `v(X,t)`.
    pub fn velocity(&self, x: f64, t: f64) -> f64 {
        let mut v = 0.0;
        self.waves(t, |off, slope, _, sv| {
            v += sv * self.pressure / self.impedance * self.arrival_factor(t, off, slope, x);
        });
        v
    }

    /// Fraction of `[x0, x1]` where `ct - off - slope X > 0`.
    fn covered(ct: f64, off: f64, slope: f64, x0: f64, x1: f64) -> f64 {
        // the set is X < ct - off for slope +1, X > off - ct for slope -1
        let len = x1 - x0;
        if slope > 0.0 {
            ((ct - off - x0) / len).clamp(0.0, 1.0)
        } else {
            ((x1 - (off - ct)) / len).clamp(0.0, 1.0)
        }
    }

    /// Average of `σ` over `[x0, x1]` at time `t`.
    pub fn stress_average(&self, x0: f64, x1: f64, t: f64) -> f64 {
        let mut s = 0.0;
        self.waves(t, |off, slope, ss, _| {
            s -= ss * self.pressure * self.covered_history(t, off, slope, x0, x1);
        });
        s
    }

    /// Average of `v` over `[x0, x1]` at time `t`.
    pub fn velocity_average(&self, x0: f64, x1: f64, t: f64) -> f64 {
        let mut v = 0.0;
        self.waves(t, |off, slope, _, sv| {
            v += sv * self.pressure / self.impedance * self.covered_history(t, off, slope, x0, x1);
        });
        v
    }

    /// Displacement `u(X,t) = ∫_0^t v(X,s) ds`.
    pub fn displacement(&self, x: f64, t: f64) -> f64 {
        let mut u = 0.0;
        self.waves(t, |off, slope, _, sv| {
            let arrival = (off + slope * x) / self.speed;
            u += sv * self.pressure / self.impedance * self.history.integral(t - arrival);
        });
        u
    }

    /// Work done by the load on a unit cross-section: `W = p u(0,t)` for a pressure; for a
    /// velocity `W = ∫ -σ(0,s) v_d ds`, with `σ(0,·)` piecewise constant between the
    /// returns of the wave.
    pub fn work(&self, t: f64) -> f64 {
        if !self.history.is_step() {
            return self.history_work(t);
        }
        match self.load {
            EndLoad::Pressure(p) => p * self.displacement(0.0, t),
            EndLoad::Velocity(v) => {
                // integrate -σ(0^+, s) v over [0, t] exactly: σ changes at s = 2kL/c
                let period = 2.0 * self.length / self.speed;
                let mut w = 0.0;
                let mut s0 = 0.0;
                while s0 < t {
                    let s1 = (s0 + period).min(t);
                    let mid = 0.5 * (s0 + s1);
                    w += -self.stress(1e-12 * self.length, mid) * v * (s1 - s0);
                    s0 = s1;
                }
                w
            }
        }
    }

    /// Work of a history load, `∫ -σ(0,s) v(0,s) ds`, by composite Simpson on each interval
    /// between the returns of the wave and their copies delayed by the history's
    /// breakpoint (where the integrand jumps or kinks).
    fn history_work(&self, t: f64) -> f64 {
        let period = 2.0 * self.length / self.speed;
        let at_end = 1e-12 * self.length;
        let power = |s: f64| -self.stress(at_end, s) * self.velocity(at_end, s);
        let mut breaks = vec![0.0, t];
        let mut k = 0.0;
        while k * period < t {
            breaks.push(k * period);
            if let Some(b) = self.history.breakpoint() {
                breaks.push(k * period + b);
            }
            k += 1.0;
        }
        breaks.retain(|&b| (0.0..=t).contains(&b));
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        let mut work = 0.0;
        for pair in breaks.windows(2) {
            let (s0, s1) = (pair[0], pair[1]);
            let n = 200;
            let h = (s1 - s0) / n as f64;
            // one-sided values at the ends: the integrand may jump there
            let shrink = 1e-9 * h;
            let mut sum = power(s0 + shrink) + power(s1 - shrink);
            for j in 1..n {
                sum += power(s0 + j as f64 * h) * if j % 2 == 1 { 4.0 } else { 2.0 };
            }
            work += sum * h / 3.0;
        }
        work
    }

    /// Kinetic plus strain energy; equals [`Self::work`] (no dissipation).
    pub fn energy(&self, t: f64) -> f64 {
        self.work(t)
    }

    /// The most recent discontinuity inside the bar at `t` (the leading front), with the
    /// stress on both sides and the interval where it is the only one.
    /// Only a step load has one (a ramp or sine starts with a kink, not a jump).
    pub fn leading_front(&self, t: f64) -> Result<Front, NoFront> {
        let ct = self.speed * t;
        let l = self.length;
        if !self.history.is_step() {
            return Err(NoFront::NotAStep);
        }
        if ct <= 0.0 {
            return Err(NoFront::NotYetFormed);
        }
        // number of full bar transits completed
        let transits = (ct / l).floor();
        let r = ct - transits * l;
        if r <= 0.0 || r >= l {
            return Err(NoFront::LeftTheBody);
        }
        let (position, direction) = if (transits as usize).is_multiple_of(2) {
            (r, 1.0)
        } else {
            (l - r, -1.0)
        };
        let eps = 1e-9 * l;
        let ahead = self.stress(position + direction * eps, t);
        let behind = self.stress(position - direction * eps, t);
        Ok(Front {
            position,
            direction,
            ahead,
            behind,
            window: (0.0, l),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn bar() -> BarExact {
        BarExact::new(6.0, 7800.0, 2e11, 1e9)
    }

    #[test]
    fn first_transit_is_a_step() {
        let b = bar();
        let t = 3.0 / b.speed;
        assert_eq!(b.stress(2.9, t), -1e9);
        assert_eq!(b.stress(3.1, t), 0.0);
        assert_relative_eq!(b.velocity(1.0, t), 1e9 / b.impedance);
        assert_relative_eq!(b.stress_average(2.9, 3.1, t), -0.5e9, max_relative = 1e-12);
    }

    #[test]
    fn free_end_reflection_cancels_stress_and_doubles_velocity() {
        let b = bar();
        let t = 8.0 / b.speed; // front reflected, now at X = 4
        assert_eq!(b.stress(5.0, t), 0.0);
        assert_eq!(b.stress(3.0, t), -1e9);
        assert_relative_eq!(b.velocity(5.0, t), 2e9 / b.impedance);
        let f = b.leading_front(t).unwrap();
        assert_relative_eq!(f.position, 4.0, max_relative = 1e-12);
        assert_eq!((f.direction, f.ahead, f.behind), (-1.0, -1e9, 0.0));
    }

    #[test]
    fn loaded_end_reflection_keeps_traction() {
        let b = bar();
        let t = 14.0 / b.speed; // after reflecting from X = 0 again, front at X = 2
        assert_relative_eq!(b.stress(0.0 + 1e-9, t), -1e9);
        assert_relative_eq!(b.stress(1.0, t), -1e9);
        assert_eq!(b.stress(3.0, t), 0.0);
        assert_relative_eq!(b.velocity(1.0, t), 3e9 / b.impedance);
    }

    #[test]
    fn velocity_load_reflects_into_tension_at_the_bonded_end() {
        let b = BarExact::with_load(6.0, 7800.0, 2e11, EndLoad::Velocity(5.0));
        let z = b.impedance;
        let t = 3.0 / b.speed;
        assert_relative_eq!(b.stress(1.0, t), -z * 5.0, max_relative = 1e-12);
        assert_relative_eq!(b.velocity(1.0, t), 5.0, max_relative = 1e-12);
        // after the free-end reflection: stress relieved, velocity doubled
        let t = 9.0 / b.speed;
        assert_eq!(b.stress(5.0, t), 0.0);
        assert_relative_eq!(b.velocity(5.0, t), 10.0, max_relative = 1e-12);
        // after the return to the bonded end: velocity back to v_d, tension Z v_d
        let t = 15.0 / b.speed;
        assert_relative_eq!(b.velocity(1.0, t), 5.0, max_relative = 1e-12);
        assert_relative_eq!(b.stress(1.0, t), z * 5.0, max_relative = 1e-12);
    }

    /// A history load: point values follow `g` delayed by the travel time, cell averages
    /// agree with a fine midpoint rule of the point values, and the energy equals the work.
    #[test]
    fn history_loads_delay_the_end_history() {
        let period = 1.5e-3;
        for history in [
            LoadHistory::Ramp { rise: 0.4e-3 },
            LoadHistory::Sine { period },
            LoadHistory::Pulse { duration: 0.3e-3 },
        ] {
            let b = bar().with_history(history);
            let t = 1.6e-3; // after one reflection from the free end (L/c = 1.18 ms)
            let x = 1.0;
            let direct = -1e9 * history.factor(t - x / b.speed);
            let reflected = 1e9 * history.factor(t - (2.0 * b.length - x) / b.speed);
            assert_relative_eq!(b.stress(x, t), direct + reflected, epsilon = 1e-3);
            let (x0, x1) = (0.7, 1.3);
            let n = 20_000;
            let dx = (x1 - x0) / n as f64;
            let mid: f64 = (0..n)
                .map(|i| b.stress(x0 + (i as f64 + 0.5) * dx, t))
                .sum::<f64>()
                / n as f64;
            assert_relative_eq!(b.stress_average(x0, x1, t), mid, epsilon = 2e3);
            let e: f64 = {
                let n = 60_000;
                let dx = b.length / n as f64;
                (0..n)
                    .map(|i| {
                        let x = (i as f64 + 0.5) * dx;
                        let (s, v) = (b.stress(x, t), b.velocity(x, t));
                        dx * (0.5 * 7800.0 * v * v + 0.5 * s * s / 2e11)
                    })
                    .sum()
            };
            assert_relative_eq!(e, b.work(t), max_relative = 1e-3);
            assert_eq!(b.leading_front(t), Err(NoFront::NotAStep));
        }
    }

    #[test]
    fn energy_balance_of_exact_solution() {
        // kinetic + strain energy integrated from point values equals p·u(0,t)
        let rho = 7800.0;
        let young = 2e11;
        for (b, &t) in [
            bar(),
            BarExact::with_load(6.0, 7800.0, 2e11, EndLoad::Velocity(5.0)),
        ]
        .iter()
        .flat_map(|b| {
            [0.4e-3, 1.0e-3, 1.9e-3, 3.3e-3]
                .iter()
                .map(move |t| (*b, t))
        }) {
            let n = 60_000;
            let dx = b.length / n as f64;
            let mut e = 0.0;
            for i in 0..n {
                let x = (i as f64 + 0.5) * dx;
                let s = b.stress(x, t);
                let v = b.velocity(x, t);
                e += dx * (0.5 * rho * v * v + 0.5 * s * s / young);
            }
            assert_relative_eq!(e, b.work(t), max_relative = 1e-3);
        }
    }
}

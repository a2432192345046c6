//! The work of the loads on [`BarExact`] (module doc of `bar.rs`): exact for step loads,
//! Gauss–Legendre between the breakpoints of the power otherwise.
use super::bar::{BarEnd, BarExact};
use super::bar_initial::gauss;
use crate::load::LoadHistory;

impl BarExact {
    /// Work done by the loads on a unit cross-section up to `t` (module doc).
    pub fn work(&self, t: f64) -> f64 {
        (0..2).map(|end| self.end_work(end, t)).sum()
    }

    /// Work of the load at end `end` (0 at `X = 0`, 1 at `X = L`).
    fn end_work(&self, end: usize, t: f64) -> f64 {
        let amplitude = self.ends[end].amplitude(self.impedance);
        if amplitude == 0.0 || t <= 0.0 {
            return 0.0;
        }
        let x = if end == 0 { 0.0 } else { self.length };
        // outward normal: traction on the body σ n, velocity into the bar n_in = -n
        let normal = if end == 0 { -1.0 } else { 1.0 };
        let only_steps = self.initial.is_none()
            && self
                .ends
                .iter()
                .all(|e| e.amplitude(self.impedance) == 0.0 || e.history().is_step());
        match self.ends[end] {
            BarEnd::Traction { pressure, history } if history.is_step() => {
                // t·v = -p n·v: W = -p n u(end, t)
                -pressure * normal * self.displacement(x, t)
            }
            BarEnd::Velocity { velocity, history } if history.is_step() => {
                // t·v = σ n (-v_d n) = -σ v_d
                if only_steps {
                    self.piecewise_velocity_work(end, velocity, t)
                } else {
                    -velocity * self.stress_impulse(x, t)
                }
            }
            _ => self.quadrature_work(end, t),
        }
    }

    /// `-v_d ∫_0^t σ(end, s) ds` for step waves: `σ(end, ·)` is piecewise constant
    /// between the returns of the waves, each interval taken at its middle (just inside
    /// the bar).
    fn piecewise_velocity_work(&self, end: usize, velocity: f64, t: f64) -> f64 {
        let loaded = self
            .ends
            .iter()
            .filter(|e| e.amplitude(self.impedance) != 0.0);
        // the stress at an end changes at multiples of 2L/c (one source) or L/c (two)
        let period = if loaded.count() == 1 { 2.0 } else { 1.0 } * self.length / self.speed;
        let x = if end == 0 {
            1e-12 * self.length
        } else {
            self.length * (1.0 - 1e-12)
        };
        let (mut w, mut s0) = (0.0, 0.0);
        while s0 < t {
            let s1 = (s0 + period).min(t);
            let mid = 0.5 * (s0 + s1);
            w += -self.stress(x, mid) * velocity * (s1 - s0);
            s0 = s1;
        }
        w
    }

    /// `∫_0^t σ n · v ds` at end `end` by Gauss–Legendre between the breakpoints (module
    /// doc).
    fn quadrature_work(&self, end: usize, t: f64) -> f64 {
        let x = if end == 0 { 0.0 } else { self.length };
        let normal = if end == 0 { -1.0 } else { 1.0 };
        let transit = self.length / self.speed;
        let mut step = 0.25 * transit;
        let mut delays = vec![0.0];
        for e in &self.ends {
            match e.history() {
                LoadHistory::Sine { period } => step = step.min(period / 8.0),
                LoadHistory::Ramp { rise: b }
                | LoadHistory::SmoothRamp { rise: b }
                | LoadHistory::Pulse { duration: b } => delays.push(b),
                LoadHistory::Step => {}
            }
        }
        let mut breaks = vec![0.0, t];
        let mut k = 0.0;
        while k * transit < t {
            for d in &delays {
                breaks.push(k * transit + d);
            }
            k += 1.0;
        }
        breaks.retain(|&b| (0.0..=t).contains(&b));
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        let power = |s: f64| normal * self.stress(x, s) * self.velocity(x, s);
        breaks
            .windows(2)
            .map(|w| gauss(w[0], w[1], ((w[1] - w[0]) / step).ceil() as usize, power))
            .sum()
    }
}

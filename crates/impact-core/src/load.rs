//! Time histories of boundary loads: a load of magnitude `p` (a pressure in Pa or a
//! velocity in m/s) acts as `p g(t)` with `g` one of
//!
//! - `step`: `g(t) = 1` (the paper's loads, §5);
//! - `ramp`: `g(t) = min(t/T, 1)`, a linear rise over `T`, then constant;
//! - `sine`: `g(t) = sin(2π t/T)`, period `T`;
//! - `pulse`: `g(t) = 1` for `t < T`, then 0 (a finite square pulse of length `T`).
//!
//! `g(t) = 0` for `t < 0`. The exact bar solutions superpose delayed copies of `g`, and
//! their cell averages need its integral `I(t) = ∫_0^t g(s) ds`, given in closed form by
//! [`LoadHistory::integral`].
use crate::options::LoadShape;
use std::f64::consts::PI;

/// A load's time history `g(t)` (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LoadHistory {
    /// `g = 1`.
    #[default]
    Step,
    /// `g = min(t/rise, 1)`.
    Ramp {
        /// Rise time `T` (s).
        rise: f64,
    },
    /// `g = sin(2π t/period)`.
    Sine {
        /// Period `T` (s).
        period: f64,
    },
    /// `g = 1` for `t < duration`, then 0.
    Pulse {
        /// Length `T` of the pulse (s).
        duration: f64,
    },
}

impl LoadHistory {
    /// The history of `shape` with time scale `duration` (rise time, period or pulse
    /// length; unused by `step`).
    pub fn new(shape: LoadShape, duration: f64) -> Self {
        match shape {
            LoadShape::Step => LoadHistory::Step,
            LoadShape::Ramp => LoadHistory::Ramp { rise: duration },
            LoadShape::Sine => LoadHistory::Sine { period: duration },
            LoadShape::Pulse => LoadHistory::Pulse { duration },
        }
    }

    /// `g(t)`.
    #[inline]
    pub fn factor(&self, t: f64) -> f64 {
        if t < 0.0 {
            return 0.0;
        }
        match *self {
            LoadHistory::Step => 1.0,
            LoadHistory::Ramp { rise } => (t / rise).min(1.0),
            LoadHistory::Sine { period } => (2.0 * PI * t / period).sin(),
            LoadHistory::Pulse { duration } => {
                if t < duration {
                    1.0
                } else {
                    0.0
                }
            }
        }
    }

    /// `I(t) = ∫_0^t g(s) ds` (0 for `t ≤ 0`).
    pub fn integral(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        match *self {
            LoadHistory::Step => t,
            LoadHistory::Ramp { rise } => {
                if t < rise {
                    0.5 * t * t / rise
                } else {
                    t - 0.5 * rise
                }
            }
            LoadHistory::Sine { period } => {
                period / (2.0 * PI) * (1.0 - (2.0 * PI * t / period).cos())
            }
            LoadHistory::Pulse { duration } => t.min(duration),
        }
    }

    /// The time after `t = 0` where `g` jumps or has a kink (ramp end, pulse end).
    pub fn breakpoint(&self) -> Option<f64> {
        match *self {
            LoadHistory::Ramp { rise } => Some(rise),
            LoadHistory::Pulse { duration } => Some(duration),
            LoadHistory::Step | LoadHistory::Sine { .. } => None,
        }
    }

    /// Whether `g` jumps from 0 to 1 at `t = 0` and stays there (the step loads whose
    /// fronts the front metrics measure).
    pub fn is_step(&self) -> bool {
        matches!(self, LoadHistory::Step)
    }

    /// The shape's name and time scale (0 for a step).
    pub fn shape(&self) -> (LoadShape, f64) {
        match *self {
            LoadHistory::Step => (LoadShape::Step, 0.0),
            LoadHistory::Ramp { rise } => (LoadShape::Ramp, rise),
            LoadHistory::Sine { period } => (LoadShape::Sine, period),
            LoadHistory::Pulse { duration } => (LoadShape::Pulse, duration),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `I' = g`: the closed-form integral against a fine midpoint rule, for every shape.
    #[test]
    fn integral_is_the_antiderivative_of_the_factor() {
        for shape in LoadShape::ALL {
            let history = LoadHistory::new(shape, 0.3);
            for &t in &[0.05, 0.2999, 0.3, 0.45, 1.1] {
                let n = 200_000;
                let h = t / n as f64;
                let sum: f64 = (0..n)
                    .map(|k| history.factor((k as f64 + 0.5) * h) * h)
                    .sum();
                assert!(
                    (sum - history.integral(t)).abs() < 1e-5,
                    "{shape}: t = {t}: {sum} against {}",
                    history.integral(t)
                );
            }
            assert_eq!(history.factor(-1e-9), 0.0);
            assert_eq!(history.integral(-1.0), 0.0);
        }
    }
}

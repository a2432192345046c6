//! [`BarExact`]: the elastic bar `0 < X < L` (or a plane wave in uniaxial strain) with
//! any condition at each end, by d'Alembert with images (Wang 2011, ch. 2; Graff §1.1).
//!
//! Each end is a traction end (`σ n = -p g(t)`, free for `p = 0`) or a velocity end
//! (velocity `v_d g(t)` into the bar; fixed or symmetry for `v_d = 0`; in 1D a symmetry
//! end is a fixed end), with `c = sqrt(M/ρ)` (`M = E` for the bar, `λ + 2μ` for a plane
//! wave), `Z = ρ c`. The problem is linear: the solution is the sum of the wave train of
//! each loaded end and of the initial state's waves ([`super::bar_initial`]).
//!
//! A load at `X = 0` sends a right-going wave `(Δσ, Δv) = (-P, P/Z) g(t - X/c)`, a load at
//! `X = L` a left-going one `(-P, -P/Z) g(t - (L - X)/c)`, `P = p` (pressure) or `Z v_d`
//! (velocity). A wave reflecting from a traction end flips `Δσ` and keeps `Δv`; from a
//! velocity end it flips `Δv` and keeps `Δσ`. Wave `n` of the end `s` reaches `X` when
//! `c t = nL + X` (moving right, `n + s` even) or `nL + L - X` (moving left), so
//!
//! `σ(X,t) = -Σ s_σ,n P g(τ_n)`, `v(X,t) = Σ s_v,n (P/Z) g(τ_n)`,
//! `τ_n = t - (offset_n + slope_n X)/c`,
//!
//! with the signs `s_σ, s_v = ±1` of the reflections so far. Cell averages integrate each
//! wave exactly with `I(τ) = ∫_0^τ g` ([`crate::load::LoadHistory::integral`]): the average
//! of `g(τ(X))` over `[x0, x1]` is `c slope (I(τ(x0)) - I(τ(x1)))/(x1 - x0)` (for a step,
//! the covered fraction of the cell). The displacement is `u = Σ s_v (P/Z) I(τ_n)`.
//!
//! Work of the loads, `W = ∫ t·v dA dt` at each loaded end: a step pressure gives
//! `W = p u(0,t)` (or `-p u(L,t)`) exactly; a step velocity with only step waves gives
//! `-v_d ∫ σ(0,s) ds` with `σ(0,·)` piecewise constant between the returns of the waves
//! (taken at the middle of each interval: exact); otherwise the power is integrated by
//! 8-point Gauss–Legendre on the intervals between the returns of the waves and of the
//! histories' breakpoints, cut to at most `L/(4c)` (and an eighth of a sine's period):
//! exact to round-off for ramp and pulse products (piecewise polynomials of degree ≤ 2),
//! to round-off in practice for sines and smooth initial states. The energy is the
//! initial state's plus the work.
use super::bar_initial::InitialWaves;
use super::{Front, NoFront};
use crate::initial::InitialState;
use crate::load::LoadHistory;

/// Load at `X = 0` (the paper's bar; [`BarExact::with_load`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EndLoad {
    /// Step pressure (positive in compression).
    Pressure(f64),
    /// Step velocity into the bar.
    Velocity(f64),
}

/// Condition at one end of the bar (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BarEnd {
    /// Traction `σ n = -p g(t)` (`p > 0` compresses; free: `p = 0`).
    Traction {
        /// Pressure `p` (Pa).
        pressure: f64,
        /// History `g`.
        history: LoadHistory,
    },
    /// Velocity `v_d g(t)` into the bar (fixed or symmetry: `v_d = 0`).
    Velocity {
        /// Velocity `v_d` (m/s).
        velocity: f64,
        /// History `g`.
        history: LoadHistory,
    },
}

impl BarEnd {
    /// A traction-free end.
    pub const FREE: BarEnd = BarEnd::Traction {
        pressure: 0.0,
        history: LoadHistory::Step,
    };
    /// A fixed end (zero velocity; the symmetry end of a 1D bar).
    pub const FIXED: BarEnd = BarEnd::Velocity {
        velocity: 0.0,
        history: LoadHistory::Step,
    };

    /// Whether the end prescribes the traction.
    pub fn is_traction(&self) -> bool {
        matches!(self, BarEnd::Traction { .. })
    }

    /// The load's history.
    pub fn history(&self) -> LoadHistory {
        match *self {
            BarEnd::Traction { history, .. } | BarEnd::Velocity { history, .. } => history,
        }
    }

    /// `P`: the stress jump of the wave the end's load sends (`p` or `Z v_d`; 0 unloaded).
    pub(super) fn amplitude(&self, impedance: f64) -> f64 {
        match *self {
            BarEnd::Traction { pressure, .. } => pressure,
            BarEnd::Velocity { velocity, .. } => impedance * velocity,
        }
    }
}

/// Exact solution of the elastic bar with any ends (see the module doc).
#[derive(Debug, Clone)]
pub struct BarExact {
    /// Bar length `L`.
    pub length: f64,
    /// Wave speed `c`.
    pub speed: f64,
    /// Impedance `Z = ρ c`.
    pub impedance: f64,
    /// Stress scale: the largest stress jump a load sends (`p` or `Z v_d`), or without
    /// loads the initial state's largest `|σ₀|` or `Z |v₀|`.
    pub pressure: f64,
    /// Conditions at `X = 0` and `X = L`.
    pub ends: [BarEnd; 2],
    /// The initial state's waves (none at rest).
    pub(super) initial: Option<InitialWaves>,
}

impl BarExact {
    /// The paper's bar: length, density, Young's modulus and a step pressure at `X = 0`,
    /// free at `X = L`.
    pub fn new(length: f64, density: f64, young: f64, pressure: f64) -> Self {
        Self::with_load(length, density, young, EndLoad::Pressure(pressure))
    }

    /// Length, density, longitudinal modulus `M` and a step load at `X = 0`, free at `L`.
    pub fn with_load(length: f64, density: f64, modulus: f64, load: EndLoad) -> Self {
        let start = match load {
            EndLoad::Pressure(pressure) => BarEnd::Traction {
                pressure,
                history: LoadHistory::Step,
            },
            EndLoad::Velocity(velocity) => BarEnd::Velocity {
                velocity,
                history: LoadHistory::Step,
            },
        };
        Self::with_ends(length, density, modulus, [start, BarEnd::FREE])
    }

    /// Length, density, longitudinal modulus `M` and the conditions at both ends, at rest.
    pub fn with_ends(length: f64, density: f64, modulus: f64, ends: [BarEnd; 2]) -> Self {
        let speed = (modulus / density).sqrt();
        let impedance = density * speed;
        let pressure = ends
            .iter()
            .map(|e| e.amplitude(impedance).abs())
            .fold(0.0, f64::max);
        Self {
            length,
            speed,
            impedance,
            pressure,
            ends,
            initial: None,
        }
    }

    /// The same bar with the load at `X = 0` following `history`.
    pub fn with_history(mut self, history: LoadHistory) -> Self {
        match &mut self.ends[0] {
            BarEnd::Traction { history: h, .. } | BarEnd::Velocity { history: h, .. } => {
                *h = history
            }
        }
        self
    }

    /// The same bar starting from `state` (read along `X`; a state at rest changes
    /// nothing). The unloaded part of each end reflects the initial waves.
    pub fn with_initial(mut self, state: &InitialState) -> Self {
        if state.is_rest() {
            self.initial = None;
            return self;
        }
        let signs = self.ends.map(|e| if e.is_traction() { 1.0 } else { -1.0 });
        let waves = InitialWaves::new(state.clone(), self.length, self.impedance, signs);
        if self.pressure == 0.0 {
            self.pressure = waves.stress_scale();
        }
        self.initial = Some(waves);
        self
    }

    /// The ends and the initial state in words, e.g. `left: pressure 1e9 Pa (step);
    /// right: free; from rest`.
    pub fn describe(&self) -> String {
        let end = |e: &BarEnd| {
            let (shape, scale) = e.history().shape();
            let history = if e.history().is_step() {
                "step".to_string()
            } else {
                format!("{shape}, {scale:e} s")
            };
            match *e {
                BarEnd::Traction { pressure: 0.0, .. } => "free".to_string(),
                BarEnd::Velocity { velocity: 0.0, .. } => {
                    "zero normal velocity (fixed or symmetry)".to_string()
                }
                BarEnd::Traction { pressure, .. } => {
                    format!("pressure {pressure:e} Pa ({history})")
                }
                BarEnd::Velocity { velocity, .. } => {
                    format!("velocity {velocity:e} m/s ({history})")
                }
            }
        };
        format!(
            "left: {}; right: {}; {}",
            end(&self.ends[0]),
            end(&self.ends[1]),
            if self.initial.is_some() {
                "from the scene's initial state"
            } else {
                "from rest"
            }
        )
    }

    /// Whether the bar starts from a state other than rest.
    pub fn has_initial_state(&self) -> bool {
        self.initial.is_some()
    }

    /// Call `f(P, g, offset, slope, s_σ, s_v)` for each wave of each loaded end that has
    /// started (module doc).
    fn waves(&self, t: f64, mut f: impl FnMut(f64, &LoadHistory, f64, f64, f64, f64)) {
        let travelled = self.speed * t;
        let l = self.length;
        for source in 0..2 {
            let end = &self.ends[source];
            let amplitude = end.amplitude(self.impedance);
            if amplitude == 0.0 {
                continue;
            }
            let history = end.history();
            let (mut ss, mut sv) = (1.0, if source == 0 { 1.0 } else { -1.0 });
            let mut n = 0usize;
            loop {
                let start = n as f64 * l;
                if start > travelled {
                    break;
                }
                let right = (n + source).is_multiple_of(2);
                let (offset, slope) = if right {
                    (start, 1.0)
                } else {
                    (start + l, -1.0)
                };
                f(amplitude, &history, offset, slope, ss, sv);
                // reflected at the end it runs into
                if self.ends[usize::from(right)].is_traction() {
                    ss = -ss;
                } else {
                    sv = -sv;
                }
                n += 1;
            }
        }
    }

    /// `g` of the wave that reaches `X` when `c t = offset + slope X`.
    #[inline]
    fn arrival_factor(&self, history: &LoadHistory, t: f64, off: f64, slope: f64, x: f64) -> f64 {
        let tau = t - (off + slope * x) / self.speed;
        if tau <= 0.0 {
            0.0
        } else {
            history.factor(tau)
        }
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

    /// Average over `[x0, x1]` of the wave's `g` (module doc).
    fn covered_history(
        &self,
        history: &LoadHistory,
        t: f64,
        off: f64,
        slope: f64,
        x0: f64,
        x1: f64,
    ) -> f64 {
        if history.is_step() {
            return Self::covered(self.speed * t, off, slope, x0, x1);
        }
        let tau = |x: f64| t - (off + slope * x) / self.speed;
        let span = (history.integral(tau(x0)) - history.integral(tau(x1))) * slope;
        span * self.speed / (x1 - x0)
    }

    /// Point value of `σ(X,t)`.
    pub fn stress(&self, x: f64, t: f64) -> f64 {
        let mut s = 0.0;
        self.waves(t, |p, g, off, slope, ss, _| {
            s -= ss * p * self.arrival_factor(g, t, off, slope, x);
        });
        if let Some(w) = &self.initial {
            s += w.point(x, t, self.speed).1;
        }
        s
    }

    /// Point value of `v(X,t)`.
    pub fn velocity(&self, x: f64, t: f64) -> f64 {
        let mut v = 0.0;
        self.waves(t, |p, g, off, slope, _, sv| {
            v += sv * p / self.impedance * self.arrival_factor(g, t, off, slope, x);
        });
        if let Some(w) = &self.initial {
            v += w.point(x, t, self.speed).0;
        }
        v
    }

    /// Average of `σ` over `[x0, x1]` at time `t`.
    pub fn stress_average(&self, x0: f64, x1: f64, t: f64) -> f64 {
        let mut s = 0.0;
        self.waves(t, |p, g, off, slope, ss, _| {
            s -= ss * p * self.covered_history(g, t, off, slope, x0, x1);
        });
        if let Some(w) = &self.initial {
            s += w.average(x0, x1, t, self.speed).1;
        }
        s
    }

    /// Average of `v` over `[x0, x1]` at time `t`.
    pub fn velocity_average(&self, x0: f64, x1: f64, t: f64) -> f64 {
        let mut v = 0.0;
        self.waves(t, |p, g, off, slope, _, sv| {
            v += sv * p / self.impedance * self.covered_history(g, t, off, slope, x0, x1);
        });
        if let Some(w) = &self.initial {
            v += w.average(x0, x1, t, self.speed).0;
        }
        v
    }

    /// Displacement `u(X,t) = ∫_0^t v(X,s) ds`.
    pub fn displacement(&self, x: f64, t: f64) -> f64 {
        let mut u = 0.0;
        self.waves(t, |p, g, off, slope, _, sv| {
            let arrival = (off + slope * x) / self.speed;
            u += sv * p / self.impedance * g.integral(t - arrival);
        });
        if let Some(w) = &self.initial {
            u += w.time_integrals(x, t, self.speed).0;
        }
        u
    }

    /// `∫_0^t σ(X,s) ds`.
    pub(super) fn stress_impulse(&self, x: f64, t: f64) -> f64 {
        let mut j = 0.0;
        self.waves(t, |p, g, off, slope, ss, _| {
            let arrival = (off + slope * x) / self.speed;
            j -= ss * p * g.integral(t - arrival);
        });
        if let Some(w) = &self.initial {
            j += w.time_integrals(x, t, self.speed).1;
        }
        j
    }

    /// Energy per unit area of the initial state (0 at rest).
    pub fn initial_energy(&self) -> f64 {
        self.initial.as_ref().map_or(0.0, |w| w.energy(self.speed))
    }

    /// Kinetic plus strain energy: the initial energy plus [`Self::work`] (no
    /// dissipation).
    pub fn energy(&self, t: f64) -> f64 {
        self.initial_energy() + self.work(t)
    }

    /// The most recent discontinuity inside the bar at `t` (the leading front), with the
    /// stress on both sides and the interval where it is the only one. Only step loads
    /// have one; fronts from both ends are both inside the bar at once (merged); on top of
    /// an initial state the stress behind is not a plateau.
    pub fn leading_front(&self, t: f64) -> Result<Front, NoFront> {
        let ct = self.speed * t;
        let l = self.length;
        let loaded: Vec<usize> = (0..2)
            .filter(|&e| self.ends[e].amplitude(self.impedance) != 0.0)
            .collect();
        // a step, or the leading edge of a pulse (a jump too), sends a front
        let jumps = |e: usize| {
            matches!(
                self.ends[e].history(),
                LoadHistory::Step | LoadHistory::Pulse { .. }
            )
        };
        let source = match loaded[..] {
            [] => return Err(NoFront::NotAStep),
            _ if loaded.iter().any(|&e| !jumps(e)) => return Err(NoFront::NotAStep),
            [source] => source,
            _ => {
                if ct > 0.0 {
                    return Err(NoFront::Merged);
                }
                loaded[0]
            }
        };
        if self.initial.is_some() {
            return Err(NoFront::NoPlateau);
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
        let right = (transits as usize + source).is_multiple_of(2);
        let (position, direction) = if right { (r, 1.0) } else { (l - r, -1.0) };
        // a pulse of length T: its trailing edge follows c T behind; the front is measured
        // while both edges are on the same leg, in a window that ends at the trailing edge
        let mut window = (0.0, l);
        if let LoadHistory::Pulse { duration } = self.ends[source].history() {
            let tail = self.speed * duration;
            if ct > tail {
                if r <= tail {
                    return Err(NoFront::Merged); // the trailing edge is on the previous leg
                }
                let trailing = position - direction * tail;
                window = if right {
                    (trailing, l)
                } else {
                    (0.0, trailing)
                };
            }
        }
        let eps = 1e-9 * l;
        let ahead = self.stress(position + direction * eps, t);
        let behind = self.stress(position - direction * eps, t);
        Ok(Front {
            position,
            direction,
            ahead,
            behind,
            window,
        })
    }
}

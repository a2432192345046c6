//! Error and front metrics, the same code for every method.
//!
//! A [`Profile`] is a field sampled where a method stores it, sorted by position, with the
//! exact average over the region each sample stands for. On it:
//! - relative L1 error `Σ w|f_h - f| / Σ w|f|` (weights `w` = sample widths) and relative
//!   L∞ error `max|f_h - f| / max|f|`;
//! - front width: with `φ = (f_h - f_ahead)/(f_behind - f_ahead)`, scan the samples within
//!   [`FRONT_WINDOW_CELLS`] cells of the exact front, from its undisturbed side towards its
//!   loaded side; the distance between the first
//!   crossing of `φ = 0.1` and the next crossing of `φ = 0.9` (linear interpolation between
//!   samples), in cell widths. A perfect step sampled at cell centres gives 0.8 cells;
//! - overshoot: the largest excursion of `φ` beyond the envelope `[min(0, φ_exact),
//!   max(1, φ_exact)]` in that window, in % of the jump: beyond the plateaus for a step, and
//!   beyond the reference profile where the solution is not flat behind the front.
//!
//! The window keeps noise far from the front (MPM's cell-crossing noise, the trail of an
//! earlier reflection) from being counted as front width; a profile smeared over more than
//! the window never reaches both levels and reports no width (treated as worst).
use crate::exact::Front;
use serde::Serialize;

/// Half-width, in cells, of the window around the exact front in which width and
/// overshoot are measured.
pub const FRONT_WINDOW_CELLS: f64 = 20.0;

/// A sampled profile along one axis.
#[derive(Debug, Clone, Default)]
pub struct Profile {
    /// Sample positions (sorted).
    pub x: Vec<f64>,
    /// Width of the region each sample stands for.
    pub width: Vec<f64>,
    /// Numerical values.
    pub value: Vec<f64>,
    /// Exact averages over each sample's region.
    pub exact: Vec<f64>,
    /// A second reference's averages over each sample's region (empty without one;
    /// [`crate::converged::Spread`]).
    pub second: Vec<f64>,
}

/// Metrics of one method at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProfileMetrics {
    /// Relative L1 error.
    pub l1_rel: f64,
    /// Relative L∞ error.
    pub linf_rel: f64,
    /// Front width in cells (`None` if the profile never reaches 10 % and 90 % of the jump).
    pub front_width_cells: Option<f64>,
    /// Overshoot in % of the jump.
    pub overshoot_pct: Option<f64>,
    /// What `l1_rel` and `linf_rel` hold.
    pub errors: ErrorBasis,
}

/// What the stress error fields hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ErrorBasis {
    /// Relative errors: `Σ w|σ_h − σ_ref| / Σ w|σ_ref|` and `max|σ_h − σ_ref| / max|σ_ref|`
    /// (where the reference vanishes, over the load's stress scale).
    Relative,
    /// Absolute errors in Pa (width-weighted mean and maximum): the reference stress and
    /// the load's scale are both zero, so no relative error is defined.
    AbsoluteZeroReference,
    /// No errors: the run has no reference (see `summary.json`'s `reference`).
    NoReference,
}

impl ErrorBasis {
    /// A sentence for tables.
    pub fn describe(self) -> &'static str {
        match self {
            ErrorBasis::Relative => "relative to the reference",
            ErrorBasis::AbsoluteZeroReference => {
                "absolute errors in Pa: the reference stress is zero, a relative error is undefined"
            }
            ErrorBasis::NoReference => "not computed: this run has no reference",
        }
    }
}

/// Why the front metrics hold what they hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrontStatus {
    /// Width, overshoot and position measured.
    Measured,
    /// The profile does not cross both 10 % and 90 % (or 50 %) of the jump near the front:
    /// the width (or the position) is undefined, the overshoot is measured.
    NotCrossed,
    /// The reference has no single front at this time (none yet, several after reflections,
    /// a vanishing jump, or no reference).
    NoFront,
}

impl FrontStatus {
    /// A sentence for tables.
    pub fn describe(self) -> &'static str {
        match self {
            FrontStatus::Measured => "measured",
            FrontStatus::NotCrossed => {
                "front width or position undefined: the profile does not cross 10 %, 50 % and 90 % \
                 of the jump near the front"
            }
            FrontStatus::NoFront => {
                "no front metrics: the reference has no single front at this time"
            }
        }
    }
}

impl Profile {
    /// Sort samples by position.
    pub fn sort(&mut self) {
        let mut idx: Vec<usize> = (0..self.x.len()).collect();
        idx.sort_by(|&a, &b| self.x[a].total_cmp(&self.x[b]));
        let pick = |v: &Vec<f64>| idx.iter().map(|&i| v[i]).collect::<Vec<_>>();
        self.x = pick(&self.x);
        self.width = pick(&self.width);
        self.value = pick(&self.value);
        self.exact = pick(&self.exact);
        if self.second.len() == idx.len() {
            self.second = pick(&self.second);
        }
    }

    /// The distance between the reference and the second one in the basis of
    /// [`Self::errors`]: `Σ w|f_A − f_B| / Σ w|f_A|` (over `scale` where the reference
    /// vanishes; width-weighted mean in Pa for [`ErrorBasis::AbsoluteZeroReference`]).
    /// By the triangle inequality, the L1 error against the second reference differs from
    /// the one against the first by at most this: the error's uncertainty from the choice
    /// of reference. `None` without a second reference.
    pub fn spread(&self, scale: f64) -> Option<f64> {
        if self.second.len() != self.x.len() || self.x.is_empty() {
            return None;
        }
        let as_run = Profile {
            x: self.x.clone(),
            width: self.width.clone(),
            value: self.second.clone(),
            exact: self.exact.clone(),
            second: Vec::new(),
        };
        Some(as_run.errors(scale).0).filter(|v| v.is_finite())
    }

    /// Relative L1 and L∞ errors against the exact averages. If the exact profile is
    /// zero everywhere, the errors are relative to `scale`.
    pub fn errors(&self, scale: f64) -> (f64, f64, ErrorBasis) {
        let mut num1 = 0.0;
        let mut den1 = 0.0;
        let mut numi: f64 = 0.0;
        let mut deni: f64 = 0.0;
        for i in 0..self.x.len() {
            let e = (self.value[i] - self.exact[i]).abs();
            num1 += self.width[i] * e;
            den1 += self.width[i] * self.exact[i].abs();
            numi = numi.max(e);
            deni = deni.max(self.exact[i].abs());
        }
        let total: f64 = self.width.iter().sum();
        if den1 == 0.0 {
            den1 = scale * total;
            deni = scale;
        }
        if den1 > 0.0 && deni > 0.0 && den1.is_finite() && deni.is_finite() {
            (num1 / den1, numi / deni, ErrorBasis::Relative)
        } else {
            let mean = if total > 0.0 { num1 / total } else { numi };
            (mean, numi, ErrorBasis::AbsoluteZeroReference)
        }
    }

    /// Samples in the window around `front`, ordered from its undisturbed side.
    fn window(&self, front: &Front, dx: f64) -> Vec<usize> {
        let lo = front.window.0.max(front.position - FRONT_WINDOW_CELLS * dx);
        let hi = front.window.1.min(front.position + FRONT_WINDOW_CELLS * dx);
        let mut order: Vec<usize> = (0..self.x.len())
            .filter(|&i| self.x[i] >= lo && self.x[i] <= hi)
            .collect();
        // start on the undisturbed side: larger X for a right-going front
        if front.direction > 0.0 {
            order.reverse();
        }
        order
    }

    /// First crossing of `φ = level` from the undisturbed side of `front` (linear
    /// interpolation between samples), in the window around it.
    pub fn crossing(&self, front: &Front, level: f64, dx: f64) -> Option<f64> {
        let jump = front.behind - front.ahead;
        if jump == 0.0 {
            return None;
        }
        let order = self.window(front, dx);
        let phi = |i: usize| (self.value[i] - front.ahead) / jump;
        order.windows(2).find_map(|w| {
            let (pa, pb) = (phi(w[0]), phi(w[1]));
            (pa < level && pb >= level).then(|| {
                let s = (level - pa) / (pb - pa);
                self.x[w[0]] + s * (self.x[w[1]] - self.x[w[0]])
            })
        })
    }

    /// Front width (cells of size `dx`) and overshoot (%) around `front`.
    pub fn front(&self, front: &Front, dx: f64) -> (Option<f64>, Option<f64>) {
        let jump = front.behind - front.ahead;
        if jump == 0.0 {
            return (None, None);
        }
        let order = self.window(front, dx);
        let phi = |i: usize| (self.value[i] - front.ahead) / jump;
        // excess beyond the envelope [min(0, φ_exact), max(1, φ_exact)]: the plateaus for
        // a step, the reference profile where the solution is not flat behind the front
        let mut overshoot: f64 = 0.0;
        for &i in &order {
            let (p, pe) = (phi(i), (self.exact[i] - front.ahead) / jump);
            let pe = if pe.is_finite() { pe } else { 1.0 };
            overshoot = overshoot.max(p - pe.max(1.0)).max(pe.min(0.0) - p);
        }
        let crossing = |from: usize, level: f64| -> Option<(usize, f64)> {
            for w in from..order.len().saturating_sub(1) {
                let (a, b) = (order[w], order[w + 1]);
                let (pa, pb) = (phi(a), phi(b));
                if pa < level && pb >= level {
                    let s = (level - pa) / (pb - pa);
                    return Some((w, self.x[a] + s * (self.x[b] - self.x[a])));
                }
            }
            None
        };
        let width = crossing(0, 0.1)
            .and_then(|(w, x10)| crossing(w, 0.9).map(|(_, x90)| (x90 - x10).abs() / dx));
        (width, Some(100.0 * overshoot))
    }

    /// All metrics at once.
    pub fn metrics(&self, front: Option<&Front>, dx: f64, scale: f64) -> ProfileMetrics {
        let (l1_rel, linf_rel, errors) = self.errors(scale);
        let (front_width_cells, overshoot_pct) = match front {
            Some(f) => self.front(f, dx),
            None => (None, None),
        };
        ProfileMetrics {
            l1_rel,
            linf_rel,
            front_width_cells,
            overshoot_pct,
            errors,
        }
    }
}

/// Energy error of a discrete energy `E_h` against the energy the state should hold,
/// `E* = W + E_0`: the work of the loads plus the energy at `t = 0` (issue 23: one rule for
/// every method and reference). Relative, `(E_h - E*)/E*`, where `E* ≠ 0`; where nothing
/// was put in (`E* = 0`: no work, a state at rest; the relative error is undefined)
/// `E_h - E* = E_h` in J. The flag says which (`true`: relative). A free-free bar with an
/// initial velocity has `W = 0` and `E* = E_0 > 0`: relative to `E_0`, never to `W`.
pub fn energy_error(energy: f64, expected: f64) -> (f64, bool) {
    if expected == 0.0 || !expected.is_finite() {
        (
            energy - if expected.is_finite() { expected } else { 0.0 },
            false,
        )
    } else {
        ((energy - expected) / expected, true)
    }
}

/// Observed orders of convergence `log(e_k/e_{k+1}) / log(2)` for errors on grids refined
/// by 2.
pub fn observed_orders(errors: &[f64]) -> Vec<f64> {
    errors
        .windows(2)
        .map(|w| (w[0] / w[1]).ln() / 2f64.ln())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step_profile(n: usize, edge: usize, smear: usize) -> Profile {
        let dx = 1.0;
        let mut p = Profile::default();
        for i in 0..n {
            let x = (i as f64 + 0.5) * dx;
            let v = if i + smear / 2 < edge {
                -1.0
            } else if i >= edge + smear.div_ceil(2) {
                0.0
            } else {
                -1.0 + ((i + smear / 2 - edge) as f64 + 1.0) / (smear as f64 + 1.0)
            };
            p.x.push(x);
            p.width.push(dx);
            p.value.push(v);
            p.exact.push(if i < edge { -1.0 } else { 0.0 });
        }
        p
    }

    #[test]
    fn perfect_step_has_width_point_eight_and_no_overshoot() {
        let p = step_profile(20, 10, 0);
        let f = Front {
            position: 10.0,
            direction: 1.0,
            ahead: 0.0,
            behind: -1.0,
            window: (0.0, 20.0),
        };
        let m = p.metrics(Some(&f), 1.0, 1.0);
        assert!((m.front_width_cells.unwrap() - 0.8).abs() < 1e-12);
        assert_eq!(m.overshoot_pct, Some(0.0));
        assert_eq!((m.l1_rel, m.linf_rel), (0.0, 0.0));
    }

    #[test]
    fn smeared_step_is_wider_and_overshoot_is_measured() {
        let mut p = step_profile(40, 20, 6);
        let f = Front {
            position: 20.0,
            direction: 1.0,
            ahead: 0.0,
            behind: -1.0,
            window: (0.0, 40.0),
        };
        let sharp = step_profile(40, 20, 0).metrics(Some(&f), 1.0, 1.0);
        let m = p.metrics(Some(&f), 1.0, 1.0);
        assert!(m.front_width_cells.unwrap() > sharp.front_width_cells.unwrap() + 3.0);
        assert!(m.l1_rel > 0.0);
        p.value[10] = -1.25; // a 25 % overshoot behind the front
        let m = p.metrics(Some(&f), 1.0, 1.0);
        assert!((m.overshoot_pct.unwrap() - 25.0).abs() < 1e-9);
    }

    #[test]
    fn left_going_front_is_scanned_from_the_right() {
        let mut p = step_profile(20, 10, 0);
        // mirror: undisturbed (0) on the left, loaded (-1) on the right
        p.value.reverse();
        p.exact.reverse();
        let f = Front {
            position: 10.0,
            direction: -1.0,
            ahead: 0.0,
            behind: -1.0,
            window: (0.0, 20.0),
        };
        let m = p.metrics(Some(&f), 1.0, 1.0);
        assert!((m.front_width_cells.unwrap() - 0.8).abs() < 1e-12);
    }
}

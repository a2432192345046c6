//! [`TimeMetrics`]: what a method is measured to at one output time against the
//! [`crate::reference::Reference`] (errors, front, energy), and how `summary.json` names each
//! value by its basis (moved out of `reference.rs`, which forms them).
use crate::exact::NoFront;
use crate::metrics::{energy_error, ErrorBasis, FrontStatus};
use serde::Serialize;

/// Metrics of one method at one output time (a row of the table and of `summary.json`).
///
/// No field is ever NaN in the outputs: where a relative error is undefined the absolute
/// one is reported, and each group says what it holds ([`ErrorBasis`], [`FrontStatus`],
/// `energy_relative`). In `summary.json` the keys name the basis (`l1_rel` or
/// `l1_abs_pa`, `energy_rel` or `energy_abs_j`); a metric that is undefined is left out,
/// and the status field beside it says why.
#[derive(Debug, Clone, Copy)]
pub struct TimeMetrics {
    /// Time (s).
    pub t: f64,
    /// L1 error of `σ_xx` in the basis `errors`.
    pub l1: f64,
    /// L∞ error of `σ_xx` in the basis `errors`.
    pub linf: f64,
    /// What `l1` and `linf` hold.
    pub errors: ErrorBasis,
    /// The uncertainty of `l1` from the choice of reference: the L1 distance between the
    /// reference and a second, independent one in the same basis
    /// ([`crate::metrics::Profile::spread`]); `None` without a second reference.
    pub l1_spread: Option<f64>,
    /// Front width in cells.
    pub front_width_cells: Option<f64>,
    /// Overshoot in % of the jump.
    pub overshoot_pct: Option<f64>,
    /// Where the profile first reaches half of the jump (m), from the undisturbed side.
    pub front_position: Option<f64>,
    /// Position of the exact front (m).
    pub front_exact: Option<f64>,
    /// Why the front metrics are or are not there.
    pub front: FrontStatus,
    /// Why the reference has no front at this time (with [`FrontStatus::NoFront`]).
    pub front_reason: Option<NoFront>,
    /// `(E_h - E*)/E*` with `E* = W + E_0` the energy the state should hold: the exact
    /// work of the loads plus the exact initial energy (the method's own work and initial
    /// energy if the reference knows neither); `E_h` in J where `E* = 0` (`energy_relative`
    /// false). [`energy_error`] states the rule.
    pub energy_error: f64,
    /// Whether `energy_error` is relative.
    pub energy_relative: bool,
    /// Width of the second front (the plastic wave of an elastoplastic reference), cells.
    pub plastic_front_width_cells: Option<f64>,
    /// Overshoot at the second front, % of its jump.
    pub plastic_overshoot_pct: Option<f64>,
    /// Where the profile crosses half of the second front's jump (m), and the exact
    /// position.
    pub plastic_front_position: Option<(f64, f64)>,
}

impl TimeMetrics {
    /// Metrics of a run without a reference: the energy balance against the method's own
    /// external work plus its own initial energy, `expected` ([`energy_error`]).
    pub fn without_reference(t: f64, energy: f64, expected: f64) -> Self {
        let (energy_error, energy_relative) = energy_error(energy, expected);
        Self {
            t,
            l1: 0.0,
            linf: 0.0,
            errors: ErrorBasis::NoReference,
            l1_spread: None,
            front_width_cells: None,
            overshoot_pct: None,
            front_position: None,
            front_exact: None,
            front: FrontStatus::NoFront,
            front_reason: Some(NoFront::NoReference),
            plastic_front_width_cells: None,
            plastic_overshoot_pct: None,
            plastic_front_position: None,
            energy_error,
            energy_relative,
        }
    }
}

impl Serialize for TimeMetrics {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(None)?;
        map.serialize_entry("t", &self.t)?;
        match self.errors {
            ErrorBasis::Relative => {
                map.serialize_entry("l1_rel", &self.l1)?;
                map.serialize_entry("linf_rel", &self.linf)?;
            }
            ErrorBasis::AbsoluteZeroReference => {
                map.serialize_entry("l1_abs_pa", &self.l1)?;
                map.serialize_entry("linf_abs_pa", &self.linf)?;
            }
            ErrorBasis::NoReference => {}
        }
        map.serialize_entry("errors", &self.errors)?;
        for (key, value) in [
            ("l1_spread", self.l1_spread),
            ("front_width_cells", self.front_width_cells),
            ("overshoot_pct", self.overshoot_pct),
            ("front_position", self.front_position),
            ("front_exact", self.front_exact),
            ("plastic_front_width_cells", self.plastic_front_width_cells),
            ("plastic_overshoot_pct", self.plastic_overshoot_pct),
            (
                "plastic_front_position",
                self.plastic_front_position.map(|p| p.0),
            ),
            (
                "plastic_front_exact",
                self.plastic_front_position.map(|p| p.1),
            ),
        ] {
            if let Some(v) = value.filter(|v| v.is_finite()) {
                map.serialize_entry(key, &v)?;
            }
        }
        map.serialize_entry("front", &self.front)?;
        if let Some(reason) = self.front_reason {
            map.serialize_entry("front_reason", &reason)?;
        }
        let key = if self.energy_relative {
            "energy_rel"
        } else {
            "energy_abs_j"
        };
        if self.energy_error.is_finite() {
            map.serialize_entry(key, &self.energy_error)?;
        }
        map.end()
    }
}

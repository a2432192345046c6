//! The scene's `[metrics]` section: where profiles and fronts are measured
//! ([`crate::line`]).
//!
//! ```toml
//! [metrics]
//! line = { from = [0.0, 0.0], to = [4.0, 0.0] }   # the paper's bottom row of the plate
//! receivers = [[0.4, 0.0, 1.2], [0.8, 0.0, 1.2]]  # where traces are recorded (Lamb)
//! interior = "dependence"   # errors only where no boundary can have acted (crate::interior)
//! reference = "fem"          # the converged reference's method (no exact solution)
//! reference_refinement = 4   # its grid, this many times finer along each axis
//! reference_spread = "dgmpm" # the second, independent reference: its distance is the
//!                            # uncertainty reported beside every error
//! ```
//!
//! [`ReferenceOptions`] holds the reference fields; the command resolves what is not stated
//! (which methods it compares decides the default method, the `impact` crate's
//! `reference` module).
use super::Scene;
use crate::error::SceneError;
use crate::interior::{margin_cells, steps_bound, InteriorRule};
use crate::line::{LineOrigin, MeasureLine};
use crate::options::{MethodKind, MpmShape, TransverseFlux};
use serde::{Deserialize, Serialize};

/// Allowed refinements of a converged reference (along each axis).
pub const REFERENCE_REFINEMENTS: std::ops::RangeInclusive<usize> = 2..=16;

/// A reference refinement `r` given as `field` (scene key or flag): refused outside
/// [`REFERENCE_REFINEMENTS`], naming the field, the value and the range.
pub fn check_reference_refinement(field: &str, r: usize) -> Result<(), SceneError> {
    if REFERENCE_REFINEMENTS.contains(&r) {
        return Ok(());
    }
    Err(SceneError::new(
        field,
        r,
        format!(
            "an integer from {} to {} (the reference grid's cells per run cell along each \
             axis)",
            REFERENCE_REFINEMENTS.start(),
            REFERENCE_REFINEMENTS.end()
        ),
    ))
}

/// The `[metrics]` section.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetricsSpec {
    /// The measuring line (default: inferred from the loads, [`MeasureLine::infer`]).
    #[serde(default)]
    pub line: Option<LineSpec>,
    /// Points where time traces of the displacement are recorded (`impact bench lamb`),
    /// one coordinate per axis, inside the body or on its boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub receivers: Option<Vec<Vec<f64>>>,
    /// Where errors are measured: `whole` (the body) or `dependence` (the clean interior no
    /// boundary can have reached, [`crate::interior`]); default `dependence` for a plane
    /// wave, `whole` otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<InteriorRule>,
    /// The converged reference's method, for a scene without an exact solution (default:
    /// chosen by the command from the methods it compares).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<MethodKind>,
    /// How many times finer than the run's grid the converged reference is, along each
    /// axis ([`REFERENCE_REFINEMENTS`]; default: the command's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_refinement: Option<usize>,
    /// The second converged reference, of another method on the same fine grid, whose
    /// distance from the first is reported beside every error as its uncertainty
    /// (default: chosen by the command).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_spread: Option<MethodKind>,
    /// The shape functions of an MPM reference (default: quadratic B-splines).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_shape: Option<MpmShape>,
    /// The transverse flux of a 2D or 3D DGMPM reference (default: CTU for linear
    /// elasticity and J2, donor-cell for Saint-Venant-Kirchhoff).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_flux: Option<TransverseFlux>,
}

/// The reference fields of `[metrics]` (each `None`: not stated, the command's default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReferenceOptions {
    /// `reference`.
    pub method: Option<MethodKind>,
    /// `reference_refinement`.
    pub refinement: Option<usize>,
    /// `reference_spread`.
    pub spread: Option<MethodKind>,
    /// `reference_shape`.
    pub shape: Option<MpmShape>,
    /// `reference_flux`.
    pub flux: Option<TransverseFlux>,
}

/// A straight line parallel to an axis, from the face a front enters by.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineSpec {
    /// Start (m), one coordinate per axis.
    pub from: Vec<f64>,
    /// End (m), one coordinate per axis.
    pub to: Vec<f64>,
}

const ALLOWED: &str = "a segment parallel to one axis inside the body, one coordinate per axis, \
     e.g. `line = { from = [0.0, 1.5], to = [4.0, 1.5] }` (2D) or \
     `{ from = [0.5, 0.5, 0.0], to = [0.5, 0.5, 1.0] }` (3D)";

impl Scene {
    /// Check `[metrics]`: the line has one coordinate per axis, lies in the body
    /// `[0, length]` and runs parallel to one axis with a non-zero length.
    pub(super) fn check_metrics(&self) -> Result<(), SceneError> {
        self.check_receivers()?;
        self.check_interior()?;
        self.check_reference()?;
        let Some(line) = self.metrics.as_ref().and_then(|m| m.line.as_ref()) else {
            return Ok(());
        };
        let shown = format!("from {:?} to {:?}", line.from, line.to);
        if line.from.len() != self.dim || line.to.len() != self.dim {
            return Err(SceneError::new("metrics.line", shown, ALLOWED));
        }
        for (name, point) in [("from", &line.from), ("to", &line.to)] {
            for (l, &x) in point.iter().enumerate() {
                let length = self.domain.length.get(l).copied().unwrap_or(0.0);
                let tol = 1e-9 * length.abs();
                if !(x.is_finite() && x >= -tol && x <= length + tol) {
                    return Err(SceneError::new(
                        format!("metrics.line.{name}[{l}]"),
                        x,
                        format!("a coordinate inside the body, in [0, {length}] m"),
                    ));
                }
            }
        }
        let moving: Vec<usize> = (0..self.dim)
            .filter(|&l| line.from[l] != line.to[l])
            .collect();
        if moving.len() != 1 {
            return Err(SceneError::new("metrics.line", shown, ALLOWED));
        }
        Ok(())
    }

    /// Where errors are measured: the stated rule, else `dependence` for a plane wave and
    /// `whole` otherwise.
    pub fn interior_rule(&self) -> InteriorRule {
        let plane = self
            .initial
            .as_ref()
            .is_some_and(|i| i.plane_wave.is_some());
        match self.metrics.as_ref().and_then(|m| m.interior) {
            Some(rule) => rule,
            None if plane => InteriorRule::Dependence,
            None => InteriorRule::Whole,
        }
    }

    /// With the `dependence` rule, each method as the scene configures it keeps a clean
    /// interior at the last output time: the margin `R s + 1` cells ([`crate::interior`],
    /// `s` bounded by the Courant number and the schedule) leaves at least one cell along
    /// every axis.
    fn check_interior(&self) -> Result<(), SceneError> {
        if self.interior_rule() != InteriorRule::Dependence {
            return Ok(());
        }
        let (times, _) = self.schedule_seconds();
        let (h, transit) = self.transit();
        for kind in MethodKind::ALL {
            let config = self.method_config(kind);
            let steps = steps_bound(&times, config.courant, h, h / transit);
            let margin = margin_cells(&config, steps);
            if let Some(l) = (0..self.dim).find(|&l| self.domain.cells[l] <= 2 * margin) {
                return Err(SceneError::new(
                    "metrics.interior",
                    "\"dependence\"",
                    format!(
                        "a clean interior: {} at Courant {} takes up to {steps} steps to t = \
                         {:.4e} s and a boundary reaches {margin} cells in from each face, \
                         which leaves no cell of the {} along {}; give more cells, an earlier \
                         last output time, or `interior = \"whole\"` (errors over the whole \
                         body)",
                        kind.name(),
                        config.courant,
                        times.last().copied().unwrap_or(0.0),
                        self.domain.cells[l],
                        super::AXIS_NAMES[l]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The reference fields of `[metrics]`.
    pub fn reference_options(&self) -> ReferenceOptions {
        let Some(m) = self.metrics.as_ref() else {
            return ReferenceOptions::default();
        };
        ReferenceOptions {
            method: m.reference,
            refinement: m.reference_refinement,
            spread: m.reference_spread,
            shape: m.reference_shape,
            flux: m.reference_flux,
        }
    }

    /// The refinement lies in [`REFERENCE_REFINEMENTS`]; the spread's method differs from
    /// the reference's; a flux only in 2D and 3D.
    fn check_reference(&self) -> Result<(), SceneError> {
        let o = self.reference_options();
        if let Some(r) = o.refinement {
            check_reference_refinement("metrics.reference_refinement", r)?;
        }
        if let (Some(a), Some(b)) = (o.method, o.spread) {
            if a == b {
                return Err(SceneError::new(
                    "metrics.reference_spread",
                    format!("\"{b}\""),
                    format!(
                        "a method other than the reference's (\"{a}\"): the spread measures how \
                         far two independent references lie apart ({})",
                        MethodKind::allowed()
                    ),
                ));
            }
        }
        if let (Some(flux), 1) = (o.flux, self.dim) {
            return Err(SceneError::new(
                "metrics.reference_flux",
                format!("\"{flux}\""),
                "a transverse flux only in 2D and 3D scenes",
            ));
        }
        Ok(())
    }

    /// Receivers have one coordinate per axis and lie in the body `[0, length]`.
    fn check_receivers(&self) -> Result<(), SceneError> {
        let Some(receivers) = self.metrics.as_ref().and_then(|m| m.receivers.as_ref()) else {
            return Ok(());
        };
        if receivers.is_empty() || receivers.len() > 64 {
            return Err(SceneError::new(
                "metrics.receivers",
                format!("{} receivers", receivers.len()),
                "1 to 64 points",
            ));
        }
        for (k, point) in receivers.iter().enumerate() {
            if point.len() != self.dim {
                return Err(SceneError::new(
                    format!("metrics.receivers[{k}]"),
                    format!("{point:?}"),
                    format!("{} coordinates (one per axis)", self.dim),
                ));
            }
            for (l, &x) in point.iter().enumerate() {
                let length = self.domain.length[l];
                let tol = 1e-9 * length.abs();
                if !(x.is_finite() && x >= -tol && x <= length + tol) {
                    return Err(SceneError::new(
                        format!("metrics.receivers[{k}][{l}]"),
                        x,
                        format!("a coordinate inside the body, in [0, {length}] m"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The receivers of `[metrics]` (none if not given).
    pub fn receivers(&self) -> Vec<Vec<f64>> {
        self.metrics
            .as_ref()
            .and_then(|m| m.receivers.clone())
            .unwrap_or_default()
    }

    /// The stated line, if any (a scene that passed [`Scene::validate`]).
    pub fn measure_line(&self) -> Option<MeasureLine> {
        let line = self.metrics.as_ref()?.line.as_ref()?;
        let axis = (0..self.dim).find(|&l| line.from[l] != line.to[l])?;
        Some(MeasureLine {
            axis,
            start: line.from[axis],
            end: line.to[axis],
            offset: {
                let mut offset = [0.0; 2];
                for (slot, k) in (0..self.dim).filter(|&k| k != axis).enumerate() {
                    offset[slot] = line.from[k];
                }
                offset
            },
            origin: LineOrigin::Stated,
        })
    }
}

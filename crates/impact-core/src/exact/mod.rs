//! Exact solutions.
//!
//! [`BarExact`] (file `bar.rs`): the elastic bar (or plane wave in uniaxial strain) with
//! any condition at each end (free, fixed, symmetry, pressure or velocity with any
//! [`crate::load`] history) and an initial state, by d'Alembert with images
//! (`bar_initial.rs` for the initial state's waves).
//!
//! [`SvkBarExact`] (file `svk.rs`): the Saint-Venant–Kirchhoff bar of §5.3.
//!
//! [`ElastoplasticWave`] (file `plastic.rs`): the elastic precursor and plastic wave of a
//! J2 rod or plane wave under a step load (issue 12).
//!
//! [`Lamb`] (file `lamb.rs`, numerics in `lamb_quadrature.rs`): Lamb's problem, a vertical
//! point force on an elastic half-space with `ν = 1/4` (Pekeris 1955), surface displacements
//! for a step and, by Duhamel, for any load history (issue 24).
//!
//! [`PlaneWave`] (file `plane.rs`): a smooth P or S pulse travelling in any direction,
//! exact until the boundaries' influence arrives ([`crate::interior`]).
//!
//! [`StandingWave`] (file `standing.rs`): a smooth standing P mode with roller edges, the
//! exact solution of the convergence suite.
mod bar;
mod bar_initial;
#[cfg(test)]
mod bar_tests;
mod bar_work;
mod lamb;
mod lamb_quadrature;
#[cfg(test)]
mod lamb_tests;
mod plane;
mod plastic;
mod select;
mod standing;
mod svk;
pub use bar::{BarEnd, BarExact, EndLoad};
pub use lamb::{Arrivals, Lamb, LambError};
pub use plane::PlaneWave;
pub use plastic::ElastoplasticWave;
pub use standing::StandingWave;
pub use svk::SvkBarExact;

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
    /// The measuring line does not start on a loaded edge: no front enters the body there.
    NotFromLoad,
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
            NoFront::NotFromLoad => {
                "no front: the measuring line does not start on a loaded edge ([metrics] line)"
            }
            NoFront::PastValidity => "no front: past the time the reference holds for",
        }
    }
}

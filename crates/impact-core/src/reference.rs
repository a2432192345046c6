//! The reference a scene is measured against, and the per-output-time metrics of a method.
//!
//! - `bar` (1D, pressure at the left end, free right end): the exact d'Alembert solution
//!   [`BarExact`]; the profile is `σ_xx` sampled where each method stores it against the
//!   exact average over the region each sample stands for.
use crate::exact::{BarExact, Front};
use crate::method::{Method, Samples};
use crate::metrics::{energy_rel, Profile, ProfileMetrics};
use crate::problem::{Boundary, Problem};
use serde::Serialize;

/// A scene's reference solution.
#[derive(Debug, Clone, Copy)]
pub enum Reference {
    /// Exact solution of the loaded elastic bar.
    Bar(BarExact),
}

/// Metrics of one method at one output time (a row of the table and of `summary.json`).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TimeMetrics {
    /// Time (s).
    pub t: f64,
    /// Relative L1 error of `σ_xx`.
    pub l1_rel: f64,
    /// Relative L∞ error of `σ_xx`.
    pub linf_rel: f64,
    /// Front width in cells.
    pub front_width_cells: Option<f64>,
    /// Overshoot in % of the jump.
    pub overshoot_pct: Option<f64>,
    /// `(E_h - W)/W` with `W` the exact work of the load (the method's own if no exact).
    pub energy_rel: f64,
}

impl Reference {
    /// The reference of `problem`, if it has an exact solution.
    pub fn for_problem<const D: usize>(problem: &Problem<D>) -> Option<Self> {
        if D != 1 {
            return None;
        }
        match (problem.boundaries[0][0], problem.boundaries[0][1]) {
            (
                Boundary::Pressure {
                    value,
                    segment: None,
                },
                Boundary::Free,
            ) => {
                let m = problem.material;
                Some(Reference::Bar(BarExact::new(
                    problem.grid.upper()[0] - problem.grid.origin[0],
                    m.density,
                    m.elastic.young,
                    value,
                )))
            }
            _ => None,
        }
    }

    /// Exact average of `σ_xx` and `v_x` over `[x0, x1]` at `t`.
    pub fn averages(&self, x0: f64, x1: f64, t: f64) -> (f64, f64) {
        match self {
            Reference::Bar(b) => (b.stress_average(x0, x1, t), b.velocity_average(x0, x1, t)),
        }
    }

    /// The leading front at `t`.
    pub fn front(&self, t: f64) -> Option<Front> {
        match self {
            Reference::Bar(b) => b.leading_front(t),
        }
    }

    /// Work done by the loads up to `t`.
    pub fn work(&self, t: f64) -> f64 {
        match self {
            Reference::Bar(b) => b.work(t),
        }
    }

    /// Stress scale for relative errors when the exact field vanishes.
    pub fn scale(&self) -> f64 {
        match self {
            Reference::Bar(b) => b.pressure.abs(),
        }
    }

    /// `σ_xx` profile along `x` of `samples` (at their reference positions) with the exact
    /// averages over each sample's region.
    pub fn profile<const D: usize>(&self, samples: &Samples<D>, t: f64) -> Profile {
        let mut p = Profile::default();
        for i in 0..samples.len() {
            let x = samples.reference[i][0];
            let h = samples.half_size[i][0];
            p.x.push(x);
            p.width.push(2.0 * h);
            p.value.push(samples.stress[i][(0, 0)]);
            p.exact.push(self.averages(x - h, x + h, t).0);
        }
        p.sort();
        p
    }

    /// All metrics of `method` at time `t` (`samples` is a reusable buffer).
    pub fn evaluate<const D: usize, M: Method<D> + ?Sized>(
        &self,
        method: &M,
        samples: &mut Samples<D>,
        t: f64,
        dx: f64,
    ) -> TimeMetrics {
        method.sample_into(samples);
        let profile = self.profile(samples, t);
        let front = self.front(t);
        let ProfileMetrics {
            l1_rel,
            linf_rel,
            front_width_cells,
            overshoot_pct,
        } = profile.metrics(front.as_ref(), dx, self.scale());
        TimeMetrics {
            t,
            l1_rel,
            linf_rel,
            front_width_cells,
            overshoot_pct,
            energy_rel: energy_rel(method.energy(), self.work(t)),
        }
    }
}

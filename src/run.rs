//! Running methods on a problem: the controller, metrics at every output time, and
//! (optionally) the output files.
use impact_core::controller::{self, Guard, RunError};
use impact_core::method::{MethodConfig, Samples};
use impact_core::reference::{Reference, TimeMetrics};
use impact_core::{Blowup, Method, Problem};
use serde::Serialize;

/// One method's run, as stored in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct RunRecord {
    /// Method name.
    pub method: String,
    /// Courant number.
    pub courant: f64,
    /// Points per cell (1 for FEM, which has no points).
    pub points_per_cell: usize,
    /// Integrator label.
    pub integrator: String,
    /// Cells.
    pub cells: usize,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// Metrics at every output time reached.
    pub times: Vec<TimeMetrics>,
    /// The blow-up that stopped the run, if any.
    pub error: Option<String>,
}

/// Hooks for progress and output during [`run_method`] (called on the rayon worker that
/// runs the step loop, see [`controller::run`]).
pub trait Observer<const D: usize>: Send {
    /// Called after each step with the current time.
    fn progress(&mut self, _t: f64) {}
    /// Called at each output time with the method state.
    fn output(
        &mut self,
        _method: &dyn Method<D>,
        _index: usize,
        _t: f64,
        _metrics: &TimeMetrics,
    ) -> anyhow::Result<()> {
        Ok(())
    }
}

/// An observer that does nothing (tests, benchmarks).
pub struct Silent;
impl<const D: usize> Observer<D> for Silent {}

/// Run one method on `problem` through every output time, computing the metrics. A
/// blow-up ends the run early: the record holds the metrics reached and the error.
pub fn run_method<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    reference: Option<&Reference>,
    observer: &mut dyn Observer<D>,
) -> anyhow::Result<(RunRecord, Option<Blowup>)> {
    let mut method = crate::build(problem, config)?;
    let dx = problem.grid.spacing[0];
    let mut samples = Samples::<D>::default();
    let mut times = Vec::new();
    let mut steps_at_output = 0;
    // shared by the output and progress hooks (never contended: one thread calls both)
    let observer = std::sync::Mutex::new(observer);
    // a hook that panicked has ended the run already; the observer is still usable
    let lock = std::sync::PoisonError::into_inner;
    let result = controller::run::<D, dyn Method<D>, anyhow::Error>(
        method.as_mut(),
        &problem.output_times,
        Guard::default(),
        |m, index, t, steps| {
            let metrics = match reference {
                Some(r) => r.evaluate(m, &mut samples, t, dx),
                None => TimeMetrics {
                    t,
                    l1_rel: f64::NAN,
                    linf_rel: f64::NAN,
                    front_width_cells: None,
                    overshoot_pct: None,
                    front_position: None,
                    front_exact: None,
                    energy_rel: impact_core::metrics::energy_rel(m.energy(), m.external_work()),
                },
            };
            steps_at_output = steps;
            times.push(metrics);
            observer
                .lock()
                .unwrap_or_else(lock)
                .output(m, index, t, &metrics)
        },
        |t| observer.lock().unwrap_or_else(lock).progress(t),
    );
    let mut record = RunRecord {
        method: config.kind.name().to_string(),
        courant: config.courant,
        points_per_cell: if config.kind == impact_core::MethodKind::Fem {
            1
        } else {
            config.points_per_cell
        },
        integrator: config.integrator_label().to_string(),
        cells: method.cells(),
        steps: steps_at_output,
        wall_s: 0.0,
        times,
        error: None,
    };
    match result {
        Ok(stats) => {
            record.steps = stats.steps;
            record.wall_s = stats.wall_s;
            Ok((record, None))
        }
        Err(RunError::Blowup(b)) => {
            record.error = Some(b.to_string());
            Ok((record, Some(b)))
        }
        Err(RunError::Output(e)) => Err(e),
    }
}

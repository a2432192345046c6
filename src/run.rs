//! Running methods on a problem: the controller, metrics at every output time, and
//! (optionally) the output files; [`run_study`] is `impact run`.
use crate::output::pieces::agree;
use impact_core::controller::{self, RunError};
use impact_core::method::{MethodConfig, Samples};
use impact_core::reference::{Reference, TimeMetrics};
use impact_core::{Blowup, Method, Problem};
use serde::Serialize;

mod files;
use files::{write_figures, write_provenance};

/// One method's run, as stored in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct RunRecord {
    /// Method name.
    pub method: String,
    /// Every option of the run (method, Courant number, points per cell and the method's
    /// own options: integrator, update, flux, Riemann solver, edges; stress update, frame,
    /// shape).
    pub options: crate::provenance::MethodOptionsRecord,
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
    /// The blow-up that stopped the run, if any (absent when the run completed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Ranks the run was split over (absent on one rank; [`crate::ranks`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranks: Option<usize>,
    /// How it was split (absent on one rank).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decomposition: Option<String>,
    /// Bytes all ranks send each other per step, summed over the ranks (absent on one
    /// rank; [`impact_core::Method::bytes_exchanged_per_step`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bytes_per_step: Option<usize>,
}

/// Hooks for progress and output during [`run_method`] (called on the rayon worker that
/// runs the step loop, see [`controller::run`]).
pub trait Observer<const D: usize>: Send {
    /// Called once with the initial state, before the first step.
    fn start(&mut self, _method: &dyn Method<D>) -> anyhow::Result<()> {
        Ok(())
    }
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

/// An observer that only moves a progress bar (cleared when dropped).
pub struct Progress {
    bar: indicatif::ProgressBar,
    t_end: f64,
}

impl Progress {
    /// Drive `bar` over `[0, t_end]`.
    pub fn new(bar: indicatif::ProgressBar, t_end: f64) -> Self {
        Self { bar, t_end }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl<const D: usize> Observer<D> for Progress {
    fn progress(&mut self, t: f64) {
        self.bar.set_position(progress_position(t, self.t_end));
    }
}

/// An observer that does nothing (tests, benchmarks).
pub struct Silent;
impl<const D: usize> Observer<D> for Silent {}

/// The clean interior of `problem` after `steps` steps of `config` where its errors keep
/// to it (`[metrics] interior = "dependence"`, [`impact_core::interior`]), `None` where they
/// cover the whole body; an error where the margin leaves no cell (the scene was checked
/// with its own Courant numbers; a flag can change them).
pub fn clean_interior<const D: usize>(
    problem: &Problem<D>,
    config: &MethodConfig,
    steps: usize,
    t: f64,
) -> anyhow::Result<Option<impact_core::interior::Interior<D>>> {
    use impact_core::interior::{margin_cells, Interior, InteriorRule};
    if problem.interior == InteriorRule::Whole {
        return Ok(None);
    }
    match Interior::after(&problem.grid, config, steps) {
        Some(inside) => Ok(Some(inside)),
        None => anyhow::bail!(
            "metrics.interior = \"dependence\": {} after {steps} steps (t = {t:.4e} s) leaves no \
             clean interior ({} cells in from each face, {:?} cells); give more cells, a larger \
             Courant number or an earlier output time, or `interior = \"whole\"`",
            config.kind().name(),
            margin_cells(config, steps),
            problem.grid.cells
        ),
    }
}

/// Run one method on `problem` through every output time, computing the metrics. A
/// blow-up ends the run early: the record holds the metrics reached and the error.
pub fn run_method<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    reference: Option<&Reference>,
    observer: &mut dyn Observer<D>,
) -> anyhow::Result<(RunRecord, Option<Blowup>)> {
    let mut method = crate::ranks::build_ranked(problem, config)?;
    // (a write that fails on one rank stops every rank: `output::pieces::agree`)
    agree(observer.start(method.as_ref()))?;
    let line = impact_core::line::MeasureLine::of(problem);
    let dx = problem.grid.spacing[line.axis];
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
        guard_for(problem),
        |m, index, t, steps| {
            let metrics = match reference {
                Some(r) => {
                    let interior = clean_interior(problem, &config, steps, t)?;
                    r.evaluate(m, &mut samples, (t, &line, dx), interior.as_ref())
                }
                None => TimeMetrics::without_reference(
                    t,
                    m.energy(),
                    m.external_work() + m.initial_energy(),
                ),
            };
            steps_at_output = steps;
            times.push(metrics);
            agree(
                observer
                    .lock()
                    .unwrap_or_else(lock)
                    .output(m, index, t, &metrics),
            )
        },
        |t| observer.lock().unwrap_or_else(lock).progress(t),
    );
    let mut record = RunRecord {
        method: config.kind().name().to_string(),
        options: crate::provenance::MethodOptionsRecord::of(&config, D),
        courant: config.courant,
        points_per_cell: if config.kind() == impact_core::MethodKind::Fem {
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
        ranks: (crate::ranks::size() > 1).then(crate::ranks::size),
        decomposition: crate::ranks::decomposition(problem, &config),
        bytes_per_step: (crate::ranks::size() > 1).then(|| {
            let mine = method.bytes_exchanged_per_step() as f64;
            crate::ranks::comm().all_reduce_sum(mine) as usize
        }),
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
        Err(e @ RunError::Interrupted { .. }) => {
            Err(crate::interrupt::Interrupted(format!("{}: {e}", record.method)).into())
        }
    }
}

/// What `impact run` does besides running: files and progress bars.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output folder.
    pub out: std::path::PathBuf,
    /// No progress bar or status line.
    pub quiet: bool,
    /// Write only summary.json (no profiles, VTK, HDF5 or plots).
    pub no_files: bool,
    /// How `.vtu` arrays are encoded.
    pub vtu: impact_io::vtu::VtuEncoding,
    /// Run without a reference (`--no-reference`).
    pub no_reference: bool,
    /// The scene as given on the command line (a shipped name, a file, or `--from
    /// <folder>`), for `provenance.json`.
    pub source: String,
    /// `--allow-unstable`: recorded in `provenance.json`.
    pub allow_unstable: bool,
}

/// The outcome of [`run_study`].
#[derive(Debug, Clone)]
pub struct RunReport {
    /// The reference the errors are measured against, in words.
    pub reference: String,
    /// One record per method, in the order run.
    pub records: Vec<RunRecord>,
    /// The blow-ups that stopped runs.
    pub failures: Vec<String>,
}

/// `impact run`: every method of `kinds` (duplicates once) on the study's problem, with
/// the reference, summary.json and (unless `no_files`) profiles, VTK, plots.
pub fn run_study<const D: usize>(
    study: &crate::Study,
    kinds: &[impact_core::MethodKind],
    options: &RunOptions,
) -> anyhow::Result<RunReport> {
    run_study_keeping::<D>(study, kinds, options, false).map(|(report, _)| report)
}

/// [`run_study`], keeping every method's fields at every output time in memory when
/// `keep` (the Python package's `impact.run`; [`crate::fields`]).
pub fn run_study_keeping<const D: usize>(
    study: &crate::Study,
    kinds: &[impact_core::MethodKind],
    options: &RunOptions,
    keep: bool,
) -> anyhow::Result<(RunReport, Vec<crate::fields::MethodFields>)> {
    use crate::output::{FileWriter, Summary};
    use crate::plots::Collected;
    use impact_core::method::{MethodKind, Model};
    let clock = crate::provenance::Clock::start();
    match options.no_reference {
        true => study.check_methods_work(kinds)?,
        false => study.check_work(kinds)?,
    }
    let problem = study.problem::<D>()?;
    let stability = check_all_stable(study, &problem, kinds.iter().map(|&k| study.config(k)))?;
    // every rank's folder opened (or every rank stops), and rank 0's staging folder, where
    // every rank writes its pieces (`output::pieces`)
    let folder = agree(impact_io::folder::OutputFolder::open(&options.out).map_err(Into::into))?;
    let dir = &folder.path().to_path_buf();
    let shared = crate::output::pieces::shared_staging(dir)?;
    let reference = match options.no_reference {
        true => None,
        false => crate::reference_for(&problem, kinds, !options.quiet)?,
    };
    let mut summary = Summary {
        scene: study.name().to_string(),
        dim: D,
        reference: reference
            .as_ref()
            .map_or("none (errors not computed)".into(), |r| r.describe()),
        reference_setup: match &reference {
            Some(impact_core::reference::Reference::Converged(_)) => {
                study.reference_setup(kinds)?
            }
            _ => None,
        },
        metrics_line: impact_core::line::MeasureLine::of(&problem).describe::<D>(),
        runs: Vec::new(),
        peak_rss_mib: None,
        peak_rss_mib_per_rank: Vec::new(),
        stability,
    };
    let (mut collected, mut failures) = (Vec::<Collected>::new(), Vec::new());
    let mut fields = Vec::new();
    let mut done: Vec<MethodKind> = Vec::new();
    for &kind in kinds {
        if done.contains(&kind) {
            continue;
        }
        done.push(kind);
        let progress = (!options.quiet).then(|| progress_bar(kind.name()));
        let mut writer = FileWriter::<D>::new(
            dir,
            kind.name(),
            &problem.grid,
            reference.as_ref(),
            progress,
            problem.t_end,
        );
        writer.files = !options.no_files;
        writer.pieces = crate::output::pieces::Pieces::of_ranks(shared.clone());
        // kept fields go through the writer's output hook, which `collect` opens
        writer.collect = !options.no_files || keep;
        writer.keep = keep.then(Vec::new);
        writer.encoding = options.vtu;
        writer.measure = problem.model.stress_measure();
        writer.line = impact_core::line::MeasureLine::of(&problem);
        if D == 2 && problem.model == Model::LinearElastic {
            writer.plane_strain = Some(problem.material);
        }
        let config = study.config(kind);
        let (mut record, blowup) = run_method(&problem, config, reference.as_ref(), &mut writer)?;
        agree(writer.finish())?;
        if let Some(frames) = writer.keep.take() {
            fields.push(crate::fields::MethodFields {
                method: kind.name().to_string(),
                stress_name: writer.measure.array_name().to_string(),
                frames,
            });
        }
        collected.push(Collected {
            name: kind.name().to_string(),
            legend: crate::plots::legend_label(kind.name(), &config),
            profiles: std::mem::take(&mut writer.profiles),
            positions: std::mem::take(&mut writer.positions),
            maps: std::mem::take(&mut writer.maps),
        });
        if let Some(b) = blowup {
            let cause = crate::guard::diagnose_blowup(&problem, config)
                .map_or(String::new(), |c| format!("; {c}"));
            let message = format!("{b}{cause}");
            record.error = Some(message.clone());
            failures.push(message);
        }
        summary.runs.push(record);
    }
    summary.peak_rss_mib = crate::output::peak_rss_mib();
    if crate::ranks::size() > 1 {
        let mine = summary.peak_rss_mib.unwrap_or(f64::NAN);
        summary.peak_rss_mib_per_rank = crate::ranks::comm().all_gather(&[mine]);
    }
    let written = || -> anyhow::Result<()> {
        impact_io::write_json(&dir.join("summary.json"), &summary)?;
        // (rank 0 alone holds the map plane: the other ranks draw nothing)
        if !options.no_files && crate::ranks::is_root() {
            write_figures(study.name(), &problem, reference.as_ref(), dir, &collected)?;
        }
        write_provenance(study, options, &done, &summary, dir, &clock)
    };
    // every rank's files and pieces written (the last collective step) before rank 0
    // publishes the folder; a commit that fails on rank 0 fails every rank
    agree(written())?;
    crate::interrupt::check()?;
    agree(
        folder
            .commit(concat!("impact ", env!("CARGO_PKG_VERSION")))
            .map_err(Into::into),
    )?;
    let report = RunReport {
        reference: summary.reference,
        records: summary.runs,
        failures,
    };
    Ok((report, fields))
}

/// The stability guard before any work (module [`crate::guard`]): every configuration of
/// `kinds` within its von Neumann limit, or `--allow-unstable`; the notes (printed on
/// stderr) of the configurations run above their limit or not checked, to record.
pub fn check_all_stable<const D: usize>(
    study: &crate::Study,
    problem: &impact_core::Problem<D>,
    configs: impl IntoIterator<Item = impact_core::method::MethodConfig>,
) -> anyhow::Result<Vec<String>> {
    use crate::guard::Stability;
    let mut notes = Vec::new();
    for config in configs {
        match crate::guard::check_stable(problem, config, study.overrides.allow_unstable)? {
            Stability::Stable => {}
            Stability::Unchecked(note) => {
                if crate::ranks::is_root() {
                    eprintln!("note: {note}");
                }
                notes.push(note);
            }
            Stability::AllowedUnstable(warning) => {
                if crate::ranks::is_root() {
                    eprintln!("warning: {warning}");
                }
                notes.push(warning);
            }
        }
    }
    Ok(notes)
}

/// The guard of a run of `problem`: the interrupt flag, and the max-norm test on the
/// loads' stress scale ([`impact_core::controller`]).
pub fn guard_for<const D: usize>(problem: &impact_core::Problem<D>) -> controller::Guard {
    let mut guard = crate::interrupt::guard();
    guard.stress_scale = problem.load_scale().0.max(f64::MIN_POSITIVE);
    guard.impedance = problem.material.density * problem.material.p_wave_speed::<D>();
    guard
}

/// A run stopped by the stability guard (exit code 3; its frames are kept).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BlewUp(pub String);

/// A progress bar on stderr over `[0, t_end]` (hidden when stderr is not a terminal), or
/// in the [`crate::progress_feed::Feed`] installed on this thread (the Python package).
pub fn progress_bar(prefix: &'static str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(PROGRESS_STEPS);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{prefix:>9} [{bar:40}] {percent:>3}% {elapsed_precise} (eta {eta})",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(prefix);
    crate::progress_feed::register(&bar);
    bar
}

/// Ticks of a progress bar.
const PROGRESS_STEPS: u64 = 1000;

/// The bar position of time `t` in `[0, t_end]`.
pub fn progress_position(t: f64, t_end: f64) -> u64 {
    ((PROGRESS_STEPS as f64 * t / t_end.max(f64::MIN_POSITIVE)) as u64).min(PROGRESS_STEPS)
}

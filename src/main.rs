//! `impact` command line: run a scene with DGMPM, MPM and FEM side by side, and check
//! that DGMPM captures the wave front more sharply than MPM.
use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand};
use impact::check::{check_study, Against, CheckOptions, Thresholds, Verdict};
use impact::run::{run_study, RunOptions, RunRecord};
use impact::{Overrides, Study};
use impact_core::method::MethodKind;
use impact_core::metrics::{ErrorBasis, FrontStatus};
use impact_core::Scene;
use std::path::PathBuf;

/// Print a line to stdout; a closed pipe (`impact run bar | head`) ends the program
/// quietly instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

/// DGMPM vs MPM vs FEM for impact waves in solids.
#[derive(Parser)]
#[command(name = "impact", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene with the selected methods; print the table and write out/<scene>/.
    Run(RunArgs),
    /// Exit 0 only if DGMPM's front width and overshoot are below MPM's at every output
    /// time. The method flags apply as in `run` (`--courant`, `--points-per-cell` to both
    /// methods; each method's own flags to it); `--dgmpm-*`/`--mpm-*` set one method.
    Check(CheckArgs),
    /// Critical Courant numbers of every method and configuration: empirical (bisection on
    /// perturbed runs) and, for DGMPM, von Neumann, on the default sweep scenes or on
    /// `--scene <name|file.toml>`; writes stability.csv and stability.png.
    Stability(StabilityArgs),
    /// Benchmarks: `impact bench work-precision --scene <name|file.toml>`, `impact bench
    /// convergence --scene <name|file.toml>`, `impact bench output`.
    Bench {
        #[command(subcommand)]
        what: BenchCommand,
    },
    /// The paper's Fig. 3, 5 and 6 and the studies (work-precision, stability, MPM
    /// variants, elastoplastic fronts) as PNG and SVG, with index.html.
    Figures(FiguresArgs),
    /// List the shipped scenes.
    Scenes,
}

#[derive(Args)]
struct FiguresArgs {
    /// Figures to make (default: all); the others already in the folder are kept.
    #[arg(value_enum)]
    figures: Vec<impact::figures::FigureName>,
    /// Output folder.
    #[arg(long, default_value = "figures")]
    out: PathBuf,
    /// Paper-scale ladders and sweeps (minutes to an hour) instead of the reduced ones.
    #[arg(long)]
    full: bool,
    /// No progress bars or status lines on stderr.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args, Clone)]
struct SceneArgs {
    /// A shipped scene name (`impact scenes`) or a path to a scene file (.toml).
    scene: String,
    #[command(flatten)]
    overrides: Overrides,
}

#[derive(Args)]
struct RunArgs {
    /// A shipped scene name (`impact scenes`) or a path to a scene file (.toml).
    #[arg(required_unless_present = "from")]
    scene: Option<String>,
    #[command(flatten)]
    overrides: Overrides,
    /// Run again the exact configuration of an output folder of `impact run` (its
    /// scene.toml and the methods and flags of its provenance.json), into a new folder
    /// (default: out/<scene>-rerun). Takes no scene, method or option flags.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "method", "no_files", "no_reference", "vtu"])]
    from: Option<PathBuf>,
    /// Methods to run, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "dgmpm,mpm,fem"
    )]
    method: Vec<MethodKind>,
    /// Output folder (default: out/<scene name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Write only summary.json, provenance.json and scene.toml (no profiles, VTK, HDF5 or
    /// plots): no I/O at output times.
    #[arg(long)]
    no_files: bool,
    /// Skip the reference (exact or converged): errors and fronts are not computed.
    #[arg(long)]
    no_reference: bool,
    /// Encoding of the `.vtu` files: zlib-compressed binary, or ASCII text.
    #[arg(long, value_enum, default_value = "binary")]
    vtu: impact_io::vtu::VtuEncoding,
}

#[derive(Args)]
struct CheckArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The MPM to compare with: the scene's (default), the scene's with one shape function
    /// (linear, gimp, bspline2, bspline3, cpdi), or `all-mpm` (every shape function, one
    /// verdict each; the gate passes only if DGMPM beats them all).
    #[arg(long)]
    against: Option<String>,
    /// DGMPM's Courant number only (`--courant` sets both methods).
    #[arg(long, allow_negative_numbers = true)]
    dgmpm_courant: Option<f64>,
    /// MPM's Courant number only.
    #[arg(long, allow_negative_numbers = true)]
    mpm_courant: Option<f64>,
    /// DGMPM's points per cell only (`--points-per-cell` sets both methods).
    #[arg(long)]
    dgmpm_points_per_cell: Option<usize>,
    /// MPM's points per cell only.
    #[arg(long)]
    mpm_points_per_cell: Option<usize>,
    /// MPM's front width over DGMPM's must exceed this at every output time (1: strictly
    /// narrower).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    min_width_ratio: f64,
    /// DGMPM's overshoot passes when at most this many % of the jump, whatever MPM's is
    /// (default: it must be below MPM's).
    #[arg(long, allow_negative_numbers = true)]
    max_overshoot: Option<f64>,
    /// Write the outcome as JSON (keys documented in the README).
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write the outcome as JUnit XML: one test case per output time.
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    /// No progress bars or status messages on stderr.
    #[arg(long)]
    quiet: bool,
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Run time against error over a refinement ladder for every method and configuration;
    /// writes work_precision.{csv,json,png}.
    WorkPrecision {
        /// Scene: a shipped scene name (bar, svk-bar, plate-wave, plate, ...) or a scene
        /// file (.toml). Its reference (exact, or in 2D converged per run) is stated; a 1D
        /// scene without an exact solution is refused.
        #[arg(long, default_value = "bar")]
        scene: String,
        /// Refinement levels (1D: 75·2^k cells; 2D: 16·2^k cells along x, y keeping the
        /// scene's cell shape). Default: 9 in 1D (to 19,200 cells), 7 for plate-wave (to
        /// 1024×768, about 17 min on 2 cores), 6 for plate (to 512×388, about 23 min: each run
        /// computes its own 4× finer reference, which would pass the 1e7-cell input limit at
        /// 1024), 5 for other 2D scenes.
        #[arg(long)]
        levels: Option<usize>,
        /// Output folder (default: out/work-precision-<scene>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run nothing: print the summary sentence of the ladder already in this folder
        /// (its work_precision.json).
        #[arg(long, value_name = "DIR", conflicts_with_all = ["levels", "out"])]
        summarize: Option<PathBuf>,
        /// Scene and method flags of `impact run` (not those the ladder sets: --cells,
        /// --courant, --points-per-cell, --integrator, --flux, --shape).
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Observed orders of accuracy on smooth exact solutions (standing waves) for every
    /// method and configuration; writes convergence.{csv,json,png,txt}.
    Convergence {
        /// Scene: a shipped scene name (smooth-bar, smooth-plate, ...) or a scene file
        /// (.toml). Errors are against its exact solution, or in 2D each level's converged
        /// reference (stated); a 1D scene without an exact solution is refused.
        #[arg(long, default_value = "smooth-bar")]
        scene: String,
        /// Refinement levels k = 1..levels (1D: 75·2^k cells; 2D: 16·2^k along x, y keeping
        /// the scene's cell shape).
        #[arg(long, default_value_t = 4)]
        levels: usize,
        /// Output folder (default: out/convergence-<scene>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Scene and method flags of `impact run` (not those the ladder sets: --cells,
        /// --courant, --points-per-cell, --integrator, --flux, --shape).
        #[command(flatten)]
        overrides: Overrides,
    },
    /// Size and write time of one output frame (samples and grid `.vtu`) of the partial
    /// plate, binary against ASCII, interleaved rounds.
    Output {
        /// Cells along x (the plate keeps its 4:3 shape).
        #[arg(long, default_value_t = 1000)]
        cells: usize,
        /// Rounds per encoding.
        #[arg(long, default_value_t = 3)]
        rounds: usize,
    },
}

#[derive(Args)]
struct StabilityArgs {
    /// Sweep on this scene (a shipped name or a scene file): its material, model, point
    /// layout and cell size, on its grid cut to at most 150 cells (1D) or 16×12 (2D) with
    /// every edge unloaded. Default: the paper's bar (1D) and the plane wave cut to 16×12
    /// cells (2D).
    #[arg(long, conflicts_with = "dim")]
    scene: Option<String>,
    /// Scene and method flags of `impact run` that the sweep does not vary (--riemann,
    /// --edges, --stress-update, --frame, --shape, --yield-stress, --hardening).
    #[command(flatten)]
    overrides: Overrides,
    /// Dimensions to sweep (default 1,2; with --scene, the scene's).
    #[arg(long, value_delimiter = ',')]
    dim: Option<Vec<usize>>,
    /// Steps of each perturbed run in 1D.
    #[arg(long, default_value_t = 20000)]
    steps_1d: usize,
    /// Steps of each perturbed run in 2D.
    #[arg(long, default_value_t = 3000)]
    steps_2d: usize,
    /// Output folder.
    #[arg(long, default_value = "out/stability")]
    out: PathBuf,
    /// Where the points sit in a cell (DGMPM and MPM): centred sub-cells, shifted by
    /// `--shift`, or at the 1D local `--positions`.
    #[arg(long, value_enum)]
    layout: Option<impact_core::method::LayoutKind>,
    /// Shift of every point in sub-cell widths, |shift| < 0.5 (`--layout shifted`).
    #[arg(long)]
    shift: Option<f64>,
    /// Local positions in (0, 1) of the points of a cell, comma-separated (`--layout
    /// given`, 1D; only that number of points per cell is swept).
    #[arg(long, value_delimiter = ',')]
    positions: Option<Vec<f64>>,
}

impl StabilityArgs {
    /// Put the layout flags on a scene (checked with the scene's validation).
    fn layout_onto(&self, scene: &mut Scene) -> Result<()> {
        use impact_core::method::LayoutKind;
        // no layout flag: the scene's layout (centred for the default sweep scenes)
        if self.layout.is_some() || self.shift.is_some() || self.positions.is_some() {
            scene.domain.layout = Some(self.layout.unwrap_or(LayoutKind::Centred));
            scene.domain.shift = self.shift;
            scene.domain.positions = None;
        }
        if let Some(list) = &self.positions {
            if scene.dim != 1 {
                bail!("--positions: 1D only (one local coordinate per point); run with --dim 1");
            }
            scene.domain.points_per_cell = list.len();
            scene.domain.positions = Some(list.iter().map(|u| vec![*u]).collect());
        } else if self.layout == Some(LayoutKind::Given) {
            bail!("--layout given needs --positions (e.g. --positions 0.2,0.7)");
        }
        scene
            .validate()
            .map_err(|e| anyhow::anyhow!("{e} (from --layout, --shift or --positions)"))
    }
}

impl SceneArgs {
    /// The study: the scene (shipped or from a file) with the overrides, validated once.
    fn study(&self) -> Result<Study> {
        Ok(Study::load(&self.scene, self.overrides.clone())?)
    }
}

/// Output times in seconds (7 significant digits) and in cell transits `h/c` of this grid.
fn describe_times(times: &[f64], transit: f64) -> String {
    times
        .iter()
        .map(|t| format!("{t:.6e} s ({:.2} transits)", t / transit))
        .collect::<Vec<_>>()
        .join(", ")
}

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

fn print_header() {
    say!(
        "{:<6} {:>7} {:>4} {:>8} {:>6} {:>8} {:>10} {:>10} {:>10} {:>11} {:>10} {:>11} {:>8} {:>8}",
        "method",
        "courant",
        "ppc",
        "integr.",
        "steps",
        "wall_s",
        "t_ms",
        "L1_rel",
        "Linf_rel",
        "front_cells",
        "overshoot%",
        "energy_rel",
        "front_m",
        "exact_m"
    );
}

/// An error in its basis: relative as `1.234e-2`, absolute as `1.234e5Pa`, none as `-`.
fn fmt_error(value: f64, basis: ErrorBasis) -> String {
    match basis {
        ErrorBasis::Relative => format!("{value:.3e}"),
        ErrorBasis::AbsoluteZeroReference => format!("{value:.2e}Pa"),
        ErrorBasis::NoReference => "-".into(),
    }
}

fn print_rows(r: &RunRecord) {
    let mut notes: Vec<String> = Vec::new();
    for t in &r.times {
        say!(
            "{:<6} {:>7.3} {:>4} {:>8} {:>6} {:>8.4} {:>10.6} {:>10} {:>10} {:>11} {:>10} {:>11} {:>8} {:>8}",
            r.method,
            r.courant,
            r.points_per_cell,
            r.integrator,
            r.steps,
            r.wall_s,
            t.t * 1e3,
            fmt_error(t.l1, t.errors),
            fmt_error(t.linf, t.errors),
            fmt_opt(t.front_width_cells, 2),
            fmt_opt(t.overshoot_pct, 2),
            if t.energy_relative {
                format!("{:.3e}", t.energy_error)
            } else {
                format!("{:.2e}J", t.energy_error)
            },
            fmt_opt(t.front_position, 3),
            fmt_opt(t.front_exact, 3)
        );
        let front_note = match (t.front, t.front_reason) {
            (FrontStatus::Measured, _) => None,
            (_, Some(reason)) => Some(format!("t = {:.4} ms: {}", t.t * 1e3, reason.describe())),
            (status, None) => Some(status.describe().to_string()),
        };
        for note in [
            (t.errors != ErrorBasis::Relative).then(|| t.errors.describe().to_string()),
            front_note,
            (!t.energy_relative).then(|| {
                "energy_rel: nothing was put in (no work, no initial energy), so the energy \
                 column is E_h in J"
                    .to_string()
            }),
        ]
        .into_iter()
        .flatten()
        {
            if !notes.contains(&note) {
                notes.push(note);
            }
        }
    }
    for note in notes {
        say!("{:<6} note: {note}", r.method);
    }
    if let Some(e) = &r.error {
        say!("{:<6} stopped: {e}", r.method);
    }
}

/// What `impact run` runs: the study, the methods and the run's options.
struct RunPlan {
    study: Study,
    methods: Vec<MethodKind>,
    options: RunOptions,
}

impl RunArgs {
    /// The plan of the flags given, or of the folder of `--from`.
    fn plan(&self) -> Result<RunPlan> {
        if let Some(folder) = &self.from {
            let given = self.overrides.given();
            if let Some(flag) = given.first() {
                bail!(
                    "invalid value for `{flag}`: given with --from (allowed with --from: --out \
                     and --quiet; the folder's scene.toml holds every option)"
                );
            }
            let (mut study, record, flags) = impact::provenance::replay_study(folder)?;
            // the replayed run was allowed above its von Neumann limit as the original was
            study.overrides.allow_unstable = record.allow_unstable;
            let vtu = <impact_io::vtu::VtuEncoding as clap::ValueEnum>::from_str(&flags.vtu, true)
                .map_err(|e| {
                    anyhow::anyhow!("--from {}: vtu {:?}: {e}", folder.display(), flags.vtu)
                })?;
            let out = self
                .out
                .clone()
                .unwrap_or_else(|| PathBuf::from("out").join(format!("{}-rerun", study.name())));
            return Ok(RunPlan {
                options: RunOptions {
                    out,
                    quiet: self.quiet,
                    no_files: flags.no_files,
                    no_reference: flags.no_reference,
                    vtu,
                    source: format!("--from {}", folder.display()),
                    allow_unstable: record.allow_unstable,
                },
                methods: flags.methods,
                study,
            });
        }
        let scene = self.scene.clone().context("a scene or --from is needed")?;
        let study = SceneArgs {
            scene: scene.clone(),
            overrides: self.overrides.clone(),
        }
        .study()?;
        Ok(RunPlan {
            options: RunOptions {
                out: self
                    .out
                    .clone()
                    .unwrap_or_else(|| PathBuf::from("out").join(study.name())),
                quiet: self.quiet,
                no_files: self.no_files,
                no_reference: self.no_reference,
                vtu: self.vtu,
                source: scene,
                allow_unstable: study.overrides.allow_unstable,
            },
            methods: self.method.clone(),
            study,
        })
    }
}

fn run_command(args: &RunArgs) -> Result<()> {
    let plan = args.plan()?;
    match plan.study.dim() {
        1 => run_scene::<1>(&plan),
        2 => run_scene::<2>(&plan),
        d => bail!("dim = {d} is not supported (allowed: 1 or 2)"),
    }
}

fn run_scene<const D: usize>(plan: &RunPlan) -> Result<()> {
    let (study, options) = (&plan.study, &plan.options);
    match options.no_reference {
        true => study.check_methods_work(&plan.methods)?,
        false => study.check_work(&plan.methods)?,
    }
    let problem = study.problem::<D>()?;
    say!(
        "scene {} ({}D, {} cells), output times: {}",
        study.name(),
        D,
        problem.grid.cell_count(),
        describe_times(&problem.output_times, study.scene.transit().1)
    );
    say!(
        "metrics line: {}",
        impact_core::line::MeasureLine::of(&problem).describe::<D>()
    );
    let report = run_study::<D>(study, &plan.methods, options)?;
    print_header();
    for r in &report.records {
        print_rows(r);
    }
    let dir = &options.out;
    if options.no_files {
        say!("wrote {}", dir.join("summary.json").display());
        if !report.failures.is_empty() {
            return Err(impact::run::BlewUp(report.failures.join("; ")).into());
        }
        return Ok(());
    }
    say!("wrote {}", dir.display());
    if !report.failures.is_empty() {
        return Err(impact::run::BlewUp(format!(
            "{} (frames written before the blow-up are kept in {})",
            report.failures.join("; "),
            dir.display()
        ))
        .into());
    }
    Ok(())
}

fn check_command(args: &CheckArgs) -> Result<bool> {
    let clock = impact::provenance::Clock::start();
    let options = CheckOptions {
        against: args.against.as_deref().map(Against::parse).transpose()?,
        dgmpm_courant: args.dgmpm_courant,
        mpm_courant: args.mpm_courant,
        dgmpm_points_per_cell: args.dgmpm_points_per_cell,
        mpm_points_per_cell: args.mpm_points_per_cell,
        thresholds: Thresholds {
            min_width_ratio: args.min_width_ratio,
            max_overshoot: args.max_overshoot,
        },
        progress: !args.quiet,
    };
    let study = args.scene.study()?;
    let reports = match study.dim() {
        1 => check_study::<1>(&study, &options)?,
        2 => check_study::<2>(&study, &options)?,
        d => bail!("dim = {d} is not supported (allowed: 1 or 2)"),
    };
    for report in &reports {
        print_check(study.name(), report);
    }
    if let Some(path) = &args.json {
        let mut record = impact::provenance::Provenance::new("check", &clock).with_study_inline(
            &study,
            &args.scene.scene,
            &[MethodKind::Dgmpm, MethodKind::Mpm],
        );
        record.reference = study
            .reference_for_errors()
            .unwrap_or_else(|e| e.to_string());
        record.runs = reports
            .iter()
            .flat_map(|r| [&r.dgmpm_record, &r.mpm_record])
            .map(|r| impact::provenance::RunEntry {
                options: r.options.clone(),
                steps: r.steps,
                wall_s: r.wall_s,
                error: r.error.clone(),
            })
            .collect();
        record.finish(&clock);
        impact::check_report::write_json(
            path,
            (study.name(), &record),
            options.thresholds,
            &reports,
        )
        .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &args.junit {
        impact::check_report::write_junit(path, study.name(), &reports)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    // a run the guard stopped: exit 3 (the reports above say which, at what time)
    if let Some(stopped) = reports
        .iter()
        .flat_map(|r| [&r.dgmpm_record.error, &r.mpm_record.error])
        .flatten()
        .next()
    {
        return Err(impact::run::BlewUp(stopped.clone()).into());
    }
    Ok(reports.iter().all(|r| r.pass))
}

fn print_check(scene: &str, report: &impact::check::CheckReport) {
    let (dg, mpm) = (&report.dgmpm, &report.mpm);
    let shape = mpm.mpm().map_or("-", |o| o.shape.name());
    say!(
        "check {scene}: DGMPM (courant {}, {} ppc, {}) vs MPM (courant {}, {} ppc, {}, {shape})",
        dg.courant,
        dg.points_per_cell,
        report.dgmpm_record.integrator,
        mpm.courant,
        mpm.points_per_cell,
        report.mpm_record.integrator
    );
    say!(
        "{:>10} {:>13} {:>13} {:>13} {:>13}  verdict",
        "t_ms",
        "dgmpm_front",
        "mpm_front",
        "dgmpm_over%",
        "mpm_over%"
    );
    for r in &report.rows {
        say!(
            "{:>10.4} {:>13} {:>13} {:>13} {:>13}  {}",
            r.t * 1e3,
            fmt_opt(r.dgmpm_front, 3),
            fmt_opt(r.mpm_front, 3),
            fmt_opt(r.dgmpm_overshoot, 3),
            fmt_opt(r.mpm_overshoot, 3),
            match r.reason {
                Some(reason) => format!("skip ({})", reason.describe()),
                None => r.verdict.label().to_string(),
            }
        );
        if let Some(s) = r.second {
            say!(
                "{:>10} {:>13} {:>13} {:>13} {:>13}  (plastic wave)",
                "",
                fmt_opt(s.dgmpm_front, 3),
                fmt_opt(s.mpm_front, 3),
                fmt_opt(s.dgmpm_overshoot, 3),
                fmt_opt(s.mpm_overshoot, 3),
            );
        }
    }
    for e in [&report.dgmpm_record.error, &report.mpm_record.error]
        .into_iter()
        .flatten()
    {
        say!("stopped: {e}");
    }
    if !report
        .rows
        .iter()
        .any(|r| matches!(r.verdict, Verdict::Pass | Verdict::Fail))
    {
        say!("no output time has a measurable front to compare: the gate gives no pass");
    }
    say!(
        "{}",
        if report.pass {
            format!("PASS: DGMPM front sharper than MPM ({shape}) at every output time")
        } else {
            format!("FAIL against MPM ({shape})")
        }
    );
}

fn work_precision_command(
    scene: &str,
    overrides: &Overrides,
    levels: Option<usize>,
    out: Option<PathBuf>,
) -> Result<()> {
    let study = Study::load(scene, overrides.clone())?;
    let levels = levels.unwrap_or_else(|| impact::ladder::default_levels(&study));
    let out = out.unwrap_or_else(|| impact::work_precision::default_out(study.name()));
    let exe = std::env::current_exe().context("locating the impact executable")?;
    let total = impact::ladder::usable_configurations(&study)
        .map_or(0, |(configs, _)| configs.len())
        * levels;
    let bar = indicatif::ProgressBar::new(total as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("work-precision [{bar:40}] {pos}/{len} {msg}")
            .expect("internal: valid template")
            .progress_chars("=> "),
    );
    let (points, sentence) = impact::work_precision::run(
        &exe,
        (&study, scene),
        levels,
        &out,
        |note| bar.suspend(|| say!("{note}")),
        |p| {
            bar.set_message(format!("{} {} cells", p.config, p.cells));
            bar.inc(1);
        },
    )?;
    bar.finish_and_clear();
    say!(
        "{:<26} {:>8} {:>7} {:>10} {:>12} {:>9} {:>10}",
        "config",
        "cells",
        "steps",
        "wall_s",
        "updates/s",
        "peak_MiB",
        "L1_rel"
    );
    for p in &points {
        say!(
            "{:<26} {:>8} {:>7} {:>10.3e} {:>12.3e} {:>9.1} {:>10.3e}{}",
            p.config,
            p.cells,
            p.steps,
            p.wall_s,
            p.updates_per_s,
            p.peak_rss_mib,
            p.l1_rel,
            p.error
                .as_ref()
                .map_or(String::new(), |e| format!("  stopped: {e}"))
        );
    }
    say!("{sentence}");
    say!("{}", impact::work_precision::ranking(&points).trim_end());
    say!("wrote {}", out.display());
    Ok(())
}

fn convergence_command(
    scene: &str,
    overrides: &Overrides,
    levels: usize,
    out: Option<PathBuf>,
) -> Result<()> {
    let study = Study::load(scene, overrides.clone())?;
    let out = out.unwrap_or_else(|| impact::convergence::default_out(study.name()));
    let table = impact::convergence::run((&study, scene), levels, &out, |note| say!("{note}"))?;
    say!("{table}wrote {}", out.display());
    Ok(())
}

fn figures_command(args: &FiguresArgs) -> Result<()> {
    let index = impact::figures::run(&impact::figures::FiguresOptions {
        out: args.out.clone(),
        full: args.full,
        only: args.figures.clone(),
        progress: !args.quiet,
    })?;
    for e in &index.entries {
        let stems: Vec<&str> = e.images.iter().map(|i| i.stem.as_str()).collect();
        say!("{:<15} {:>7.2} s  {}", e.name, e.seconds, stems.join(", "));
    }
    say!("wrote {}", args.out.join("index.html").display());
    Ok(())
}

fn stability_command(args: &StabilityArgs) -> Result<()> {
    use impact::stability::{sweep, StabilityRow};
    let clock = impact::provenance::Clock::start();
    for (flag, steps, most) in [
        ("--steps-1d", args.steps_1d, 1_000_000),
        ("--steps-2d", args.steps_2d, 100_000),
    ] {
        if steps == 0 || steps > most {
            bail!("invalid value for `{flag}`: {steps} (allowed: 1 to {most} steps per perturbed run)");
        }
    }
    let mut scenes =
        impact::ladder::sweep_scenes(args.scene.as_deref(), args.dim.as_deref(), &args.overrides)?;
    for scene in scenes.iter_mut() {
        if args.positions.is_some() && scene.dim != 1 && args.scene.is_none() {
            continue;
        }
        args.layout_onto(scene)?;
    }
    let folder = impact_io::folder::OutputFolder::open(&args.out)?;
    say!(
        "{:>3} {:<6} {:>4} {:>8} {:>5} {:>9} {:>10} {:>12} {:>9}",
        "dim",
        "method",
        "ppc",
        "integr.",
        "flux",
        "update",
        "empirical",
        "von_neumann",
        "monotone"
    );
    let print = |r: &StabilityRow| {
        say!(
            "{:>3} {:<6} {:>4} {:>8} {:>5} {:>9} {:>10.4} {:>12} {:>9}",
            r.dim,
            r.method,
            r.points_per_cell,
            r.integrator,
            r.flux,
            r.update,
            r.empirical,
            r.von_neumann.map_or("-".to_string(), |v| format!("{v:.4}")),
            r.monotone.map_or("-".to_string(), |v| format!("{v:.4}"))
        )
    };
    let mut rows = Vec::new();
    let mut record = impact::provenance::Provenance::new("stability", &clock);
    record.reference = "none: the sweep measures stability limits, not errors".into();
    for scene in &scenes {
        let study = Study::new(scene.clone(), Overrides::default())?;
        let skipped = match scene.dim {
            1 => impact::stability::refused::<1>(&study.problem::<1>()?, scene),
            _ => impact::stability::refused::<2>(&study.problem::<2>()?, scene),
        };
        for note in &skipped {
            say!("skipped: {note}");
        }
        record.notes.extend(skipped);
        match scene.dim {
            1 => rows.extend(sweep(&study.problem::<1>()?, scene, args.steps_1d, print)),
            _ => rows.extend(sweep(&study.problem::<2>()?, scene, args.steps_2d, print)),
        }
    }
    impact::interrupt::check()?;
    impact::stability::write(folder.path(), &rows)?;
    // the swept scenes: scene.toml (one scene) or scene-<d>d.toml (the default sweep)
    for scene in &scenes {
        let file = match scenes.len() {
            1 => impact::provenance::SCENE_FILE.to_string(),
            _ => format!("scene-{}d.toml", scene.dim),
        };
        impact::provenance::write_scene(&folder.path().join(&file), scene)?;
        record.scene = Some(scene.name.clone());
        record.scene_file = Some(file);
    }
    if scenes.len() > 1 {
        record.scene = None;
        record.scene_file = None;
        record
            .notes
            .push("swept scenes: scene-1d.toml and scene-2d.toml".into());
    }
    record.scene_source = args.scene.clone();
    record.overrides = args.overrides.given();
    record.configurations = scenes
        .iter()
        .flat_map(|scene| {
            match scene.dim {
                1 => impact::stability::configurations::<1>(scene),
                _ => impact::stability::configurations::<2>(scene),
            }
            .into_iter()
            .map(|c| impact::provenance::MethodOptionsRecord::of(&c, scene.dim))
        })
        .collect();
    record.write(folder.path(), &clock)?;
    impact::interrupt::check()?;
    folder.commit(concat!("impact ", env!("CARGO_PKG_VERSION")))?;
    say!("wrote {}", args.out.display());
    Ok(())
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = impact::interrupt::install() {
        eprintln!("error: cannot install the SIGINT/SIGTERM handlers: {e}");
        std::process::exit(2);
    }
    let result = match &cli.command {
        Command::Run(a) => run_command(a).map(|_| true),
        Command::Figures(a) => figures_command(a).map(|_| true),
        Command::Check(a) => check_command(a),
        Command::Stability(a) => stability_command(a).map(|_| true),
        Command::Bench {
            what:
                BenchCommand::WorkPrecision {
                    summarize: Some(dir),
                    ..
                },
        } => impact::work_precision::summarize_dir(dir).map(|sentence| {
            say!("{sentence}");
            true
        }),
        Command::Bench {
            what:
                BenchCommand::WorkPrecision {
                    scene,
                    levels,
                    out,
                    overrides,
                    ..
                },
        } => work_precision_command(scene, overrides, *levels, out.clone()).map(|_| true),
        Command::Bench {
            what:
                BenchCommand::Convergence {
                    scene,
                    levels,
                    out,
                    overrides,
                },
        } => convergence_command(scene, overrides, *levels, out.clone()).map(|_| true),
        Command::Bench {
            what: BenchCommand::Output { cells, rounds },
        } => impact::output_bench::run(*cells, *rounds).map(|(count, t, costs)| {
            say!("plate, {count} cells, DGMPM frame at t = {t:.6e} s");
            say!(
                "{:<8} {:>14} {:>14} {:>12}  per round",
                "encoding",
                "samples_bytes",
                "grid_bytes",
                "median_s"
            );
            for c in &costs {
                let rounds: Vec<String> = c.seconds.iter().map(|s| format!("{s:.3}")).collect();
                say!(
                    "{:<8} {:>14} {:>14} {:>12.3}  {}",
                    format!("{:?}", c.encoding).to_lowercase(),
                    c.samples_bytes,
                    c.grid_bytes,
                    c.median(),
                    rounds.join(" ")
                );
            }
            true
        }),
        Command::Scenes => {
            for name in impact_core::scene::BUILTIN {
                say!("{name}");
            }
            Ok(true)
        }
    };
    match result {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            // exit codes: 0 done or the gate passes, 1 the gate fails, 2 bad input,
            // 3 a run blew up (its frames kept), 130 interrupted
            let code = if e.downcast_ref::<impact::interrupt::Interrupted>().is_some() {
                130
            } else if e.downcast_ref::<impact::run::BlewUp>().is_some() {
                3
            } else {
                2
            };
            std::process::exit(code);
        }
    }
}

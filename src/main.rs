//! `impact` command line: run a scene with DGMPM, MPM and FEM side by side, and check
//! that DGMPM captures the wave front more sharply than MPM.
use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use impact::output::{stress_map, stress_plot, FileWriter, Summary};
use impact::run::{run_method, RunRecord, Silent};
use impact::{scene_config, Overrides};
use impact_core::method::{
    Integrator, MethodKind, MpmFrame, PointUpdate, RiemannSolver, StressUpdate, TransverseFlux,
};
use impact_core::{Problem, Scene};
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
    /// time (each at the scene's Courant number; the method flags change DGMPM only).
    Check(CheckArgs),
    /// Critical Courant numbers of every method and configuration: empirical (bisection on
    /// perturbed runs) and, for DGMPM, von Neumann; writes stability.csv and stability.png.
    Stability(StabilityArgs),
    /// Benchmarks: `impact bench work-precision --scene bar|svk-bar|plate-wave|plate`.
    Bench {
        #[command(subcommand)]
        what: BenchCommand,
    },
    /// List the shipped scenes.
    Scenes,
}

#[derive(Args, Clone)]
struct SceneArgs {
    /// A shipped scene name (`impact scenes`) or a path to a scene file (.toml).
    scene: String,
    /// Cells along x (other axes scaled to keep the cell shape).
    #[arg(long)]
    cells: Option<usize>,
    /// Courant number c·Δt/Δx, in (0, 2].
    #[arg(long, allow_negative_numbers = true)]
    courant: Option<f64>,
    /// Material points per cell (1D: 1..64; 2D: 1, 4, 9, ...).
    #[arg(long)]
    points_per_cell: Option<usize>,
    /// DGMPM time integrator.
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// DGMPM point update after the nodal solve.
    #[arg(long, value_enum)]
    update: Option<UpdateArg>,
    /// MPM stress update.
    #[arg(long, value_enum)]
    stress_update: Option<StressUpdateArg>,
    /// DGMPM Riemann solver for Saint-Venant-Kirchhoff.
    #[arg(long, value_enum)]
    riemann: Option<RiemannArg>,
    /// Direction of the pressure load on the loaded end.
    #[arg(long, value_enum)]
    load: Option<LoadArg>,
    /// Magnitude of the pressure load in Pa (keeps the direction unless --load is given).
    #[arg(long, allow_negative_numbers = true)]
    load_magnitude: Option<f64>,
    /// DGMPM transverse flux in 2D: donor-cell upwind or corner transport upwind.
    #[arg(long, value_enum)]
    flux: Option<FluxArg>,
    /// MPM frame: shape functions at reference (total) or current (updated) positions.
    #[arg(long, value_enum)]
    frame: Option<FrameArg>,
    /// End time in seconds (outputs after it are dropped; it becomes the last output).
    #[arg(long, allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Output times in seconds, comma-separated and increasing.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    output_times: Option<Vec<f64>>,
}

#[derive(Args)]
struct RunArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Methods to run, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "dgmpm,mpm,fem")]
    method: Vec<MethodArg>,
    /// Output folder (default: out/<scene name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Write only summary.json (no profiles, VTK, HDF5 or plots): no I/O at output times.
    #[arg(long)]
    no_files: bool,
}

#[derive(Args)]
struct CheckArgs {
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Run time against error over a refinement ladder for every method and configuration;
    /// writes work_precision.{csv,json,png}.
    WorkPrecision {
        /// Scene: bar, svk-bar, plate-wave or plate.
        #[arg(long, default_value = "bar")]
        scene: String,
        /// Refinement levels (1D: 75·2^k cells; 2D: 16·2^k × 12·2^k). Default: 9 in 1D
        /// (to 19,200 cells), 7 for plate-wave (to 1024×768, about 17 min on 2 cores), 6 for
        /// plate (to 512×388, about 23 min: each run computes its own 4× finer reference, which
        /// would pass the 1e7-cell input limit at 1024).
        #[arg(long)]
        levels: Option<usize>,
        /// Output folder (default: out/work-precision-<scene>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run nothing: print the summary sentence of the ladder already in this folder
        /// (its work_precision.json).
        #[arg(long, value_name = "DIR", conflicts_with_all = ["levels", "out"])]
        summarize: Option<PathBuf>,
    },
}

#[derive(Args)]
struct StabilityArgs {
    /// Dimensions to sweep.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    dim: Vec<usize>,
    /// Steps of each perturbed run in 1D.
    #[arg(long, default_value_t = 20000)]
    steps_1d: usize,
    /// Steps of each perturbed run in 2D.
    #[arg(long, default_value_t = 3000)]
    steps_2d: usize,
    /// Output folder.
    #[arg(long, default_value = "out/stability")]
    out: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum MethodArg {
    Dgmpm,
    Mpm,
    Fem,
}

#[derive(Clone, Copy, ValueEnum)]
enum IntegratorArg {
    Euler,
    Rk2,
}

#[derive(Clone, Copy, ValueEnum)]
enum UpdateArg {
    Nodal,
    Increment,
}

#[derive(Clone, Copy, ValueEnum)]
enum RiemannArg {
    Approximate,
    Exact,
}

#[derive(Clone, Copy, ValueEnum)]
enum LoadArg {
    Compression,
    Tension,
}

#[derive(Clone, Copy, ValueEnum)]
enum FluxArg {
    Dcu,
    Ctu,
}

#[derive(Clone, Copy, ValueEnum)]
enum FrameArg {
    TotalLagrangian,
    UpdatedLagrangian,
}

#[derive(Clone, Copy, ValueEnum)]
enum StressUpdateArg {
    Usl,
    Musl,
    Usf,
}

impl SceneArgs {
    fn load(&self) -> Result<Scene> {
        let looks_like_file = self.scene.ends_with(".toml") || self.scene.contains('/');
        let mut scene = if looks_like_file {
            Scene::from_file(std::path::Path::new(&self.scene))?
        } else {
            match Scene::builtin(&self.scene) {
                Some(s) => s,
                None => bail!(
                    "unknown scene {:?}: give a shipped scene ({}) or a path to a .toml file",
                    self.scene,
                    impact_core::scene::BUILTIN.join(", ")
                ),
            }
        };
        self.overrides().apply_to_scene(&mut scene)?;
        scene.validate()?;
        Ok(scene)
    }

    fn overrides(&self) -> Overrides {
        Overrides {
            cells: self.cells,
            courant: self.courant,
            points_per_cell: self.points_per_cell,
            integrator: self.integrator.map(|i| match i {
                IntegratorArg::Euler => Integrator::Euler,
                IntegratorArg::Rk2 => Integrator::Rk2,
            }),
            update: self.update.map(|u| match u {
                UpdateArg::Nodal => PointUpdate::Nodal,
                UpdateArg::Increment => PointUpdate::Increment,
            }),
            stress_update: self.stress_update.map(|u| match u {
                StressUpdateArg::Usl => StressUpdate::Usl,
                StressUpdateArg::Musl => StressUpdate::Musl,
                StressUpdateArg::Usf => StressUpdate::Usf,
            }),
            frame: self.frame.map(|f| match f {
                FrameArg::TotalLagrangian => MpmFrame::TotalLagrangian,
                FrameArg::UpdatedLagrangian => MpmFrame::UpdatedLagrangian,
            }),
            flux: self.flux.map(|f| match f {
                FluxArg::Dcu => TransverseFlux::DonorCell,
                FluxArg::Ctu => TransverseFlux::Ctu,
            }),
            riemann: self.riemann.map(|r| match r {
                RiemannArg::Approximate => RiemannSolver::Approximate,
                RiemannArg::Exact => RiemannSolver::Exact,
            }),
            compression: self.load.map(|l| matches!(l, LoadArg::Compression)),
            load_magnitude: self.load_magnitude,
            t_end: self.t_end,
            output_times: self.output_times.clone(),
        }
    }
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

fn print_rows(r: &RunRecord) {
    for t in &r.times {
        say!(
            "{:<6} {:>7.3} {:>4} {:>8} {:>6} {:>8.4} {:>10.4} {:>10.3e} {:>10.3e} {:>11} {:>10} {:>11.3e} {:>8} {:>8}",
            r.method,
            r.courant,
            r.points_per_cell,
            r.integrator,
            r.steps,
            r.wall_s,
            t.t * 1e3,
            t.l1_rel,
            t.linf_rel,
            fmt_opt(t.front_width_cells, 2),
            fmt_opt(t.overshoot_pct, 2),
            t.energy_rel,
            fmt_opt(t.front_position, 3),
            fmt_opt(t.front_exact, 3)
        );
    }
    if let Some(e) = &r.error {
        say!("{:<6} stopped: {e}", r.method);
    }
}

fn run_command(args: &RunArgs) -> Result<()> {
    let scene = args.scene.load()?;
    match scene.dim {
        1 => run_scene::<1>(&scene, args),
        2 => run_scene::<2>(&scene, args),
        d => bail!("dim = {d} is not supported (allowed: 1 or 2)"),
    }
}

fn run_scene<const D: usize>(scene: &Scene, args: &RunArgs) -> Result<()> {
    let overrides = args.scene.overrides();
    let mut problem = Problem::<D>::from_scene(scene)?;
    overrides.apply_to_problem(&mut problem)?;
    let reference = impact::reference_for(&problem, !args.quiet)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&scene.name));
    impact_io::create_dir(&dir)?;
    let mut kinds: Vec<MethodKind> = Vec::new();
    for m in &args.method {
        let k = match m {
            MethodArg::Dgmpm => MethodKind::Dgmpm,
            MethodArg::Mpm => MethodKind::Mpm,
            MethodArg::Fem => MethodKind::Fem,
        };
        if !kinds.contains(&k) {
            kinds.push(k);
        }
    }
    let mut summary = Summary {
        scene: scene.name.clone(),
        dim: D,
        reference: reference
            .as_ref()
            .map_or("none (errors not computed)".into(), |r| r.describe()),
        runs: Vec::new(),
        peak_rss_mib: None,
    };
    let mut plots = Vec::new();
    let mut dgmpm_positions = Vec::new();
    let mut maps: Vec<(String, impact::output::CellMap)> = Vec::new();
    let mut failures = Vec::new();
    say!(
        "scene {} ({}D, {} cells, output times {:?} ms)",
        scene.name,
        D,
        problem.grid.cell_count(),
        problem
            .output_times
            .iter()
            .map(|t| (t * 1e6).round() / 1e3)
            .collect::<Vec<_>>()
    );
    let mut rows = Vec::new();
    for kind in kinds {
        let mut config = scene_config(scene, kind);
        overrides.apply_to_config(&mut config)?;
        let progress = (!args.quiet).then(|| {
            let bar = indicatif::ProgressBar::new(1000);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{prefix:>6} [{bar:40}] {percent:>3}% {elapsed_precise}",
                )
                .expect("internal: valid template")
                .progress_chars("=> "),
            );
            bar.set_prefix(kind.name());
            bar
        });
        let mut writer = FileWriter::<D>::new(
            &dir,
            kind.name(),
            &problem.grid,
            reference.as_ref(),
            progress,
            problem.t_end,
        );
        writer.files = !args.no_files;
        if D == 2 && problem.model == impact_core::method::Model::LinearElastic {
            writer.plane_strain = Some(problem.material);
        }
        let (record, blowup) = run_method(&problem, config, reference.as_ref(), &mut writer)?;
        writer.finish()?;
        if kind == MethodKind::Dgmpm {
            dgmpm_positions = std::mem::take(&mut writer.positions);
        }
        maps.push((kind.name().to_string(), writer.last_map.take()));
        plots.push((
            kind.name().to_string(),
            std::mem::take(&mut writer.profiles),
        ));
        if let Some(b) = blowup {
            failures.push(b.to_string());
        }
        rows.push(record.clone());
        summary.runs.push(record);
    }
    print_header();
    for r in &rows {
        print_rows(r);
    }
    summary.peak_rss_mib = impact::output::peak_rss_mib();
    impact_io::write_json(&dir.join("summary.json"), &summary)?;
    if args.no_files {
        say!("wrote {}", dir.join("summary.json").display());
        if !failures.is_empty() {
            bail!("{}", failures.join("; "));
        }
        return Ok(());
    }
    let length = problem.grid.upper()[0] - problem.grid.origin[0];
    let band = if D > 1 { problem.grid.spacing[1] } else { 0.0 };
    stress_plot(
        &dir.join("stress.png"),
        &scene.name,
        &plots,
        reference.as_ref(),
        length,
        band,
    )?;
    if D == 1 && matches!(problem.model, impact_core::method::Model::Svk(_)) {
        impact::output::svk_plot(
            &dir.join("svk.png"),
            &scene.name,
            &dgmpm_positions,
            &plots,
            reference.as_ref(),
            length,
        )?;
    }
    if D == 2 {
        let g = &problem.grid;
        let grid2 = impact_core::Grid::<2> {
            origin: impact_core::Vector::<2>::new(g.origin[0], g.origin[1 % D]),
            spacing: impact_core::Vector::<2>::new(g.spacing[0], g.spacing[1 % D]),
            cells: [g.cells[0], g.cells[1 % D]],
        };
        stress_map(&dir.join("stress_map.png"), &grid2, &maps)?;
    }
    say!("wrote {}", dir.display());
    if !failures.is_empty() {
        bail!(
            "{} (frames written before the blow-up are kept in {})",
            failures.join("; "),
            dir.display()
        );
    }
    Ok(())
}

fn check_command(args: &CheckArgs) -> Result<bool> {
    let scene = args.scene.load()?;
    match scene.dim {
        1 => check_scene::<1>(&scene, args),
        2 => check_scene::<2>(&scene, args),
        d => bail!("dim = {d} is not supported (allowed: 1 or 2)"),
    }
}

fn check_scene<const D: usize>(scene: &Scene, args: &CheckArgs) -> Result<bool> {
    let overrides = args.scene.overrides();
    let mut problem = Problem::<D>::from_scene(scene)?;
    overrides.apply_to_problem(&mut problem)?;
    let reference = impact::reference_for(&problem, false)?.with_context(|| {
        format!(
            "scene {} has no reference to measure fronts against",
            scene.name
        )
    })?;
    let mut dg = scene_config(scene, MethodKind::Dgmpm);
    overrides.apply_to_config(&mut dg)?;
    let mpm = scene_config(scene, MethodKind::Mpm);
    let (dg_rec, dg_err) = run_method(&problem, dg, Some(&reference), &mut Silent)?;
    let (mpm_rec, mpm_err) = run_method(&problem, mpm, Some(&reference), &mut Silent)?;
    say!(
        "check {}: DGMPM (courant {}, {} ppc, {}) vs MPM (courant {}, {} ppc, {})",
        scene.name,
        dg.courant,
        dg.points_per_cell,
        dg_rec.integrator,
        mpm.courant,
        mpm.points_per_cell,
        mpm_rec.integrator
    );
    say!(
        "{:>10} {:>13} {:>13} {:>13} {:>13}  verdict",
        "t_ms",
        "dgmpm_front",
        "mpm_front",
        "dgmpm_over%",
        "mpm_over%"
    );
    let mut ok = dg_err.is_none() && mpm_err.is_none();
    let worse = |v: Option<f64>| v.unwrap_or(f64::INFINITY);
    let n = dg_rec.times.len().max(mpm_rec.times.len());
    let mut compared = 0;
    for k in 0..n {
        let (d, m) = (dg_rec.times.get(k), mpm_rec.times.get(k));
        let t = d.or(m).map(|x| x.t).unwrap_or(0.0);
        let (dw, mw) = (
            d.and_then(|x| x.front_width_cells),
            m.and_then(|x| x.front_width_cells),
        );
        let (dov, mov) = (
            d.and_then(|x| x.overshoot_pct),
            m.and_then(|x| x.overshoot_pct),
        );
        let verdict = if d.is_none() || m.is_none() {
            ok = false;
            "FAIL (run stopped)"
        } else if reference.front(t).is_none() {
            "skip (no front)"
        } else {
            compared += 1;
            if worse(dw) < worse(mw) && worse(dov) < worse(mov) {
                "pass"
            } else {
                ok = false;
                "FAIL"
            }
        };
        say!(
            "{:>10.4} {:>13} {:>13} {:>13} {:>13}  {verdict}",
            t * 1e3,
            fmt_opt(dw, 3),
            fmt_opt(mw, 3),
            fmt_opt(dov, 3),
            fmt_opt(mov, 3)
        );
    }
    for e in [dg_err, mpm_err].into_iter().flatten() {
        say!("stopped: {e}");
    }
    if compared == 0 {
        say!("no output time has a front to compare");
        ok = false;
    }
    say!(
        "{}",
        if ok {
            "PASS: DGMPM front sharper than MPM at every output time"
        } else {
            "FAIL"
        }
    );
    Ok(ok)
}

fn work_precision_command(scene: &str, levels: Option<usize>, out: Option<PathBuf>) -> Result<()> {
    let levels = levels.unwrap_or(match scene {
        "plate-wave" => 7,
        "plate" => 6,
        _ => 9,
    });
    let out = out.unwrap_or_else(|| impact::work_precision::default_out(scene));
    let exe = std::env::current_exe().context("locating the impact executable")?;
    let total =
        impact::work_precision::configurations(if scene.starts_with("plate") { 2 } else { 1 })
            .len()
            * levels;
    let bar = indicatif::ProgressBar::new(total as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("work-precision [{bar:40}] {pos}/{len} {msg}")
            .expect("internal: valid template")
            .progress_chars("=> "),
    );
    let (points, sentence) = impact::work_precision::run(&exe, scene, levels, &out, |p| {
        bar.set_message(format!("{} {} cells", p.config, p.cells));
        bar.inc(1);
    })?;
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
    say!("wrote {}", out.display());
    Ok(())
}

fn stability_command(args: &StabilityArgs) -> Result<()> {
    use impact::stability::{sweep, StabilityRow};
    for &d in &args.dim {
        if !(d == 1 || d == 2) {
            bail!("--dim {d} is not supported (allowed: 1 and/or 2)");
        }
    }
    if args.steps_1d == 0 || args.steps_2d == 0 {
        bail!("--steps-1d/--steps-2d must be at least 1");
    }
    impact_io::create_dir(&args.out)?;
    say!(
        "{:>3} {:<6} {:>4} {:>8} {:>5} {:>10} {:>12}",
        "dim",
        "method",
        "ppc",
        "integr.",
        "flux",
        "empirical",
        "von_neumann"
    );
    let print = |r: &StabilityRow| {
        say!(
            "{:>3} {:<6} {:>4} {:>8} {:>5} {:>10.4} {:>12}",
            r.dim,
            r.method,
            r.points_per_cell,
            r.integrator,
            r.flux,
            r.empirical,
            r.von_neumann.map_or("-".to_string(), |v| format!("{v:.4}"))
        )
    };
    let mut rows = Vec::new();
    if args.dim.contains(&1) {
        let scene = Scene::builtin("bar").expect("shipped scene");
        let problem = Problem::<1>::from_scene(&scene)?;
        rows.extend(sweep(&problem, &scene, args.steps_1d, print));
    }
    if args.dim.contains(&2) {
        let mut scene = Scene::builtin("plate-wave").expect("shipped scene");
        scene.domain.cells = vec![16, 12];
        let problem = Problem::<2>::from_scene(&scene)?;
        rows.extend(sweep(&problem, &scene, args.steps_2d, print));
    }
    impact::stability::write(&args.out, &rows)?;
    say!("wrote {}", args.out.display());
    Ok(())
}

fn main() {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Run(a) => run_command(a).map(|_| true),
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
            what: BenchCommand::WorkPrecision {
                scene, levels, out, ..
            },
        } => work_precision_command(scene, *levels, out.clone()).map(|_| true),
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
            std::process::exit(2);
        }
    }
}

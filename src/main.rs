//! `impact` command line: run a scene with DGMPM, MPM and FEM side by side, and check
//! that DGMPM captures the wave front more sharply than MPM.
use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand};
use impact::check::{check_study, Verdict};
use impact::run::{run_study, RunOptions, RunRecord};
use impact::{Overrides, Study};
use impact_core::method::MethodKind;
use impact_core::metrics::{ErrorBasis, FrontStatus};
use std::path::PathBuf;

/// Print a line to stdout; a closed pipe (`impact run bar | head`) ends the program
/// quietly instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        // (on several ranks, rank 0 speaks for all)
        if !impact::ranks::is_root() {
        } else if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

mod commands;
mod table;
use commands::*;
use table::*;

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
    #[command(flatten)]
    gate: impact::flags::CheckFlags,
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
        /// 1024×768, about 17 min on 2 cores), 5 for plate (to 256×194: each run computes its
        /// own 8× finer references, which would pass the 1e7-cell input limit at 512), 5 for
        /// other 2D scenes.
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
    /// Lamb's problem: every method's surface displacement traces at the scene's receivers
    /// against Pekeris' exact solution, on grids of half, 1 and 2 times the scene's cells;
    /// writes lamb.{csv,txt} and lamb_traces.png.
    Lamb {
        /// Scene: `lamb` (shipped) or a scene file with a pressure on a square patch of one
        /// face, Poisson's ratio 0.25 and `[metrics] receivers` on that face.
        #[arg(long, default_value = "lamb")]
        scene: String,
        /// Grids: 1 to 4 (half, 1, 2, 4 times the scene's cells).
        #[arg(long, default_value_t = 3)]
        levels: usize,
        /// Methods (default: all three).
        #[arg(long, value_delimiter = ',')]
        method: Vec<MethodKind>,
        /// Output folder (default: out/lamb-<scene>).
        #[arg(long)]
        out: Option<PathBuf>,
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
    /// layout and cell size, on its grid cut to at most 150 cells (1D), or cut or widened to
    /// 16×12 (2D) or 12×12×12 (3D), with every edge unloaded. Default: the paper's bar (1D)
    /// and the plane wave cut to 16×12 cells (2D).
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

impl SceneArgs {
    /// The study: the scene (shipped or from a file) with the overrides, validated once.
    fn study(&self) -> Result<Study> {
        Ok(Study::load(&self.scene, self.overrides.clone())?)
    }
}

fn main() {
    let cli = Cli::parse();
    // MPI when launched by mpirun/srun with the `mpi` feature (finalised before exiting)
    let ranks = impact::ranks::init().unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2);
    });
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
            what:
                BenchCommand::Lamb {
                    scene,
                    levels,
                    method,
                    out,
                },
        } => lamb_command(scene, *levels, method, out.clone()).map(|_| true),
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
        Ok(false) => {
            drop(ranks);
            std::process::exit(1)
        }
        Err(e) => {
            // every rank fails alike (inputs and blow-ups are seen by all): one message
            if impact::ranks::is_root() {
                eprintln!("error: {e:#}");
            }
            // exit codes: 0 done or the gate passes, 1 the gate fails, 2 bad input,
            // 3 a run blew up (its frames kept), 130 interrupted
            let code = if e.downcast_ref::<impact::interrupt::Interrupted>().is_some() {
                130
            } else if e.downcast_ref::<impact::run::BlewUp>().is_some() {
                3
            } else {
                2
            };
            drop(ranks);
            std::process::exit(code);
        }
    }
}

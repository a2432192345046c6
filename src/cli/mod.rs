//! The `impact` command line: the commands and their flags (clap), one file per command
//! holding its flags, its function and what it prints; the work is the library's
//! (`impact::…`), which the Python package shares.
use anyhow::Result;
use clap::{Args, Parser, Subcommand};
use impact::{Overrides, Study};
use impact_core::metrics::ErrorBasis;

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

/// `work` on the output folder `out` on rank 0, and on a private scratch folder on the other
/// ranks (removed after): on several ranks every rank runs the same command (`impact::ranks`)
/// and only rank 0's files are kept, so the ranks never contend for one folder's lock.
fn in_own_folder<T>(
    out: &std::path::Path,
    work: impl FnOnce(&std::path::Path) -> Result<T>,
) -> Result<T> {
    if impact::ranks::is_root() {
        return work(out);
    }
    let result = work(&impact::ranks::scratch_output());
    let _ = std::fs::remove_dir_all(impact::ranks::scratch_folder());
    result
}

mod bench;
mod check;
mod figures;
mod run;
mod scenes;
mod stability;

/// DGMPM vs MPM vs FEM for impact waves in solids.
#[derive(Parser)]
#[command(name = "impact", version, about)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Run a scene with the selected methods; print the table and write out/<scene>/.
    Run(run::RunArgs),
    /// Exit 0 only if DGMPM's front width and overshoot are below MPM's at every output
    /// time. The method flags apply as in `run` (`--courant`, `--points-per-cell` to both
    /// methods; each method's own flags to it); `--dgmpm-*`/`--mpm-*` set one method.
    Check(check::CheckArgs),
    /// Critical Courant numbers of every method and configuration: empirical (bisection on
    /// perturbed runs) and, for DGMPM, von Neumann, on the default sweep scenes or on
    /// `--scene <name|file.toml>`; writes stability.csv and stability.png.
    Stability(stability::StabilityArgs),
    /// Benchmarks: `impact bench work-precision --scene <name|file.toml>`, `impact bench
    /// convergence --scene <name|file.toml>`, `impact bench output`.
    Bench {
        #[command(subcommand)]
        what: bench::BenchCommand,
    },
    /// The paper's Fig. 3, 5 and 6 and the studies (work-precision, stability, MPM
    /// variants, elastoplastic fronts) as PNG and SVG, with index.html.
    Figures(figures::FiguresArgs),
    /// List the shipped scenes.
    Scenes,
}

#[derive(Args, Clone)]
pub(crate) struct SceneArgs {
    /// A shipped scene name (`impact scenes`) or a path to a scene file (.toml).
    pub(crate) scene: String,
    #[command(flatten)]
    pub(crate) overrides: Overrides,
}

impl SceneArgs {
    /// The study: the scene (shipped or from a file) with the overrides, validated once.
    pub(crate) fn study(&self) -> Result<Study> {
        Ok(Study::load(&self.scene, self.overrides.clone())?)
    }
}

/// Run the command; `Ok(false)` when a gate fails (exit 1).
pub(crate) fn dispatch(command: &Command) -> Result<bool> {
    match command {
        Command::Run(a) => run::command(a).map(|_| true),
        Command::Figures(a) => figures::command(a).map(|_| true),
        Command::Check(a) => check::command(a),
        Command::Stability(a) => stability::command(a).map(|_| true),
        Command::Bench { what } => bench::command(what).map(|_| true),
        Command::Scenes => scenes::command().map(|_| true),
    }
}

/// An optional number with `digits` decimals, `-` when absent (the tables of `run` and
/// `check`).
pub(crate) fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

/// An error in its basis: relative as `1.234e-2`, absolute as `1.234e5Pa`, none as `-`.
pub(crate) fn fmt_error(value: f64, basis: ErrorBasis) -> String {
    match basis {
        ErrorBasis::Relative => format!("{value:.3e}"),
        ErrorBasis::AbsoluteZeroReference => format!("{value:.2e}Pa"),
        ErrorBasis::NoReference => "-".into(),
    }
}

/// An L1 error with the reference's uncertainty where there is a second reference:
/// `4.100e-2±8e-4` (the spread in the error's basis, [`impact_core::converged::Spread`]).
pub(crate) fn fmt_l1(t: &impact_core::reference::TimeMetrics) -> String {
    match (t.l1_spread, t.errors) {
        (Some(s), ErrorBasis::Relative) => format!("{}±{s:.1e}", fmt_error(t.l1, t.errors)),
        (Some(s), ErrorBasis::AbsoluteZeroReference) => {
            format!("{}±{s:.1e}Pa", fmt_error(t.l1, t.errors))
        }
        _ => fmt_error(t.l1, t.errors),
    }
}

//! `impact bench`: work-precision, convergence, lamb and output; their flags and what
//! they print (stdout).
use anyhow::{Context, Result};
use clap::Subcommand;
use impact::{Overrides, Study};
use impact_core::method::MethodKind;
use std::path::PathBuf;

#[derive(Subcommand)]
pub(crate) enum BenchCommand {
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

pub(crate) fn command(what: &BenchCommand) -> Result<()> {
    match what {
        BenchCommand::WorkPrecision {
            summarize: Some(dir),
            ..
        } => {
            let sentence = impact::work_precision::summarize_dir(dir)?;
            say!("{sentence}");
            Ok(())
        }
        BenchCommand::WorkPrecision {
            scene,
            levels,
            out,
            overrides,
            ..
        } => work_precision(scene, overrides, *levels, out.clone()),
        BenchCommand::Convergence {
            scene,
            levels,
            out,
            overrides,
        } => convergence(scene, overrides, *levels, out.clone()),
        BenchCommand::Lamb {
            scene,
            levels,
            method,
            out,
        } => lamb(scene, *levels, method, out.clone()),
        BenchCommand::Output { cells, rounds } => output(*cells, *rounds),
    }
}

fn work_precision(
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
    let (points, sentence) = super::in_own_folder(&out, |folder| {
        impact::work_precision::run(
            &exe,
            (&study, scene),
            levels,
            folder,
            |note| bar.suspend(|| say!("{note}")),
            |p| {
                bar.set_message(format!("{} {} cells", p.config, p.cells));
                bar.inc(1);
            },
        )
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
            "{:<26} {:>8} {:>7} {:>10.3e} {:>12.3e} {:>9.1} {:>10.3e}{}{}",
            p.config,
            p.cells,
            p.steps,
            p.wall_s,
            p.updates_per_s,
            p.peak_rss_mib,
            p.l1_rel,
            p.l1_spread
                .map_or(String::new(), |s| format!(" ± {s:.1e} (reference spread)")),
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

fn convergence(
    scene: &str,
    overrides: &Overrides,
    levels: usize,
    out: Option<PathBuf>,
) -> Result<()> {
    let study = Study::load(scene, overrides.clone())?;
    let out = out.unwrap_or_else(|| impact::convergence::default_out(study.name()));
    let table = super::in_own_folder(&out, |folder| {
        impact::convergence::run((&study, scene), levels, folder, |note| say!("{note}"))
    })?;
    say!("{table}wrote {}", out.display());
    Ok(())
}

fn lamb(scene: &str, levels: usize, methods: &[MethodKind], out: Option<PathBuf>) -> Result<()> {
    let study = Study::load(scene, Overrides::default())?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("lamb-{}", study.name())));
    let methods = if methods.is_empty() {
        MethodKind::ALL.to_vec()
    } else {
        methods.to_vec()
    };
    let table = super::in_own_folder(&out, |folder| {
        impact::lamb_study::run((&study, scene), levels, &methods, folder)
    })?;
    say!("{table}wrote {}", out.display());
    Ok(())
}

fn output(cells: usize, rounds: usize) -> Result<()> {
    let (count, t, costs) = impact::output_bench::run(cells, rounds)?;
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
    Ok(())
}

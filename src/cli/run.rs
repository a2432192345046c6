//! `impact run`: its flags, its plan (from the flags or `--from`), and the table it prints
//! (stdout) with its notes.
use super::{fmt_error, fmt_l1, fmt_opt, SceneArgs};
use anyhow::{bail, Context, Result};
use clap::Args;
use impact::run::{run_study, RunOptions, RunRecord};
use impact::{Overrides, Study};
use impact_core::method::MethodKind;
use impact_core::metrics::{ErrorBasis, FrontStatus};
use std::path::PathBuf;

#[derive(Args)]
pub(crate) struct RunArgs {
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
    #[command(flatten)]
    methods: impact::flags::MethodFlag,
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
    /// How the ranks of an MPI run split the grid: parts along x, y, z (their product is the
    /// rank count; axes not named get one part). Default: slabs along the last axis. Boxes
    /// for DGMPM, MPM (both frames; in the updated one points migrate between the boxes)
    /// and FEM.
    #[arg(long, value_name = "PX,PY[,PZ]", value_delimiter = ',')]
    ranks_grid: Option<Vec<usize>>,
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
            methods: self.methods.method.clone(),
            study,
        })
    }
}

pub(crate) fn command(args: &RunArgs) -> Result<()> {
    let mut plan = args.plan()?;
    if let Some(parts) = &args.ranks_grid {
        impact::ranks::set_rank_grid(impact_core::comm::RankGrid(parts.clone()));
    }
    impact::ranks::check_rank_grid(plan.study.dim())?;
    // ranks other than 0 run the same code silently into a scratch folder (`ranks`)
    let scratch = (!impact::ranks::is_root()).then(impact::ranks::scratch_folder);
    if scratch.is_some() {
        plan.options.out = impact::ranks::scratch_output();
        plan.options.quiet = true;
    }
    let result = match plan.study.dim() {
        1 => run_scene::<1>(&plan),
        2 => run_scene::<2>(&plan),
        3 => run_scene::<3>(&plan),
        d => bail!("dim = {d} is not supported (allowed: 1, 2 or 3)"),
    };
    if let Some(folder) = scratch {
        let _ = std::fs::remove_dir_all(folder);
    }
    result
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
    say!("reference: {}", report.reference);
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

/// Output times in seconds (7 significant digits) and in cell transits `h/c` of this grid.
fn describe_times(times: &[f64], transit: f64) -> String {
    times
        .iter()
        .map(|t| format!("{t:.6e} s ({:.2} transits)", t / transit))
        .collect::<Vec<_>>()
        .join(", ")
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
            fmt_l1(t),
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
            t.l1_spread.map(|_| {
                "L1_rel ± the reference's uncertainty: the L1 distance between the reference and \
                 the second, independent one (`reference:` above)"
                    .to_string()
            }),
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

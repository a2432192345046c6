//! The commands: `run` (its plan from the flags or `--from`), `check`, `bench
//! work-precision`, `bench convergence`, `figures`, `stability`.
use super::*;

/// What `impact run` runs: the study, the methods and the run's options.
pub(crate) struct RunPlan {
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

pub(crate) fn run_command(args: &RunArgs) -> Result<()> {
    let mut plan = args.plan()?;
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

pub(crate) fn run_scene<const D: usize>(plan: &RunPlan) -> Result<()> {
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

pub(crate) fn check_command(args: &CheckArgs) -> Result<bool> {
    let clock = impact::provenance::Clock::start();
    let options = args.gate.options(!args.quiet)?;
    let study = args.scene.study()?;
    let reports = match study.dim() {
        1 => check_study::<1>(&study, &options)?,
        2 => check_study::<2>(&study, &options)?,
        3 => check_study::<3>(&study, &options)?,
        d => bail!("dim = {d} is not supported (allowed: 1, 2 or 3)"),
    };
    for report in &reports {
        print_check(study.name(), report);
    }
    if let Some(path) = &args.json {
        let source = &args.scene.scene;
        impact::check_report::write_outcome(path, (&study, source), &options, &reports, &clock)
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

pub(crate) fn work_precision_command(
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

pub(crate) fn convergence_command(
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

pub(crate) fn lamb_command(
    scene: &str,
    levels: usize,
    methods: &[MethodKind],
    out: Option<PathBuf>,
) -> Result<()> {
    let study = Study::load(scene, Overrides::default())?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("lamb-{}", study.name())));
    let methods = if methods.is_empty() {
        MethodKind::ALL.to_vec()
    } else {
        methods.to_vec()
    };
    let table = impact::lamb_study::run((&study, scene), levels, &methods, &out)?;
    say!("{table}wrote {}", out.display());
    Ok(())
}

pub(crate) fn figures_command(args: &FiguresArgs) -> Result<()> {
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

pub(crate) fn stability_command(args: &StabilityArgs) -> Result<()> {
    let options = impact::stability_run::StabilityOptions {
        scene: args.scene.clone(),
        dim: args.dim.clone(),
        overrides: args.overrides.clone(),
        steps_1d: args.steps_1d,
        steps_2d: args.steps_2d,
        out: args.out.clone(),
        layout: args.layout,
        shift: args.shift,
        positions: args.positions.clone(),
    };
    impact::stability_run::run(&options, |line| say!("{line}"))?;
    say!("wrote {}", args.out.display());
    Ok(())
}

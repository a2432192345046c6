//! `impact check`: its flags, the gate, and the table it prints (stdout).
use super::{fmt_l1, fmt_opt, SceneArgs};
use anyhow::{bail, Context, Result};
use clap::Args;
use impact::check::{check_study, Verdict};
use std::path::PathBuf;

#[derive(Args)]
pub(crate) struct CheckArgs {
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

pub(crate) fn command(args: &CheckArgs) -> Result<bool> {
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
    // (on several ranks, rank 0 writes the files for all)
    let root = impact::ranks::is_root();
    if let Some(path) = args.json.as_ref().filter(|_| root) {
        let source = &args.scene.scene;
        impact::check_report::write_outcome(path, (&study, source), &options, &reports, &clock)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = args.junit.as_ref().filter(|_| root) {
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
    let shape = impact::check::mpm_label(mpm);
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
    say!("reference: {}", report.reference);
    for (name, record) in [("DGMPM", &report.dgmpm_record), ("MPM", &report.mpm_record)] {
        let errors: Vec<String> = record
            .times
            .iter()
            .map(|t| format!("{:.4} ms {}", t.t * 1e3, fmt_l1(t)))
            .collect();
        say!(
            "L1 of the stress along the line, {name}: {}",
            errors.join(", ")
        );
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

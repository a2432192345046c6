//! `impact check --json FILE` and `--junit FILE`: the gate's outcome for CI systems.
//!
//! JSON (`CheckJson`): `scene`, `pass`, `thresholds`, and per compared MPM a `reports`
//! entry with `mpm_shape`, `pass`, the two configurations (`dgmpm`, `mpm`: method,
//! courant, points_per_cell, integrator), their `stopped` messages, and `rows`, one per
//! output time (`t` in s, `verdict` = `pass|fail|run-stopped|no-front`, `dgmpm_front`,
//! `mpm_front` in cells, `dgmpm_overshoot`, `mpm_overshoot` in %, and `second` for the
//! plastic wave of an elastoplastic reference); each configuration also carries every
//! option (`options`), and `provenance` says what produced the file
//! ([`crate::provenance::Provenance`]; `check` writes no folder, so no `scene.toml`: the
//! resolved scene is in `provenance.resolved_scene`).
//!
//! JUnit XML (the schema GitHub Actions' test reporters, GitLab's `artifacts:reports:junit`
//! and Jenkins' `junit` step read): one `<testsuite>` per compared MPM, one `<testcase>`
//! per output time, with a `<failure>` when that time fails (or a run stopped before it)
//! and `<skipped>` when the reference has no front then.
use crate::check::{CheckReport, CheckRow, Thresholds, Verdict};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// One configuration, as the JSON states it.
#[derive(Debug, Serialize)]
struct ConfigJson<'a> {
    method: &'a str,
    courant: f64,
    points_per_cell: usize,
    integrator: &'a str,
    options: &'a crate::provenance::MethodOptionsRecord,
}

#[derive(Debug, Serialize)]
struct ReportJson<'a> {
    mpm_shape: String,
    pass: bool,
    dgmpm: ConfigJson<'a>,
    mpm: ConfigJson<'a>,
    stopped: Vec<&'a str>,
    rows: &'a [CheckRow],
    /// What the fronts and errors are measured against.
    reference: &'a str,
    /// Each run's metrics per output time (`l1_rel` with `l1_spread`, the reference's
    /// uncertainty, for a converged reference).
    dgmpm_times: &'a [impact_core::reference::TimeMetrics],
    mpm_times: &'a [impact_core::reference::TimeMetrics],
}

/// The `--json` document.
#[derive(Debug, Serialize)]
struct CheckJson<'a> {
    scene: &'a str,
    pass: bool,
    thresholds: Thresholds,
    reports: Vec<ReportJson<'a>>,
    provenance: &'a crate::provenance::Provenance,
}

fn config(record: &crate::run::RunRecord) -> ConfigJson<'_> {
    ConfigJson {
        method: &record.method,
        courant: record.courant,
        points_per_cell: record.points_per_cell,
        integrator: &record.integrator,
        options: &record.options,
    }
}

/// MPM's shape functions, and its transfer where not FLIP (`bspline2 apic`).
fn shape(report: &CheckReport) -> String {
    crate::check::mpm_label(&report.mpm)
}

/// Write the JSON document (atomically), with what produced it (`provenance`: command
/// line, version, commit, machine, options of every run, reference).
pub fn write_json(
    path: &Path,
    (scene, provenance): (&str, &crate::provenance::Provenance),
    thresholds: Thresholds,
    reports: &[CheckReport],
) -> anyhow::Result<()> {
    let doc = CheckJson {
        provenance,
        scene,
        pass: reports.iter().all(|r| r.pass),
        thresholds,
        reports: reports
            .iter()
            .map(|r| ReportJson {
                mpm_shape: shape(r),
                pass: r.pass,
                dgmpm: config(&r.dgmpm_record),
                mpm: config(&r.mpm_record),
                stopped: [&r.dgmpm_record.error, &r.mpm_record.error]
                    .into_iter()
                    .flatten()
                    .map(String::as_str)
                    .collect(),
                rows: &r.rows,
                reference: &r.reference,
                dgmpm_times: &r.dgmpm_record.times,
                mpm_times: &r.mpm_record.times,
            })
            .collect(),
    };
    impact_io::write_json(path, &doc)?;
    Ok(())
}

/// XML text with `&`, `<`, `>`, `"` escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn cells(v: Option<f64>) -> String {
    v.map_or("undefined".into(), |x| format!("{x:.3}"))
}

/// What a failing row measured, for the `<failure>` message.
fn failure_message(row: &CheckRow) -> String {
    let mut text = format!(
        "front width DGMPM {} vs MPM {} cells, overshoot DGMPM {} vs MPM {} %",
        cells(row.dgmpm_front),
        cells(row.mpm_front),
        cells(row.dgmpm_overshoot),
        cells(row.mpm_overshoot)
    );
    if let Some(s) = row.second {
        let _ = write!(
            text,
            "; plastic wave: width DGMPM {} vs MPM {} cells, overshoot DGMPM {} vs MPM {} %",
            cells(s.dgmpm_front),
            cells(s.mpm_front),
            cells(s.dgmpm_overshoot),
            cells(s.mpm_overshoot)
        );
    }
    text
}

/// Write the JUnit XML document (atomically).
pub fn write_junit(path: &Path, scene: &str, reports: &[CheckReport]) -> anyhow::Result<()> {
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let total: usize = reports.iter().map(|r| r.rows.len()).sum();
    let failing = |r: &CheckReport| {
        r.rows
            .iter()
            .filter(|row| matches!(row.verdict, Verdict::Fail | Verdict::RunStopped))
            .count()
    };
    let failures: usize = reports.iter().map(failing).sum();
    let _ = writeln!(
        xml,
        "<testsuites name=\"impact check {}\" tests=\"{total}\" failures=\"{failures}\">",
        escape(scene)
    );
    for r in reports {
        let skipped = r
            .rows
            .iter()
            .filter(|row| row.verdict == Verdict::NoFront)
            .count();
        let suite = format!("impact check {scene}: DGMPM vs MPM ({})", shape(r));
        let wall = r.dgmpm_record.wall_s + r.mpm_record.wall_s;
        let _ = writeln!(
            xml,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" skipped=\"{skipped}\" \
             time=\"{wall:.3}\">",
            escape(&suite),
            r.rows.len(),
            failing(r)
        );
        for row in &r.rows {
            let _ = write!(
                xml,
                "    <testcase classname=\"impact.check.{}\" name=\"t = {:.6e} s\">",
                escape(scene),
                row.t
            );
            match row.verdict {
                Verdict::Pass => {}
                Verdict::Fail => {
                    let _ = write!(
                        xml,
                        "<failure message=\"{}\" type=\"gate\"/>",
                        escape(&failure_message(row))
                    );
                }
                Verdict::RunStopped => {
                    let why = [&r.dgmpm_record.error, &r.mpm_record.error]
                        .into_iter()
                        .flatten()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join("; ");
                    let _ = write!(
                        xml,
                        "<failure message=\"a run stopped before this time: {}\" type=\"stopped\"/>",
                        escape(&why)
                    );
                }
                Verdict::NoFront => {
                    let why = row.reason.map_or(
                        "the reference has no front at this time",
                        impact_core::exact::NoFront::describe,
                    );
                    let _ = write!(xml, "<skipped message=\"{}\"/>", escape(why));
                }
            }
            xml.push_str("</testcase>\n");
        }
        xml.push_str("  </testsuite>\n");
    }
    xml.push_str("</testsuites>\n");
    impact_io::write_atomic(path, |w| w.write_all(xml.as_bytes()))?;
    Ok(())
}

/// `impact check --json <path>`: the provenance of the check of `study` (`source`: the
/// scene as given) with the verdicts of `reports`, as [`write_json`] writes them.
pub fn write_outcome(
    path: &Path,
    (study, source): (&crate::Study, &str),
    options: &crate::check::CheckOptions,
    reports: &[CheckReport],
    clock: &crate::provenance::Clock,
) -> anyhow::Result<()> {
    use impact_core::MethodKind;
    let kinds = [MethodKind::Dgmpm, MethodKind::Mpm];
    let mut record =
        crate::provenance::Provenance::new("check", clock).with_study_inline(study, source, &kinds);
    record.reference = study
        .reference_for_errors(&kinds)
        .unwrap_or_else(|e| e.to_string());
    record.runs = reports
        .iter()
        .flat_map(|r| [&r.dgmpm_record, &r.mpm_record])
        .map(|r| crate::provenance::RunEntry {
            options: r.options.clone(),
            steps: r.steps,
            wall_s: r.wall_s,
            error: r.error.clone(),
        })
        .collect();
    record.finish(clock);
    write_json(path, (study.name(), &record), options.thresholds, reports)
}

//! The tables `impact run` and `impact check` print (stdout) and their notes.
use super::*;
/// Output times in seconds (7 significant digits) and in cell transits `h/c` of this grid.
pub(crate) fn describe_times(times: &[f64], transit: f64) -> String {
    times
        .iter()
        .map(|t| format!("{t:.6e} s ({:.2} transits)", t / transit))
        .collect::<Vec<_>>()
        .join(", ")
}

pub(crate) fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

pub(crate) fn print_header() {
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

pub(crate) fn print_rows(r: &RunRecord) {
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

pub(crate) fn print_check(scene: &str, report: &impact::check::CheckReport) {
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

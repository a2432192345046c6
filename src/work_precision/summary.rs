//! The ladder's summary: which configuration reaches a target error fastest, by what
//! factor the others follow ([`summarize`], [`ranking`]), from the points of a run or of a
//! ladder already written ([`summarize_dir`]).
use super::Point;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Error at or below which a configuration counts as exact (round-off).
pub(super) const EXACT: f64 = 1e-12;

/// Which configuration reaches a target error fastest and by what factor the fastest
/// DGMPM, MPM and FEM configurations follow. The target is the median over configurations
/// of their finest non-exact error. When some configurations are exact on the scene
/// (DGMPM at Courant 1 on the bar and the plane wave: any target is met on the coarsest
/// grid, so factors against them are degenerate), a second sentence repeats the comparison
/// without them.
pub fn summarize(scene: &str, points: &[Point]) -> String {
    let mut labels: Vec<&str> = points.iter().map(|p| p.config.as_str()).collect();
    labels.dedup();
    let finest = |label: &str| {
        points
            .iter()
            .filter(|p| p.config == label && p.error.is_none() && p.l1_rel.is_finite())
            .map(|p| p.l1_rel)
            .reduce(f64::min)
    };
    let exact: Vec<&str> = labels
        .iter()
        .copied()
        .filter(|l| finest(l).is_some_and(|e| e <= EXACT))
        .collect();
    let mut errors: Vec<f64> = labels
        .iter()
        .filter_map(|l| finest(l))
        .filter(|e| *e > EXACT)
        .collect();
    errors.sort_by(f64::total_cmp);
    let target = errors.get(errors.len() / 2).copied().unwrap_or(1e-2);
    let all = format!("{scene}: {}", fastest(points, &labels, target));
    if exact.is_empty() {
        return all;
    }
    let others: Vec<&str> = labels
        .iter()
        .copied()
        .filter(|l| !exact.contains(l))
        .collect();
    format!(
        "{all}. Without the configurations that are exact on this scene ({}): {}",
        exact.join(", "),
        fastest(points, &others, target)
    )
}

/// The sentence of [`summarize`] over the configurations `labels`.
fn fastest(points: &[Point], labels: &[&str], target: f64) -> String {
    let mut times: Vec<(&str, f64)> = labels
        .iter()
        .filter_map(|l| {
            let mine: Vec<&Point> = points.iter().filter(|p| p.config == *l).collect();
            time_to_reach(&mine, target).map(|t| (*l, t))
        })
        .collect();
    times.sort_by(|a, b| a.1.total_cmp(&b.1));
    let Some(&(label, t_best)) = times.first() else {
        return format!("no configuration reaches L1 {target:.2e}");
    };
    let family = |prefix: &str, name: &str| {
        let present = labels.iter().any(|l| l.starts_with(prefix));
        match times.iter().find(|(l, _)| l.starts_with(prefix)) {
            _ if !present => None,
            Some((l, _)) if *l == label => Some(format!("{name} is that one")),
            Some((l, t)) => Some(format!("{name} (`{l}`) needs {:.1}× longer", t / t_best)),
            None => Some(format!("{name} does not reach it on this ladder")),
        }
    };
    let rest: Vec<String> = [("dgmpm", "DGMPM"), ("mpm", "MPM"), ("fem", "FEM")]
        .iter()
        .filter_map(|(p, n)| family(p, n))
        .collect();
    format!(
        "L1 error {target:.2e} is reached fastest by `{label}` in {t_best:.3e} s; {}",
        rest.join("; ")
    )
}

/// Every configuration's wall time to reach the target error of [`summarize`], fastest
/// first (and those that never do), as lines `label  time  factor`.
pub fn ranking(points: &[Point]) -> String {
    let mut labels: Vec<&str> = points.iter().map(|p| p.config.as_str()).collect();
    labels.dedup();
    let mut errors: Vec<f64> = labels
        .iter()
        .filter_map(|l| {
            points
                .iter()
                .filter(|p| p.config == *l && p.error.is_none() && p.l1_rel.is_finite())
                .map(|p| p.l1_rel)
                .reduce(f64::min)
        })
        .filter(|e| *e > EXACT)
        .collect();
    errors.sort_by(f64::total_cmp);
    let target = errors.get(errors.len() / 2).copied().unwrap_or(1e-2);
    let mut rows: Vec<(&str, Option<f64>)> = labels
        .iter()
        .map(|l| {
            let mine: Vec<&Point> = points.iter().filter(|p| p.config == *l).collect();
            (*l, time_to_reach(&mine, target))
        })
        .collect();
    rows.sort_by(|a, b| match (a.1, b.1) {
        (Some(x), Some(y)) => x.total_cmp(&y),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    let best = rows.iter().find_map(|r| r.1).unwrap_or(f64::NAN);
    let mut text = format!("time to reach L1 {target:.2e}:\n");
    for (label, time) in rows {
        text += &match time {
            Some(t) => format!("  {label:<32} {t:>10.3e} s {:>10.1}×\n", t / best),
            None => format!("  {label:<32} {:>12} {:>11}\n", "not reached", "-"),
        };
    }
    text
}

/// The summary sentence of a ladder already run (`work_precision.json` in `dir`).
pub fn summarize_dir(dir: &Path) -> Result<String> {
    let path = dir.join("work_precision.json");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let points: Vec<Point> = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a work-precision result", path.display()))?;
    let Some(first) = points.first() else {
        bail!("{}: no runs in it", path.display());
    };
    Ok(format!(
        "{}\n{}",
        summarize(&first.scene.clone(), &points),
        ranking(&points).trim_end()
    ))
}

/// Wall time a configuration needs to reach `target` (log-log interpolation between its
/// ladder points; `None` if it never does).
fn time_to_reach(points: &[&Point], target: f64) -> Option<f64> {
    let usable: Vec<&&Point> = points
        .iter()
        .filter(|p| p.error.is_none() && p.l1_rel.is_finite())
        .collect();
    if let Some(p) = usable.iter().find(|p| p.l1_rel <= target) {
        let i = usable
            .iter()
            .position(|q| std::ptr::eq(**q, **p))
            .unwrap_or(0);
        if i == 0 {
            return Some(p.wall_s);
        }
        let a = usable[i - 1];
        let (le0, le1) = (a.l1_rel.max(1e-300).ln(), p.l1_rel.max(1e-300).ln());
        let s = if le1 == le0 {
            1.0
        } else {
            (target.ln() - le0) / (le1 - le0)
        };
        return Some((a.wall_s.ln() + s * (p.wall_s.ln() - a.wall_s.ln())).exp());
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(config: &str, cells: usize, wall_s: f64, l1_rel: f64) -> Point {
        Point {
            scene: "bar".into(),
            config: config.into(),
            cells_x: cells,
            cells,
            steps: cells,
            wall_s,
            updates_per_s: 0.0,
            peak_rss_mib: 0.0,
            l1_rel,
            l1_spread: None,
            error: None,
        }
    }

    /// The target is the median of the finest non-exact errors; an exact configuration wins
    /// the first sentence, and the second compares the others, with log-log interpolation.
    #[test]
    fn summary_leaves_exact_configurations_out_of_the_second_comparison() {
        let points = vec![
            point("dgmpm exact", 100, 1e-3, 1e-15),
            point("dgmpm exact", 200, 4e-3, 1e-15),
            point("dgmpm slow", 100, 1.0, 4e-2),
            point("dgmpm slow", 200, 4.0, 1e-2),
            point("mpm", 100, 0.1, 8e-2),
            point("mpm", 200, 0.4, 2e-2),
            point("fem", 100, 0.01, 1e-1),
            point("fem", 200, 0.04, 5e-2),
        ];
        // finest non-exact errors 1e-2, 2e-2, 5e-2: the median is 2e-2
        let s = summarize("bar", &points);
        assert!(
            s.starts_with("bar: L1 error 2.00e-2 is reached fastest by `dgmpm exact`"),
            "{s}"
        );
        assert!(
            s.contains("Without the configurations that are exact on this scene (dgmpm exact)"),
            "{s}"
        );
        // mpm reaches 2e-2 exactly at its finest level (0.4 s); dgmpm slow halfway in log
        // between (1 s, 4e-2) and (4 s, 1e-2): 2 s; FEM never
        let tail = s.split("Without").nth(1).unwrap();
        assert!(
            tail.contains("reached fastest by `mpm` in 4.000e-1 s"),
            "{s}"
        );
        assert!(
            tail.contains("DGMPM (`dgmpm slow`) needs 5.0× longer"),
            "{s}"
        );
        assert!(tail.contains("FEM does not reach it on this ladder"), "{s}");
    }
}

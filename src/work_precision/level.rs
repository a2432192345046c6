//! One run of the work-precision ladder: a child `impact run` process on one rank
//! ([`run_one`]), the same study in this process split over the ranks under `mpirun`
//! ([`run_ranked`]), and the [`Point`] read off its record.
use super::{cells_x, Config, Point};
use crate::Study;
use anyhow::{Context, Result};
use std::path::Path;
use std::process::Command;

/// Run one configuration at one level as a child process of `exe` on the scene file
/// `scene` (the study's resolved `scene.toml`).
pub(super) fn run_one(
    exe: &Path,
    scene: &Path,
    name: &str,
    c: &Config,
    k: usize,
    (t, budget): (f64, Option<f64>),
    dir: &Path,
) -> Result<Point> {
    let dim = c.dim;
    let out = dir.join(format!("run-{}-{k}", c.label.replace(' ', "_")));
    let nx = cells_x(dim, k);
    let mut cmd = Command::new(exe);
    cmd.arg("run")
        .arg(scene)
        .args(["--quiet", "--no-files"])
        .args([
            "--cells",
            &nx.to_string(),
            "--output-times",
            &format!("{t:e}"),
        ])
        .args(c.flags(dim))
        .arg("--out")
        .arg(&out);
    if let Some(b) = budget {
        cmd.args(["--work-budget", &format!("{b:e}")]);
    }
    let status = cmd
        .output()
        .with_context(|| format!("running {}", exe.display()))?;
    let text = std::fs::read_to_string(out.join("summary.json")).with_context(|| {
        format!(
            "{} {}: {}",
            c.label,
            nx,
            String::from_utf8_lossy(&status.stderr)
        )
    })?;
    let s: serde_json::Value = serde_json::from_str(&text)?;
    // a scratch run: its numbers are read, its folder goes
    let _ = impact_io::folder::remove(&out);
    let peak = s["peak_rss_mib"].as_f64().unwrap_or(f64::NAN);
    Ok(point_of(name, c, nx, &s["runs"][0], peak))
}

/// The [`Point`] of the run of `c` at `nx` cells along x from its record `r` (a run of
/// summary.json) and its peak memory.
fn point_of(name: &str, c: &Config, nx: usize, r: &serde_json::Value, peak: f64) -> Point {
    let steps = r["steps"].as_u64().unwrap_or(0) as usize;
    let cells = r["cells"].as_u64().unwrap_or(0) as usize;
    let wall = r["wall_s"].as_f64().unwrap_or(f64::NAN);
    Point {
        scene: name.into(),
        config: c.label.clone(),
        cells_x: nx,
        cells,
        steps,
        wall_s: wall,
        updates_per_s: cells as f64 * steps as f64 / wall,
        peak_rss_mib: peak,
        l1_rel: r["times"][0]["l1_rel"].as_f64().unwrap_or(f64::NAN),
        l1_spread: r["times"][0]["l1_spread"].as_f64(),
        error: r["error"].as_str().map(String::from).or_else(|| {
            r["times"][0]["l1_rel"]
                .is_null()
                .then(|| format!("no relative error: {}", r["times"][0]["errors"]))
        }),
    }
}

/// [`run_one`] in this process, split over its ranks (under `mpirun`: a child process
/// cannot join the ranks): the same study as the child's (the resolved `scene` at `nx`
/// cells, the fixed time `t`, the work budget) run by [`crate::run::run_method`], which
/// splits it like `impact run` ([`crate::ranks::build_ranked`]) and measures the gathered
/// samples on every rank. Its wall time is this rank's stepping; its peak memory this
/// process's since the level started where Linux can reset it (`/proc/self/clear_refs`),
/// else since the process started.
pub(super) fn run_ranked<const D: usize>(
    scene: &Path,
    name: &str,
    c: &Config,
    k: usize,
    (t, budget): (f64, Option<f64>),
) -> Result<Point> {
    let nx = cells_x(D, k);
    let overrides = crate::study::Overrides {
        cells: Some(nx),
        output_times: Some(vec![t]),
        work_budget: budget,
        ..Default::default()
    };
    let level = Study::load(&scene.to_string_lossy(), overrides)?;
    let kind = c.config.kind();
    level.check_work(&[kind])?;
    let problem = level.problem::<D>()?;
    let reference = crate::reference_for(&problem, &[kind], false)?;
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let (record, _) = crate::run::run_method(
        &problem,
        c.config,
        reference.as_ref(),
        &mut crate::run::Silent,
    )
    .with_context(|| format!("{} {nx}", c.label))?;
    let peak = crate::output::peak_rss_mib().unwrap_or(f64::NAN);
    Ok(point_of(name, c, nx, &serde_json::to_value(&record)?, peak))
}

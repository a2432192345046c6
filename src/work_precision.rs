//! Work-precision: run time against error. Each configuration runs a refinement ladder at a
//! fixed time; each run is a separate `impact run --no-files` process, so its wall time
//! (stepping only), steps and peak memory (`VmHWM`) are its own. Under `mpirun` (several
//! ranks) each run is the same study run in this process instead, split over the ranks like
//! `impact run` (`run_ranked`); rank 0 alone prints and writes. Errors are relative L1 of
//! σ_xx (Π for SVK) against the scene's reference: exact for `bar`, `svk-bar` and
//! `plate-wave`; for `plate`, each run's converged reference (DGMPM on a grid 8× finer,
//! with FEM's on the same grid for the spread beside each error, `l1_spread`; stated in the
//! resolved `scene.toml` so every run of the ladder has the same one).
//!
//! Any scene runs (a shipped name or a scene file), with every `impact run` flag the ladder
//! does not set itself ([`crate::ladder::LADDER_FLAGS`]): the study's resolved scene is written to the
//! output folder as `scene.toml` and each run reads it. The reference is stated before the
//! ladder starts; a 1D scene without an exact solution is refused (no errors to measure).
//! Ladder configurations the scene's model refuses (CTU with Saint-Venant-Kirchhoff in 2D)
//! are skipped, each named with its reason.
//!
//! Courant numbers per configuration stay inside the measured stability limits
//! (`impact stability`): DGMPM 1 point per cell Euler 1.0 (2D: CTU 1.0, DCU 0.6); several
//! points per cell with Euler 0.6; RK2 1.0 (2D: DCU 0.95, CTU 0.7); MPM 0.5; FEM 0.9.
mod level;
mod summary;

use level::{run_one, run_ranked};

use summary::EXACT;
pub use summary::{ranking, summarize, summarize_dir};

use crate::ladder::{provenance, usable_configurations, LADDER_FLAGS};
use crate::Study;
use anyhow::{bail, Result};
use impact_core::method::{
    Integrator, MethodConfig, MethodKind, MpmShape, MpmTransfer, TransverseFlux,
};
use impact_core::Scene;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One configuration of the ladder.
#[derive(Debug, Clone)]
pub struct Config {
    /// Label in tables and plots.
    pub label: String,
    /// The configuration (the scene's, with the ladder's points per cell, integrator,
    /// flux and Courant number); its flags come from [`MethodConfig::to_flags`].
    pub config: MethodConfig,
    /// The scene's dimension.
    pub dim: usize,
}

impl Config {
    /// The `impact run` flags of this configuration in dimension `dim`.
    pub fn flags(&self, dim: usize) -> Vec<String> {
        self.config.to_flags(dim)
    }
}

/// One run of the ladder.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Point {
    /// Scene.
    pub scene: String,
    /// Configuration label.
    pub config: String,
    /// Cells along x.
    pub cells_x: usize,
    /// Cells in all.
    pub cells: usize,
    /// Steps.
    pub steps: usize,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// Cell- (point-) updates per second.
    pub updates_per_s: f64,
    /// Peak resident memory of the run's process (MiB).
    pub peak_rss_mib: f64,
    /// Relative L1 error at the fixed time (left out of the JSON when the run has none:
    /// `error` then says why).
    #[serde(skip_serializing_if = "not_finite", default = "not_measured")]
    pub l1_rel: f64,
    /// The reference's uncertainty beside `l1_rel`: the L1 distance between the converged
    /// reference and the second one (absent for an exact reference).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub l1_spread: Option<f64>,
    /// Error text if the run stopped or measured no relative error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

fn not_finite(value: &f64) -> bool {
    !value.is_finite()
}

fn not_measured() -> f64 {
    f64::NAN
}

/// The configurations of the ladder for `scene`: DGMPM Euler and RK2 × points per cell
/// (× donor-cell/CTU in 2D and 3D), MPM at 1 and several points per cell (4; 8 in 3D),
/// FEM; every other option is the scene's.
pub fn configurations(scene: &Scene) -> Vec<Config> {
    let dgmpm = |ppc: usize, integrator: Integrator, flux: TransverseFlux, courant: f64| {
        let mut config = scene.method_config(MethodKind::Dgmpm);
        config.points_per_cell = ppc;
        config.courant = courant;
        if let Some(o) = config.dgmpm_mut() {
            (o.integrator, o.flux) = (integrator, flux);
        }
        let flux_label = if scene.dim > 1 {
            format!(" {}", flux.name())
        } else {
            String::new()
        };
        Config {
            label: format!(
                "dgmpm {}{flux_label} {ppc}ppc C{courant:?}",
                integrator.name()
            ),
            config,
            dim: scene.dim,
        }
    };
    let mut out = Vec::new();
    // several points per cell: 2 per axis in 2D and 3D (4, 8), 4 in 1D
    let several = if scene.dim == 3 { 8 } else { 4 };
    let layouts: &[usize] = if scene.dim == 1 {
        &[1, 2, 4]
    } else {
        &[1, several]
    };
    for &ppc in layouts {
        // Courant numbers inside the measured stability limits (module doc)
        let euler = if ppc == 1 { 1.0 } else { 0.6 };
        if scene.dim == 1 {
            out.push(dgmpm(
                ppc,
                Integrator::Euler,
                TransverseFlux::DonorCell,
                euler,
            ));
            out.push(dgmpm(ppc, Integrator::Rk2, TransverseFlux::DonorCell, 1.0));
            // order 2 (limited wave corrections, 1D)
            out.extend(crate::ladder::order2_configurations(scene, ppc));
        } else {
            out.push(dgmpm(ppc, Integrator::Euler, TransverseFlux::Ctu, euler));
            // donor-cell with Euler at 4 points per cell: von Neumann limit 0.5518 (the
            // run refuses 0.6, the Courant number used until issue 23); in 3D at one point
            // per cell below the limits 0.4833 (DCU Euler), 0.7636 (DCU RK2) and 0.6460
            // (CTU RK2)
            let three = scene.dim == 3 && ppc == 1;
            out.push(dgmpm(
                ppc,
                Integrator::Euler,
                TransverseFlux::DonorCell,
                match (three, ppc) {
                    (true, _) => 0.45,
                    (false, 1) => 0.6,
                    _ => 0.5,
                },
            ));
            let (rk2_dcu, rk2_ctu) = if three { (0.75, 0.6) } else { (0.95, 0.7) };
            out.push(dgmpm(
                ppc,
                Integrator::Rk2,
                TransverseFlux::DonorCell,
                rk2_dcu,
            ));
            out.push(dgmpm(ppc, Integrator::Rk2, TransverseFlux::Ctu, rk2_ctu));
            // (not 3D at 8 points per cell: the ladders' cost)
            if ppc == 1 || scene.dim == 2 {
                out.extend(crate::ladder::order2_configurations(scene, ppc));
            }
        }
    }
    for ppc in [1, several] {
        let mut config = scene.method_config(MethodKind::Mpm);
        (config.points_per_cell, config.courant) = (ppc, 0.5);
        let tag = transfer_tag(&config);
        out.push(Config {
            label: format!("mpm{tag} {ppc}ppc C0.5"),
            config,
            dim: scene.dim,
        });
    }
    // the smooth shape functions (issue 11): at one point per cell in the total Lagrangian
    // frame GIMP and the quadratic B-spline equal the hat, so they run at several points per
    // cell
    for (shape, ppc) in [
        (MpmShape::Gimp, several),
        (MpmShape::Bspline2, several),
        (MpmShape::Bspline3, 1),
        (MpmShape::Cpdi, several),
    ] {
        let mut config = scene.method_config(MethodKind::Mpm);
        (config.points_per_cell, config.courant) = (ppc, 0.5);
        if let Some(o) = config.mpm_mut() {
            o.shape = shape;
        }
        let tag = transfer_tag(&config);
        out.push(Config {
            label: format!("mpm{tag} {} {ppc}ppc C0.5", shape.name()),
            config,
            dim: scene.dim,
        });
    }
    // APIC (issue 26): with the quadratic B-spline at several points per cell (the MPM
    // most codes run today), and with hats at one point per cell (where its affine
    // velocity is the nodal velocity gradient: `impact_mpm`'s `affine` module)
    for (shape, ppc) in [(MpmShape::Bspline2, several), (MpmShape::Linear, 1)] {
        let mut config = scene.method_config(MethodKind::Mpm);
        (config.points_per_cell, config.courant) = (ppc, 0.5);
        if let Some(o) = config.mpm_mut() {
            (o.shape, o.transfer, o.flip_fraction) = (shape, MpmTransfer::Apic, None);
        }
        out.push(Config {
            label: format!("mpm apic {} {ppc}ppc C0.5", shape.name()),
            config,
            dim: scene.dim,
        });
    }
    let mut fem = scene.method_config(MethodKind::Fem);
    fem.courant = 0.9;
    out.push(Config {
        label: "fem C0.9".into(),
        config: fem,
        dim: scene.dim,
    });
    out
}

/// The MPM transfer of `config` as a label part: empty for FLIP, else ` pic`, ...
fn transfer_tag(config: &MethodConfig) -> String {
    match config.mpm().map(|o| o.transfer_tag()) {
        Some(tag) if !tag.is_empty() => format!(" {tag}"),
        _ => String::new(),
    }
}

/// Cells along x of level `k` (1D: 75·2^k; 2D: 16·2^k, with 12·2^k along y; 3D: 4·2^k,
/// the other axes in the scene's proportions).
pub fn cells_x(dim: usize, k: usize) -> usize {
    match dim {
        1 => 75 << k,
        2 => 16 << k,
        _ => 4 << k,
    }
}

/// Run the ladder on `study` (`source`: the scene as given; `levels` refinements) and
/// write `work_precision.csv`, `work_precision.json`, `work_precision.png`,
/// `provenance.json` and `scene.toml` into `out`. Each run is `impact run` on the resolved
/// `scene.toml` at the study's first output time. `notes` receives the reference used and
/// the configurations skipped before anything runs. Returns the points and a summary
/// sentence: which configuration reaches a target error fastest, by what factor.
pub fn run(
    exe: &Path,
    (study, source): (&Study, &str),
    levels: usize,
    out: &Path,
    mut notes: impl FnMut(&str),
    mut progress: impl FnMut(&Point),
) -> Result<(Vec<Point>, String)> {
    let clock = crate::provenance::Clock::start();
    if levels == 0 || levels > 10 {
        bail!("--levels {levels}: allowed 1 to 10");
    }
    study.overrides.refuse(
        "bench work-precision",
        LADDER_FLAGS,
        "sets the grid, the Courant number and the options its ladder varies",
    )?;
    let reference = study.reference_for_errors(&MethodKind::ALL)?;
    let (configs, skipped) = usable_configurations(study)?;
    notes(&format!("reference: {reference}"));
    for (label, why) in &skipped {
        notes(&format!("skipped `{label}`: {why}"));
    }
    if configs.is_empty() {
        bail!(
            "no configuration of the ladder runs on scene {}",
            study.name()
        );
    }
    // the fixed time: the study's first output time
    let t = match study.dim() {
        1 => study.problem::<1>()?.output_times[0],
        2 => study.problem::<2>()?.output_times[0],
        _ => study.problem::<3>()?.output_times[0],
    };
    let folder = impact_io::folder::OutputFolder::open(out)?;
    let record = provenance(
        "bench work-precision",
        study,
        source,
        &reference,
        &configs,
        &skipped,
        folder.path(),
    )?;
    let scene_file = folder.path().join(crate::provenance::SCENE_FILE);
    let name = study.name();
    let mut points = Vec::new();
    for c in &configs {
        for k in 0..levels {
            let budget = study.overrides.work_budget;
            let at = (t, budget);
            let p = match (crate::ranks::size(), c.dim) {
                (1, _) => run_one(exe, &scene_file, name, c, k, at, folder.path())?,
                (_, 1) => run_ranked::<1>(&scene_file, name, c, k, at)?,
                (_, 2) => run_ranked::<2>(&scene_file, name, c, k, at)?,
                _ => run_ranked::<3>(&scene_file, name, c, k, at)?,
            };
            progress(&p);
            points.push(p);
        }
    }
    write(folder.path(), name, &points)?;
    record.write(folder.path(), &clock)?;
    crate::interrupt::check()?;
    folder.commit(concat!("impact ", env!("CARGO_PKG_VERSION")))?;
    let sentence = summarize(name, &points);
    Ok((points, sentence))
}

fn write(out: &Path, scene: &str, points: &[Point]) -> Result<()> {
    impact_io::write_atomic(&out.join("work_precision.csv"), |w| {
        writeln!(
            w,
            "scene,config,cells_x,cells,steps,wall_s,updates_per_s,peak_rss_mib,l1_rel,error,\
             l1_spread"
        )?;
        for p in points {
            writeln!(
                w,
                "{},{},{},{},{},{:.6e},{:.6e},{:.1},{:.6e},{},{}",
                p.scene,
                p.config,
                p.cells_x,
                p.cells,
                p.steps,
                p.wall_s,
                p.updates_per_s,
                p.peak_rss_mib,
                p.l1_rel,
                p.error.as_deref().unwrap_or("").replace(',', ";"),
                p.l1_spread.map_or(String::new(), |s| format!("{s:.6e}"))
            )?;
        }
        Ok(())
    })?;
    impact_io::write_json(&out.join("work_precision.json"), &points)?;
    impact_io::plot::save(&out.join("work_precision.png"), &figure(scene, points))?;
    Ok(())
}

/// Error against wall time on log-log axes, one series per configuration: one colour per
/// method (DGMPM blue, MPM vermillion, FEM green, as in every figure), one marker shape per
/// variant of a method, in order.
pub fn figure(scene: &str, points: &[Point]) -> impact_io::plot::LineFigure {
    use impact_io::plot::{Axis, LineFigure, Panel, PrintWidth, Series};
    let mut labels: Vec<&str> = points.iter().map(|p| p.config.as_str()).collect();
    labels.dedup();
    // configurations exact to round-off everywhere would squeeze the others into a band
    // 12 decades above them: named in the title instead of drawn
    let exact: Vec<&str> = labels
        .iter()
        .copied()
        .filter(|l| {
            let mine: Vec<&Point> = points.iter().filter(|p| p.config == *l).collect();
            !mine.is_empty() && mine.iter().all(|p| p.error.is_none() && p.l1_rel <= EXACT)
        })
        .collect();
    let method_colour = |label: &str| match label.split(' ').next() {
        Some("dgmpm") => 1,
        Some("mpm") => 2,
        Some("fem") => 3,
        _ => 4,
    };
    let mut variants_seen = [0usize; 5];
    let series = labels
        .iter()
        .map(|l| {
            let colour = method_colour(l);
            let marker = variants_seen[colour];
            variants_seen[colour] += 1;
            (l, colour, marker)
        })
        .map(|(l, colour, marker)| Series {
            label: {
                let shown = legend_text(l);
                if exact.contains(l) {
                    format!("{shown}: exact, not drawn")
                } else {
                    shown
                }
            },
            points: points
                .iter()
                .filter(|p| {
                    p.config == *l && p.error.is_none() && p.l1_rel > EXACT && p.wall_s > 0.0
                })
                .map(|p| (p.wall_s, p.l1_rel))
                .collect(),
            colour,
            reference: false,
            marker: Some(marker),
        })
        .collect();
    LineFigure::new(
        vec![Panel {
            title: format!("{scene}: work-precision"),
            x: Axis::log("wall time of the stepping (s)"),
            y: Axis::log("relative L1 error of σₓₓ"),
            series,
        }],
        1,
        PrintWidth::Full,
        0.5,
    )
}

/// A configuration's label as a legend prints it: the method upper-case, the points per
/// cell and the Courant number spaced (`dgmpm euler 1ppc C1.0` → `DGMPM euler 1 ppc C 1.0`).
pub fn legend_text(label: &str) -> String {
    let words: Vec<String> = label
        .split(' ')
        .map(|w| {
            if let Some(n) = w.strip_suffix("ppc").filter(|n| n.parse::<usize>().is_ok()) {
                format!("{n} ppc")
            } else if let Some(c) = w.strip_prefix('C').filter(|c| c.parse::<f64>().is_ok()) {
                format!("C {c}")
            } else {
                w.to_string()
            }
        })
        .collect();
    crate::plots::display_name(&words.join(" "))
}

/// The default output folder.
pub fn default_out(scene: &str) -> PathBuf {
    PathBuf::from("out").join(format!("work-precision-{scene}"))
}

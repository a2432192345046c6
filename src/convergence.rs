//! `impact bench convergence`: observed orders of accuracy on smooth exact solutions.
//!
//! Scenes `smooth-bar` (1D standing wave, fixed ends) and `smooth-plate` (2D standing P
//! mode (1, 1) with roller edges: four oblique plane waves), both with the exact solution
//! [`impact_core::exact::StandingWave`]. Every configuration of the work-precision ladder
//! ([`crate::work_precision::configurations`]) runs a refinement ladder (1D: 75·2^k cells,
//! 2D: 16·2^k × 12·2^k, `k = 1..=levels`) to the scene's last output time, in this process.
//! Under `mpirun` each level's run is split over the ranks like `impact run`'s
//! ([`crate::ranks::build_ranked`]: slabs, or boxes with `--ranks-grid`); its samples are
//! gathered in the global order on every rank, so every rank measures the same errors, and
//! rank 0 alone prints and writes. The errors equal one rank's bit for bit where the
//! decomposed run's fields do (DGMPM's cell and fused paths, FEM), and to round-off where
//! they do (DGMPM's nodal paths, MPM: shape functions formed from the slab's origin;
//! `docs/mpi.md`). The converged references stay whole on every rank (no collective
//! calls: a cache hit on one rank and a miss on another cannot desynchronise them; the
//! cache's lock makes one rank compute and write each entry, the others read it).
//!
//! Errors are over the whole body, each sample against the exact average over its region
//! (the cell average a finite-volume scheme carries; the point value differs from it by
//! `O(h²)`), relative to the exact field's norm, for `σ_xx` and `v_x`:
//! `L1 = Σ V_i |e_i| / Σ V_i |q_i|`, `L2 = sqrt(Σ V_i e_i² / Σ V_i q_i²)`. The observed
//! order between levels is `log2(e_k / e_{k+1})`. The last output time is 3/8 of the
//! mode's period, where neither field passes through zero.
//!
//! On a scene without an exact solution each level is measured against its converged
//! reference ([`crate::reference_for`]), and beside every error the table, CSV and JSON
//! give the reference's spread in the same norm ([`SpreadErrors`]): how far the second,
//! independent reference lies from the first, which bounds how much the error depends on
//! the choice of judge.
//!
//! Where the scene measures its errors in the clean interior (`[metrics] interior =
//! "dependence"`, the default for a plane wave; [`impact_core::interior`]), a level whose
//! margin leaves no cell is skipped (printed), and every level of a configuration is
//! measured over the clean interior of its coarsest level that has one: the margin in metres,
//! `(R s + 1) h` with `s ≈ c t/(C h)` steps, shrinks under refinement, so that box is clean
//! on every finer level, and one region makes the errors comparable.
//!
//! What it measures (`impact bench convergence --scene smooth-bar --levels 5`, and
//! `--scene smooth-plate --levels 4`; BENCHMARKS.md has the tables):
//! - FEM: order 2.00 in L1 and L2 of both fields, 1D and 2D.
//! - DGMPM: about 1 in 2D (1 point per cell, CTU: 1.11 in σ, 1.04 in v); in 1D at Courant
//!   1 the one-point scheme transports exactly and only the initial point values (centre
//!   values, not cell averages) are in error, `O(h²)`. RK2 at Courant 1.0 sits on its von
//!   Neumann limit and with 2 points per cell its error stalls between 1200 and 2400 cells
//!   (3.27e-4, 3.23e-4); at Courant 0.9 it converges at first order.
//! - MPM: stress at order 2 with B-splines (quadratic, 4 points per cell: 2.00 in L2) and
//!   with hats at one point per cell in the total Lagrangian frame; 1 with hats or GIMP at
//!   4 points per cell. Velocity at order 1 with every shape function and the same error:
//!   USL's stress drives the velocity from `t_n` to `t_{n+1}` where leapfrog would take it
//!   at `t_{n+1/2}`, an `O(Δt)` lag (halving the Courant number at 600 cells halves the
//!   velocity error: 1.34e-3 to 6.98e-4).
use crate::work_precision::cells_x;
use anyhow::{bail, Context, Result};
use impact_core::controller;
use impact_core::interior::{margin_cells, steps_bound, Interior, InteriorRule};
use impact_core::method::MethodKind;
use impact_core::method::Samples;
use impact_core::reference::Reference;
use impact_core::{Method, Problem, Scene};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Relative errors of one run.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct FieldErrors {
    /// L1 of `σ_xx`.
    pub l1_stress: f64,
    /// L2 of `σ_xx`.
    pub l2_stress: f64,
    /// L1 of `v_x`.
    pub l1_velocity: f64,
    /// L2 of `v_x`.
    pub l2_velocity: f64,
    /// The reference's uncertainty beside each error (no exact solution: the second
    /// converged reference's distance from the first in the same norms); `None` against
    /// an exact solution.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub spread: Option<SpreadErrors>,
}

/// The spread of a converged reference in the norms of [`FieldErrors`]: for the first
/// reference `f_A` and the second `f_B` averaged over each sample's region,
/// `Σ V_i |f_A − f_B| / Σ V_i |f_A|` (L1) and `sqrt(Σ V_i (f_A − f_B)² / Σ V_i f_A²)` (L2).
/// By the triangle inequality an error's value moves by at most its spread when the
/// other reference judges ([`impact_core::converged::Spread`]).
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct SpreadErrors {
    /// L1 spread of `σ_xx`.
    pub l1_stress_spread: f64,
    /// L2 spread of `σ_xx`.
    pub l2_stress_spread: f64,
    /// L1 spread of `v_x`.
    pub l1_velocity_spread: f64,
    /// L2 spread of `v_x`.
    pub l2_velocity_spread: f64,
}

/// One run of the ladder.
#[derive(Debug, Clone, Serialize)]
pub struct Level {
    /// Configuration label.
    pub config: String,
    /// Cells along x.
    pub cells_x: usize,
    /// Errors at the last output time.
    #[serde(flatten)]
    pub errors: FieldErrors,
}

/// The errors of `samples` against `reference` at `t` (module doc); with `interior`, over
/// the samples whose region lies in it.
pub fn field_errors<const D: usize>(
    samples: &Samples<D>,
    reference: &Reference,
    t: f64,
    interior: Option<&Interior<D>>,
) -> FieldErrors {
    // the component the reference holds: along x for the exact solutions, along the
    // measuring line's axis for a converged reference
    let a = match reference {
        Reference::Converged(c) => c.line.axis,
        _ => 0,
    };
    let mut sums = [0.0f64; 8];
    // |f_A − f_B| sums (L1, L2) of σ and v, for the spread
    let mut spread_sums = [0.0f64; 4];
    let (mut measured, mut with_spread) = (0usize, 0usize);
    for i in 0..samples.len() {
        let (x, h) = (samples.reference[i], samples.half_size[i]);
        if interior.is_some_and(|inside| !inside.holds(&x, &h)) {
            continue;
        }
        let volume: f64 = h.iter().map(|v| 2.0 * v).product();
        let (stress, velocity) = reference.averages(&(x - h), &(x + h), t);
        measured += 1;
        if let Some((second_stress, second_velocity)) =
            reference.spread_averages(&(x - h), &(x + h), t)
        {
            {
                let (d_stress, d_velocity) = (stress - second_stress, velocity - second_velocity);
                spread_sums[0] += volume * d_stress.abs();
                spread_sums[1] += volume * d_stress * d_stress;
                spread_sums[2] += volume * d_velocity.abs();
                spread_sums[3] += volume * d_velocity * d_velocity;
                with_spread += 1;
            }
        }
        let e_stress = samples.stress[i][(a, a)] - stress;
        let e_velocity = samples.velocity[i][a] - velocity;
        for (k, (e, q)) in [(e_stress, stress), (e_velocity, velocity)]
            .iter()
            .enumerate()
        {
            sums[4 * k] += volume * e.abs();
            sums[4 * k + 1] += volume * q.abs();
            sums[4 * k + 2] += volume * e * e;
            sums[4 * k + 3] += volume * q * q;
        }
    }
    FieldErrors {
        l1_stress: sums[0] / sums[1],
        l2_stress: (sums[2] / sums[3]).sqrt(),
        l1_velocity: sums[4] / sums[5],
        l2_velocity: (sums[6] / sums[7]).sqrt(),
        spread: (measured > 0 && with_spread == measured).then(|| SpreadErrors {
            l1_stress_spread: spread_sums[0] / sums[1],
            l2_stress_spread: (spread_sums[1] / sums[3]).sqrt(),
            l1_velocity_spread: spread_sums[2] / sums[5],
            l2_velocity_spread: (spread_sums[3] / sums[7]).sqrt(),
        }),
    }
}

/// Run one configuration on `problem` to its last output, split over this process's ranks
/// (module doc), and measure it.
fn run_level<const D: usize>(
    problem: &Problem<D>,
    config: impact_core::method::MethodConfig,
    reference: &Reference,
    region: Option<&Interior<D>>,
) -> Result<FieldErrors> {
    let mut method = crate::ranks::build_ranked(problem, config)?;
    let mut samples = Samples::<D>::default();
    let mut errors = FieldErrors::default();
    let last = problem.output_times.len() - 1;
    controller::run::<D, dyn Method<D>, anyhow::Error>(
        method.as_mut(),
        &problem.output_times,
        crate::run::guard_for(problem),
        |m, index, t, steps| {
            if index == last {
                m.sample_into(&mut samples);
                // the region was chosen for the most steps the run can take: check it
                let own = crate::run::clean_interior(problem, &config, steps, t)?;
                if let (Some(own), Some(region)) = (own, region) {
                    anyhow::ensure!(
                        (0..D).all(|l| own.lo[l] <= region.lo[l] + 1e-12
                            && region.hi[l] <= own.hi[l] + 1e-12),
                        "internal: the measured region leaves the clean interior"
                    );
                }
                errors = field_errors(&samples, reference, t, region);
            }
            Ok(())
        },
        |_| {},
    )
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(errors)
}

/// The cells of level `k` on `scene`: 1D `75·2^k`; 2D `16·2^k` along x and y keeping the
/// scene's cell shape (`12·2^k` on the 4:3 plates).
pub fn level_cells(scene: &Scene, k: usize) -> Vec<usize> {
    let nx = cells_x(scene.dim, k);
    let first = scene.domain.cells[0] as f64;
    scene
        .domain
        .cells
        .iter()
        .enumerate()
        .map(|(l, &n)| match l {
            0 => nx,
            _ => ((n as f64) * nx as f64 / first).round().max(1.0) as usize,
        })
        .collect()
}

/// The clean interior of `config` on `problem` at its last output time for the most
/// steps it can take ([`impact_core::interior`]): `Ok(None)` where the errors cover the
/// whole body, `Err(why)` where the margin leaves no cell.
pub fn bound_interior<const D: usize>(
    problem: &Problem<D>,
    config: &impact_core::method::MethodConfig,
) -> Result<Option<Interior<D>>, String> {
    if problem.interior == InteriorRule::Whole {
        return Ok(None);
    }
    let speed = problem.material.p_wave_speed::<D>();
    let steps = steps_bound(
        &problem.output_times,
        config.courant,
        problem.grid.min_spacing(),
        speed,
    );
    match Interior::after(&problem.grid, config, steps) {
        Some(inside) => Ok(Some(inside)),
        None => Err(format!(
            "no clean interior: {} cells in from each face after up to {steps} steps",
            margin_cells(config, steps)
        )),
    }
}

/// The refinement ladder `k = 1..=levels` of each configuration on `scene` (dimension `D`),
/// against the scene's exact solution or (2D) each level's converged reference.
pub fn ladder<const D: usize>(
    scene: &Scene,
    configs: &[crate::work_precision::Config],
    levels: usize,
) -> Result<Vec<Level>> {
    let mut out = Vec::new();
    for config in configs {
        // the region measured at every level: the clean interior of the coarsest level that
        // has one (the margin in metres shrinks under refinement, so it lies in the finer
        // levels' interiors; one region for all levels makes the errors comparable)
        let mut region: Option<Interior<D>> = None;
        for k in 1..=levels {
            let mut s = scene.clone();
            // output times stay physical: transits count on the scene's own grid
            if s.time.output_transits.is_some() {
                s.time.output_times = Some(s.schedule_seconds().0);
                s.time.output_transits = None;
            }
            s.domain.cells = level_cells(scene, k);
            // the interior is checked per configuration below (the scene's check uses the
            // scene's own Courant numbers and options)
            let mut checked = s.clone();
            checked
                .metrics
                .get_or_insert_with(Default::default)
                .interior = Some(InteriorRule::Whole);
            checked.validate()?;
            let problem = Problem::<D>::from_valid_scene(&s)?;
            match bound_interior(&problem, &config.config) {
                Err(why) => {
                    crate::root_eprintln!(
                        "{:<32} {:>5} cells: skipped, {why}",
                        config.label,
                        s.domain.cells[0]
                    );
                    continue;
                }
                Ok(own) => region = region.or(own),
            }
            let reference =
                crate::reference_for(&problem, &MethodKind::ALL, false)?.with_context(|| {
                    format!(
                        "scene {} at {:?} cells has no reference to measure errors against",
                        s.name, s.domain.cells
                    )
                })?;
            let errors = run_level(&problem, config.config, &reference, region.as_ref())
                .with_context(|| format!("{} at {:?} cells", config.label, s.domain.cells))?;
            crate::root_eprintln!(
                "{:<32} {:>5} cells: L2 σ {:.3e}, v {:.3e}",
                config.label,
                s.domain.cells[0],
                errors.l2_stress,
                errors.l2_velocity
            );
            out.push(Level {
                config: config.label.clone(),
                cells_x: s.domain.cells[0],
                errors,
            });
        }
    }
    Ok(out)
}

/// Run the ladders on `study` (`source`: the scene as given) and write
/// `convergence.{csv,json,png,txt}`, `provenance.json` and `scene.toml` into `out`;
/// `notes` receives the reference and the configurations skipped before anything runs.
/// Returns the table printed.
pub fn run(
    (study, source): (&crate::Study, &str),
    levels: usize,
    out: &Path,
    mut notes: impl FnMut(&str),
) -> Result<String> {
    let clock = crate::provenance::Clock::start();
    if !(2..=8).contains(&levels) {
        bail!("--levels {levels}: allowed: 2 to 8 (at least 4 for the orders the issue asks)");
    }
    study.overrides.refuse(
        "bench convergence",
        crate::ladder::LADDER_FLAGS,
        "sets the grid, the Courant number and the options its ladder varies",
    )?;
    let reference = study.reference_for_errors(&MethodKind::ALL)?;
    let (configs, skipped) = crate::ladder::usable_configurations(study)?;
    notes(&format!("reference: {reference}"));
    for (label, why) in &skipped {
        notes(&format!("skipped `{label}`: {why}"));
    }
    let scene = crate::provenance::resolved_scene(study, &MethodKind::ALL);
    let runs = match scene.dim {
        1 => ladder::<1>(&scene, &configs, levels)?,
        2 => ladder::<2>(&scene, &configs, levels)?,
        _ => ladder::<3>(&scene, &configs, levels)?,
    };
    let table = table(&runs);
    let folder = impact_io::folder::OutputFolder::open(out)?;
    let record = crate::ladder::provenance(
        "bench convergence",
        study,
        source,
        &reference,
        &configs,
        &skipped,
        folder.path(),
    )?;
    write(folder.path(), study.name(), &runs)?;
    std::fs::write(folder.path().join("convergence.txt"), &table)?;
    record.write(folder.path(), &clock)?;
    folder.commit("impact bench convergence")?;
    Ok(table)
}

/// Observed orders `log2(e_k/e_{k+1})` of one error over a configuration's levels.
pub fn orders(levels: &[&Level], error: impl Fn(&FieldErrors) -> f64) -> Vec<f64> {
    impact_core::metrics::observed_orders(
        &levels.iter().map(|l| error(&l.errors)).collect::<Vec<_>>(),
    )
}

/// The table: per configuration, the finest errors and the mean observed orders of the
/// last two refinements.
pub fn table(runs: &[Level]) -> String {
    let mut labels: Vec<&str> = runs.iter().map(|r| r.config.as_str()).collect();
    labels.dedup();
    let mut text = format!(
        "{:<32} {:>10} {:>10} {:>10} {:>10}   orders (last two refinements, mean)\n{:<32} {:>10} {:>10} {:>10} {:>10}   L1σ   L2σ   L1v   L2v\n",
        "configuration", "L1 σ_xx", "L2 σ_xx", "L1 v_x", "L2 v_x", "", "(finest)", "", "", ""
    );
    for label in labels {
        let levels: Vec<&Level> = runs.iter().filter(|r| r.config == label).collect();
        let last = levels.last().expect("internal: a label has runs").errors;
        let mean = |f: fn(&FieldErrors) -> f64| {
            let o = orders(&levels, f);
            let tail = &o[o.len().saturating_sub(2)..];
            tail.iter().sum::<f64>() / tail.len().max(1) as f64
        };
        text += &format!(
            "{label:<32} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e}   {:>4.2}  {:>4.2}  {:>4.2}  {:>4.2}\n",
            last.l1_stress,
            last.l2_stress,
            last.l1_velocity,
            last.l2_velocity,
            mean(|e| e.l1_stress),
            mean(|e| e.l2_stress),
            mean(|e| e.l1_velocity),
            mean(|e| e.l2_velocity),
        );
        if let Some(spread) = last.spread {
            text += &format!(
                "{:<32} {:>10.1e} {:>10.1e} {:>10.1e} {:>10.1e}   (± the reference's spread)\n",
                "",
                spread.l1_stress_spread,
                spread.l2_stress_spread,
                spread.l1_velocity_spread,
                spread.l2_velocity_spread,
            );
        }
    }
    text
}

fn write(out: &Path, scene: &str, runs: &[Level]) -> Result<()> {
    use impact_io::plot::{line_panels, Axis, Panel, Series};
    impact_io::write_atomic(&out.join("convergence.csv"), |w| {
        writeln!(
            w,
            "scene,config,cells_x,l1_stress,l2_stress,l1_velocity,l2_velocity,\
             l1_stress_spread,l2_stress_spread,l1_velocity_spread,l2_velocity_spread"
        )?;
        for r in runs {
            let e = r.errors;
            // the spread columns are empty against an exact solution
            let spread = e.spread.map_or(",,,".to_string(), |s| {
                format!(
                    "{:.6e},{:.6e},{:.6e},{:.6e}",
                    s.l1_stress_spread,
                    s.l2_stress_spread,
                    s.l1_velocity_spread,
                    s.l2_velocity_spread
                )
            });
            writeln!(
                w,
                "{scene},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{spread}",
                r.config, r.cells_x, e.l1_stress, e.l2_stress, e.l1_velocity, e.l2_velocity
            )?;
        }
        Ok(())
    })?;
    impact_io::write_json(&out.join("convergence.json"), &runs)?;
    let mut labels: Vec<&str> = runs.iter().map(|r| r.config.as_str()).collect();
    labels.dedup();
    let panel = |title: &str, error: fn(&FieldErrors) -> f64| Panel {
        title: format!("{scene}: {title}"),
        x: Axis::log("cells along x"),
        y: Axis::log(format!("relative {title}")),
        series: labels
            .iter()
            .enumerate()
            .map(|(k, l)| Series {
                label: l.to_string(),
                points: runs
                    .iter()
                    .filter(|r| r.config == *l && error(&r.errors) > 0.0)
                    .map(|r| (r.cells_x as f64, error(&r.errors)))
                    .collect(),
                colour: k + 1,
                reference: false,
                marker: None,
            })
            .collect(),
    };
    line_panels(
        &out.join("convergence.png"),
        vec![
            panel("L2 error of σₓₓ", |e| e.l2_stress),
            panel("L2 error of vₓ", |e| e.l2_velocity),
        ],
    )?;
    Ok(())
}

/// Default output folder of a ladder.
pub fn default_out(scene: &str) -> PathBuf {
    PathBuf::from("out").join(format!("convergence-{scene}"))
}

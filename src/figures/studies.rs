//! The figures no paper has: work-precision, the stability map, DGMPM against every MPM
//! shape function, and the elastoplastic fronts.
use super::paper::{numbers, run_configs, Run};
use super::{Entry, Target};
use crate::plots::{profile_figure, Collected};
use anyhow::{Context, Result};
use impact_core::method::{MethodConfig, MethodKind, MpmShape, RiemannSolver, TransverseFlux};
use impact_core::{Problem, Scene};

/// Work-precision ladders of the four scenes, one image each. Reduced levels by default
/// (bar and svk-bar 6, to 4,800 cells; plate-wave 4, to 128×96; plate 3, to 64×48); `--full`: those
/// of `impact bench work-precision` (9, 9, 7, 6). Runs `impact run` child processes like
/// the bench (timings from separate processes), so it needs the `impact` executable.
pub fn work_precision(target: &Target) -> Result<Entry> {
    let exe = std::env::current_exe().context("locating the impact executable")?;
    let scratch = std::env::temp_dir().join(format!("impact-figures-{}", std::process::id()));
    impact_io::create_dir(&scratch)?;
    let mut images = Vec::new();
    let mut lines = Vec::new();
    let mut levels_used = Vec::new();
    for (scene, reduced, full) in [
        ("bar", 6, 9),
        ("svk-bar", 6, 9),
        ("plate-wave", 4, 7),
        ("plate", 3, 6),
    ] {
        let levels = if target.full { full } else { reduced };
        levels_used.push(format!("{scene} {levels}"));
        let out = scratch.join(format!("work-precision-{scene}"));
        let (points, sentence) = crate::work_precision::run(&exe, scene, levels, &out, |_| {})?;
        let stem = format!("work_precision_{}", scene.replace('-', "_"));
        images.push(target.save(&stem, &crate::work_precision::figure(scene, &points))?);
        lines.push(sentence);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    lines.insert(0, format!("levels: {}", levels_used.join(", ")));
    Ok(Entry {
        name: "work-precision".into(),
        title: "Work-precision: relative L1 error against stepping time".into(),
        images,
        command: format!(
            "{}   # the ladders: impact bench work-precision --scene bar|svk-bar|plate-wave|plate",
            target.command
        ),
        numbers: lines,
        seconds: 0.0,
    })
}

/// The stability map: every configuration's critical Courant numbers. Perturbed runs of
/// 2,000 steps in 1D and 300 in 2D by default; `--full`: 20,000 and 3,000 (those of
/// `impact stability`).
pub fn stability(target: &Target) -> Result<Entry> {
    use crate::stability::sweep;
    let (steps_1d, steps_2d) = if target.full {
        (20_000, 3_000)
    } else {
        (2_000, 300)
    };
    let bar = Scene::builtin("bar").expect("internal: a shipped scene");
    let mut rows = sweep(&Problem::<1>::from_scene(&bar)?, &bar, steps_1d, |_| {});
    let mut plate = Scene::builtin("plate-wave").expect("internal: a shipped scene");
    plate.domain.cells = vec![16, 12];
    rows.extend(sweep(
        &Problem::<2>::from_scene(&plate)?,
        &plate,
        steps_2d,
        |_| {},
    ));
    let image = target.save("stability", &crate::stability::figure(&rows))?;
    let mut lines = vec![format!(
        "perturbed runs of {steps_1d} steps (1D) and {steps_2d} (2D); the full sweep: impact stability"
    )];
    for r in &rows {
        lines.push(format!(
            "{}D {} {} ppc {} {} {}: empirical {:.3}, von Neumann {}, monotone {}",
            r.dim,
            r.method,
            r.points_per_cell,
            r.integrator,
            r.flux,
            r.update,
            r.empirical,
            r.von_neumann.map_or("-".into(), |v| format!("{v:.3}")),
            r.monotone.map_or("-".into(), |v| format!("{v:.3}"))
        ));
    }
    Ok(Entry {
        name: "stability".into(),
        title: "Stability map: critical Courant numbers".into(),
        images: vec![image],
        command: target.command.clone(),
        numbers: lines,
        seconds: 0.0,
    })
}

/// DGMPM against MPM with every shape function on the bar (the scene's MPM otherwise).
pub fn mpm_variants(target: &Target) -> Result<Entry> {
    let scene = Scene::builtin("bar").expect("internal: a shipped scene");
    let problem = Problem::<1>::from_scene(&scene)?;
    let reference = crate::reference_for(&problem, target.progress)?;
    let mut configs = vec![("dgmpm".to_string(), scene.method_config(MethodKind::Dgmpm))];
    for shape in MpmShape::ALL {
        let mut config = scene.method_config(MethodKind::Mpm);
        if let Some(o) = config.mpm_mut() {
            o.shape = shape;
        }
        configs.push((format!("mpm {}", shape.name()), config));
    }
    let runs = run_configs(&problem, &configs, reference.as_ref(), target.progress)?;
    let image = profiles(
        target,
        "mpm_variants_bar",
        "bar",
        &problem,
        &runs,
        &reference,
    )?;
    Ok(Entry {
        name: "mpm-variants".into(),
        title: "DGMPM against MPM with every shape function (bar)".into(),
        images: vec![image],
        command: format!(
            "{}   # the gate: impact check bar --against all-mpm",
            target.command
        ),
        numbers: numbers(&runs),
        seconds: 0.0,
    })
}

/// Profiles of `runs` at the problem's output times into `<stem>.png/.svg`.
fn profiles<const D: usize>(
    target: &Target,
    stem: &str,
    scene: &str,
    problem: &Problem<D>,
    runs: &[Run],
    reference: &Option<impact_core::reference::Reference>,
) -> Result<super::Image> {
    let collected: Vec<Collected> = runs.iter().map(|r| r.collected.clone()).collect();
    let length = problem.grid.upper()[0] - problem.grid.origin[0];
    let band = if D > 1 {
        problem.grid.spacing[D - 1]
    } else {
        0.0
    };
    let figure = profile_figure(
        scene,
        problem.model.stress_measure(),
        &collected,
        reference.as_ref(),
        (length, band),
        &problem.output_times,
    );
    target.save(stem, &figure)
}

/// The plastic wave's width and overshoot of each run, one line each.
fn plastic_numbers(runs: &[Run]) -> Vec<String> {
    let fmt = |v: Option<f64>| v.map_or("-".into(), |x| format!("{x:.2}"));
    runs.iter()
        .map(|run| {
            let times = &run.record.times;
            format!(
                "{}: plastic wave width {} cells, overshoot {} %",
                run.collected.name,
                times
                    .iter()
                    .map(|t| fmt(t.plastic_front_width_cells))
                    .collect::<Vec<_>>()
                    .join(" / "),
                times
                    .iter()
                    .map(|t| fmt(t.plastic_overshoot_pct))
                    .collect::<Vec<_>>()
                    .join(" / ")
            )
        })
        .collect()
}

/// The elastoplastic fronts of ep-bar and ep-plate-wave: DGMPM with the elastic and the
/// elastoplastic Riemann solvers (in 2D the latter with DCU at Courant 0.6, since CTU is
/// refused with it), MPM, FEM and the exact two-wave solution.
pub fn elastoplastic(target: &Target) -> Result<Entry> {
    let mut images = Vec::new();
    let mut lines = Vec::new();
    for name in ["ep-bar", "ep-plate-wave"] {
        let scene = Scene::builtin(name).expect("internal: a shipped scene");
        let mut solver = scene.method_config(MethodKind::Dgmpm);
        let mut label = "dgmpm ep-solver".to_string();
        if let Some(o) = solver.dgmpm_mut() {
            o.riemann = RiemannSolver::Elastoplastic;
            if scene.dim == 2 {
                o.flux = TransverseFlux::DonorCell;
                solver.courant = 0.6;
                label.push_str(" dcu C0.6");
            }
        }
        let mut configs: Vec<(String, MethodConfig)> = super::paper::three_methods(&scene);
        configs.insert(1, (label, solver));
        let stem = format!("elastoplastic_{}", name.replace('-', "_"));
        lines.push(format!("{name}:"));
        if scene.dim == 1 {
            let problem = Problem::<1>::from_scene(&scene)?;
            let reference = crate::reference_for(&problem, target.progress)?;
            let runs = run_configs(&problem, &configs, reference.as_ref(), target.progress)?;
            images.push(profiles(target, &stem, name, &problem, &runs, &reference)?);
            lines.extend(numbers(&runs));
            lines.extend(plastic_numbers(&runs));
        } else {
            let problem = Problem::<2>::from_scene(&scene)?;
            let reference = crate::reference_for(&problem, target.progress)?;
            let runs = run_configs(&problem, &configs, reference.as_ref(), target.progress)?;
            images.push(profiles(target, &stem, name, &problem, &runs, &reference)?);
            lines.extend(numbers(&runs));
            lines.extend(plastic_numbers(&runs));
        }
    }
    Ok(Entry {
        name: "elastoplastic".into(),
        title: "Elastoplastic fronts: precursor and plastic wave (ep-bar, ep-plate-wave)".into(),
        images,
        command: format!(
            "{}   # the gate: impact check ep-bar; impact check ep-plate-wave",
            target.command
        ),
        numbers: lines,
        seconds: 0.0,
    })
}

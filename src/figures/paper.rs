//! The paper's figures (Fig. 3, 5, 6) from the shipped scenes `bar`, `plate`, `svk-bar`,
//! and the in-process runs every figure uses ([`run_configs`]).
use super::{Entry, Target};
use crate::output::FileWriter;
use crate::plots::{map_figure, profile_figure, svk_figure, Collected};
use crate::run::{run_method, RunRecord};
use anyhow::Result;
use impact_core::method::{MethodConfig, MethodKind, Model};
use impact_core::reference::Reference;
use impact_core::{Problem, Scene};
use impact_io::plot::{LineFigure, Stacked};

/// One method's run for a figure: what the plots need and its record.
pub struct Run {
    /// Profiles, positions and maps.
    pub collected: Collected,
    /// Metrics and timing.
    pub record: RunRecord,
}

/// Run each `(label, config)` on `problem` in process, keeping profiles and maps (no
/// files); a progress bar each when `progress`.
pub fn run_configs<const D: usize>(
    problem: &Problem<D>,
    configs: &[(String, MethodConfig)],
    reference: Option<&Reference>,
    progress: bool,
) -> Result<Vec<Run>> {
    let mut runs = Vec::new();
    for (label, config) in configs {
        let bar = progress.then(|| crate::run::progress_bar(config.kind().name()));
        let dir = std::env::temp_dir();
        let mut writer =
            FileWriter::<D>::new(&dir, label, &problem.grid, reference, bar, problem.t_end);
        writer.files = false;
        writer.collect = true;
        writer.measure = problem.model.stress_measure();
        if D == 2 && problem.model == Model::LinearElastic {
            writer.plane_strain = Some(problem.material);
        }
        let (record, _) = run_method(problem, *config, reference, &mut writer)?;
        writer.finish()?;
        runs.push(Run {
            collected: Collected {
                name: label.clone(),
                profiles: std::mem::take(&mut writer.profiles),
                positions: std::mem::take(&mut writer.positions),
                maps: std::mem::take(&mut writer.maps),
            },
            record,
        });
    }
    Ok(runs)
}

/// The scene's three methods, labelled by name.
pub fn three_methods(scene: &Scene) -> Vec<(String, MethodConfig)> {
    MethodKind::ALL
        .iter()
        .map(|&k| (k.name().to_string(), scene.method_config(k)))
        .collect()
}

fn list(values: impl Iterator<Item = String>) -> String {
    values.collect::<Vec<_>>().join(" / ")
}

fn opt(value: Option<f64>, digits: usize) -> String {
    value.map_or("-".into(), |v| format!("{v:.digits$}"))
}

/// One line per run: errors, front widths and overshoots at each output time, run time.
pub fn numbers(runs: &[Run]) -> Vec<String> {
    let mut lines = Vec::new();
    if let Some(first) = runs.first() {
        lines.push(format!(
            "output times: {} ms",
            list(
                first
                    .record
                    .times
                    .iter()
                    .map(|t| format!("{:.4}", t.t * 1e3))
            )
        ));
    }
    for run in runs {
        let r = &run.record;
        lines.push(format!(
            "{} (Courant {}, {} ppc, {}): L1 {}; front width {} cells; overshoot {} %; \
             stepping {:.2e} s, {} steps{}",
            run.collected.name,
            r.courant,
            r.points_per_cell,
            r.integrator,
            list(r.times.iter().map(|t| format!("{:.3e}", t.l1))),
            list(r.times.iter().map(|t| opt(t.front_width_cells, 2))),
            list(r.times.iter().map(|t| opt(t.overshoot_pct, 2))),
            r.wall_s,
            r.steps,
            r.error
                .as_ref()
                .map_or(String::new(), |e| format!("; stopped: {e}"))
        ));
    }
    lines
}

/// The shipped scene `name` as a problem with its reference.
fn scene_problem<const D: usize>(
    name: &str,
    progress: bool,
) -> Result<(Scene, Problem<D>, Option<Reference>)> {
    let scene = Scene::builtin(name).expect("internal: a shipped scene");
    let problem = Problem::<D>::from_scene(&scene)?;
    let reference = crate::reference_for(&problem, progress)?;
    Ok((scene, problem, reference))
}

/// Fig. 3: the elastic bar.
pub fn fig3(target: &Target) -> Result<Entry> {
    let (scene, problem, reference) = scene_problem::<1>("bar", target.progress)?;
    let runs = run_configs(
        &problem,
        &three_methods(&scene),
        reference.as_ref(),
        target.progress,
    )?;
    let collected: Vec<Collected> = runs.iter().map(|r| r.collected.clone()).collect();
    let times = problem.output_times.clone();
    let length = problem.grid.upper()[0] - problem.grid.origin[0];
    let measure = problem.model.stress_measure();
    let figure = profile_figure(
        "bar",
        measure,
        &collected,
        reference.as_ref(),
        (length, 0.0),
        &times,
    );
    let image = target.save("fig3_bar", &figure)?;
    Ok(Entry {
        name: "fig3".into(),
        title: "Fig. 3: elastic bar, σₓₓ at three times (DGMPM, MPM, FEM, exact)".into(),
        images: vec![image],
        command: format!("{}   # data: impact run bar", target.command),
        numbers: numbers(&runs),
        seconds: 0.0,
    })
}

/// Fig. 5: the partial plate impact, maps above the bottom-row profiles.
pub fn fig5(target: &Target) -> Result<Entry> {
    let (scene, problem, reference) = scene_problem::<2>("plate", target.progress)?;
    // the paper's order of the maps: MPM, FEM, DGMPM
    let configs: Vec<(String, MethodConfig)> =
        [MethodKind::Mpm, MethodKind::Fem, MethodKind::Dgmpm]
            .iter()
            .map(|&k| (k.name().to_string(), scene.method_config(k)))
            .collect();
    let runs = run_configs(&problem, &configs, reference.as_ref(), target.progress)?;
    let collected: Vec<Collected> = runs.iter().map(|r| r.collected.clone()).collect();
    let times = problem.output_times.clone();
    let grid = crate::run::plane_grid(&problem.grid);
    let maps = map_figure(&grid, &collected, reference.as_ref(), &times)
        .ok_or_else(|| anyhow::anyhow!("the plate runs kept no maps"))?;
    let length = problem.grid.upper()[0] - problem.grid.origin[0];
    let mut profiles = profile_figure(
        "plate",
        problem.model.stress_measure(),
        &collected,
        reference.as_ref(),
        (length, problem.grid.spacing[1]),
        &times,
    );
    profiles.columns = times.len().max(1);
    profiles.panel_size = (560, 340);
    let image = target.save("fig5_plate", &Stacked(maps, profiles))?;
    let mut lines = numbers(&runs);
    if let Some(r) = &reference {
        lines.insert(0, format!("reference: {}", r.describe()));
    }
    Ok(Entry {
        name: "fig5".into(),
        title: "Fig. 5: partial plate impact, σₓₓ maps and bottom-row profiles".into(),
        images: vec![image],
        command: format!("{}   # data: impact run plate", target.command),
        numbers: lines,
        seconds: 0.0,
    })
}

/// Fig. 6: the Saint-Venant–Kirchhoff bar.
pub fn fig6(target: &Target) -> Result<Entry> {
    let (scene, problem, reference) = scene_problem::<1>("svk-bar", target.progress)?;
    let runs = run_configs(
        &problem,
        &three_methods(&scene),
        reference.as_ref(),
        target.progress,
    )?;
    let collected: Vec<Collected> = runs.iter().map(|r| r.collected.clone()).collect();
    let length = problem.grid.upper()[0] - problem.grid.origin[0];
    let figure: LineFigure = svk_figure("svk-bar", &collected, reference.as_ref(), length);
    let image = target.save("fig6_svk_bar", &figure)?;
    Ok(Entry {
        name: "fig6".into(),
        title: "Fig. 6: Saint-Venant–Kirchhoff bar, displacement and Πₓₓ".into(),
        images: vec![image],
        command: format!("{}   # data: impact run svk-bar", target.command),
        numbers: numbers(&runs),
        seconds: 0.0,
    })
}

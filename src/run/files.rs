//! The files `impact run` writes besides the frames ([`super::run_study`]): the provenance
//! record with the scene, and the figures.
/// `provenance.json` and `scene.toml` of a run of `kinds` into `dir`.
pub(super) fn write_provenance(
    study: &crate::Study,
    options: &super::RunOptions,
    kinds: &[impact_core::MethodKind],
    summary: &crate::output::Summary,
    dir: &std::path::Path,
    clock: &crate::provenance::Clock,
) -> anyhow::Result<()> {
    use crate::provenance::{Provenance, RunEntry, RunFlags};
    let mut record =
        Provenance::new("run", clock).with_study(study, &options.source, kinds, dir)?;
    record.reference = summary.reference.clone();
    record.allow_unstable = options.allow_unstable;
    record.run = Some(RunFlags {
        methods: kinds.to_vec(),
        no_reference: options.no_reference,
        no_files: options.no_files,
        vtu: format!("{:?}", options.vtu).to_lowercase(),
    });
    record.runs = summary
        .runs
        .iter()
        .map(|r| RunEntry {
            options: r.options.clone(),
            steps: r.steps,
            wall_s: r.wall_s,
            error: r.error.clone(),
        })
        .collect();
    record.write(dir, clock)
}

/// The run's figures: `stress.png` (profiles at up to three output times), `svk.png` (1D
/// SVK) and `stress_map.png` (2D, and the plane through the measuring line in 3D: every
/// method and the reference at those times).
pub(super) fn write_figures<const D: usize>(
    name: &str,
    problem: &impact_core::Problem<D>,
    reference: Option<&impact_core::reference::Reference>,
    dir: &std::path::Path,
    runs: &[crate::plots::Collected],
) -> anyhow::Result<()> {
    use crate::plots::{map_figure, picked_times, profile_figure, svk_figure};
    use impact_core::method::Model;
    use impact_io::plot::save;
    let line = impact_core::line::MeasureLine::of(problem);
    let times = picked_times(runs);
    let measure = problem.model.stress_measure();
    let on = (&line, &problem.grid);
    let profiles = profile_figure(name, measure, runs, reference, on, &times);
    save(&dir.join("stress.png"), &profiles)?;
    if D == 1 && matches!(problem.model, Model::Svk(_)) {
        save(&dir.join("svk.png"), &svk_figure(name, runs, reference, on))?;
    }
    if let Some(plane) = crate::plane::MapPlane::of(&problem.grid, &line) {
        let grid = &problem.grid;
        let average = |lo: &impact_core::Vector<2>, hi: &impact_core::Vector<2>, t: f64| {
            let (lo, hi) = plane.lift(grid, lo, hi);
            reference.map_or(f64::NAN, |r| r.averages(&lo, &hi, t).0)
        };
        let labelled = reference.map(|r| {
            (
                crate::plots::reference_label(r),
                &average as &dyn Fn(&impact_core::Vector<2>, &impact_core::Vector<2>, f64) -> f64,
            )
        });
        let plane_grid = plane.grid(grid);
        let where_ = plane.describe(grid);
        if let Some(maps) = map_figure(&plane_grid, &where_, runs, labelled, &times) {
            save(&dir.join("stress_map.png"), &maps)?;
        }
    }
    Ok(())
}

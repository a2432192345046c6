//! The paper's figures (Fig. 3, 5, 6) from the shipped scenes `bar`, `plate`, `svk-bar`,
//! and the in-process runs every figure uses ([`Shipped`]).
use super::{Entry, Target};
use crate::output::FileWriter;
use crate::plots::{map_figure, profile_figure, svk_figure, Collected};
use crate::run::{run_method, RunRecord};
use anyhow::Result;
use impact_core::method::{MethodConfig, MethodKind, Model};
use impact_core::reference::Reference;
use impact_core::{Problem, Scene};
use impact_io::plot::{LineFigure, Stacked};

/// A shipped scene run by several configurations in process, for a figure.
pub struct Shipped<const D: usize> {
    /// The scene's name.
    pub name: &'static str,
    /// Its problem.
    pub problem: Problem<D>,
    /// Its reference (exact or converged).
    pub reference: Option<Reference>,
    /// What each run kept for the plots (profiles, positions, maps), labelled.
    pub collected: Vec<Collected>,
    /// Each run's metrics and timing, in the same order.
    pub records: Vec<RunRecord>,
}

impl<const D: usize> Shipped<D> {
    /// Run the configurations `configs(scene)` gives, each `(label, config)`, on the
    /// shipped scene `name` with its reference, keeping profiles and maps (no files); a
    /// progress bar each when `progress`.
    pub fn run(
        name: &'static str,
        progress: bool,
        configs: impl FnOnce(&Scene) -> Vec<(String, MethodConfig)>,
    ) -> Result<Self> {
        Self::run_with(name, progress, true, configs)
    }

    /// [`Self::run`], with its reference only when `with_reference` (a 3D converged
    /// reference takes minutes).
    pub fn run_with(
        name: &'static str,
        progress: bool,
        with_reference: bool,
        configs: impl FnOnce(&Scene) -> Vec<(String, MethodConfig)>,
    ) -> Result<Self> {
        let scene = Scene::builtin(name).expect("internal: a shipped scene");
        let problem = Problem::<D>::from_scene(&scene)?;
        let reference = match with_reference {
            true => crate::reference_for(&problem, &impact_core::MethodKind::ALL, progress)?,
            false => None,
        };
        let (mut collected, mut records) = (Vec::new(), Vec::new());
        for (label, config) in configs(&scene) {
            let bar = progress.then(|| crate::run::progress_bar(config.kind().name()));
            let dir = std::env::temp_dir();
            let mut writer = FileWriter::<D>::new(
                &dir,
                &label,
                &problem.grid,
                reference.as_ref(),
                bar,
                problem.t_end,
            );
            writer.files = false;
            writer.collect = true;
            writer.measure = problem.model.stress_measure();
            writer.line = impact_core::line::MeasureLine::of(&problem);
            if D == 2 && problem.model == Model::LinearElastic {
                writer.plane_strain = Some(problem.material);
            }
            let (record, _) = run_method(&problem, config, reference.as_ref(), &mut writer)?;
            writer.finish()?;
            collected.push(Collected {
                legend: crate::plots::legend_label(&label, &config),
                name: label,
                profiles: std::mem::take(&mut writer.profiles),
                positions: std::mem::take(&mut writer.positions),
                maps: std::mem::take(&mut writer.maps),
            });
            records.push(record);
        }
        Ok(Self {
            name,
            problem,
            reference,
            collected,
            records,
        })
    }

    /// Profiles of σₓₓ (Πₓₓ) along the measuring line at every output time, every run and
    /// the reference (in 2D the plate's stated bottom row of cells).
    pub fn profile_figure(&self) -> LineFigure {
        let line = impact_core::line::MeasureLine::of(&self.problem);
        profile_figure(
            self.name,
            self.problem.model.stress_measure(),
            &self.collected,
            self.reference.as_ref(),
            (&line, &self.problem.grid),
            &self.problem.output_times,
        )
    }

    /// One line per run: errors, front widths and overshoots at each output time, run
    /// time.
    pub fn numbers(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(first) = self.records.first() {
            lines.push(format!(
                "output times: {} ms",
                list(first.times.iter().map(|t| format!("{:.4}", t.t * 1e3)))
            ));
        }
        for (c, r) in self.collected.iter().zip(&self.records) {
            lines.push(format!(
                "{} (Courant {}, {} ppc, {}): L1 {}; front width {} cells; overshoot {} %; \
                 stepping {:.2e} s, {} steps{}",
                c.name,
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

/// Fig. 3: the elastic bar.
pub fn fig3(target: &Target) -> Result<Entry> {
    let bar = Shipped::<1>::run("bar", target.progress, three_methods)?;
    let image = target.save("fig3_bar", bar.profile_figure())?;
    Ok(Entry {
        name: "fig3".into(),
        title: "Fig. 3: elastic bar, σₓₓ at three times (DGMPM, MPM, FEM, exact)".into(),
        images: vec![image],
        command: format!("{}   # data: impact run bar", target.command),
        numbers: bar.numbers(),
        seconds: 0.0,
    })
}

/// Fig. 5: the partial plate impact, maps above the bottom-row profiles.
pub fn fig5(target: &Target) -> Result<Entry> {
    // the paper's order of the maps: MPM, FEM, DGMPM
    let plate = Shipped::<2>::run("plate", target.progress, |scene| {
        [MethodKind::Mpm, MethodKind::Fem, MethodKind::Dgmpm]
            .iter()
            .map(|&k| (k.name().to_string(), scene.method_config(k)))
            .collect()
    })?;
    let times = &plate.problem.output_times;
    let grid = &plate.problem.grid;
    let average = |lo: &impact_core::Vector<2>, hi: &impact_core::Vector<2>, t: f64| {
        plate
            .reference
            .as_ref()
            .map_or(f64::NAN, |r| r.averages(lo, hi, t).0)
    };
    let reference = plate.reference.as_ref().map(|r| {
        (
            crate::plots::reference_label(r),
            &average as &dyn Fn(&impact_core::Vector<2>, &impact_core::Vector<2>, f64) -> f64,
        )
    });
    let maps = map_figure(grid, "", &plate.collected, reference, times)
        .ok_or_else(|| anyhow::anyhow!("the plate runs kept no maps"))?;
    let mut profiles = plate.profile_figure();
    profiles.columns = times.len().max(1);
    profiles.aspect = 0.62;
    let image = target.save("fig5_plate", Stacked(maps, profiles))?;
    let mut lines = plate.numbers();
    if let Some(r) = &plate.reference {
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
    let bar = Shipped::<1>::run("svk-bar", target.progress, three_methods)?;
    let line = impact_core::line::MeasureLine::of(&bar.problem);
    let on = (&line, &bar.problem.grid);
    let figure = svk_figure("svk-bar", &bar.collected, bar.reference.as_ref(), on);
    let image = target.save("fig6_svk_bar", figure)?;
    Ok(Entry {
        name: "fig6".into(),
        title: "Fig. 6: Saint-Venant–Kirchhoff bar, displacement and Πₓₓ".into(),
        images: vec![image],
        command: format!("{}   # data: impact run svk-bar", target.command),
        numbers: bar.numbers(),
        seconds: 0.0,
    })
}

//! `impact bench output`: size and write time of one output frame of the plate, per VTU
//! encoding (BENCHMARKS.md, issue 13).
//!
//! DGMPM (the scene's configuration) steps the partial plate at `cells` cells along x to
//! its first output time (0.163 ms: the front 1 m into the plate, a quarter of the cells
//! stressed); then the frame — the samples' `.vtu` and the grid's `.vtu` — is written
//! `rounds` times per encoding, the encodings interleaved, into a scratch folder. Reported:
//! the bytes of each file and the median wall time of writing both.
use crate::output::FileWriter;
use crate::run::Observer;
use anyhow::Result;
use impact_core::method::MethodKind;
use impact_core::reference::TimeMetrics;
use impact_core::{Method, Problem, Scene};
use impact_io::vtu::VtuEncoding;

/// One encoding's figures.
#[derive(Debug, Clone)]
pub struct FrameCost {
    /// The encoding.
    pub encoding: VtuEncoding,
    /// Bytes of the samples' file.
    pub samples_bytes: u64,
    /// Bytes of the grid's file.
    pub grid_bytes: u64,
    /// Wall time of writing both, per round (s).
    pub seconds: Vec<f64>,
}

impl FrameCost {
    /// The median write time (s).
    pub fn median(&self) -> f64 {
        let mut s = self.seconds.clone();
        s.sort_by(f64::total_cmp);
        s.get(s.len() / 2).copied().unwrap_or(f64::NAN)
    }
}

/// Measure (module doc).
pub fn run(cells: usize, rounds: usize) -> Result<(usize, f64, Vec<FrameCost>)> {
    let mut scene = Scene::builtin("plate").expect("internal: a shipped scene");
    let (times, _) = scene.schedule_seconds();
    let ratio = cells as f64 / scene.domain.cells[0] as f64;
    scene.domain.cells = vec![
        cells,
        (scene.domain.cells[1] as f64 * ratio).round() as usize,
    ];
    scene.time.output_transits = None;
    scene.time.output_times = Some(vec![times[0]]);
    scene.validate()?;
    let problem = Problem::<2>::from_scene(&scene)?;
    let mut method = crate::build(&problem, scene.method_config(MethodKind::Dgmpm))?;
    let t = times[0];
    let dt = method.stable_dt();
    let steps = (t / dt).ceil() as usize;
    for k in 0..steps {
        let step = dt.min(t - k as f64 * dt);
        method.step(k as f64 * dt, step);
    }
    let scratch = std::env::temp_dir().join(format!("impact-output-bench-{}", std::process::id()));
    impact_io::create_dir(&scratch)?;
    let expected = method.external_work() + method.initial_energy();
    let metrics = TimeMetrics::without_reference(t, method.energy(), expected);
    let mut costs: Vec<FrameCost> = [VtuEncoding::Binary, VtuEncoding::Ascii]
        .into_iter()
        .map(|encoding| FrameCost {
            encoding,
            samples_bytes: 0,
            grid_bytes: 0,
            seconds: Vec::new(),
        })
        .collect();
    for _ in 0..rounds {
        for cost in &mut costs {
            let mut writer = FileWriter::<2>::new(&scratch, "dgmpm", &problem.grid, None, None, t);
            writer.encoding = cost.encoding;
            writer.collect = false;
            writer.plane_strain = Some(problem.material);
            let start = std::time::Instant::now();
            writer.output(method.as_ref() as &dyn Method<2>, 0, t, &metrics)?;
            cost.seconds.push(start.elapsed().as_secs_f64());
            let size = |name: &str| std::fs::metadata(scratch.join(name)).map_or(0, |m| m.len());
            cost.samples_bytes = size("dgmpm_t0.vtu");
            cost.grid_bytes = size("dgmpm_grid_t0.vtu");
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    Ok((problem.grid.cell_count(), t, costs))
}

//! 3D speed and memory (issues 24, 29): `cargo bench --bench three_d [-- N [STEPS]]` (default
//! N = 128: a 128³ block, 3 timed steps). `THREE_D_ROWS=<comma-separated label prefixes>`
//! runs only those rows (e.g. `dgmpm,fem`; the 2D comparison runs when a DGMPM CTU row
//! does); `THREE_D_STEP_ONLY=<label prefix>` builds that one row on the calling thread and
//! runs its warm-up step and `STEPS` steps, nothing else (for callgrind: the difference of
//! two step counts' totals over the difference of cell-updates). `THREE_D_CELLS=nx,ny,nz`
//! steps another block of cells `1/N` m wide (a scene holds at most 1e7 cells × points).
//!
//! Each method on the 3D plane wave (`block-wave`'s conditions on an N³ cube, one point per
//! cell; the rows `dgmpm 8ppc` and `mpm 8ppc` at eight, 2 per axis): heap bytes per cell held after `build` and the peak over its first step (a
//! counting global allocator, exact), then ns per cell-update of one step, built and
//! stepped inside a one-thread pool (the serial loops) and inside a two-thread pool (the
//! parallel loops), the median of `STEPS` steps after one warm-up step. DGMPM CTU is also
//! timed in 2D on a grid of the same cell count (`√(N³)` squared), for the 3D/2D cost ratio
//! per cell-update the issue targets (at most 3×). DGMPM runs its default path (the fused
//! 3D sweep) and, in the rows marked "cell path", the phase-by-phase cell path it replaced
//! (`StepPath::Cell`, the same results).
use impact_core::method::{MethodConfig, MethodKind, TransverseFlux};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};
use std::time::Instant;

mod counting;
use counting::Counting;

#[global_allocator]
static GLOBAL: Counting = Counting;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}

/// `config` on `problem`; `cell_path`: DGMPM on its phase-by-phase cell path.
fn build<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    cell_path: bool,
) -> Box<dyn Method<D>> {
    if !cell_path {
        return impact::build(problem, config).expect("builds");
    }
    let mut dgmpm = Dgmpm::<D>::new(problem, config).expect("builds");
    dgmpm
        .solver
        .set_step_path(StepPath::Cell, &dgmpm.state.points)
        .expect("the cell path applies");
    Box::new(dgmpm)
}

/// Median ns per cell-update of `steps` steps (after one warm-up step) of `config` on
/// `problem` (`cell_path`: [`build`]), built and stepped in a pool of `threads`.
fn time<const D: usize>(
    problem: &Problem<D>,
    (config, cell_path): (MethodConfig, bool),
    threads: usize,
    steps: usize,
) -> f64 {
    let pool = pool(threads);
    pool.install(|| {
        let mut method = build(problem, config, cell_path);
        let dt = method.stable_dt();
        method.step(0.0, dt);
        let mut times = Vec::new();
        for k in 1..=steps {
            let start = Instant::now();
            method.step(k as f64 * dt, dt);
            times.push(start.elapsed().as_secs_f64());
        }
        method.check_finite().expect("finite");
        times.sort_by(f64::total_cmp);
        times[times.len() / 2] * 1e9 / problem.grid.cell_count() as f64
    })
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(128);
    let steps = args.get(1).copied().unwrap_or(3);
    let mut scene = Scene::builtin("block-wave").expect("shipped scene");
    // `THREE_D_CELLS=nx,ny,nz`: another block (cells of 1/N m), e.g. 256 × 256 × 152, the
    // largest 256² block under the scene's cap of 1e7 cells × points per cell
    let cells: Vec<usize> = match std::env::var("THREE_D_CELLS") {
        Ok(list) => list
            .split(',')
            .map(|c| c.parse().expect("a cell count"))
            .collect(),
        Err(_) => vec![n; 3],
    };
    scene.domain.length = cells.iter().map(|&c| c as f64 / n as f64).collect();
    scene.domain.cells = cells.clone();
    let cells_label = format!("{}x{}x{}", cells[0], cells[1], cells[2]);
    let problem = Problem::<3>::from_scene(&scene).expect("valid scene");
    let cells = problem.grid.cell_count() as f64;
    let ctu = |mut c: MethodConfig| {
        if let Some(o) = c.dgmpm_mut() {
            o.flux = TransverseFlux::Ctu;
        }
        c
    };
    let mut dcu = scene.method_config(MethodKind::Dgmpm);
    if let Some(o) = dcu.dgmpm_mut() {
        o.flux = TransverseFlux::DonorCell;
    }
    dcu.courant = 0.48;
    let dgmpm_ctu = ctu(scene.method_config(MethodKind::Dgmpm));
    // eight points per cell (2 per axis), the 3D material point rows
    let eight = |mut c: MethodConfig| {
        c.points_per_cell = 8;
        c
    };
    let configs = [
        ("dgmpm CTU Euler", (dgmpm_ctu, false)),
        ("dgmpm CTU cell path", (dgmpm_ctu, true)),
        ("dgmpm DCU Euler", (dcu, false)),
        ("dgmpm DCU cell path", (dcu, true)),
        (
            "mpm USL linear",
            (scene.method_config(MethodKind::Mpm), false),
        ),
        ("fem hex8", (scene.method_config(MethodKind::Fem), false)),
        ("dgmpm 8ppc CTU Euler", (eight(dgmpm_ctu), false)),
        (
            "mpm 8ppc USL linear",
            (eight(scene.method_config(MethodKind::Mpm)), false),
        ),
    ];
    if let Ok(only) = std::env::var("THREE_D_STEP_ONLY") {
        let (_, (config, cell_path)) = configs
            .iter()
            .find(|(label, _)| label.starts_with(only.as_str()))
            .expect("THREE_D_STEP_ONLY names a row");
        let mut method = build(&problem, *config, *cell_path);
        let dt = method.stable_dt();
        for k in 0..=steps {
            method.step(k as f64 * dt, dt);
        }
        method.check_finite().expect("finite");
        return;
    }
    let rows = std::env::var("THREE_D_ROWS").unwrap_or_default();
    let wanted = |label: &str| rows.is_empty() || rows.split(',').any(|r| label.starts_with(r));
    println!(
        "{cells_label} block, one point per cell unless the row says 8ppc ({cells:.3e} cells)"
    );
    println!(
        "{:<20} {:>10} {:>12} {:>14} {:>14}",
        "method", "B/cell", "peak B/cell", "ns/cell 1 thr", "ns/cell 2 thr"
    );
    let mut dgmpm_3d = 0.0;
    for (label, config) in configs {
        if !wanted(label) {
            continue;
        }
        let before = counting::reset_peak();
        let mut method = build(&problem, config.0, config.1);
        let held = counting::live() - before;
        let dt = method.stable_dt();
        method.step(0.0, dt);
        let peak = counting::peak() - before;
        drop(method);
        let one = time(&problem, config, 1, steps);
        let two = time(&problem, config, 2, steps);
        if label == "dgmpm CTU Euler" {
            dgmpm_3d = one;
        }
        println!(
            "{label:<20} {:>10.1} {:>12.1} {:>14.1} {:>14.1}",
            held as f64 / cells,
            peak as f64 / cells,
            one,
            two
        );
    }
    if dgmpm_3d == 0.0 {
        return;
    }
    let side = cells.sqrt().round() as usize;
    let mut plate = Scene::builtin("plate-wave").expect("shipped scene");
    plate.domain.cells = vec![side, side];
    plate.domain.length = vec![1.0, 1.0];
    plate.metrics = None;
    let plate_problem = Problem::<2>::from_scene(&plate).expect("valid scene");
    let two_d = time(
        &plate_problem,
        (ctu(plate.method_config(MethodKind::Dgmpm)), false),
        1,
        steps,
    );
    println!(
        "dgmpm CTU Euler 2D {side}²: {two_d:.1} ns/cell-update (1 thread); 3D/2D = {:.2}",
        dgmpm_3d / two_d
    );
}

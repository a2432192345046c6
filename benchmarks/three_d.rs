//! 3D speed and memory (issue 24): `cargo bench --bench three_d [-- N [STEPS]]` (default
//! N = 128: a 128³ block, 3 timed steps).
//!
//! Each method on the 3D plane wave (`block-wave`'s conditions on an N³ cube, one point per
//! cell): heap bytes per cell held after `build` and the peak over its first step (a
//! counting global allocator, exact), then ns per cell-update of one step, built and
//! stepped inside a one-thread pool (the serial loops) and inside a two-thread pool (the
//! parallel loops), the median of `STEPS` steps after one warm-up step. DGMPM CTU is also
//! timed in 2D on a grid of the same cell count (`√(N³)` squared), for the 3D/2D cost ratio
//! per cell-update the issue targets (at most 3×).
use impact_core::method::{MethodConfig, MethodKind, TransverseFlux};
use impact_core::{Problem, Scene};
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

/// Median ns per cell-update of `steps` steps (after one warm-up step) of `config` on
/// `problem`, built and stepped in a pool of `threads`.
fn time<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    threads: usize,
    steps: usize,
) -> f64 {
    let pool = pool(threads);
    pool.install(|| {
        let mut method = impact::build(problem, config).expect("builds");
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
    scene.domain.length = vec![1.0; 3];
    scene.domain.cells = vec![n; 3];
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
    let configs = [
        (
            "dgmpm CTU Euler",
            ctu(scene.method_config(MethodKind::Dgmpm)),
        ),
        ("dgmpm DCU Euler", dcu),
        ("mpm USL linear", scene.method_config(MethodKind::Mpm)),
        ("fem hex8", scene.method_config(MethodKind::Fem)),
    ];
    println!("{n}³ block, one point per cell ({cells:.3e} cells)");
    println!(
        "{:<18} {:>10} {:>12} {:>14} {:>14}",
        "method", "B/cell", "peak B/cell", "ns/cell 1 thr", "ns/cell 2 thr"
    );
    let mut dgmpm_3d = 0.0;
    for (label, config) in configs {
        let before = counting::reset_peak();
        let mut method = impact::build(&problem, config).expect("builds");
        let held = counting::live() - before;
        let dt = method.stable_dt();
        method.step(0.0, dt);
        let peak = counting::peak() - before;
        drop(method);
        let one = time(&problem, config, 1, steps);
        let two = time(&problem, config, 2, steps);
        if label.starts_with("dgmpm CTU") {
            dgmpm_3d = one;
        }
        println!(
            "{label:<18} {:>10.1} {:>12.1} {:>14.1} {:>14.1}",
            held as f64 / cells,
            peak as f64 / cells,
            one,
            two
        );
    }
    let side = cells.sqrt().round() as usize;
    let mut plate = Scene::builtin("plate-wave").expect("shipped scene");
    plate.domain.cells = vec![side, side];
    plate.domain.length = vec![1.0, 1.0];
    plate.metrics = None;
    let plate_problem = Problem::<2>::from_scene(&plate).expect("valid scene");
    let two_d = time(
        &plate_problem,
        ctu(plate.method_config(MethodKind::Dgmpm)),
        1,
        steps,
    );
    println!(
        "dgmpm CTU Euler 2D {side}²: {two_d:.1} ns/cell-update (1 thread); 3D/2D = {:.2}",
        dgmpm_3d / two_d
    );
}

//! DGMPM's RK2 step against its forward Euler step, in one process on one thread (issue
//! 29's target: RK2 at one point per cell at most 2.5× Euler's time per cell-update).
//! `cargo bench --bench rk2_euler [-- NX NY [ROUNDS] [STEPS]]` (default plate-wave
//! 600×450, 15 rounds of 20 steps each).
//!
//! Both methods are built on the plate-wave scene (Euler: the scene's CTU at its Courant
//! number; RK2: Heun's cell sweeps at Courant 0.5), stepped 3 times to warm up, then each
//! round times `STEPS` steps of Euler and then of RK2 (`Method::step` only: no stability
//! guard, no output). Prints the medians of the rounds' ns per cell-update, their ratio
//! and the median of the per-round ratios. The whole-run measurement
//! (`benchmarks/interleaved_times.py`, which times the controller's loop of separate
//! processes, the guard's checks included) is the other figure in BENCHMARKS.md.
mod common;
use impact_core::method::{Integrator, MethodKind};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::Dgmpm;
use std::time::Instant;

/// DGMPM on plate-wave with `cells`, forward Euler (the scene's) or RK2 at Courant 0.5,
/// and its cell count.
fn build(cells: &[usize], rk2: bool) -> (Dgmpm<2>, usize) {
    let mut scene = Scene::builtin("plate-wave").expect("shipped scene");
    scene.domain.cells = cells.to_vec();
    let problem = Problem::<2>::from_scene(&scene).expect("a valid scene");
    let mut config = scene.method_config(MethodKind::Dgmpm);
    if rk2 {
        config.courant = 0.5;
        if let Some(o) = config.dgmpm_mut() {
            o.integrator = Integrator::Rk2;
        }
    }
    let count = problem.grid.cell_count();
    let method = Dgmpm::new(&problem, config).expect("a valid configuration");
    (method, count)
}

/// Seconds of `steps` steps of `method`.
fn seconds(method: &mut Dgmpm<2>, steps: usize) -> f64 {
    let dt = method.stable_dt();
    let start = Instant::now();
    for k in 0..steps {
        method.step(k as f64 * dt, dt);
    }
    start.elapsed().as_secs_f64()
}

fn main() {
    // `NX NY [ROUNDS] [STEPS]`, or nothing: 600×450 (the measurement)
    let (cells, rest) = match std::env::args().skip(1).any(|a| a.parse::<usize>().is_ok()) {
        true => common::plate_arguments(),
        false => (vec![600, 450], Vec::new()),
    };
    let rounds = rest.first().copied().unwrap_or(15).max(1);
    let steps = rest.get(1).copied().unwrap_or(20).max(1);
    common::pool(1).install(|| {
        let (mut euler, count) = build(&cells, false);
        let (mut rk2, _) = build(&cells, true);
        assert!(rk2.solver.heun_cells(), "RK2 runs on Heun's cell sweeps");
        seconds(&mut euler, 3);
        seconds(&mut rk2, 3);
        let per_update = |s: f64| s / (steps * count) as f64 * 1e9;
        let (mut e, mut r) = (Vec::new(), Vec::new());
        for _ in 0..rounds {
            e.push(per_update(seconds(&mut euler, steps)));
            r.push(per_update(seconds(&mut rk2, steps)));
        }
        let ratios = r.iter().zip(&e).map(|(r, e)| r / e).collect();
        let (e_med, r_med) = (common::median(e), common::median(r));
        println!(
            "plate-wave {}x{}, one thread, {rounds} rounds of {steps} steps: Euler {e_med:.1} ns, \
             RK2 {r_med:.1} ns per cell-update; RK2/Euler {:.3} (median of the rounds' ratios {:.3})",
            cells[0],
            cells[1],
            r_med / e_med,
            common::median(ratios)
        );
    });
}

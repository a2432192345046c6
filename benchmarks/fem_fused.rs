//! The FEM step's fused pass against its two phases, in one process (issue 14):
//! `cargo bench --bench fem_fused [-- NX NY]` (default: the 1000×750 plate).
//!
//! Four builds of the FEM on the partial plate impact: the serial loops (built in a
//! one-thread pool) and the parallel ones (the global pool), each with the fused step
//! (`Stencil::step_into`: the nodal update one layer ahead of the stencil force) and with
//! its two phases (`FemSolver::set_fused_step(false)`, the reference it equals bit for
//! bit). Each round steps each build `STEPS` steps, the serial ones on one thread and the
//! parallel ones on two; medians over `ROUNDS` rounds (the first one warms up) of the time
//! per step, and the ratios. The builds are interleaved in one process because separate
//! processes on the shared VM drift by up to ±30 % (BENCHMARKS.md).
mod common;
use common::{median, plate_arguments, pool};
use impact_core::method::MethodKind;
use impact_core::{Method, Problem, Scene};
use impact_fem::Fem;
use std::time::Instant;

const ROUNDS: usize = 20;
const STEPS: usize = 8;

fn main() {
    let (cells, _) = plate_arguments();
    let (one, two) = (pool(1), pool(2));
    let mut scene = Scene::builtin("plate").expect("shipped scene");
    scene.domain.cells = cells.clone();
    let problem = Problem::<2>::from_scene(&scene).expect("valid scene");
    let config = scene.method_config(MethodKind::Fem);
    // serial two phases, serial fused, parallel two phases, parallel fused
    let mut builds: Vec<Fem<2>> = (0..4)
        .map(|k| {
            let build = || Fem::<2>::new(&problem, config).expect("builds");
            let mut fem = if k < 2 { one.install(build) } else { build() };
            fem.solver.set_fused_step(k % 2 == 1);
            fem
        })
        .collect();
    let dt = builds[0].stable_dt();
    let mut times = vec![vec![]; 4];
    for round in 0..=ROUNDS {
        for (k, fem) in builds.iter_mut().enumerate() {
            let pool = if k < 2 { &one } else { &two };
            let t = pool.install(|| {
                let start = Instant::now();
                for n in round * STEPS..(round + 1) * STEPS {
                    fem.step(n as f64 * dt, dt);
                }
                start.elapsed().as_secs_f64() / STEPS as f64
            });
            if round > 0 {
                times[k].push(t * 1e3);
            }
        }
    }
    let m: Vec<f64> = times.into_iter().map(median).collect();
    println!(
        "plate {}x{}, ms per step, medians of {ROUNDS} interleaved rounds of {STEPS} steps",
        cells[0], cells[1]
    );
    println!(
        "serial loops, 1 thread:    two phases {:.2}, fused {:.2} ({:.3}x)",
        m[0],
        m[1],
        m[0] / m[1]
    );
    println!(
        "parallel loops, 2 threads: two phases {:.2}, fused {:.2} ({:.3}x)",
        m[2],
        m[3],
        m[2] / m[3]
    );
    println!(
        "2 threads over 1: two phases {:.2}x, fused {:.2}x",
        m[0] / m[2],
        m[1] / m[3]
    );
}

//! Thread scaling of one step, measured inside one process (issue 14):
//! `cargo bench --bench threads [-- NX NY [THREADS...]]` (default: the 1000×750 plate, one
//! and two threads; on a bigger machine, e.g. `-- 2000 1500 1 2 4 8 16`).
//!
//! Each method (DGMPM, MPM, FEM, their defaults on the partial plate impact) is built twice:
//! inside a one-thread pool, so that its loops take their serial form (what a run with
//! `RAYON_NUM_THREADS=1` executes), and in the global pool, so that they take their
//! parallel form. Each round steps the serial build on one thread, then the parallel build
//! on a pool of each thread count, at least `STEPS` steps each and at least `WINDOW` seconds
//! of the serial build (the step count is set from the warm-up round, so a cheap step is
//! not timed over a window short enough for the machine's noise to dominate; each build
//! keeps its own state; the step's cost does not depend on the state of the wave); the
//! median over `ROUNDS` rounds
//! of the time per step is reported, and the speed-up of each count over the serial
//! build. Separate processes (criterion runs, `benchmarks/scaling.sh`) varied by up to
//! ±30 % from one run to the next on the shared 2-core VM (page placement, neighbours),
//! so the ratio is taken within one process, its runs interleaved.
//!
//! First, a STREAM-style triad `a = b + s·c` over 40 M doubles on each pool (the same
//! loop as `roofline.rs`, split in chunks of 64 K on the pool): a phase bound by memory
//! bandwidth cannot speed up by more than the triad does.
mod common;
use common::{median, plate_arguments, pool};
use impact_core::method::MethodKind;
use impact_core::{Method, Problem, Scene};
use std::time::Instant;

const ROUNDS: usize = 7;
const STEPS: usize = 4;
/// Shortest timed window of the serial build, seconds.
const WINDOW: f64 = 0.08;

/// "1 thread", "n threads".
fn threads(n: usize) -> String {
    match n {
        1 => "1 thread".into(),
        _ => format!("{n} threads"),
    }
}

/// Bandwidth of one triad pass on `pool`, GB/s (24 B per element: two reads, one write).
fn triad(pool: &rayon::ThreadPool, a: &mut [f64], b: &[f64], c: &[f64]) -> f64 {
    use rayon::prelude::*;
    let start = Instant::now();
    pool.install(|| {
        let chunk = 1 << 16;
        a.par_chunks_mut(chunk)
            .zip(b.par_chunks(chunk))
            .zip(c.par_chunks(chunk))
            .for_each(|((a, b), c)| {
                for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
                    *a = b + 3.0 * c;
                }
            });
    });
    std::hint::black_box(&a);
    24.0 * a.len() as f64 / start.elapsed().as_secs_f64() / 1e9
}

/// Seconds per step of `steps` steps of `m` on `pool`, from step `first` on.
fn time_steps(
    pool: &rayon::ThreadPool,
    m: &mut dyn Method<2>,
    (first, steps): (usize, usize),
) -> f64 {
    let dt = m.stable_dt();
    pool.install(|| {
        let start = Instant::now();
        for k in first..first + steps {
            m.step(k as f64 * dt, dt);
        }
        start.elapsed().as_secs_f64() / steps as f64
    })
}

fn main() {
    let (cells, counts) = plate_arguments();
    let counts = if counts.is_empty() {
        vec![1, 2]
    } else {
        counts
    };
    let one = pool(1);
    let pools: Vec<_> = counts.iter().map(|&n| pool(n)).collect();
    let mut scene = Scene::builtin("plate").expect("shipped scene");
    scene.domain.cells = cells.clone();
    let problem = Problem::<2>::from_scene(&scene).expect("valid scene");
    println!(
        "plate {}x{}, global pool of {} threads; ms per step, medians of {ROUNDS} interleaved rounds of at least {STEPS} steps and {WINDOW} s",
        cells[0],
        cells[1],
        rayon::current_num_threads()
    );
    {
        let n = 40_000_000;
        let (mut a, b, c) = (vec![0.0; n], vec![1.0; n], vec![2.0; n]);
        let mut bandwidth = vec![vec![]; counts.len()];
        for _ in 0..ROUNDS {
            for (p, v) in pools.iter().zip(&mut bandwidth) {
                v.push(triad(p, &mut a, &b, &c));
            }
        }
        let medians: Vec<f64> = bandwidth.into_iter().map(median).collect();
        print!("triad (median GB/s)");
        for (n, gb) in counts.iter().zip(&medians) {
            print!("; {} {gb:.1} ({:.2}x)", threads(*n), gb / medians[0]);
        }
        println!();
    }
    for kind in MethodKind::ALL {
        let config = scene.method_config(kind);
        let mut serial = one.install(|| impact::build(&problem, config).expect("builds"));
        let mut parallel = impact::build(&problem, config).expect("builds");
        let mut serial_times = vec![];
        let mut times = vec![vec![]; counts.len()];
        let (mut first, mut steps) = (0, STEPS);
        for round in 0..=ROUNDS {
            let t = time_steps(&one, serial.as_mut(), (first, steps));
            let runs: Vec<f64> = pools
                .iter()
                .map(|p| time_steps(p, parallel.as_mut(), (first, steps)))
                .collect();
            first += steps;
            if round == 0 {
                steps = STEPS.max((WINDOW / t).ceil() as usize);
            }
            // round 0 warms up
            if round > 0 {
                serial_times.push(t);
                runs.into_iter()
                    .zip(&mut times)
                    .for_each(|(t, v)| v.push(t));
            }
        }
        let base = median(serial_times);
        print!(
            "{:<6} serial build, 1 thread {:.2}",
            kind.name(),
            base * 1e3
        );
        for (n, t) in counts.iter().zip(times) {
            let t = median(t);
            print!("; {} {:.2} ({:.2}x)", threads(*n), t * 1e3, base / t);
        }
        println!();
    }
}

//! The memory roofline of DGMPM's step on one core (issue 14): `cargo bench --bench
//! roofline`.
//!
//! 1. A STREAM-style triad `a[i] = b[i] + s·c[i]` over 40 M doubles (three 320 MB arrays),
//!    one thread, 10 passes: bandwidth counted as STREAM does, 24 B per element (two reads,
//!    one write); best and median pass.
//! 2. One DGMPM step on one thread (a rayon pool of 1), interleaved with the triad passes:
//!    the 1000×750 plate at 1 point per cell (cell path, Euler, CTU, Courant 1), the bar
//!    at 10^6 cells (cell path), and the 1000×750 plate with RK2 (the nodal path); median
//!    of 10 steps after 3 warm-up steps, in ns per cell-update.
//! 3. The bytes the 2D cell path must move per cell and step, counted from the code (each
//!    array read or written once per phase, caches assumed to reuse a neighbour's data
//!    within a row; `T` = 32 B stress, `V` = 16 B velocity or position, `F` = 48 B one
//!    face's flux, two faces per cell):
//!    - `interface_fluxes`: read `T + V` (48), write both axes' fluxes `2F` (96);
//!    - `transverse_corrections`: y-corrections read the x-fluxes `F` and write the scratch
//!      `F`; x-corrections read the y-fluxes `F` and update the x-fluxes `2F`; the scratch
//!      is added to the y-fluxes: `F + 2F` (48 + 48 + 48 + 96 + 48 + 96 = 384);
//!    - `cell_update`: read `2F` and the mass (104), update `T + V` (96);
//!    - `move_points`: read `V`, update the position `2V` (48).
//!
//!    776 B per cell and step, 920 B if the pure writes (144 B) also read their lines
//!    first (write-allocate). The roofline time is bytes / triad bandwidth.
use impact_core::method::{Integrator, MethodKind};
use impact_core::{Method, Problem, Scene};
use std::time::Instant;

const TRIAD: usize = 40_000_000;
/// Bytes per cell and step of the 2D cell path with CTU (module doc), without and with
/// write-allocate traffic.
const CELL_PATH_BYTES: (f64, f64) = (776.0, 920.0);

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One triad pass: seconds.
fn triad(a: &mut [f64], b: &[f64], c: &[f64], s: f64) -> f64 {
    let start = Instant::now();
    for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
        *a = b + s * c;
    }
    std::hint::black_box(&a);
    start.elapsed().as_secs_f64()
}

/// A method on the shipped scene `name` with `cells`, its config edited.
fn method<const D: usize>(
    name: &str,
    cells: Vec<usize>,
    edit: impl Fn(&mut impact_core::method::MethodConfig),
) -> (Box<dyn Method<D>>, usize) {
    let mut scene = Scene::builtin(name).expect("shipped scene");
    scene.domain.cells = cells;
    let problem = Problem::<D>::from_scene(&scene).expect("valid scene");
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    let count = problem.grid.cell_count();
    (
        impact::build(&problem, config).expect("valid method"),
        count,
    )
}

/// Seconds of one step.
fn step<const D: usize>(m: &mut dyn Method<D>, k: usize) -> f64 {
    let dt = m.stable_dt();
    let start = Instant::now();
    m.step(k as f64 * dt, dt);
    start.elapsed().as_secs_f64()
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    pool.install(|| {
        let (mut a, b, c) = (vec![0.0; TRIAD], vec![1.0; TRIAD], vec![2.0; TRIAD]);
        let (mut plate, plate_cells) = method::<2>("plate", vec![1000, 750], |_| {});
        let (mut bar, bar_cells) = method::<1>("bar", vec![1_000_000], |_| {});
        let (mut rk2, rk2_cells) = method::<2>("plate", vec![1000, 750], |c| {
            c.courant = 0.5;
            if let Some(o) = c.dgmpm_mut() {
                o.integrator = Integrator::Rk2;
            }
        });
        for k in 0..3 {
            step(plate.as_mut(), k);
            step(bar.as_mut(), k);
            step(rk2.as_mut(), k);
        }
        let (mut triads, mut plates, mut bars, mut rk2s) = (vec![], vec![], vec![], vec![]);
        for k in 3..13 {
            triads.push(triad(&mut a, &b, &c, 3.0));
            plates.push(step(plate.as_mut(), k) / plate_cells as f64 * 1e9);
            bars.push(step(bar.as_mut(), k) / bar_cells as f64 * 1e9);
            rk2s.push(step(rk2.as_mut(), k) / rk2_cells as f64 * 1e9);
        }
        let bandwidth = |s: f64| 24.0 * TRIAD as f64 / s / 1e9;
        let best = triads.iter().copied().fold(f64::INFINITY, f64::min);
        let triad_median = median(triads.clone());
        println!(
            "triad, one thread: best {:.1} GB/s, median {:.1} GB/s (10 passes of 40 M doubles)",
            bandwidth(best),
            bandwidth(triad_median)
        );
        let plate_ns = median(plates.clone());
        println!(
            "dgmpm plate 1000x750, 1 ppc, cell path, CTU: {plate_ns:.1} ns per cell-update \
             (median of 10; min {:.1})",
            plates.iter().copied().fold(f64::INFINITY, f64::min)
        );
        for (label, bytes) in [
            ("without write-allocate", CELL_PATH_BYTES.0),
            ("with write-allocate", CELL_PATH_BYTES.1),
        ] {
            let floor_ns = bytes / bandwidth(triad_median);
            println!(
                "  {bytes:.0} B per cell ({label}): roofline {floor_ns:.1} ns at the median \
                 triad bandwidth, reached {:.0} %",
                100.0 * floor_ns / plate_ns
            );
        }
        println!(
            "dgmpm bar 10^6 cells, cell path: {:.1} ns per cell-update",
            median(bars)
        );
        println!(
            "dgmpm plate 1000x750, RK2 (nodal path), CTU: {:.1} ns per cell-update",
            median(rk2s)
        );
    });
}

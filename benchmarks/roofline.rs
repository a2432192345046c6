//! The memory roofline of DGMPM's step on one core (issue 14): `cargo bench --bench
//! roofline`.
//!
//! 1. A STREAM-style triad `a[i] = b[i] + s·c[i]` over 40 M doubles (three 320 MB arrays),
//!    one thread, 10 passes: bandwidth counted as STREAM does, 24 B per element (two reads,
//!    one write); best and median pass.
//! 2. One DGMPM step on one thread (a rayon pool of 1), interleaved with the triad passes:
//!    the 1000×750 plate at 1 point per cell (Euler, CTU, Courant 1) on the fused path
//!    (the default) and on the phase-by-phase cell path, the bar at 10^6 cells on both,
//!    and the 1000×750 plate with RK2 (Courant 0.5) on the Heun cell sweeps (the default)
//!    and on the phase-by-phase nodal path; median of 10 steps after 3 warm-up steps, in ns
//!    per cell-update.
//! 3. The bytes a 2D step must move per cell, counted from the code (each array read or
//!    written once per phase, caches assumed to reuse a neighbour's data within a row;
//!    `T` = 32 B stress, `V` = 16 B velocity or position, `F` = 48 B one face's flux, two
//!    faces per cell):
//!    - the cell path: `interface_fluxes` reads `T + V` (48) and writes both axes' fluxes
//!      `2F` (96); `transverse_corrections`: y-corrections read the x-fluxes `F` and write
//!      the scratch `F`, x-corrections read the y-fluxes `F` and update the x-fluxes `2F`,
//!      the scratch is added to the y-fluxes `F + 2F` (384); `cell_update` reads `2F` and
//!      the mass (104) and updates `T + V` (96); `move_points` reads `V` and updates the
//!      position `2V` (48): 776 B, 920 B if the pure writes (144 B) also read their lines
//!      first (write-allocate);
//!    - the fused path: reads `T + V` and the mass (56), writes the next `T + V` (48) and
//!      updates the position `2V` (32): 136 B, 184 B with write-allocate (its face rows
//!      stay in cache: about 430 KB per band at 1000 cells a row);
//!    - the fused path in 1D (`T` = `V` = 8 B): reads `T + V` and the mass (24), writes the
//!      next `T + V` (16), updates the position (16): 56 B, 72 B with write-allocate;
//!    - RK2 at one point per cell, the Heun cell sweeps (`fused/heun.rs`; no nodal field,
//!      the side-state weights one cell's copy on a uniform grid, in cache), in 2D one
//!      wavefront (`fused/heun/wavefront.rs`): stage 1 reads the point's `T + V` and mass
//!      (56) and writes the next `T + V` (48) and the cells' four side states (traction
//!      and velocity, `4·32` = 128) into a ring of 6 rows per thread (768 KB at 1000
//!      cells a row: in cache, rewritten every 4 rows); stage 2 runs one row behind, so
//!      its reads of the side states, of the next `T + V` and of the mass and its update
//!      of the next `T + V` (swapped into the points after) hit the lines stage 1 has
//!      just touched; it moves the points (32): 136 B, 184 B with write-allocate, the
//!      fused Euler step's (plus the rows next to each thread's group of bands, read
//!      twice: 2 rows in `ny / threads`). (Before, two whole-grid sweeps: stage 1 wrote
//!      the side states (128), stage 2 read them (128) and read the next `T + V` and the
//!      mass again (56) and wrote it (48): 496 B, 672 B; with whole side states and
//!      `move_points`: 640 B, 880 B; the fused nodal sweep before that: 800 B, 992 B.)
//!
//!    The roofline time is bytes / triad bandwidth.
use impact_core::method::{Integrator, MethodKind};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};
use std::time::Instant;

const TRIAD: usize = 40_000_000;
/// Bytes per cell and step of the 2D cell path with CTU (module doc), without and with
/// write-allocate traffic.
const CELL_PATH_BYTES: (f64, f64) = (776.0, 920.0);
/// The same for the fused path, in 2D and in 1D.
const FUSED_PATH_BYTES: (f64, f64) = (136.0, 184.0);
const FUSED_BAR_BYTES: (f64, f64) = (56.0, 72.0);
/// The same for RK2 at one point per cell (2D, the Heun cell sweeps).
const FUSED_NODAL_RK2_BYTES: (f64, f64) = (136.0, 184.0);

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

/// DGMPM on the shipped scene `name` with `cells`, its config edited, on step path `path`
/// (`None`: the default).
fn method<const D: usize>(
    name: &str,
    cells: Vec<usize>,
    path: Option<StepPath>,
    edit: impl Fn(&mut impact_core::method::MethodConfig),
) -> (Dgmpm<D>, usize) {
    let mut scene = Scene::builtin(name).expect("shipped scene");
    scene.domain.cells = cells;
    let problem = Problem::<D>::from_scene(&scene).expect("valid scene");
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    let count = problem.grid.cell_count();
    let mut m = Dgmpm::new(&problem, config).expect("valid method");
    if let Some(path) = path {
        m.solver
            .set_step_path(path, &m.state.points)
            .expect("the path applies");
    }
    (m, count)
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
        let plate_run = |path| method::<2>("plate", vec![1000, 750], path, |_| {});
        let bar_run = |path| method::<1>("bar", vec![1_000_000], path, |_| {});
        let (mut plate, plate_cells) = plate_run(None);
        let (mut plate_cell, _) = plate_run(Some(StepPath::Cell));
        let (mut bar, bar_cells) = bar_run(None);
        let (mut bar_cell, _) = bar_run(Some(StepPath::Cell));
        let rk2_run = |path| {
            method::<2>("plate", vec![1000, 750], path, |c| {
                c.courant = 0.5;
                if let Some(o) = c.dgmpm_mut() {
                    o.integrator = Integrator::Rk2;
                }
            })
        };
        let (mut rk2, rk2_cells) = rk2_run(None);
        let (mut rk2_phases, _) = rk2_run(Some(StepPath::SinglePoint));
        assert_eq!(plate.solver.step_path(), StepPath::Fused);
        assert_eq!(bar.solver.step_path(), StepPath::Fused);
        assert_eq!(rk2.solver.step_path(), StepPath::FusedNodal);
        assert!(rk2.solver.heun_cells());
        let runs: [(&str, &mut dyn Method<2>, usize); 4] = [
            ("plate 1000x750, fused path", &mut plate, plate_cells),
            ("plate 1000x750, cell path", &mut plate_cell, plate_cells),
            ("plate 1000x750, RK2, Heun cell sweeps", &mut rk2, rk2_cells),
            (
                "plate 1000x750, RK2, nodal phases",
                &mut rk2_phases,
                rk2_cells,
            ),
        ];
        let bars: [(&str, &mut dyn Method<1>, usize); 2] = [
            ("bar 10^6 cells, fused path", &mut bar, bar_cells),
            ("bar 10^6 cells, cell path", &mut bar_cell, bar_cells),
        ];
        let (mut runs, mut bars) = (runs, bars);
        for k in 0..3 {
            runs.iter_mut().for_each(|(_, m, _)| {
                step(*m, k);
            });
            bars.iter_mut().for_each(|(_, m, _)| {
                step(*m, k);
            });
        }
        let mut triads = vec![];
        let mut times = vec![vec![]; runs.len() + bars.len()];
        for k in 3..13 {
            triads.push(triad(&mut a, &b, &c, 3.0));
            for (i, (_, m, cells)) in runs.iter_mut().enumerate() {
                times[i].push(step(*m, k) / *cells as f64 * 1e9);
            }
            for (i, (_, m, cells)) in bars.iter_mut().enumerate() {
                times[runs.len() + i].push(step(*m, k) / *cells as f64 * 1e9);
            }
        }
        let bandwidth = |s: f64| 24.0 * TRIAD as f64 / s / 1e9;
        let best = triads.iter().copied().fold(f64::INFINITY, f64::min);
        let triad_median = median(triads.clone());
        println!(
            "triad, one thread: best {:.1} GB/s, median {:.1} GB/s (10 passes of 40 M doubles)",
            bandwidth(best),
            bandwidth(triad_median)
        );
        let labels = runs.iter().map(|r| r.0).chain(bars.iter().map(|r| r.0));
        let medians: Vec<f64> = times.iter().map(|t| median(t.clone())).collect();
        for ((label, t), m) in labels.zip(&times).zip(&medians) {
            let min = t.iter().copied().fold(f64::INFINITY, f64::min);
            println!("dgmpm {label}: {m:.1} ns per cell-update (median of 10; min {min:.1})");
        }
        for (path, ns, bytes) in [
            ("plate, fused", medians[0], FUSED_PATH_BYTES),
            ("plate, cell", medians[1], CELL_PATH_BYTES),
            ("plate RK2, fused nodal", medians[2], FUSED_NODAL_RK2_BYTES),
            ("bar, fused", medians[4], FUSED_BAR_BYTES),
        ] {
            for (label, bytes) in [
                ("without write-allocate", bytes.0),
                ("with write-allocate", bytes.1),
            ] {
                let floor_ns = bytes / bandwidth(triad_median);
                println!(
                    "  {path} path, {bytes:.0} B per cell ({label}): roofline {floor_ns:.1} ns \
                     at the median triad bandwidth, reached {:.0} %",
                    100.0 * floor_ns / ns
                );
            }
        }
        println!(
            "fused over phase path: plate {:.2}x, bar {:.2}x, plate RK2 {:.2}x",
            medians[1] / medians[0],
            medians[5] / medians[4],
            medians[3] / medians[2]
        );
    });
}

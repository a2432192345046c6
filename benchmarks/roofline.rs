//! The memory roofline of the steps on one core (issues 14, 29): `cargo bench --bench
//! roofline`.
//!
//! 1. A STREAM-style triad `a[i] = b[i] + s·c[i]` over 40 M doubles (three 320 MB arrays),
//!    one thread, 10 passes: bandwidth counted as STREAM does, 24 B per element (two reads,
//!    one write); best and median pass.
//! 2. One step of each row on one thread (a rayon pool of 1), interleaved with the triad
//!    passes: DGMPM on the 1000×750 plate at 1 point per cell (Euler, CTU, Courant 1) on
//!    the fused path (the default) and on the phase-by-phase cell path, the bar at 10^6
//!    cells on both, and the 1000×750 plate with RK2 (Courant 0.5) on the Heun cell sweeps
//!    (the default) and on the phase-by-phase nodal path; issue 29's other paths on the
//!    1000×750 plate-wave: DGMPM at 4 points per cell (Courant 0.5) with Euler and with
//!    RK2, MPM USL with linear hats at 1 point per cell and with quadratic B-splines at 4;
//!    median of 10 steps after 3 warm-up steps, in ns per cell-update (DGMPM) or
//!    point-update (MPM).
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
//!      and velocity, `4·32` = 128) into a ring of 4 rows per thread (512 KB at 1000
//!      cells a row, 307 KB at 600: in L2, rewritten every 4 rows); stage 2 runs one row behind, so
//!      its reads of the side states, of the next `T + V` and of the mass and its update
//!      of the next `T + V` (swapped into the points after) hit the lines stage 1 has
//!      just touched; it moves the points (32): 136 B, 184 B with write-allocate, the
//!      fused Euler step's (plus the rows next to each thread's group of bands, read
//!      twice: 2 rows in `ny / threads`). (Before, two whole-grid sweeps: stage 1 wrote
//!      the side states (128), stage 2 read them (128) and read the next `T + V` and the
//!      mass again (56) and wrote it (48): 496 B, 672 B; with whole side states and
//!      `move_points`: 640 B, 880 B; the fused nodal sweep before that: 800 B, 992 B.)
//!    - DGMPM at 4 ppc, Euler (`fused/nodal.rs`, the cell layouts of `layouts.rs` in L2):
//!      1,096 B per cell; RK2 1,484 B per cell (benchmarks/history.md, "DGMPM 4 ppc
//!      memory, the cell layouts"); write-allocate not counted;
//!    - MPM, per point (`m` 8, `V` 16, `T` 32 B; a node's sums in cache while its points
//!      add to or read them): USL hats at 1 ppc 353 B (history, "MPM per point and 3D at
//!      128³"); quadratic B-splines at 4 ppc 252 B (the same point arrays, the nodes' 145 B
//!      shared by 4 points, and the point's `u32` index into the table of distinct rows of
//!      weights, read by the scatter and by the gather: the table, 216 B a row, stays in
//!      cache; 676 B when each point read its own row); write-allocate not counted.
//!
//!    The roofline time is bytes / triad bandwidth.
use impact_core::method::{Integrator, MethodConfig, MethodKind, MpmShape};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};
use std::time::Instant;

const TRIAD: usize = 40_000_000;
/// Bytes per cell and step of the 2D cell path with CTU (module doc), without and with
/// write-allocate traffic.
const CELL_PATH_BYTES: (f64, Option<f64>) = (776.0, Some(920.0));
/// The same for the fused path, in 2D and in 1D.
const FUSED_PATH_BYTES: (f64, Option<f64>) = (136.0, Some(184.0));
const FUSED_BAR_BYTES: (f64, Option<f64>) = (56.0, Some(72.0));
/// The same for RK2 at one point per cell (2D, the Heun cell sweeps).
const FUSED_NODAL_RK2_BYTES: (f64, Option<f64>) = (136.0, Some(184.0));
/// DGMPM at 4 points per cell, per cell (module doc), Euler and RK2.
const FOUR_PPC_EULER_BYTES: (f64, Option<f64>) = (1096.0, None);
const FOUR_PPC_RK2_BYTES: (f64, Option<f64>) = (1484.0, None);
/// MPM per point (module doc): USL hats at 1 ppc, quadratic B-splines at 4 ppc.
const MPM_HATS_BYTES: (f64, Option<f64>) = (353.0, None);
const MPM_BSPLINES_BYTES: (f64, Option<f64>) = (252.0, None);

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

/// One 2D row of the bench: its label, the method, the updates per step (cells or points),
/// the unit's name and the bytes per update counted from the code (module doc; `None`:
/// not counted, the row only gives a ratio).
struct Row {
    label: &'static str,
    method: Box<dyn Method<2>>,
    updates: usize,
    unit: &'static str,
    bytes: Option<(f64, Option<f64>)>,
}

/// The shipped scene `name` with `cells`, and its configuration for `kind`, edited.
fn other_method(
    name: &str,
    cells: Vec<usize>,
    kind: MethodKind,
    edit: impl Fn(&mut MethodConfig),
) -> Box<dyn Method<2>> {
    let mut scene = Scene::builtin(name).expect("shipped scene");
    scene.domain.cells = cells;
    let problem = Problem::<2>::from_scene(&scene).expect("valid scene");
    let mut config = scene.method_config(kind);
    edit(&mut config);
    impact::build(&problem, config).expect("valid method")
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
        let (plate, plate_cells) = plate_run(None);
        let (plate_cell, _) = plate_run(Some(StepPath::Cell));
        let (mut bar, bar_cells) = bar_run(None);
        let (mut bar_cell, _) = bar_run(Some(StepPath::Cell));
        let rk2 = |c: &mut MethodConfig| {
            c.courant = 0.5;
            if let Some(o) = c.dgmpm_mut() {
                o.integrator = Integrator::Rk2;
            }
        };
        let rk2_run = |path| method::<2>("plate", vec![1000, 750], path, rk2);
        let (rk2_heun, rk2_cells) = rk2_run(None);
        let (rk2_phases, _) = rk2_run(Some(StepPath::SinglePoint));
        assert_eq!(plate.solver.step_path(), StepPath::Fused);
        assert_eq!(bar.solver.step_path(), StepPath::Fused);
        assert_eq!(rk2_heun.solver.step_path(), StepPath::FusedNodal);
        assert!(rk2_heun.solver.heun_cells());
        // the 4-ppc and MPM paths on the plate-wave scene (Courant 0.5 at 4 ppc)
        let four = |c: &mut MethodConfig| {
            c.points_per_cell = 4;
            c.courant = 0.5;
        };
        let wave = [1000, 750];
        let wave_cells = wave[0] * wave[1];
        let dgmpm_four = other_method("plate-wave", wave.to_vec(), MethodKind::Dgmpm, four);
        let dgmpm_four_rk2 = other_method("plate-wave", wave.to_vec(), MethodKind::Dgmpm, |c| {
            four(c);
            rk2(c);
        });
        let mpm_hats = other_method("plate-wave", wave.to_vec(), MethodKind::Mpm, |_| {});
        let mpm_bsplines = other_method("plate-wave", wave.to_vec(), MethodKind::Mpm, |c| {
            four(c);
            if let Some(o) = c.mpm_mut() {
                o.shape = MpmShape::Bspline2;
            }
        });
        let row = |label, method: Box<dyn Method<2>>, updates, unit, bytes| Row {
            label,
            method,
            updates,
            unit,
            bytes,
        };
        let mut runs = [
            row(
                "DGMPM plate 1000x750, fused path",
                Box::new(plate),
                plate_cells,
                "cell",
                Some(FUSED_PATH_BYTES),
            ),
            row(
                "DGMPM plate 1000x750, cell path",
                Box::new(plate_cell),
                plate_cells,
                "cell",
                Some(CELL_PATH_BYTES),
            ),
            row(
                "DGMPM plate 1000x750, RK2, Heun cell sweeps",
                Box::new(rk2_heun),
                rk2_cells,
                "cell",
                Some(FUSED_NODAL_RK2_BYTES),
            ),
            row(
                "DGMPM plate 1000x750, RK2, nodal phases",
                Box::new(rk2_phases),
                rk2_cells,
                "cell",
                None,
            ),
            row(
                "DGMPM plate-wave 1000x750, Euler, 4 ppc",
                dgmpm_four,
                wave_cells,
                "cell",
                Some(FOUR_PPC_EULER_BYTES),
            ),
            row(
                "DGMPM plate-wave 1000x750, RK2, 4 ppc",
                dgmpm_four_rk2,
                wave_cells,
                "cell",
                Some(FOUR_PPC_RK2_BYTES),
            ),
            row(
                "MPM plate-wave 1000x750, USL hats, 1 ppc",
                mpm_hats,
                wave_cells,
                "point",
                Some(MPM_HATS_BYTES),
            ),
            row(
                "MPM plate-wave 1000x750, USL B-splines, 4 ppc",
                mpm_bsplines,
                4 * wave_cells,
                "point",
                Some(MPM_BSPLINES_BYTES),
            ),
        ];
        let mut bars: [(&str, &mut dyn Method<1>, usize); 2] = [
            ("DGMPM bar 10^6 cells, fused path", &mut bar, bar_cells),
            ("DGMPM bar 10^6 cells, cell path", &mut bar_cell, bar_cells),
        ];
        for k in 0..3 {
            runs.iter_mut().for_each(|r| {
                step(r.method.as_mut(), k);
            });
            bars.iter_mut().for_each(|(_, m, _)| {
                step(*m, k);
            });
        }
        let mut triads = vec![];
        let mut times = vec![vec![]; runs.len() + bars.len()];
        for k in 3..13 {
            triads.push(triad(&mut a, &b, &c, 3.0));
            for (i, r) in runs.iter_mut().enumerate() {
                times[i].push(step(r.method.as_mut(), k) / r.updates as f64 * 1e9);
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
        let medians: Vec<f64> = times.iter().map(|t| median(t.clone())).collect();
        let labelled = runs
            .iter()
            .map(|r| (r.label, r.unit, r.bytes))
            .chain(bars.iter().map(|b| (b.0, "cell", None)));
        for (((label, unit, _), t), m) in labelled.clone().zip(&times).zip(&medians) {
            let min = t.iter().copied().fold(f64::INFINITY, f64::min);
            println!("{label}: {m:.1} ns per {unit}-update (median of 10; min {min:.1})");
        }
        let bar_bytes = [(runs.len(), FUSED_BAR_BYTES)];
        let counted = labelled
            .enumerate()
            .filter_map(|(i, (label, unit, bytes))| bytes.map(|b| (label, unit, medians[i], b)))
            .chain(bar_bytes.map(|(i, b)| (bars[0].0, "cell", medians[i], b)));
        for (label, unit, ns, bytes) in counted {
            let with_allocate = bytes.1.map(|b| ("with write-allocate", b));
            for (kind, bytes) in [("without write-allocate", bytes.0)]
                .into_iter()
                .chain(with_allocate)
            {
                let floor_ns = bytes / bandwidth(triad_median);
                println!(
                    "  {label}: {bytes:.0} B per {unit} ({kind}): roofline {floor_ns:.1} ns \
                     at the median triad bandwidth, reached {:.0} %",
                    100.0 * floor_ns / ns
                );
            }
        }
        let bar = runs.len();
        println!(
            "fused over phase path: plate {:.2}x, bar {:.2}x, plate RK2 {:.2}x",
            medians[1] / medians[0],
            medians[bar + 1] / medians[bar],
            medians[3] / medians[2]
        );
    });
}

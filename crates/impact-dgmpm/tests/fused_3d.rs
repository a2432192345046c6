//! The fused 3D cell path ([`StepPath::Fused`], `fused/block.rs`) equals the
//! phase-by-phase cell path ([`StepPath::Cell`]: face arrays, `ctu3.rs`'s fluctuation and
//! source arrays, `cell_update`) bit for bit: the bits of every component of every
//! point's stress, velocity and position compared after every step (zero signs included),
//! for donor-cell and CTU (both edge treatments) on
//! (a) a plane wave along each axis (symmetry sides),
//! (b) a partial impact on a patch of one face with free, symmetry, bonded-velocity
//!     (a patch cut by face edges, `cover = "fraction"`), frictionless-velocity and
//!     pressure (ramped) faces, so that every kind of two-edge corner meets,
//! (c) a non-cubic grid (other cell counts and sizes per axis),
//!
//! serially (a one-thread pool) and on a two-thread pool with more than 4,096 cells; the
//! grids have more z-layers than a slab, so slab edges are crossed. The work and impulse
//! of the loads, sums over the boundary faces taken in another order, agree to 1e-13.
use impact_core::method::{EdgeTreatment, MethodKind, TransverseFlux};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};

const STEEL: &str = "model = \"linear-elastic\"\nyoung = 2.0e11\npoisson = 0.3\ndensity = 7800.0";

/// A 3D scene from its `[domain]` lengths and cells and its `[boundary]` table's body.
fn scene(lengths: [f64; 3], cells: [usize; 3], boundary: &str) -> Scene {
    let text = format!(
        "name = \"fused-3d\"\ndim = 3\n[domain]\nlength = {lengths:?}\ncells = {cells:?}\n\
         [material]\n{STEEL}\n[boundary]\n{boundary}\n[time]\noutput_transits = [4]\n"
    );
    Scene::from_toml(&text, "fused 3D test").unwrap()
}

/// Runs `steps` steps of the default path (which must be the fused one) and of the cell
/// path on `threads` threads, comparing the points after every step; returns the number
/// of values compared and the largest relative difference of the work and impulse.
fn compare(
    label: &str,
    scene: &Scene,
    flux: TransverseFlux,
    edges: EdgeTreatment,
    steps: usize,
    threads: usize,
) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let problem = Problem::<3>::from_scene(scene).unwrap();
        let mut config = scene.method_config(MethodKind::Dgmpm);
        let options = config.dgmpm_mut().unwrap();
        (options.flux, options.edges) = (flux, edges);
        config.courant = if flux == TransverseFlux::Ctu {
            1.0
        } else {
            0.48
        };
        let mut fused = Dgmpm::<3>::new(&problem, config).unwrap();
        assert_eq!(fused.solver.step_path(), StepPath::Fused, "{label}");
        let mut cell = fused.clone();
        cell.solver
            .set_step_path(StepPath::Cell, &cell.state.points)
            .unwrap();
        let dt = fused.stable_dt();
        for n in 0..steps {
            fused.step(n as f64 * dt, dt);
            cell.step(n as f64 * dt, dt);
            let (a, b) = (&fused.state.points, &cell.state.points);
            for p in 0..b.len() {
                let bits =
                    |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(x, y)| x.to_bits() == y.to_bits());
                let same = bits(a.stress[p].as_slice(), b.stress[p].as_slice())
                    && bits(a.velocity[p].as_slice(), b.velocity[p].as_slice())
                    && bits(a.position[p].as_slice(), b.position[p].as_slice());
                assert!(
                    same,
                    "{label}: step {n}, point {p}: fused {:?} {:?}, cell path {:?} {:?}",
                    a.stress[p], a.velocity[p], b.stress[p], b.velocity[p]
                );
            }
        }
        let (scale_s, scale_v) = cell.state.points.peaks();
        assert!(
            scale_s > 1e5 && scale_v > 1e-3,
            "{label}: a wave must be there"
        );
        let (wa, wb) = (fused.external_work(), cell.external_work());
        let (ia, ib) = (fused.external_impulse(), cell.external_impulse());
        let work = (wa - wb).abs() / wb.abs().max(f64::MIN_POSITIVE);
        let impulse = (ia - ib).norm() / ib.norm().max(f64::MIN_POSITIVE);
        println!("{label}: states equal, work {work:.1e}, impulse {impulse:.1e}");
        assert!(
            work <= 1e-13 && impulse <= 1e-13,
            "{label}: {work:e} {impulse:e}"
        );
    });
}

/// Every flux and edge treatment, serial; `parallel`: also on two threads.
fn compare_all(label: &str, scene: &Scene, steps: usize, parallel: bool) {
    let runs = [
        (TransverseFlux::DonorCell, EdgeTreatment::Restricted),
        (TransverseFlux::Ctu, EdgeTreatment::Restricted),
        (TransverseFlux::Ctu, EdgeTreatment::Ghost),
    ];
    for (flux, edges) in runs {
        for threads in [1, 2].into_iter().take(1 + usize::from(parallel)) {
            let label = format!("{label}, {flux:?} {edges:?}, {threads} thread(s)");
            compare(&label, scene, flux, edges, steps, threads);
        }
    }
}

/// (a) A plane P wave along each axis: a pressure on the low face normal to it, symmetry
/// on the four sides, the far face free; 18 cells along the wave (more than two slabs).
#[test]
fn fused_plane_waves_along_each_axis_equal_the_cell_path() {
    for axis in 0..3 {
        let name = ["x", "y", "z"];
        let mut boundary = String::new();
        for (k, n) in name.iter().enumerate() {
            let (low, high) = match k == axis {
                true => (
                    "{ kind = \"pressure\", value = 1.0e8 }",
                    "{ kind = \"free\" }",
                ),
                false => ("{ kind = \"symmetry\" }", "{ kind = \"symmetry\" }"),
            };
            boundary += &format!("{n}.low = {low}\n{n}.high = {high}\n");
        }
        let mut cells = [3, 4, 2];
        cells[axis] = 18;
        let mut lengths = [0.3, 0.4, 0.2];
        lengths[axis] = 1.8;
        let scene = scene(lengths, cells, &boundary);
        compare_all(
            &format!("plane wave along {}", name[axis]),
            &scene,
            24,
            false,
        );
    }
}

/// (b) A partial impact: a frictionless impactor on a patch of x.low, a bonded impactor
/// on a patch of z.low whose ends cut faces (`cover = "fraction"`), a ramped pressure on
/// x.high, symmetry on y.low, free y.high and z.high: free/symmetry/velocity/traction
/// edges meet in two-edge corners. 6,120 cells (parallel) on 17 layers (three slabs).
#[test]
fn fused_partial_impact_equals_the_cell_path() {
    let boundary = "x.low = { kind = \"normal-velocity\", value = 20.0, from = [0.0, 0.0], to = [0.9, 0.5] }\n\
        x.high = { kind = \"pressure\", value = 5.0e7, history = \"ramp\", duration = 2.0e-5 }\n\
        y.low = { kind = \"symmetry\" }\ny.high = { kind = \"free\" }\n\
        z.low = { kind = \"velocity\", value = 10.0, from = [0.43, 0.61], to = [1.37, 1.5], cover = \"fraction\" }\n\
        z.high = { kind = \"free\" }";
    let scene = scene([2.0, 1.8, 1.7], [20, 18, 17], boundary);
    compare_all("partial impact", &scene, 30, true);
}

/// (c) A non-cubic grid: 9 × 7 × 11 cells of 0.1 × 0.2 × 0.05 m (a slab edge at layer 8),
/// an impact on a patch of y.high, symmetry on x.low and z.low, the rest free; and the
/// same on 16 × 14 × 21 cells (4,704: parallel).
#[test]
fn fused_non_cubic_grids_equal_the_cell_path() {
    let boundary = "y.high = { kind = \"normal-velocity\", value = 15.0, from = [0.2, 0.1], to = [0.7, 0.4] }\n\
        x.low = { kind = \"symmetry\" }\nz.low = { kind = \"symmetry\" }";
    let small = scene([0.9, 1.4, 0.55], [9, 7, 11], boundary);
    compare_all("non-cubic 9x7x11", &small, 30, false);
    let large = scene([1.6, 2.8, 1.05], [16, 14, 21], boundary);
    compare_all("non-cubic 16x14x21", &large, 20, true);
}

/// Grids one or two cells wide along some axes, where every face plane or row is a
/// boundary and the ghost rings meet: a pressure on z.low, free and symmetry sides.
#[test]
fn fused_tiny_grids_equal_the_cell_path() {
    let boundary = "z.low = { kind = \"pressure\", value = 1.0e8 }\n\
        x.low = { kind = \"symmetry\" }\ny.high = { kind = \"symmetry\" }";
    for cells in [[1, 1, 1], [1, 3, 2], [2, 1, 5], [3, 2, 1]] {
        let lengths = cells.map(|n| 0.1 * n as f64);
        let scene = scene(lengths, cells, boundary);
        compare_all(&format!("tiny {cells:?}"), &scene, 12, false);
    }
}

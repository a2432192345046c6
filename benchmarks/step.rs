//! One step of each method on the paper's bar (150 and 150,000 cells) and plate (33×25
//! and 1000×750 cells).
//!
//! `cargo bench --bench step`; throughput is in cells (elements) per second, i.e.
//! cell-updates per second (points per second for MPM at one point per cell).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use impact_core::method::{MethodConfig, MethodKind, RiemannSolver, TransverseFlux};
use impact_core::{Problem, Scene};
use impact_dgmpm::StepPath;
use std::time::Duration;

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("bar_step");
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    group.sample_size(30);
    for cells in [150usize, 150_000] {
        let mut scene = Scene::builtin("bar").expect("shipped scene");
        scene.domain.cells = vec![cells];
        let problem = Problem::<1>::from_scene(&scene).expect("valid scene");
        for kind in MethodKind::ALL {
            let config = scene.method_config(kind);
            let mut method = impact::build(&problem, config).expect("valid method");
            let dt = method.stable_dt();
            group.throughput(Throughput::Elements(cells as u64));
            let mut t = 0.0;
            group.bench_with_input(BenchmarkId::new(kind.name(), cells), &cells, |b, _| {
                b.iter(|| {
                    method.step(t, dt);
                    t += dt;
                })
            });
        }
    }
    group.finish();
}

fn plate_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("plate_step");
    group.measurement_time(Duration::from_secs(4));
    group.warm_up_time(Duration::from_secs(1));
    group.sample_size(10);
    for cells in [[33usize, 25], [1000, 750]] {
        let mut scene = Scene::builtin("plate").expect("shipped scene");
        scene.domain.cells = cells.to_vec();
        let problem = Problem::<2>::from_scene(&scene).expect("valid scene");
        let count = cells[0] * cells[1];
        for kind in MethodKind::ALL {
            let config = scene.method_config(kind);
            let mut method = impact::build(&problem, config).expect("valid method");
            let dt = method.stable_dt();
            group.throughput(Throughput::Elements(count as u64));
            let mut t = 0.0;
            let id = format!("{}x{}", cells[0], cells[1]);
            group.bench_with_input(BenchmarkId::new(kind.name(), id), &count, |b, _| {
                b.iter(|| {
                    method.step(t, dt);
                    t += dt;
                })
            });
        }
    }
    group.finish();
}

/// Time one DGMPM step of `m` under `id` in `group`.
fn dgmpm_step<const D: usize>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: BenchmarkId,
    m: &mut impact_dgmpm::Dgmpm<D>,
) {
    let dt = impact_core::Method::stable_dt(m);
    let mut t = 0.0;
    group.bench_function(id, |b| {
        b.iter(|| {
            impact_core::Method::step(m, t, dt);
            t += dt;
        })
    });
}

fn dgmpm<const D: usize>(
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
) -> impact_dgmpm::Dgmpm<D> {
    let problem = Problem::<D>::from_scene(scene).expect("valid scene");
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    impact_dgmpm::Dgmpm::<D>::new(&problem, config).expect("valid method")
}

/// What each skip saves: one DGMPM step with and without it (issue #5).
/// - `one_point`: the general nodal phases, the particles→nodes fast path, the cell path;
/// - `transverse`: donor-cell (no transverse solve) against CTU, same Courant number;
/// - `hyperelastic`: the linear bar against the same bar in Saint-Venant–Kirchhoff
///   (approximate solver): the cost of the hyperelastic flux a linear scene never pays;
/// - `dimension`: the 1D bar against the same bar as a 2D strip of N×1 cells (donor-cell).
fn skips(c: &mut Criterion) {
    let mut group = c.benchmark_group("skips");
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    group.sample_size(20);
    let cells = 150_000;
    let mut bar = Scene::builtin("bar").expect("shipped scene");
    bar.domain.cells = vec![cells];
    group.throughput(Throughput::Elements(cells as u64));
    for (label, path) in [
        ("general", StepPath::Nodal),
        ("p2n_fast", StepPath::SinglePoint),
        ("cell_path", StepPath::Cell),
    ] {
        let mut m = dgmpm::<1>(&bar, |_| {});
        m.solver
            .set_step_path(path, &m.state.points)
            .expect("applies at one point per cell");
        dgmpm_step(
            &mut group,
            BenchmarkId::new("one_point/bar_150000", label),
            &mut m,
        );
    }
    let mut plate = Scene::builtin("plate").expect("shipped scene");
    plate.domain.cells = vec![400, 300];
    group.throughput(Throughput::Elements(400 * 300));
    for (label, path) in [
        ("general", StepPath::Nodal),
        ("p2n_fast", StepPath::SinglePoint),
        ("cell_path", StepPath::Cell),
    ] {
        let mut m = dgmpm::<2>(&plate, |_| {});
        m.solver
            .set_step_path(path, &m.state.points)
            .expect("applies at one point per cell");
        dgmpm_step(
            &mut group,
            BenchmarkId::new("one_point/plate_400x300", label),
            &mut m,
        );
    }
    for flux in [TransverseFlux::DonorCell, TransverseFlux::Ctu] {
        let mut m = dgmpm::<2>(&plate, |c| {
            c.dgmpm_mut().expect("dgmpm").flux = flux;
            c.courant = 0.5;
        });
        dgmpm_step(
            &mut group,
            BenchmarkId::new("transverse/plate_400x300", format!("{flux:?}")),
            &mut m,
        );
    }
    group.throughput(Throughput::Elements(cells as u64));
    let mut svk = Scene::builtin("svk-bar").expect("shipped scene");
    svk.domain.cells = vec![cells];
    let mut m = dgmpm::<1>(&bar, |_| {});
    dgmpm_step(
        &mut group,
        BenchmarkId::new("hyperelastic/bar_150000", "linear"),
        &mut m,
    );
    let mut m = dgmpm::<1>(&svk, |c| {
        c.dgmpm_mut().expect("dgmpm").riemann = RiemannSolver::Approximate
    });
    dgmpm_step(
        &mut group,
        BenchmarkId::new("hyperelastic/bar_150000", "svk_approximate"),
        &mut m,
    );
    let mut m = dgmpm::<1>(&bar, |c| c.courant = 0.5);
    dgmpm_step(
        &mut group,
        BenchmarkId::new("dimension/bar_150000", "1d"),
        &mut m,
    );
    let mut strip = Scene::builtin("plate-wave").expect("shipped scene");
    strip.domain.length = vec![6.0, 6.0 / cells as f64];
    strip.domain.cells = vec![cells, 1];
    let mut m = dgmpm::<2>(&strip, |c| {
        c.dgmpm_mut().expect("dgmpm").flux = TransverseFlux::DonorCell;
        c.courant = 0.5;
    });
    dgmpm_step(
        &mut group,
        BenchmarkId::new("dimension/bar_150000", "2d_strip"),
        &mut m,
    );
    group.finish();
}

/// The phases of one DGMPM cell-path step (the fused path runs them in one sweep) on the 1000×750 plate (1 point per cell, CTU,
/// Courant 1), timed alone: Godunov fluxes, CTU corrections, cell update. Run with
/// `RAYON_NUM_THREADS=1` for per-core figures.
fn phases(c: &mut Criterion) {
    let mut group = c.benchmark_group("phases");
    group.measurement_time(Duration::from_secs(4));
    group.warm_up_time(Duration::from_secs(1));
    group.sample_size(10);
    let mut plate = Scene::builtin("plate").expect("shipped scene");
    plate.domain.cells = vec![1000, 750];
    group.throughput(Throughput::Elements(1000 * 750));
    let mut m = dgmpm::<2>(&plate, |_| {});
    // the plate's default is the fused path; its phases are the cell path's
    m.solver
        .set_step_path(StepPath::Cell, &m.state.points)
        .expect("the cell path applies");
    let dt = impact_core::Method::stable_dt(&m);
    // a few steps so that the wave is in the plate
    for k in 0..20 {
        impact_core::Method::step(&mut m, k as f64 * dt, dt);
    }
    let (solver, state) = (&mut m.solver, &mut m.state);
    group.bench_function("plate_1000x750/interface_fluxes", |b| {
        b.iter(|| solver.interface_fluxes(&state.points))
    });
    group.bench_function("plate_1000x750/transverse_corrections", |b| {
        b.iter(|| solver.transverse_corrections(&state.points, dt))
    });
    group.bench_function("plate_1000x750/cell_update", |b| {
        // the same fluxes each time: the state drifts linearly, which does not change the work
        b.iter(|| solver.cell_update(&mut state.points, dt))
    });
    group.finish();
}

criterion_group!(benches, step, plate_step, skips, phases);
criterion_main!(benches);

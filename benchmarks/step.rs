//! One step of each method on the paper's bar (150 and 150,000 cells) and plate (33×25
//! and 1000×750 cells).
//!
//! `cargo bench --bench step`; throughput is in cells (elements) per second, i.e.
//! cell-updates per second (points per second for MPM at one point per cell).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene};
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
            let config = impact::scene_config(&scene, kind);
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
            let config = impact::scene_config(&scene, kind);
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

/// DGMPM one step with and without the one-point-per-cell fast path of particles→nodes.
fn fast_path(c: &mut Criterion) {
    let mut group = c.benchmark_group("fast_path");
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    group.sample_size(20);
    let mut bar = Scene::builtin("bar").expect("shipped scene");
    bar.domain.cells = vec![150_000];
    let bar_problem = Problem::<1>::from_scene(&bar).expect("valid scene");
    for fast in [false, true] {
        let config = impact::scene_config(&bar, MethodKind::Dgmpm);
        let mut m = impact_dgmpm::Dgmpm::<1>::new(&bar_problem, config).expect("valid method");
        m.solver.set_single_point_fast_path(fast);
        let dt = impact_core::Method::stable_dt(&m);
        group.throughput(Throughput::Elements(150_000));
        let mut t = 0.0;
        let id = if fast { "on" } else { "off" };
        group.bench_with_input(BenchmarkId::new("bar_150000", id), &fast, |b, _| {
            b.iter(|| {
                impact_core::Method::step(&mut m, t, dt);
                t += dt;
            })
        });
    }
    group.finish();
}

criterion_group!(benches, step, plate_step, fast_path);
criterion_main!(benches);

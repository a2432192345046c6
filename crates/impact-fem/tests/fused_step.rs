//! The stencil path's fused step (`Stencil::step_into`: the nodal update one layer ahead
//! of the internal force) against its two phases (`FemSolver::nodal_update`, then
//! `Stencil::accelerations_into`): the same displacement, velocity and acceleration bit
//! for bit after every step, and the same work and impulse: the bar (1D), the plane
//! wave, the partial plate impact (a prescribed velocity on part of an edge, symmetry
//! edges), strips one element wide, and in parallel (2 threads) with bands whose halo
//! layers are the neighbours' (the last band a single layer on a 60×56 mesh).
use impact_core::method::MethodKind;
use impact_core::{Method, Problem, Scene};
use impact_fem::Fem;

/// Largest difference between the fused and the two-phase run over `steps` steps, relative
/// to the largest velocity and acceleration; the loads' work and impulse must agree too.
fn difference<const D: usize>(name: &str, cells: Vec<usize>, steps: usize) -> f64 {
    difference_in::<D>(name, cells, steps, 1)
}

/// [`difference`], the fused step running in `bands` bands.
fn difference_in<const D: usize>(name: &str, cells: Vec<usize>, steps: usize, bands: usize) -> f64 {
    let mut scene = Scene::builtin(name).unwrap();
    scene.domain.cells = cells.clone();
    let problem = Problem::<D>::from_scene(&scene).unwrap();
    let mut fused = Fem::<D>::new(&problem, scene.method_config(MethodKind::Fem)).unwrap();
    assert!(fused.solver.uses_stencil());
    assert_eq!(fused.solver.fused_bands(), bands, "{name} {cells:?}");
    let mut phases = fused.clone();
    phases.solver.set_fused_step(false);
    let dt = fused.stable_dt();
    let mut worst: f64 = 0.0;
    for n in 0..steps {
        fused.step(n as f64 * dt, dt);
        phases.step(n as f64 * dt, dt);
        let (a, b) = (&fused.state, &phases.state);
        let peak =
            |field: &[impact_core::Vector<D>]| field.iter().map(|x| x.amax()).fold(0.0, f64::max);
        let (scale_v, scale_a) = (peak(&b.velocity_half), peak(&b.acceleration));
        let scale_u = peak(&b.displacement);
        let fields = [
            (&a.displacement, &b.displacement, scale_u),
            (&a.velocity_half, &b.velocity_half, scale_v),
            (&a.acceleration, &b.acceleration, scale_a),
        ];
        for (x, y, scale) in fields {
            for (p, q) in x.iter().zip(y) {
                worst = worst.max((p - q).amax() / scale.max(f64::MIN_POSITIVE));
            }
        }
        assert_eq!(a.work, b.work, "{name}: work");
        assert_eq!(a.impulse, b.impulse, "{name}: impulse");
    }
    let peak_v = fused.state.velocity_half.iter().map(|v| v.amax());
    assert!(
        peak_v.fold(0.0, f64::max) > 0.1,
        "{name}: the wave must be there"
    );
    println!("{name} {cells:?}: largest relative difference {worst:.1e}");
    worst
}

#[test]
fn the_fused_step_equals_the_two_phases() {
    let cases: [(&str, Vec<usize>); 5] = [
        ("plate-wave", vec![40, 30]),
        ("plate", vec![40, 30]),
        ("plate-wave", vec![6, 1]),
        ("plate-wave", vec![1, 4]),
        ("plate", vec![4, 3]),
    ];
    for (name, cells) in cases {
        assert_eq!(difference::<2>(name, cells, 40), 0.0);
    }
    // 2,001 nodes: slabs of 512 nodes, the last one shorter
    assert_eq!(difference::<1>("bar", vec![2000], 200), 0.0);
}

#[test]
fn the_fused_step_equals_the_two_phases_in_parallel_bands() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        // 61 layers in bands of 8; 57 layers: the last band holds one layer
        for (cells, bands) in [(vec![100, 60], 8), (vec![80, 56], 8)] {
            assert_eq!(difference_in::<2>("plate", cells, 30, bands), 0.0);
        }
        assert_eq!(difference_in::<1>("bar", vec![5000], 60, 8), 0.0);
    });
}

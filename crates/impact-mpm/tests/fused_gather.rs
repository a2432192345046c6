//! USL's fused gather (phases 3 and 5 in one pass over each point's nodes) equals the
//! separate phases to 1e-13, step after step: the plate and the bar with linear hats,
//! GIMP, the quadratic (also at two points per axis: its 9-node instance through the table
//! of rows) and the cubic B-spline, the updated Lagrangian frame, two points per axis, and
//! J2.
//! One shared row of weights (total Lagrangian, one point per cell) equals a row per point.
use impact_core::method::{MethodConfig, MethodKind, MpmFrame, MpmShape};
use impact_core::{Method, Problem, Scene};
use impact_mpm::Mpm;

/// Largest difference between the fused and the separate run after 60 steps
/// (`MaterialPoints::difference`).
fn difference<const D: usize>(scene: &Scene, edit: impl Fn(&mut MethodConfig)) -> f64 {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    edit(&mut config);
    let mut fused = Mpm::<D>::new(&problem, config).unwrap();
    let mut separate = fused.clone();
    separate.solver.set_fused_gather(false);
    let dt = fused.stable_dt();
    for n in 0..60 {
        fused.step(n as f64 * dt, dt);
        separate.step(n as f64 * dt, dt);
    }
    let (a, b) = (&fused.state.points, &separate.state.points);
    let (scale_s, scale_v) = b.peaks();
    assert!(
        scale_s > 1e6 && scale_v > 0.1,
        "{}: the wave must be there",
        scene.name
    );
    a.difference(b)
}

fn check<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    let worst = difference::<D>(scene, edit);
    println!("{label}: {worst:.1e}");
    assert!(
        worst <= 1e-13,
        "{label}: fused and separate gathers differ by {worst:e}"
    );
}

#[test]
fn fused_gather_matches_the_separate_phases() {
    let mut plate = Scene::builtin("plate").unwrap();
    plate.domain.cells = vec![40, 30];
    check::<2>("plate, hats", &plate, |_| {});
    for shape in [MpmShape::Gimp, MpmShape::Bspline2, MpmShape::Bspline3] {
        check::<2>(&format!("plate, {shape:?}"), &plate, |c| {
            c.mpm_mut().unwrap().shape = shape
        });
    }
    check::<2>("plate, updated Lagrangian", &plate, |c| {
        c.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian
    });
    check::<2>("plate, 4 points per cell", &plate, |c| {
        c.points_per_cell = 4
    });
    // the table of distinct rows read by the 9-node instance of the fused gather
    check::<2>("plate, Bspline2, 4 points per cell", &plate, |c| {
        c.points_per_cell = 4;
        c.mpm_mut().unwrap().shape = MpmShape::Bspline2;
    });
    let mut bar = Scene::builtin("bar").unwrap();
    bar.domain.cells = vec![300];
    check::<1>("bar, hats", &bar, |_| {});
    let mut plastic = Scene::builtin("ep-plate").unwrap();
    plastic.domain.cells = vec![40, 30];
    check::<2>("ep-plate (J2)", &plastic, |_| {});
}

/// Total Lagrangian with one point per cell stores one row of weights for every point
/// (the same local position in every cell); the run equals one with a row per point to
/// 1e-12 (the rows agree to 1e-12 of their size). More points per cell, or the updated
/// Lagrangian frame, keep a row per point.
#[test]
fn one_shared_row_of_weights_equals_a_row_per_point() {
    let mut plate = Scene::builtin("plate").unwrap();
    plate.domain.cells = vec![40, 30];
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Mpm);
    let mut shared = Mpm::<2>::new(&problem, config).unwrap();
    assert!(shared.solver.shares_weights());
    let mut per_point = shared.clone();
    per_point.solver.unshare_weights(&per_point.state.points);
    assert!(!per_point.solver.shares_weights());
    let dt = shared.stable_dt();
    for n in 0..60 {
        shared.step(n as f64 * dt, dt);
        per_point.step(n as f64 * dt, dt);
    }
    let (a, b) = (&shared.state.points, &per_point.state.points);
    let worst = a.difference(b);
    println!("shared row against a row per point: {worst:.1e}");
    assert!(b.peaks().0 > 1e6 && worst <= 1e-12, "{worst:e}");
    for edit in [
        |c: &mut MethodConfig| c.points_per_cell = 4,
        |c: &mut MethodConfig| c.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian,
    ] {
        let mut config = plate.method_config(MethodKind::Mpm);
        edit(&mut config);
        assert!(!Mpm::<2>::new(&problem, config)
            .unwrap()
            .solver
            .shares_weights());
    }
}

//! The total Lagrangian weights stored once per distinct row (a table and a row index per
//! point, `weights.rs`) give the run of a row per point bit for bit, step after step: the
//! plate at 4 points per cell with hats, GIMP, quadratic B-splines and CPDI, APIC and MUSL,
//! and the 3D block at 8 points per cell with quadratic B-splines.
use impact_core::method::{MethodConfig, MethodKind, MpmShape, MpmTransfer, StressUpdate};
use impact_core::{Method, Problem, Scene};
use impact_mpm::Mpm;

/// The run with the table against the same run with a row per point, after 40 steps:
/// their points' positions, velocities, stresses, volumes, deformation gradients and CPDI
/// domains equal exactly (`==`); the table holds fewer rows than there are points.
fn check<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    edit(&mut config);
    let mut table = Mpm::<D>::new(&problem, config).unwrap();
    let (rows, indexed) = table.solver.weight_rows();
    let count = table.state.points.len();
    println!("{label}: {rows} rows for {count} points");
    assert!(indexed && rows < count / 10, "{label}: {rows} rows");
    let mut per_point = table.clone();
    per_point.solver.unshare_weights(&per_point.state.points);
    assert_eq!(per_point.solver.weight_rows(), (count, false));
    let dt = table.stable_dt();
    for n in 0..40 {
        table.step(n as f64 * dt, dt);
        per_point.step(n as f64 * dt, dt);
    }
    let (a, b) = (&table.state.points, &per_point.state.points);
    assert!(b.peaks().0 > 1e6, "{label}: the wave must be there");
    let same = a.position == b.position
        && a.velocity == b.velocity
        && a.stress == b.stress
        && a.volume == b.volume
        && a.deformation == b.deformation
        && a.domain == b.domain;
    assert!(same, "{label}: differs by {:e}", a.difference(b));
    assert!(
        table.state.affine == per_point.state.affine,
        "{label}: APIC's C_p"
    );
}

#[test]
fn a_table_of_distinct_rows_equals_a_row_per_point() {
    let mut plate = Scene::builtin("plate").unwrap();
    plate.domain.cells = vec![40, 30];
    let four = |shape: MpmShape| {
        move |c: &mut MethodConfig| {
            c.points_per_cell = 4;
            c.mpm_mut().unwrap().shape = shape;
        }
    };
    check::<2>("plate, hats", &plate, four(MpmShape::Linear));
    check::<2>("plate, GIMP", &plate, four(MpmShape::Gimp));
    check::<2>("plate, B-splines", &plate, four(MpmShape::Bspline2));
    check::<2>("plate, CPDI", &plate, four(MpmShape::Cpdi));
    check::<2>("plate, B-splines, APIC", &plate, |c| {
        four(MpmShape::Bspline2)(c);
        c.mpm_mut().unwrap().transfer = MpmTransfer::Apic;
    });
    check::<2>("plate, B-splines, MUSL", &plate, |c| {
        four(MpmShape::Bspline2)(c);
        c.mpm_mut().unwrap().stress_update = StressUpdate::Musl;
    });
    let mut block = Scene::builtin("block-wave").unwrap();
    block.domain.cells = vec![12, 4, 4];
    check::<3>("block, B-splines, 8 a cell", &block, |c| {
        c.points_per_cell = 8;
        c.mpm_mut().unwrap().shape = MpmShape::Bspline2;
    });
}

//! The table of distinct rows of weights (`weights.rs`) against a row evaluated per point.
use crate::Mpm;
use impact_core::method::{MethodKind, MpmShape};
use impact_core::{Problem, Scene};

/// MPM on the plate (40 × 30 cells) with 4 points per cell and `shape`.
fn plate(shape: MpmShape) -> Mpm<2> {
    let mut scene = Scene::builtin("plate").unwrap();
    scene.domain.cells = vec![40, 30];
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    config.points_per_cell = 4;
    config.mpm_mut().unwrap().shape = shape;
    Mpm::<2>::new(&problem, config).unwrap()
}

/// Every point's row read through `table`'s storage equals, bit for bit, the row
/// `update_shapes` evaluates for that point alone (a row per point), and so does its base
/// node. Returns the rows the table holds.
fn assert_rows_per_point(table: &Mpm<2>) -> usize {
    let mut per_point = table.clone();
    per_point.solver.unshare_weights(&per_point.state.points);
    per_point.solver.update_shapes(&per_point.state.points);
    let (a, b) = (&table.solver, &per_point.solver);
    let nodes = a.stencil.nodes;
    let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let gradient_bits = |g: &[impact_core::Vector<2>]| {
        g.iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .collect::<Vec<_>>()
    };
    for p in 0..table.state.points.len() {
        let (ra, rb) = (a.weight_row_start(p), b.weight_row_start(p));
        assert_eq!(a.point_base[p], b.point_base[p], "point {p}");
        let (sa, sb) = (&a.shape[ra..ra + nodes], &b.shape[rb..rb + nodes]);
        assert_eq!(bits(sa), bits(sb), "point {p}'s values");
        let (ga, gb) = (
            &a.shape_gradient[ra..ra + nodes],
            &b.shape_gradient[rb..rb + nodes],
        );
        assert_eq!(
            gradient_bits(ga),
            gradient_bits(gb),
            "point {p}'s gradients"
        );
    }
    a.weight_rows().0
}

/// A uniform seeding (4 points per cell): few distinct rows (the local positions differ in
/// their last bits from cell to cell, so more than 4), read through the index,
/// each point's exactly.
#[test]
fn the_table_holds_each_points_row_on_a_uniform_seeding() {
    for shape in [
        MpmShape::Bspline2,
        MpmShape::Linear,
        MpmShape::Gimp,
        MpmShape::Cpdi,
    ] {
        let mpm = plate(shape);
        let (rows, indexed) = mpm.solver.weight_rows();
        let count = mpm.state.points.len();
        println!("{shape:?}: {rows} rows for {count} points");
        assert!(indexed && rows < count / 10, "{shape:?}: {rows} rows");
        assert_eq!(assert_rows_per_point(&mpm), rows);
    }
}

/// An irregular seeding (each point moved by its own fraction of a cell, some points by
/// the same): the table holds each point's row exactly, however many rows that takes.
#[test]
fn the_table_holds_each_points_row_on_a_jittered_seeding() {
    let mut mpm = plate(MpmShape::Bspline2);
    let h = mpm.solver.grid.spacing;
    let points = &mut mpm.state.points;
    for (p, x) in points.reference.iter_mut().enumerate() {
        // a quarter of the points stay (their rows repeat); the others move by their own
        // fraction of a cell, up to 0.19 h per axis
        let shift = if p % 4 == 0 {
            0.0
        } else {
            ((p * 7919) % 97) as f64 * 0.002
        };
        x[0] += shift * h[0];
        x[1] -= 0.5 * shift * h[1];
    }
    let points = mpm.state.points.clone();
    assert!(mpm.solver.tabulate_weights(&points));
    mpm.solver.sort_by_layer();
    let rows = assert_rows_per_point(&mpm);
    println!("jittered: {rows} rows for {} points", points.len());
    assert!(
        mpm.solver.weight_rows().1,
        "some rows repeat: the index is kept"
    );
    assert!(rows > points.len() / 4, "the jitter must give more rows");
}

//! The fused cell path ([`StepPath::Fused`]) equals the phase-by-phase cell path
//! ([`StepPath::Cell`]) to 1e-13, step after step: the bar (Courant 1 and 0.6), the plate
//! with its partial impactor (CTU and donor-cell, both edge treatments, a segment end
//! cutting a face under `cover = "fraction"`), the plane wave with symmetry edges, a
//! pressure load with a ramp, and J2 with the elastic solver. The 2D grids have more rows
//! than a band, with a short last band, so band edges are crossed; serial and parallel.
use impact_core::method::{
    EdgeKind, EdgeTreatment, LoadShape, MethodConfig, MethodKind, SegmentCover, TransverseFlux,
};
use impact_core::scene::EdgeSpec;
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};

/// Largest difference between the two runs after `steps` steps, relative to each field's
/// peak (positions absolute, in m), and the work and impulse differences relative to
/// their size.
fn compare<const D: usize>(
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    steps: usize,
    wave: bool,
) -> (f64, f64) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    let mut fused = Dgmpm::<D>::new(&problem, config).unwrap();
    assert_eq!(fused.solver.step_path(), StepPath::Fused, "{}", scene.name);
    let mut cell = fused.clone();
    cell.solver
        .set_step_path(StepPath::Cell, &cell.state.points)
        .unwrap();
    let dt = fused.stable_dt();
    for n in 0..steps {
        fused.step(n as f64 * dt, dt);
        cell.step(n as f64 * dt, dt);
    }
    let (a, b) = (&fused.state.points, &cell.state.points);
    let (scale_s, scale_v) = b.peaks();
    // `wave`: a wave of the load's size; otherwise at least some stress and motion
    let (least_s, least_v) = if wave { (1e6, 0.1) } else { (0.0, 0.0) };
    assert!(
        scale_s > least_s && scale_v > least_v,
        "{}: the wave must be there",
        scene.name
    );
    let worst = a.difference(b);
    let (wa, wb) = (fused.external_work(), cell.external_work());
    let (ia, ib) = (fused.external_impulse(), cell.external_impulse());
    let budget = (wa - wb).abs() / wb.abs().max(f64::MIN_POSITIVE);
    let impulse = (ia - ib).norm() / ib.norm().max(f64::MIN_POSITIVE);
    (worst, budget.max(impulse))
}

fn check<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    let (worst, budget) = compare::<D>(scene, edit, 60, true);
    println!("{label}: state {worst:.1e}, work and impulse {budget:.1e}");
    assert!(worst <= 1e-13, "{label}: state differs by {worst:e}");
    assert!(
        budget <= 1e-13,
        "{label}: work or impulse differs by {budget:e}"
    );
}

fn plate(cells: [usize; 2]) -> Scene {
    let mut scene = Scene::builtin("plate").unwrap();
    scene.domain.cells = cells.to_vec();
    scene
}

#[test]
fn fused_bar_matches_the_cell_path() {
    let mut bar = Scene::builtin("bar").unwrap();
    bar.domain.cells = vec![5000];
    check::<1>("bar, Courant 1", &bar, |_| {});
    check::<1>("bar, Courant 0.6", &bar, |c| c.courant = 0.6);
    // a short bar: one chunk, both ends in it
    let mut short = Scene::builtin("bar").unwrap();
    short.domain.cells = vec![50];
    check::<1>("bar, 50 cells", &short, |c| c.courant = 0.8);
}

#[test]
fn fused_plate_matches_the_cell_path() {
    // 75 rows: two full bands and a short one
    let scene = plate([30, 75]);
    for flux in [TransverseFlux::Ctu, TransverseFlux::DonorCell] {
        for edges in [EdgeTreatment::Restricted, EdgeTreatment::Ghost] {
            let label = format!("plate {flux:?} {edges:?}");
            check::<2>(&label, &scene, |c| {
                let o = c.dgmpm_mut().unwrap();
                (o.flux, o.edges) = (flux, edges);
                c.courant = if flux == TransverseFlux::Ctu {
                    1.0
                } else {
                    0.5
                };
            });
        }
    }
    // a segment end that cuts a face, its load shared by the covered fraction
    let mut cut = plate([30, 75]);
    let left = cut.boundary.left.as_mut().unwrap();
    (left.to, left.cover) = (Some(1.03), Some(SegmentCover::Fraction));
    check::<2>("plate, fractional cover", &cut, |c| c.courant = 0.9);
    // more than 4,096 cells: the bands run on rayon's pool
    check::<2>("plate 80x90, parallel", &plate([80, 90]), |_| {});
}

/// Grids one or two cells wide, where every face row or column is a boundary.
#[test]
fn fused_tiny_grids_match_the_cell_path() {
    for cells in [[1, 1], [1, 6], [6, 1], [2, 2], [3, 33]] {
        let mut scene = Scene::builtin("plate-wave").unwrap();
        scene.domain.cells = cells.to_vec();
        let (worst, budget) = compare::<2>(&scene, |c| c.courant = 0.9, 20, false);
        println!("plate-wave {cells:?}: state {worst:.1e}, work and impulse {budget:.1e}");
        assert!(
            worst <= 1e-13 && budget <= 1e-13,
            "{cells:?}: {worst:e} {budget:e}"
        );
    }
}

#[test]
fn fused_plane_wave_pressure_and_plasticity_match_the_cell_path() {
    let mut wave = Scene::builtin("plate-wave").unwrap();
    wave.domain.cells = vec![24, 40];
    check::<2>("plate-wave", &wave, |c| c.courant = 0.9);
    // a ramped pressure on the top edge and on the right edge's upper part
    let mut pressure = plate([20, 70]);
    let load = |from: Option<f64>| EdgeSpec {
        kind: EdgeKind::Pressure,
        value: Some(1e8),
        from,
        to: None,
        cover: None,
        history: Some(LoadShape::Ramp),
        duration: Some(2e-5),
    };
    pressure.boundary.top = Some(load(None));
    pressure.boundary.right = Some(load(Some(2.0)));
    check::<2>("plate, pressure", &pressure, |c| c.courant = 0.8);
    let mut plastic = Scene::builtin("ep-plate").unwrap();
    plastic.domain.cells = vec![24, 40];
    check::<2>("ep-plate, elastic solver", &plastic, |_| {});
}

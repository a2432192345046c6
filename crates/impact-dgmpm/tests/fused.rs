//! The fused cell path ([`StepPath::Fused`]) equals the phase-by-phase cell path
//! ([`StepPath::Cell`]) to 1e-13, step after step: the bar (Courant 1 and 0.6), the plate
//! with its partial impactor (CTU and donor-cell, both edge treatments, a segment end
//! cutting a face under `cover = "fraction"`), the plane wave with symmetry edges, a
//! pressure load with a ramp, and J2 with the elastic solver. The 2D grids have more rows
//! than a band, with a short last band, so band edges are crossed; serial and parallel.
//!
//! The fused nodal sweep ([`StepPath::FusedNodal`]) equals the phase-by-phase nodal paths
//! ([`StepPath::SinglePoint`] at one point per cell, [`StepPath::Nodal`] otherwise) to
//! 1e-13 on the same scenes with RK2, several points per cell and the increment update
//! (with forward Euler, whose one stage also runs phase 5, and with RK2). RK2 at one point
//! per cell runs the Heun cell sweeps (`fused/heun.rs`, asserted), agreeing to round-off.
use impact_core::method::{
    EdgeKind, EdgeTreatment, Integrator, LoadShape, MethodConfig, MethodKind, PointUpdate,
    SegmentCover, TransverseFlux,
};
use impact_core::scene::EdgeSpec;
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};

/// Largest difference between the two runs after `steps` steps, relative to each field's
/// peak (positions absolute, in m), and the work and impulse differences relative to
/// their size; then the largest difference with the stress relative to the larger of its
/// peak and `Z_p |v|_peak` (the stress the peak velocity carries in a wave, the size of
/// the terms whose round-off the paths share out differently: `tiny` below).
/// `[fused, reference]`: the path the configuration takes by default and the one it is
/// compared with.
fn compare<const D: usize>(
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    steps: usize,
    wave: bool,
    [fused_path, reference]: [StepPath; 2],
) -> (f64, f64, f64) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    let rk2_single =
        config.points_per_cell == 1 && config.dgmpm().unwrap().integrator == Integrator::Rk2;
    let mut fused = Dgmpm::<D>::new(&problem, config).unwrap();
    assert_eq!(fused.solver.step_path(), fused_path, "{}", scene.name);
    // RK2 at one point per cell (points at the cells' centres): the Heun cell sweeps
    assert_eq!(fused.solver.heun_cells(), rk2_single, "{}", scene.name);
    let mut cell = fused.clone();
    cell.solver
        .set_step_path(reference, &cell.state.points)
        .unwrap();
    run_both(&mut fused, &mut cell, steps);
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
    let (impedance, _) = problem.material.impedances::<D>();
    let stress_scale = scale_s.max(impedance * scale_v);
    let in_wave_units = (0..a.len()).fold(0.0_f64, |worst, i| {
        let stress = (a.stress[i] - b.stress[i]).amax() / stress_scale;
        let velocity = (a.velocity[i] - b.velocity[i]).amax() / scale_v;
        let position = (a.position[i] - b.position[i]).amax();
        let volume = (a.volume[i] - b.volume[i]).abs() / b.volume[i];
        worst.max(stress).max(velocity).max(position).max(volume)
    });
    let (wa, wb) = (fused.external_work(), cell.external_work());
    let (ia, ib) = (fused.external_impulse(), cell.external_impulse());
    let budget = (wa - wb).abs() / wb.abs().max(f64::MIN_POSITIVE);
    let impulse = (ia - ib).norm() / ib.norm().max(f64::MIN_POSITIVE);
    (worst, budget.max(impulse), in_wave_units)
}

/// `steps` steps of both runs with the first one's stable step.
fn run_both<const D: usize>(first: &mut Dgmpm<D>, second: &mut Dgmpm<D>, steps: usize) {
    let dt = first.stable_dt();
    for n in 0..steps {
        first.step(n as f64 * dt, dt);
        second.step(n as f64 * dt, dt);
    }
}

fn check<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    check_paths::<D>(label, scene, edit, [StepPath::Fused, StepPath::Cell]);
}

fn check_paths<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    paths: [StepPath; 2],
) {
    let (worst, budget, _) = compare::<D>(scene, edit, 60, true, paths);
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
    (left.to, left.cover) = (
        Some(impact_core::scene::Coordinates::One(1.03)),
        Some(SegmentCover::Fraction),
    );
    check::<2>("plate, fractional cover", &cut, |c| c.courant = 0.9);
    // more than 4,096 cells: the bands run on rayon's pool
    check::<2>("plate 80x90, parallel", &plate([80, 90]), |_| {});
}

/// Grids one or two cells wide, where every face row or column is a boundary: both fused
/// sweeps (forward Euler: the cell path's; RK2: the Heun cell sweeps, `fused/heun.rs`). The stress is compared relative to the larger of its
/// peak and `Z_p |v|_peak`: on the 1×1 grid the stress peak (2.8e5 Pa) is 800 times less
/// than `Z_p |v|_peak`, the size of the nodal volume terms `C : sym(V v_h ⊗ ∇S_i)` that the
/// phase path adds up and that cancel exactly in the cell update (`Σ_i ∇S_i = 0`), so the
/// two differ by their round-off, 1.6e-13 of that small peak (2e-16 of `Z_p |v|_peak`).
#[test]
fn fused_tiny_grids_match_the_phase_paths() {
    let runs = [
        (Integrator::Euler, [StepPath::Fused, StepPath::Cell], 0.9),
        (
            Integrator::Rk2,
            [StepPath::FusedNodal, StepPath::SinglePoint],
            0.7,
        ),
    ];
    for (integrator, paths, courant) in runs {
        for cells in [[1, 1], [1, 6], [6, 1], [2, 2], [3, 33]] {
            let mut scene = Scene::builtin("plate-wave").unwrap();
            scene.domain.cells = cells.to_vec();
            let edit = |c: &mut MethodConfig| {
                c.dgmpm_mut().unwrap().integrator = integrator;
                c.courant = courant;
            };
            let (worst, budget, in_wave_units) = compare::<2>(&scene, edit, 20, false, paths);
            println!("plate-wave {integrator:?} {cells:?}: state {worst:.1e} ({in_wave_units:.1e} in wave units), work and impulse {budget:.1e}");
            assert!(
                in_wave_units <= 1e-13 && budget <= 1e-13,
                "{integrator:?} {cells:?}: {in_wave_units:e} {budget:e}"
            );
            if integrator == Integrator::Euler {
                assert!(worst <= 1e-13, "{cells:?}: {worst:e} relative to the peaks");
            }
        }
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
        from: from.map(impact_core::scene::Coordinates::One),
        to: None,
        cover: None,
        centre: None,
        radius: None,
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

/// RK2 or several points per cell: the configuration's default path is the fused nodal
/// sweep; compared with the phase-by-phase nodal path.
fn check_nodal<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    let reference = match config.points_per_cell {
        1 => StepPath::SinglePoint,
        _ => StepPath::Nodal,
    };
    check_paths::<D>(label, scene, edit, [StepPath::FusedNodal, reference]);
}

fn rk2(config: &mut MethodConfig, courant: f64) {
    config.dgmpm_mut().unwrap().integrator = Integrator::Rk2;
    config.courant = courant;
}

#[test]
fn fused_nodal_bar_matches_the_nodal_paths() {
    let mut bar = Scene::builtin("bar").unwrap();
    bar.domain.cells = vec![5000];
    check_nodal::<1>("bar, RK2, Courant 1", &bar, |c| rk2(c, 1.0));
    check_nodal::<1>("bar, RK2, Courant 0.6", &bar, |c| rk2(c, 0.6));
    check_nodal::<1>("bar, 4 ppc, Euler", &bar, |c| {
        (c.points_per_cell, c.courant) = (4, 0.5)
    });
    // 2^D points per cell: RK2's stage fields in the points' arrays (`fused/nodal.rs`)
    check_nodal::<1>("bar, 2 ppc, RK2", &bar, |c| {
        rk2(c, 0.8);
        c.points_per_cell = 2;
    });
    check_nodal::<1>("bar, 2 ppc, RK2, increment", &bar, |c| {
        rk2(c, 0.8);
        c.points_per_cell = 2;
        c.dgmpm_mut().unwrap().update = PointUpdate::Increment;
    });
    check_nodal::<1>("bar, 2 ppc, Euler, increment", &bar, |c| {
        (c.points_per_cell, c.courant) = (2, 0.5);
        c.dgmpm_mut().unwrap().update = PointUpdate::Increment;
    });
    let mut short = Scene::builtin("bar").unwrap();
    short.domain.cells = vec![50];
    check_nodal::<1>("bar, 50 cells, RK2", &short, |c| rk2(c, 0.8));
}

#[test]
fn fused_nodal_plate_matches_the_nodal_paths() {
    let scene = plate([30, 75]);
    for flux in [TransverseFlux::Ctu, TransverseFlux::DonorCell] {
        for edges in [EdgeTreatment::Restricted, EdgeTreatment::Ghost] {
            let label = format!("plate RK2 {flux:?} {edges:?}");
            check_nodal::<2>(&label, &scene, |c| {
                rk2(c, 0.7);
                let o = c.dgmpm_mut().unwrap();
                (o.flux, o.edges) = (flux, edges);
            });
        }
    }
    check_nodal::<2>("plate, 4 ppc, Euler CTU", &scene, |c| {
        (c.points_per_cell, c.courant) = (4, 0.6)
    });
    check_nodal::<2>("plate, 4 ppc, Euler CTU, increment", &scene, |c| {
        (c.points_per_cell, c.courant) = (4, 0.6);
        c.dgmpm_mut().unwrap().update = PointUpdate::Increment;
    });
    // 2^D points per cell: RK2's stage fields in the points' arrays (`fused/nodal.rs`)
    for flux in [TransverseFlux::Ctu, TransverseFlux::DonorCell] {
        check_nodal::<2>(&format!("plate, 4 ppc, RK2 {flux:?}"), &scene, |c| {
            rk2(c, 0.7);
            c.points_per_cell = 4;
            c.dgmpm_mut().unwrap().flux = flux;
        });
    }
    check_nodal::<2>("plate 80x90, 4 ppc, RK2, parallel", &plate([80, 90]), |c| {
        rk2(c, 0.7);
        c.points_per_cell = 4;
    });
    check_nodal::<2>("plate, 4 ppc, RK2 DCU, increment", &scene, |c| {
        rk2(c, 0.9);
        c.points_per_cell = 4;
        let o = c.dgmpm_mut().unwrap();
        (o.flux, o.update) = (TransverseFlux::DonorCell, PointUpdate::Increment);
    });
    let mut cut = plate([30, 75]);
    let left = cut.boundary.left.as_mut().unwrap();
    (left.to, left.cover) = (
        Some(impact_core::scene::Coordinates::One(1.03)),
        Some(SegmentCover::Fraction),
    );
    check_nodal::<2>("plate, fractional cover, RK2", &cut, |c| rk2(c, 0.7));
    check_nodal::<2>("plate, RK2, increment", &scene, |c| {
        rk2(c, 0.7);
        c.dgmpm_mut().unwrap().update = PointUpdate::Increment;
    });
    check_nodal::<2>("plate 80x90, RK2, parallel", &plate([80, 90]), |c| {
        rk2(c, 0.7)
    });
}

#[test]
fn fused_nodal_plane_wave_pressure_and_plasticity_match_the_nodal_paths() {
    let mut wave = Scene::builtin("plate-wave").unwrap();
    wave.domain.cells = vec![24, 40];
    check_nodal::<2>("plate-wave, RK2", &wave, |c| rk2(c, 0.7));
    let mut pressure = plate([20, 70]);
    pressure.boundary.top = Some(EdgeSpec {
        kind: EdgeKind::Pressure,
        value: Some(1e8),
        from: None,
        to: None,
        cover: None,
        centre: None,
        radius: None,
        history: Some(LoadShape::Ramp),
        duration: Some(2e-5),
    });
    check_nodal::<2>("plate, pressure, RK2", &pressure, |c| rk2(c, 0.7));
    let mut plastic = Scene::builtin("ep-plate").unwrap();
    plastic.domain.cells = vec![24, 40];
    check_nodal::<2>("ep-plate, elastic solver, RK2", &plastic, |c| rk2(c, 0.7));
}

/// RK2 at one point per cell with the points off the cells' centres (a shifted layout and
/// a given one): the Heun cell sweeps' side weights are then unequal per node (and may be
/// stored per cell where the local coordinates round differently), still equal to the
/// phase-by-phase path to round-off.
#[test]
fn heun_sweeps_off_centre_match_the_nodal_path() {
    use impact_core::options::LayoutKind;
    let mut shifted = plate([30, 75]);
    (shifted.domain.layout, shifted.domain.shift) = (Some(LayoutKind::Shifted), Some(0.3));
    check_nodal::<2>("plate, shifted 0.3, RK2 CTU", &shifted, |c| rk2(c, 0.6));
    let mut given = plate([30, 75]);
    (given.domain.layout, given.domain.positions) =
        (Some(LayoutKind::Given), Some(vec![vec![0.2, 0.7]]));
    check_nodal::<2>("plate, given (0.2, 0.7), RK2 DCU", &given, |c| {
        rk2(c, 0.5);
        c.dgmpm_mut().unwrap().flux = TransverseFlux::DonorCell;
    });
    let mut bar = Scene::builtin("bar").unwrap();
    (bar.domain.cells, bar.domain.layout, bar.domain.positions) =
        (vec![400], Some(LayoutKind::Given), Some(vec![vec![0.15]]));
    check_nodal::<1>("bar, given 0.15, RK2", &bar, |c| rk2(c, 0.6));
}

/// RK2 at one point per cell with every point moved to its own place in its cell (a
/// deterministic jitter of up to 0.35 cell widths, so no two cells share their weights):
/// the Heun cell sweeps read each cell's own block of side weights (stored once per
/// distinct cell, with an index per cell), equal to the phase-by-phase path to round-off.
/// A wrong block would be a different cell's weights, far beyond round-off.
#[test]
fn heun_sweeps_with_a_block_per_cell_match_the_nodal_path() {
    let scene = plate([24, 40]);
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    rk2(&mut config, 0.5);
    let mut fused = Dgmpm::<2>::new(&problem, config).unwrap();
    let spacing = problem.grid.spacing;
    let points = &mut fused.state.points;
    for (i, (x, reference)) in points
        .position
        .iter_mut()
        .zip(&mut points.reference)
        .enumerate()
    {
        // a fixed sequence in (-0.35, 0.35) per axis (golden-ratio steps); the weights are
        // formed at the reference positions
        let jitter = |k: usize| ((i * 2 + k) as f64 * 0.618_033_988_749_895).fract() * 0.7 - 0.35;
        for k in 0..2 {
            x[k] += jitter(k) * spacing[k];
        }
        *reference = *x;
    }
    let points = fused.state.points.clone();
    // the weights formed anew from the moved points
    fused
        .solver
        .set_step_path(StepPath::SinglePoint, &points)
        .unwrap();
    fused
        .solver
        .set_step_path(StepPath::FusedNodal, &points)
        .unwrap();
    assert!(fused.solver.heun_cells());
    let mut reference = fused.clone();
    reference
        .solver
        .set_step_path(StepPath::SinglePoint, &points)
        .unwrap();
    run_both(&mut fused, &mut reference, 60);
    let worst = fused.state.points.difference(&reference.state.points);
    assert!(
        reference.state.points.peaks().0 > 1e6,
        "the wave must be there"
    );
    println!("plate 24x40, jittered points, RK2: state {worst:.1e}");
    assert!(worst <= 1e-13, "state differs by {worst:e}");
}

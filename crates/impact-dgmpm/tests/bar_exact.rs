//! Paper §5.1 claim: with one point per cell at the centre, Courant 1 and forward Euler,
//! DGMPM is the exact upwind shift: every point equals the exact cell average.
use impact_core::exact::BarExact;
use impact_core::method::{
    DgmpmOptions, Integrator, MethodConfig, MethodOptions, RiemannSolver, TransverseFlux,
};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::{Dgmpm, StepPath};

fn config(courant: f64, ppc: usize, integrator: Integrator) -> MethodConfig {
    MethodConfig {
        courant,
        points_per_cell: ppc,
        options: MethodOptions::Dgmpm(DgmpmOptions {
            integrator,
            riemann: RiemannSolver::Exact,
            ..DgmpmOptions::default()
        }),
    }
}

#[test]
fn courant_one_single_point_is_exact_at_every_step() {
    let scene = Scene::builtin("bar").unwrap();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let m = problem.material;
    let exact = BarExact::new(6.0, m.density, m.elastic.young, 1e9);
    let mut dg = Dgmpm::new(&problem, config(1.0, 1, Integrator::Euler)).unwrap();
    let dt = dg.stable_dt();
    let dx = problem.grid.spacing[0];
    let scale_s = 1e9;
    let scale_v = 1e9 / exact.impedance;
    // 400 steps: two transits, so reflections at both ends are covered
    for n in 1..=400 {
        dg.step((n - 1) as f64 * dt, dt);
        let t = n as f64 * dt;
        let p = &dg.state.points;
        for i in 0..p.len() {
            let x = p.reference[i][0];
            let s = exact.stress_average(x - 0.5 * dx, x + 0.5 * dx, t);
            let v = exact.velocity_average(x - 0.5 * dx, x + 0.5 * dx, t);
            assert!(
                (p.stress[i][(0, 0)] - s).abs() <= 1e-10 * scale_s,
                "step {n} point {i}: σ = {} vs exact {s}",
                p.stress[i][(0, 0)]
            );
            assert!(
                (p.velocity[i][0] - v).abs() <= 1e-10 * scale_v,
                "step {n} point {i}: v"
            );
        }
    }
    // energy: the scheme is exact, so energy equals the exact work
    let t = 400.0 * dt;
    let e = dg.energy();
    assert!(
        (e - exact.work(t)).abs() < 1e-9 * exact.work(t),
        "{e} vs {}",
        exact.work(t)
    );
    assert!((dg.external_work() - exact.work(t)).abs() < 1e-9 * exact.work(t));
}

/// The one-point-per-cell fast path of particles→nodes matches the general path to 1e-14
/// (relative to the largest stress and velocity) over each step from the same state, for
/// 60 steps (bar with Euler and RK2; plate with CTU).
#[test]
fn single_point_fast_path_matches_the_general_path() {
    fn compare<const D: usize>(name: &str, integrator: Integrator) {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<D>::from_scene(&scene).unwrap();
        let mut c = config(1.0, 1, integrator);
        c.courant = 0.9;
        let mut fast = Dgmpm::<D>::new(&problem, c).unwrap();
        // the nodal phases (the cell path skips particles→nodes altogether)
        fast.solver
            .set_step_path(StepPath::SinglePoint, &fast.state.points)
            .unwrap();
        let mut general = fast.clone();
        general
            .solver
            .set_step_path(StepPath::Nodal, &general.state.points)
            .unwrap();
        let dt = fast.stable_dt();
        let mut worst: f64 = 0.0;
        for n in 0..60 {
            general.state = fast.state.clone();
            fast.step(n as f64 * dt, dt);
            general.step(n as f64 * dt, dt);
            let (a, b) = (&fast.state.points, &general.state.points);
            let scale_s = a.stress.iter().map(|s| s.abs().max()).fold(0.0, f64::max);
            let scale_v = a.velocity.iter().map(|v| v.abs().max()).fold(0.0, f64::max);
            for i in 0..a.len() {
                worst = worst.max((a.stress[i] - b.stress[i]).abs().max() / scale_s);
                worst = worst.max((a.velocity[i] - b.velocity[i]).abs().max() / scale_v);
            }
        }
        println!("{name} {integrator:?}: largest relative difference in a step {worst:.1e}");
        assert!(worst <= 1e-14, "{name} {integrator:?}: {worst:e}");
        assert!(
            fast.state.points.stress.iter().any(|s| s.abs().max() > 1e6),
            "the wave must be there"
        );
    }
    compare::<1>("bar", Integrator::Euler);
    compare::<1>("bar", Integrator::Rk2);
    compare::<2>("plate", Integrator::Euler);
}

/// The cell path (one point per cell, forward Euler: the cell-centred Godunov update)
/// equals the nodal phases 1-5 to round-off, step after step: bar, plate with CTU and with
/// donor-cell, the SVK bar in tension with the exact solver and the SVK plate.
#[test]
fn cell_path_matches_the_nodal_phases() {
    fn compare<const D: usize>(scene: Scene, flux: TransverseFlux, exact: bool) {
        let name = scene.name.clone();
        let problem = Problem::<D>::from_scene(&scene).unwrap();
        let mut c = config(0.6, 1, Integrator::Euler);
        let o = c.dgmpm_mut().unwrap();
        o.flux = flux;
        if !exact {
            o.riemann = RiemannSolver::Approximate;
        }
        let mut cell = Dgmpm::<D>::new(&problem, c).unwrap();
        // linear scenes default to the fused path (tests/fused.rs compares it with this one)
        let points = cell.state.points.clone();
        cell.solver.set_step_path(StepPath::Cell, &points).unwrap();
        assert_eq!(
            cell.solver.step_path(),
            StepPath::Cell,
            "{name}: the cell path applies"
        );
        let mut nodal = cell.clone();
        nodal
            .solver
            .set_step_path(StepPath::SinglePoint, &nodal.state.points)
            .unwrap();
        assert_eq!(nodal.solver.step_path(), StepPath::SinglePoint);
        let dt = cell.stable_dt();
        for n in 0..80 {
            cell.step(n as f64 * dt, dt);
            nodal.step(n as f64 * dt, dt);
        }
        let (a, b) = (&cell.state.points, &nodal.state.points);
        let (scale_s, scale_v) = a.peaks();
        assert!(
            scale_s > 1e6 && scale_v > 0.1,
            "{name}: the wave must be there"
        );
        let worst = b.difference(a);
        println!("{name} {flux:?}: largest relative difference {worst:.1e}");
        assert!(worst <= 1e-12, "{name} {flux:?}: {worst:e}");
        let (wa, wb) = (cell.external_work(), nodal.external_work());
        assert!(
            (wa - wb).abs() <= 1e-12 * wa.abs(),
            "{name}: work {wa} vs {wb}"
        );
        let (ia, ib) = (cell.external_impulse(), nodal.external_impulse());
        assert!((ia - ib).norm() <= 1e-12 * ia.norm(), "{name}: impulse");
    }
    let builtin = |name: &str| Scene::builtin(name).unwrap();
    compare::<1>(builtin("bar"), TransverseFlux::DonorCell, true);
    compare::<2>(builtin("plate"), TransverseFlux::Ctu, true);
    compare::<2>(builtin("plate"), TransverseFlux::DonorCell, true);
    let mut tension = builtin("svk-bar");
    if let Some(edge) = tension.boundary.left.as_mut() {
        edge.value = Some(-8e8);
    }
    compare::<1>(tension, TransverseFlux::DonorCell, true);
    compare::<2>(builtin("svk-plate"), TransverseFlux::DonorCell, false);
}

//! Paper §5.1 claim: with one point per cell at the centre, Courant 1 and forward Euler,
//! DGMPM is the exact upwind shift: every point equals the exact cell average.
use impact_core::exact::BarExact;
use impact_core::method::{
    Integrator, MethodConfig, MethodKind, MpmFrame, PointUpdate, StressUpdate, TransverseFlux,
};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::Dgmpm;

fn config(courant: f64, ppc: usize, integrator: Integrator) -> MethodConfig {
    MethodConfig {
        kind: MethodKind::Dgmpm,
        courant,
        points_per_cell: ppc,
        integrator,
        update: PointUpdate::Nodal,
        stress_update: StressUpdate::Usl,
        frame: MpmFrame::TotalLagrangian,
        flux: TransverseFlux::Ctu,
        riemann: impact_core::method::RiemannSolver::Exact,
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
/// (bar with Euler and RK2; plate with CTU), step after step.
#[test]
fn single_point_fast_path_matches_the_general_path() {
    fn compare<const D: usize>(name: &str, integrator: Integrator) {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<D>::from_scene(&scene).unwrap();
        let mut c = config(1.0, 1, integrator);
        c.courant = 0.9;
        let mut fast = Dgmpm::<D>::new(&problem, c).unwrap();
        let mut general = fast.clone();
        general.solver.set_single_point_fast_path(false);
        let dt = fast.stable_dt();
        let scale_s = 1e8;
        for n in 0..60 {
            fast.step(n as f64 * dt, dt);
            general.step(n as f64 * dt, dt);
        }
        let (a, b) = (&fast.state.points, &general.state.points);
        let mut worst: f64 = 0.0;
        for i in 0..a.len() {
            worst = worst.max((a.stress[i] - b.stress[i]).abs().max() / scale_s);
            worst = worst.max((a.velocity[i] - b.velocity[i]).abs().max() / 5.0);
        }
        assert!(worst <= 1e-14, "{name} {integrator:?}: {worst:e}");
        assert!(
            a.stress.iter().any(|s| s.abs().max() > 1e6),
            "the wave must be there"
        );
    }
    compare::<1>("bar", Integrator::Euler);
    compare::<1>("bar", Integrator::Rk2);
    compare::<2>("plate", Integrator::Euler);
}

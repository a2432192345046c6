//! Paper §5.1 (elastic bar) claims and exactness properties, across the three methods.
use crate::common::*;
use impact_core::controller::{self, Guard};
use impact_core::method::{Integrator, MethodKind, PointUpdate, Samples};
use impact_core::Method;

/// DGMPM, 1 point per cell, Courant 1, Euler: every point equals the exact cell average at
/// the default output times (before and after the reflection), reached by the controller.
#[test]
fn dgmpm_single_point_courant_one_is_exact_at_default_output_times() {
    let (scene, problem, reference) = bar(150, None);
    let impact_core::reference::Reference::Bar(exact) = reference else {
        panic!("the bar has an exact solution")
    };
    let mut dg = impact::build(&problem, scene.method_config(MethodKind::Dgmpm)).unwrap();
    let dx = problem.grid.spacing[0];
    let mut samples = Samples::<1>::default();
    let mut checked = 0;
    controller::run::<1, dyn Method<1>, String>(
        dg.as_mut(),
        &problem.output_times,
        Guard::default(),
        |m, _, t, steps| {
            assert_eq!(
                steps,
                (t / problem.cell_transit_time()).round() as usize,
                "whole Courant-1 steps"
            );
            m.sample_into(&mut samples);
            for i in 0..samples.len() {
                let x = samples.reference[i][0];
                let s = exact.stress_average(x - dx / 2.0, x + dx / 2.0, t);
                let v = exact.velocity_average(x - dx / 2.0, x + dx / 2.0, t);
                assert!(
                    (samples.stress[i][(0, 0)] - s).abs() <= 1e-10 * 1e9,
                    "t={t} x={x}"
                );
                assert!((samples.velocity[i][0] - v).abs() <= 1e-10 * 1e9 / exact.impedance);
            }
            checked += 1;
            Ok(())
        },
        |_| {},
    )
    .unwrap();
    assert_eq!(checked, 3);
    // the last output time lies after the reflection from the free end
    assert!(problem.output_times[2] * exact.speed > 6.0);
}

/// Paper §5.1: "This property is lost with more points in each cell but it can be improved
/// by using a Runge-Kutta 2 time integrator." With 2 points per cell, Euler at Courant 1
/// is stopped by the guard; RK2 at Courant 1 is stable (and here exact again).
#[test]
fn more_points_per_cell_lose_courant_one_with_euler_and_rk2_restores_it() {
    let (scene, problem, reference) = bar(150, None);
    for ppc in [2, 3, 4] {
        let (_, err) = run(
            &problem,
            dgmpm(&scene, 1.0, ppc, Integrator::Euler),
            &reference,
        );
        let err = err.expect("Euler at Courant 1 with several points per cell must blow up");
        assert_eq!(err.method, "dgmpm");
        let (rec, err) = run(
            &problem,
            dgmpm(&scene, 1.0, ppc, Integrator::Rk2),
            &reference,
        );
        assert!(err.is_none(), "RK2 at Courant 1, {ppc} ppc: {err:?}");
        for t in &rec.times {
            assert!(t.l1 < 1e-10, "RK2 {ppc} ppc at t={}: L1 {}", t.t, t.l1);
        }
    }
}

/// The default point update (`Nodal`) against `Increment`: with 2 points per cell, Euler,
/// Courant 0.5, the nodal update is monotone (no overshoot) while adding the increment
/// leaves undamped sub-cell modes that overshoot the plateau by more than 50 %.
#[test]
fn nodal_point_update_is_monotone_where_increment_overshoots() {
    let (scene, problem, reference) = bar(150, None);
    let nodal = dgmpm(&scene, 0.5, 2, Integrator::Euler);
    let mut increment = nodal;
    increment.dgmpm_mut().unwrap().update = PointUpdate::Increment;
    let (rec, err) = run(&problem, nodal, &reference);
    assert!(err.is_none());
    for t in &rec.times {
        assert!(
            t.overshoot_pct.unwrap() < 1.0,
            "nodal overshoot {:?}",
            t.overshoot_pct
        );
    }
    let (rec, err) = run(&problem, increment, &reference);
    let worst = rec
        .times
        .iter()
        .filter_map(|t| t.overshoot_pct)
        .fold(0.0, f64::max);
    assert!(err.is_some() || worst > 50.0, "increment overshoot {worst}");
}

/// Central differences with lumped mass on a uniform mesh at Courant 1 reproduce the
/// exact nodal displacements (d'Alembert sampled on the grid), with the half-step start.
#[test]
fn fem_courant_one_reproduces_exact_nodal_displacements() {
    let (scene, problem, reference) = bar(150, None);
    let impact_core::reference::Reference::Bar(exact) = reference else {
        panic!("the bar has an exact solution")
    };
    let cfg = config(&scene, MethodKind::Fem, |c| c.courant = 1.0);
    let mut fem = impact_fem::Fem::new(&problem, cfg).unwrap();
    let dt = fem.stable_dt();
    let steps = (problem.output_times[2] / dt).round() as usize;
    let mut checked = 0;
    for n in 1..=steps {
        fem.step((n - 1) as f64 * dt, dt);
        let t = n as f64 * dt;
        let u = &fem.state.displacement;
        let scale = exact.displacement(0.0, t);
        for (i, ui) in u.iter().enumerate() {
            let x = fem.solver.grid().vertex_position(i)[0];
            let ue = exact.displacement(x, t);
            assert!(
                (ui[0] - ue).abs() <= 1e-10 * scale,
                "step {n} node {i}: {} vs {ue}",
                ui[0]
            );
        }
        checked += 1;
    }
    assert_eq!(
        checked, 200,
        "200 Courant-1 steps, past the reflection at step 150"
    );
}

/// MPM at Courant 1 is unstable: the guard stops it with method, step, time and place.
#[test]
fn mpm_courant_one_is_stopped_by_the_guard() {
    let (scene, problem, reference) = bar(150, None);
    let cfg = config(&scene, MethodKind::Mpm, |c| c.courant = 1.0);
    let (rec, err) = run(&problem, cfg, &reference);
    let err = err.expect("MPM at Courant 1 must be stopped");
    assert_eq!(err.method, "mpm");
    assert!(err.step > 0 && err.time > 0.0 && err.time <= problem.t_end);
    assert!(err.place[0] >= 0.0 && err.place[0] <= 6.0);
    assert!(rec.error.as_deref().unwrap().contains("blew up at step"));
    // every metric recorded before the blow-up is finite
    for t in &rec.times {
        assert!(t.l1.is_finite() && t.energy_error.is_finite());
    }
}

/// Energy balance: kinetic + strain energy against the exact work of the load.
/// DGMPM at Courant 1 is exact; FEM (central differences conserve a discrete energy) and
/// MPM stay within a few per cent; DGMPM below Courant 1 dissipates (upwinding).
#[test]
fn energy_against_work_of_the_load() {
    let (scene, problem, reference) = bar(150, None);
    let (dg, _) = run(&problem, scene.method_config(MethodKind::Dgmpm), &reference);
    let (fem, _) = run(&problem, scene.method_config(MethodKind::Fem), &reference);
    let (mpm, _) = run(&problem, scene.method_config(MethodKind::Mpm), &reference);
    let (diss, _) = run(
        &problem,
        dgmpm(&scene, 0.5, 1, Integrator::Euler),
        &reference,
    );
    for k in 0..3 {
        assert!(dg.times[k].energy_error.abs() < 1e-12);
        assert!(
            fem.times[k].energy_error.abs() < 5e-3,
            "fem {}",
            fem.times[k].energy_error
        );
        assert!(
            mpm.times[k].energy_error.abs() < 5e-2,
            "mpm {}",
            mpm.times[k].energy_error
        );
        assert!(
            diss.times[k].energy_error < -1e-3,
            "upwind dissipates: {}",
            diss.times[k].energy_error
        );
    }
}

/// The paper's comparison (Fig. 3): at the default settings DGMPM's front is sharper and
/// has no overshoot, MPM's front is smeared over several cells and oscillates.
#[test]
fn dgmpm_front_is_sharper_than_mpm_and_fem() {
    let (scene, problem, reference) = bar(150, None);
    let (dg, _) = run(&problem, scene.method_config(MethodKind::Dgmpm), &reference);
    let (mpm, _) = run(&problem, scene.method_config(MethodKind::Mpm), &reference);
    let (fem, _) = run(&problem, scene.method_config(MethodKind::Fem), &reference);
    for k in 0..3 {
        let w = |r: &impact::run::RunRecord| r.times[k].front_width_cells.unwrap_or(f64::INFINITY);
        assert!(
            w(&dg) < 1.0,
            "a perfect step sampled at cell centres is 0.8 cells"
        );
        assert!(w(&mpm) > 3.0 && w(&fem) > 2.0);
        assert!(dg.times[k].overshoot_pct.unwrap() < 1e-6);
        assert!(mpm.times[k].overshoot_pct.unwrap() > 10.0);
    }
}

//! Time-dependent loads (ramp, sine, pulse) against the exact bar solution with the
//! load's history, and segment coverage (`cover = "centre" | "fraction"`) by the load's
//! resultant.
use crate::common::*;
use impact_core::method::{LoadShape, MethodKind, SegmentCover};
use impact_core::metrics::observed_orders;
use impact_core::reference::Reference;
use impact_core::{Problem, Scene};

/// The paper's bar under a history pressure, `cells` cells, one output at `t`.
fn history_bar(
    cells: usize,
    shape: LoadShape,
    duration: f64,
    t: f64,
) -> (Scene, Problem<1>, Reference) {
    let mut scene = Scene::builtin("bar").unwrap();
    scene.domain.cells = vec![cells];
    let left = scene.boundary.left.as_mut().unwrap();
    left.history = Some(shape);
    left.duration = (shape != LoadShape::Step).then_some(duration);
    let mut problem = Problem::<1>::from_scene(&scene).unwrap();
    problem.set_schedule(Some(vec![t]), None).unwrap();
    let reference = Reference::for_problem(&problem).unwrap();
    (scene, problem, reference)
}

const C0: f64 = 5063.696835418333; // sqrt(2e11/7800)

/// A sine pressure of period 0.4 ms (about 2 m of wavelength on the 6 m bar, 25 cells
/// per wavelength at 150 cells) after its reflection from the free end: every method
/// converges to the exact solution, at least at first order in L1. DGMPM at Courant 1
/// (exact transport in 1D) with the load's step average at the boundary reproduces the
/// exact cell averages to round-off at every resolution.
#[test]
fn sine_load_converges_to_the_exact_bar_solution() {
    let t = 1.5 * 6.0 / C0;
    for kind in MethodKind::ALL {
        let errors: Vec<f64> = [150, 300, 600]
            .iter()
            .map(|&cells| {
                let (scene, problem, reference) = history_bar(cells, LoadShape::Sine, 0.4e-3, t);
                let (rec, blowup) = run(&problem, scene.method_config(kind), &reference);
                assert!(blowup.is_none(), "{kind}: {blowup:?}");
                rec.times[0].l1
            })
            .collect();
        let orders = observed_orders(&errors);
        println!("{kind}: sine load, L1 {errors:?}, orders {orders:.2?}");
        assert!(errors[2] < 0.05, "{kind}: L1 {errors:?}");
        if kind == MethodKind::Dgmpm {
            assert!(errors.iter().all(|&e| e < 1e-12), "{kind}: L1 {errors:?}");
            continue;
        }
        assert!(
            orders.iter().all(|&o| o > 0.8),
            "{kind}: orders {orders:?} (errors {errors:?})"
        );
    }
}

/// A finite pulse delivers the impulse `p T` (per unit area) and the energy it delivers
/// equals the work the method counts; after the pulse the work no longer grows. A ramp
/// reaches the step's solution behind its rise.
#[test]
fn pulse_impulse_and_ramp_plateau() {
    let duration = 0.2e-3;
    let t = 0.9 * 6.0 / C0;
    for kind in MethodKind::ALL {
        let (scene, problem, _) = history_bar(300, LoadShape::Pulse, duration, t);
        let mut m = impact::build(&problem, scene.method_config(kind)).unwrap();
        let dt = m.stable_dt();
        let steps = (t / dt).floor() as usize;
        for k in 0..steps {
            m.step(k as f64 * dt, dt);
        }
        let impulse = -m.external_impulse()[0];
        let momentum = -m.momentum()[0];
        let expected = -1e9 * duration;
        println!(
            "{kind}: pulse impulse {impulse:.6e} (p T = {expected:.6e}), momentum {momentum:.6e}"
        );
        assert!(
            ((impulse - expected) / expected).abs() < 0.02,
            "{kind}: impulse {impulse} against p T = {expected}"
        );
        assert!(
            ((momentum - expected) / expected).abs() < 0.02,
            "{kind}: momentum {momentum}"
        );
        let (energy, work) = (m.energy(), m.external_work());
        assert!(
            ((energy - work) / work).abs() < 0.05,
            "{kind}: energy {energy}, work {work}"
        );

        let (scene, problem, reference) = history_bar(300, LoadShape::Ramp, 0.1e-3, 0.6e-3);
        let (rec, blowup) = run(&problem, scene.method_config(kind), &reference);
        assert!(blowup.is_none());
        println!("{kind}: ramp L1 {:.3e}", rec.times[0].l1);
        assert!(
            rec.times[0].l1 < 0.05,
            "{kind}: ramp L1 {}",
            rec.times[0].l1
        );
    }
}

/// The partial plate with a pressure on `[0, 0.95]` m of the left edge (cells of 0.12 m:
/// the end cuts the eighth cell at 0.95 = 7.92 cells): under `fraction` the resultant
/// impulse is `p · 0.95 m · t` in every method; under `centre` it is `p` times the width
/// of the faces (DGMPM, MPM) or tributary lengths (FEM) the rule takes in full.
#[test]
fn segment_cover_sets_the_resultant() {
    let mut scene = Scene::builtin("plate").unwrap();
    let pressure = 1e8;
    let length = 0.95;
    let t = 4.0 * 0.12 / 6001.0; // before any wave reaches another edge
    for cover in SegmentCover::ALL {
        let left = scene.boundary.left.as_mut().unwrap();
        left.kind = impact_core::method::EdgeKind::Pressure;
        left.value = Some(pressure);
        left.to = Some(impact_core::scene::Coordinates::One(length));
        left.cover = Some(cover);
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        for kind in MethodKind::ALL {
            let mut m = impact::build(&problem, scene.method_config(kind)).unwrap();
            let dt = m.stable_dt();
            let steps = (t / dt).ceil() as usize;
            for k in 0..steps {
                m.step(k as f64 * dt, dt);
            }
            // central differences: the impulse reaches v^{n-1/2}, half a step behind
            let lag = if kind == MethodKind::Fem { 0.5 } else { 0.0 };
            let elapsed = (steps as f64 - lag) * dt;
            let force = m.external_impulse()[0] / elapsed;
            let expected = match cover {
                SegmentCover::Fraction => pressure * length,
                // faces (DGMPM, MPM points) centred at 0.06 + 0.12 k ≤ 0.95: 8 faces;
                // FEM nodes at 0.12 k ≤ 0.95 (8 nodes): 7.5 tributary widths
                SegmentCover::Centre => match kind {
                    MethodKind::Fem => pressure * 7.5 * 0.12,
                    _ => pressure * 8.0 * 0.12,
                },
            };
            println!("{cover} {kind}: resultant {force:.6e} N/m (expected {expected:.6e})");
            assert!(
                ((force - expected) / expected).abs() < 1e-9,
                "{cover} {kind}: resultant {force} against {expected}"
            );
        }
    }
}

/// Loads are integrated exactly over each step (`impact_core::load`): the impulse a
/// ramp, sine or pulse pressure delivers, `Method::external_impulse`, equals `p I(T)` to
/// 1e-12 in every method at several resolutions (step sizes unrelated to the pulse's
/// end). FEM's central differences count the impulse that reached `v^{N-1/2}`, half a
/// step behind: `p I(T - Δt/2)`; its full-step velocity (the outputs') carries the
/// momentum `p I(T)`. The momentum of every method equals `p I(T)` (free right end).
#[test]
fn history_loads_deliver_their_impulse_to_round_off() {
    let pressure = 1e9;
    for shape in LoadShape::ALL {
        let duration = 0.23e-3;
        let history = impact_core::LoadHistory::new(shape, duration);
        for cells in [800, 1000, 1200] {
            let (scene, problem, _) = history_bar(cells, shape, duration, 0.9 * 6.0 / C0);
            for kind in MethodKind::ALL {
                let mut m = impact::build(&problem, scene.method_config(kind)).unwrap();
                let dt = m.stable_dt();
                let steps = (0.9 * 6.0 / C0 / dt).floor() as usize;
                for k in 0..steps {
                    m.step(k as f64 * dt, dt);
                }
                let end = steps as f64 * dt;
                let reached = if kind == MethodKind::Fem {
                    end - 0.5 * dt
                } else {
                    end
                };
                let expected = pressure * history.integral(reached);
                let impulse = m.external_impulse()[0];
                let error = (impulse - expected).abs() / expected.abs();
                println!("{shape} {cells} {kind}: impulse error {error:.2e}");
                assert!(
                    error < 1e-12,
                    "{shape} {cells} {kind}: impulse {impulse:e} against p I(T) = {expected:e}"
                );
                // momentum of the full-step state from the samples: ρ |region| v
                let mut samples = impact_core::Samples::<1>::default();
                m.sample_into(&mut samples);
                let momentum: f64 = (0..samples.len())
                    .map(|i| 7800.0 * 2.0 * samples.half_size[i][0] * samples.velocity[i][0])
                    .sum();
                let full = pressure * history.integral(end);
                let error = (momentum - full).abs() / full.abs();
                println!("{shape} {cells} {kind}: momentum error {error:.2e}");
                assert!(
                    error < 1e-11,
                    "{shape} {cells} {kind}: momentum {momentum:e} against {full:e}"
                );
            }
        }
    }
}

/// A pulse-loaded bar converges under refinement: DGMPM at Courant 1 (exact transport in
/// 1D) takes the pulse's exact step average and matches the exact averages to round-off
/// (with the load at the step's midpoint, L1 stayed at 8.33e-4 at every resolution); at 2
/// points per cell (Courant 0.5) and for MPM and FEM the L1 error decreases.
#[test]
fn pulse_loaded_bar_converges() {
    let t = 0.9 * 6.0 / C0;
    let mut dgmpm_exact = Vec::new();
    let mut rows = Vec::new();
    for cells in [200, 400, 800] {
        let (scene, problem, reference) = history_bar(cells, LoadShape::Pulse, 0.23e-3, t);
        let (rec, _) = run(&problem, scene.method_config(MethodKind::Dgmpm), &reference);
        dgmpm_exact.push(rec.times[0].l1);
        let two = dgmpm(&scene, 0.5, 2, impact_core::method::Integrator::Euler);
        let mut row = vec![run(&problem, two, &reference).0.times[0].l1];
        for kind in [MethodKind::Mpm, MethodKind::Fem] {
            row.push(run(&problem, scene.method_config(kind), &reference).0.times[0].l1);
        }
        rows.push(row);
    }
    println!("pulse: DGMPM Courant 1 L1 {dgmpm_exact:?}; [DGMPM 2 ppc, MPM, FEM] L1 {rows:?}");
    assert!(dgmpm_exact.iter().all(|&e| e < 1e-12), "{dgmpm_exact:?}");
    for j in 0..3 {
        assert!(
            rows[1][j] < rows[0][j] && rows[2][j] < rows[1][j],
            "column {j} of {rows:?}"
        );
    }
}

/// A prescribed velocity acts at its step average too: FEM's loaded node moves by
/// `v_d I(T)` to round-off under a ramp, sine or pulse velocity, whatever the step.
#[test]
fn velocity_loads_give_the_exact_displacement() {
    for shape in [LoadShape::Ramp, LoadShape::Sine, LoadShape::Pulse] {
        let duration = 0.23e-3;
        let history = impact_core::LoadHistory::new(shape, duration);
        let mut scene = Scene::builtin("bar").unwrap();
        scene.domain.cells = vec![1000];
        let left = scene.boundary.left.as_mut().unwrap();
        left.kind = impact_core::method::EdgeKind::Velocity;
        left.value = Some(4.0);
        left.history = Some(shape);
        left.duration = Some(duration);
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        let mut fem = impact_fem::Fem::new(&problem, scene.method_config(MethodKind::Fem)).unwrap();
        let dt = impact_core::Method::stable_dt(&fem);
        let steps = (0.9 * 6.0 / C0 / dt).floor() as usize;
        for k in 0..steps {
            impact_core::Method::step(&mut fem, k as f64 * dt, dt);
        }
        let expected = 4.0 * history.integral(steps as f64 * dt);
        let u = fem.state.displacement[0][0];
        println!("{shape}: loaded node moved {u:e} (v_d I(T) = {expected:e})");
        assert!(
            (u - expected).abs() < 1e-12 * expected.abs(),
            "{shape}: {u:e} against {expected:e}"
        );
    }
}

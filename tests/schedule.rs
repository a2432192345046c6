//! The controller's schedule takes no sliver steps (`impact_core::controller`, issue 23):
//! an output time a hair past a whole number of stable steps gives the result of that
//! number of steps changed by the order of the hair, not by a sliver step's projection.
use crate::common::*;
use impact_core::controller::{self, Guard};
use impact_core::method::{Integrator, Method, Samples};

/// `σ_xx` at the points of DGMPM (2 points per cell, Courant 0.5) on the paper's bar run
/// by the controller to `t`.
fn stress_at(t: f64) -> Vec<f64> {
    let (scene, problem, _) = bar(150, Some(vec![t]));
    let mut m = impact::build(&problem, dgmpm(&scene, 0.5, 2, Integrator::Euler)).unwrap();
    let mut stress = Vec::new();
    let mut samples = Samples::<1>::default();
    controller::run::<1, dyn Method<1>, std::convert::Infallible>(
        m.as_mut(),
        &[t],
        Guard::default(),
        |m, _, _, _| {
            m.sample_into(&mut samples);
            stress = samples.stress.iter().map(|s| s[(0, 0)]).collect();
            Ok(())
        },
        |_| {},
    )
    .unwrap();
    stress
}

fn largest_change(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Moving an output time that is a whole number of steps by 1e-10 (relative) changes the
/// 2-point-per-cell DGMPM stress by O(1e-10) of the load (1e9 Pa); a sliver step of that
/// size, as the schedule took before, changes it by about 1e-2.
#[test]
fn a_hair_past_a_whole_number_of_steps_changes_the_result_by_a_hair() {
    let (scene, problem, _) = bar(150, None);
    let config = dgmpm(&scene, 0.5, 2, Integrator::Euler);
    let dt = impact::build(&problem, config).unwrap().stable_dt();
    let whole = 230.0 * dt;
    let base = stress_at(whole);
    let pressure = 1e9;
    for shift in [1e-10, -1e-10, 1e-9] {
        let moved = stress_at(whole * (1.0 + shift));
        let change = largest_change(&base, &moved) / pressure;
        println!("output time moved by {shift:e}: largest change {change:.2e} of the load");
        assert!(change < 1e-7, "moved by {shift:e}: change {change:e}");
    }
    // what the sliver did: 230 stable steps, then one of 1e-10 of the output time
    let mut m = impact::build(&problem, config).unwrap();
    for k in 0..230 {
        m.step(k as f64 * dt, dt);
    }
    m.step(whole, whole * 1e-10);
    let mut samples = Samples::<1>::default();
    m.sample_into(&mut samples);
    let sliver: Vec<f64> = samples.stress.iter().map(|s| s[(0, 0)]).collect();
    let change = largest_change(&base, &sliver) / pressure;
    println!("a sliver step of 1e-10 of the output time: largest change {change:.2e} of the load");
    assert!(
        change > 1e-4,
        "the sliver step changed σ by only {change:e}"
    );
}

/// An end time of exactly one stable step takes one step, and DGMPM at Courant 1 is exact
/// after it.
#[test]
fn an_end_time_of_one_step_takes_one_step() {
    let scene = impact_core::Scene::builtin("bar").unwrap();
    let problem = impact_core::Problem::<1>::from_scene(&scene).unwrap();
    let transit = problem.cell_transit_time();
    let out = crate::common::tmp("one-step");
    let t_end = format!("{transit:e}");
    let o = impact(&[
        "run",
        "bar",
        "--method",
        "dgmpm",
        "--t-end",
        &t_end,
        "--quiet",
        "--no-files",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let run = &summary["runs"][0];
    assert_eq!(run["steps"], 1, "{run}");
    let l1 = run["times"][0]["l1_rel"].as_f64().unwrap();
    assert!(l1 < 1e-12, "{l1}");
}

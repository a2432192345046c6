//! 1D bars with any ends, loads at either end and initial velocities against the exact
//! d'Alembert solution with images (`impact_core::exact::BarExact`, issue 23): DGMPM at
//! Courant 1 and one point per cell is exact transport in 1D, so it matches the exact
//! cell averages to round-off; every method's energy is measured by one rule.
use crate::common::*;
use impact_core::method::MethodKind;
use impact_core::reference::Reference;
use impact_core::{Problem, Scene};

/// The paper's bar (150 cells, 6 m, steel) with the `[boundary]` and `[initial]` TOML
/// given, at the paper's output times (50, 100 and 200 cell transits: before the first
/// reflection, at it, and after it).
fn scene(boundary: &str, initial: &str) -> (Scene, Problem<1>, Reference) {
    let text = impact_core::scene::builtin("bar").unwrap();
    let head = &text[..text.find("[boundary]").unwrap()];
    let tail = &text[text.find("[time]").unwrap()..];
    let toml = format!("{head}[boundary]\n{boundary}\n{initial}\n{tail}");
    let scene = Scene::from_toml(&toml, "test").unwrap();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let reference = Reference::exact(&problem).unwrap();
    (scene, problem, reference)
}

/// DGMPM's largest L1 (relative) over the output times, and the run's energy errors.
fn dgmpm_l1(scene: &Scene, problem: &Problem<1>, reference: &Reference) -> f64 {
    let (rec, blowup) = run(problem, scene.method_config(MethodKind::Dgmpm), reference);
    assert!(blowup.is_none());
    rec.times.iter().map(|t| t.l1).fold(0.0, f64::max)
}

/// A fixed or symmetric far end (the same in 1D), a load on the right end, loads on both
/// ends with pulse and sine histories: DGMPM at Courant 1 reproduces the exact cell
/// averages to round-off before and after the reflections.
#[test]
fn dgmpm_courant_one_is_exact_for_any_ends() {
    let cases = [
        r#"left = { kind = "pressure", value = 1.0e9 }
right = { kind = "velocity", value = 0.0 }"#,
        r#"left = { kind = "pressure", value = 1.0e9 }
right = { kind = "symmetry" }"#,
        r#"left = { kind = "free" }
right = { kind = "pressure", value = 1.0e9 }"#,
        r#"left = { kind = "symmetry" }
right = { kind = "velocity", value = 4.0 }"#,
        r#"left = { kind = "pressure", value = 6.0e8, history = "pulse", duration = 2.1e-4 }
right = { kind = "velocity", value = 3.0, history = "sine", duration = 3.3e-4 }"#,
        r#"left = { kind = "velocity", value = 2.0, history = "ramp", duration = 1.7e-4 }
right = { kind = "symmetry" }"#,
    ];
    for boundary in cases {
        let (scene, problem, reference) = scene(boundary, "");
        let l1 = dgmpm_l1(&scene, &problem, &reference);
        println!("{boundary:?}: DGMPM L1 {l1:.2e}");
        assert!(l1 < 1e-12, "{boundary}: L1 {l1:e}");
    }
}

/// A fixed far end doubles the stress of the reflected wave and a symmetric one is the
/// same in 1D: the exact references agree everywhere, the reflected plateau is `-2p`.
#[test]
fn symmetric_end_is_a_fixed_end_in_1d() {
    let fixed = scene(
        "left = { kind = \"pressure\", value = 1.0e9 }\nright = { kind = \"velocity\", value = 0.0 }",
        "",
    )
    .2;
    let symmetric = scene(
        "left = { kind = \"pressure\", value = 1.0e9 }\nright = { kind = \"symmetry\" }",
        "",
    )
    .2;
    let c = (2e11f64 / 7800.0).sqrt();
    let t = 9.0 / c; // reflected at X = 6, back at X = 3
    for x in [0.5, 2.9, 3.1, 5.5] {
        let lo = nalgebra::Vector1::new(x - 0.02);
        let hi = nalgebra::Vector1::new(x + 0.02);
        assert_eq!(fixed.averages(&lo, &hi, t), symmetric.averages(&lo, &hi, t));
    }
    let lo = nalgebra::Vector1::new(4.0);
    let hi = nalgebra::Vector1::new(4.04);
    assert!((fixed.averages(&lo, &hi, t).0 + 2e9).abs() < 1e-3);
}

/// d'Alembert for an initial velocity: a linear profile (its cell-centre values are its
/// cell averages) on a free-free and a fixed-free bar is transported exactly by DGMPM
/// at Courant 1; a sine profile keeps the midpoint-rule error of the initial sampling,
/// `(Δx k)²/24 = 1.8e-5`, and does not grow.
#[test]
fn initial_velocity_against_dalembert() {
    for boundary in [
        "left = { kind = \"free\" }\nright = { kind = \"free\" }",
        "left = { kind = \"velocity\", value = 0.0 }\nright = { kind = \"free\" }",
    ] {
        let (scene, problem, reference) = scene(boundary, "[initial]\nvelocity = [\"2 + 0.5*x\"]");
        let l1 = dgmpm_l1(&scene, &problem, &reference);
        println!("linear initial velocity, {boundary:?}: DGMPM L1 {l1:.2e}");
        assert!(l1 < 1e-12, "{boundary}: L1 {l1:e}");
    }
    let (scene, problem, reference) = scene(
        "left = { kind = \"free\" }\nright = { kind = \"free\" }",
        "[initial]\nvelocity = [\"5*sin(PI*x/6)\"]",
    );
    let (rec, _) = run(&problem, scene.method_config(MethodKind::Dgmpm), &reference);
    let dx = 6.0 / 150.0;
    let sampling = (dx * std::f64::consts::PI / 6.0).powi(2) / 24.0;
    for t in &rec.times {
        println!(
            "sine initial velocity: t = {:.3e}: L1 {:.3e} (sampling {sampling:.3e})",
            t.t, t.l1
        );
        assert!((t.l1 - sampling).abs() < 0.02 * sampling, "L1 {}", t.l1);
    }
}

/// Energy measured by one rule in every method: a free-free bar with an initial velocity
/// (no work is done) reports `(E_h - E₀)/E₀` relative to the initial energy, small in
/// every method (it was 3.09e19 for DGMPM, whose round-off work it divided by).
#[test]
fn energy_of_a_free_free_bar_with_an_initial_velocity_is_relative_in_every_method() {
    let (scene, problem, reference) = scene(
        "left = { kind = \"free\" }\nright = { kind = \"free\" }",
        "[initial]\nvelocity = [\"5*sin(PI*x/6)\"]",
    );
    for kind in MethodKind::ALL {
        for with_reference in [true, false] {
            let (rec, _) = impact::run::run_method(
                &problem,
                scene.method_config(kind),
                with_reference.then_some(&reference),
                &mut impact::run::Silent,
            )
            .unwrap();
            for t in &rec.times {
                println!(
                    "{kind} (reference {with_reference}): t = {:.3e}: energy {:.3e} (relative {})",
                    t.t, t.energy_error, t.energy_relative
                );
                assert!(t.energy_relative, "{kind}: energy in J");
                assert!(
                    t.energy_error.abs() < 1e-2,
                    "{kind}: energy {}",
                    t.energy_error
                );
            }
        }
    }
}

/// The plane wave (2D, symmetry top and bottom) uses the same solution for a load on the
/// right edge or on both, and a fixed far edge: DGMPM at Courant 1 (CTU) matches the
/// exact uniaxial-strain averages along the bottom row to round-off.
#[test]
fn plane_waves_loaded_on_either_edge_are_exact() {
    let text = impact_core::scene::builtin("plate-wave").unwrap();
    let head = &text[..text.find("[boundary]").unwrap()];
    let tail = &text[text.find("[time]").unwrap()..];
    for edges in [
        "left = { kind = \"free\" }\nright = { kind = \"normal-velocity\", value = 5.0 }",
        "left = { kind = \"pressure\", value = 4.0e8 }\nright = { kind = \"symmetry\" }",
        "left = { kind = \"velocity\", value = 5.0, history = \"pulse\", duration = 1.2e-4 }\nright = { kind = \"pressure\", value = 2.0e8, history = \"ramp\", duration = 1.0e-4 }",
    ] {
        let toml = format!(
            "{head}[boundary]\n{edges}\nbottom = {{ kind = \"symmetry\" }}\ntop = {{ kind = \"symmetry\" }}\n{tail}"
        );
        let scene = Scene::from_toml(&toml, "test").unwrap();
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        let reference = Reference::exact(&problem).unwrap();
        let (rec, _) = impact::run::run_method(
            &problem,
            scene.method_config(MethodKind::Dgmpm),
            Some(&reference),
            &mut impact::run::Silent,
        )
        .unwrap();
        let l1 = rec.times.iter().map(|t| t.l1).fold(0.0, f64::max);
        println!("plane wave {edges:?}: DGMPM L1 {l1:.2e}");
        assert!(l1 < 1e-12, "{edges}: L1 {l1:e}");
    }
}

/// Scenes without an exact solution say why (the CLI prints it and falls back to a
/// converged reference).
#[test]
fn scenes_without_an_exact_solution_say_why() {
    let text = impact_core::scene::builtin("plate").unwrap();
    let problem = Problem::<2>::from_scene(&Scene::from_toml(text, "plate").unwrap()).unwrap();
    let why = Reference::exact(&problem).unwrap_err();
    assert!(why.contains("symmetry sides across x"), "{why}");
    let text = impact_core::scene::builtin("svk-bar").unwrap();
    let mut scene = Scene::from_toml(text, "svk-bar").unwrap();
    scene.boundary.right = scene.boundary.left.clone();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let why = Reference::exact(&problem).unwrap_err();
    assert!(why.contains("Saint-Venant–Kirchhoff"), "{why}");
}

/// MPM counts the work and the impulse a velocity or pressure end delivers with every
/// shape: with a smooth stencil the padding nodes beyond a velocity end take the mirror of
/// the interior (`impact_mpm` `edges` module) and the forces folded across it are the
/// wall's, so they count (`grid_update`'s `FoldChange`); a pressure's power is taken on
/// the nodes it acts on. Before the wave reaches the free end the body's momentum equals
/// the counted impulse (FLIP, to round-off), the counted work is within 3 % of the exact
/// one (`ρ c V² t`, `p² t / (ρ c)`), and the energy errors measured against the counted and
/// the exact work agree to 2 % (a pressure: 5 % and 5 %, the load's power taken with the
/// lumped mean nodal velocity; cubic B-splines at one point per cell overcount it by 39 %,
/// printed and not asserted, 24 % under before). Both frames: in the updated Lagrangian
/// frame a pressure's power is the loaded point's (B-splines at 4 points per cell and cubic
/// ones at one miss the exact work by 7 to 20 %: printed, not asserted; `load_power`'s
/// doc). Quadratic B-splines at 4 points per cell
/// counted three quarters of the velocity end's work before (energy error +33 %), cubic
/// ones 77 % of the pressure's (+30 %).
#[test]
fn mpm_counts_the_work_and_impulse_of_its_ends_with_every_shape() {
    use impact_core::method::{MpmFrame, MpmShape};
    // both frames, every shape, 1, 2 and 4 points per cell
    let frames_shapes_and_points = || {
        [MpmFrame::TotalLagrangian, MpmFrame::UpdatedLagrangian]
            .into_iter()
            .flat_map(|frame| MpmShape::ALL.into_iter().map(move |shape| (frame, shape)))
            .flat_map(|(frame, shape)| [1, 2, 4].map(|ppc| (frame, shape, ppc)))
    };
    const C0: f64 = 5063.696835418333; // sqrt(2e11/7800)
    let impedance = 7800.0 * C0;
    let ends = [
        ("velocity", 5.0, impedance * 25.0, 0.03, 0.02),
        ("pressure", 1.0e9, 1.0e18 / impedance, 0.05, 0.05),
    ];
    let mut failures = Vec::new();
    for (kind, value, power, work_tolerance, energy_tolerance) in ends {
        let (scene, problem, reference) = scene(
            &format!(
                "left = {{ kind = \"{kind}\", value = {value:e} }}\nright = {{ kind = \"free\" }}"
            ),
            "",
        );
        let first = problem.output_times[0];
        for (frame, shape, points_per_cell) in frames_shapes_and_points() {
            {
                let cfg = config(&scene, MethodKind::Mpm, |c| {
                    c.points_per_cell = points_per_cell;
                    let options = c.mpm_mut().unwrap();
                    options.shape = shape;
                    options.frame = frame;
                });
                let mut m = impact::build(&problem, cfg).unwrap();
                let dt = m.stable_dt();
                let steps = (first / dt).floor() as usize;
                for k in 0..steps {
                    m.step(k as f64 * dt, dt);
                }
                let (p, j) = (m.momentum()[0], m.external_impulse()[0]);
                let t = steps as f64 * dt;
                let exact_work = power * t;
                let work = m.external_work();
                println!(
                "{kind} {frame:?} {shape} {points_per_cell} ppc: momentum {p:.6e} impulse {j:.6e}, work {work:.6e} (exact {exact_work:.6e})"
            );
                if (p - j).abs() > 1e-10 * j.abs() {
                    failures.push(format!(
                        "{kind} {frame:?} {shape} {points_per_cell} ppc: momentum {p} impulse {j}"
                    ));
                }
                // known gaps (`impact_mpm` `loads::load_power`'s doc): a pressure with cubic
                // B-splines at one point per cell (total Lagrangian: the nodes' lumped mean
                // velocity), and with B-splines at 4 points per cell and cubic ones at one
                // (updated Lagrangian: the loaded point's velocity); printed, not asserted
                let known_gap = kind == "pressure"
                    && match frame {
                        MpmFrame::TotalLagrangian => {
                            shape == MpmShape::Bspline3 && points_per_cell == 1
                        }
                        MpmFrame::UpdatedLagrangian => {
                            matches!(shape, MpmShape::Bspline2 | MpmShape::Bspline3)
                                && (points_per_cell == 4
                                    || shape == MpmShape::Bspline3 && points_per_cell == 1)
                        }
                    };
                if !known_gap && (work / exact_work - 1.0).abs() > work_tolerance {
                    failures.push(format!(
                        "{kind} {frame:?} {shape} {points_per_cell} ppc: work {work} against {exact_work}"
                    ));
                }
                let errors: Vec<f64> = [true, false]
                    .map(|with_reference| {
                        let (rec, _) = impact::run::run_method(
                            &problem,
                            cfg,
                            with_reference.then_some(&reference),
                            &mut impact::run::Silent,
                        )
                        .unwrap();
                        rec.times[0].energy_error
                    })
                    .to_vec();
                println!("  energy error against the exact work, the own: {errors:?}");
                if !known_gap && (errors[0] - errors[1]).abs() > energy_tolerance {
                    failures.push(format!(
                        "{kind} {frame:?} {shape} {points_per_cell} ppc: energy errors {errors:?}"
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

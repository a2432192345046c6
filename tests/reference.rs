//! The converged reference of a scene without an exact solution (issue 26): which method
//! judges, the spread between two independent references, the cache, and what the outputs
//! say.
mod common;

use impact::run::{run_method, RunOptions, Silent};
use impact::{Overrides, Study};
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene};
use std::process::Command;

/// One cache folder for this test binary ([`common::use_fresh_cache`]).
fn use_test_cache() {
    common::use_fresh_cache("impact-reference-cache");
}

/// The paper's plate (33x25) with the reference options `o`.
fn plate(o: Overrides) -> Study {
    Study::new(Scene::builtin("plate").unwrap(), o).unwrap()
}

/// DGMPM's relative L1 errors on the plate at each output time against the reference of
/// `o`, with the spread beside each.
fn dgmpm_errors(o: Overrides) -> Vec<(f64, f64)> {
    use_test_cache();
    let study = plate(o);
    let problem: Problem<2> = study.problem().unwrap();
    let reference = impact::reference_for(&problem, &MethodKind::ALL, false)
        .unwrap()
        .expect("the plate has a converged reference");
    let (record, blowup) = run_method(
        &problem,
        study.config(MethodKind::Dgmpm),
        Some(&reference),
        &mut Silent,
    )
    .unwrap();
    assert!(blowup.is_none());
    record
        .times
        .iter()
        .map(|t| (t.l1, t.l1_spread.expect("a second reference")))
        .collect()
}

fn with(reference: MethodKind, spread: MethodKind, refinement: usize) -> Overrides {
    Overrides {
        reference: Some(reference),
        reference_spread: Some(spread),
        reference_refinement: Some(refinement),
        ..Default::default()
    }
}

/// DGMPM and FEM both converge to the plate's one solution, so the distance between their
/// references (the spread) shrinks as both are refined: at least by 2^-0.5 per halving of
/// the cell (each first-order scheme's L1 error at a jump falls at least as h^(1/2)),
/// asserted with margin as 0.85. And the spread bounds how far the error moves when the
/// two references swap roles (triangle inequality: |e_A − e_B ΣB/ΣA| ≤ spread).
#[test]
fn fem_and_dgmpm_references_of_the_plate_converge_to_each_other() {
    let (d, f) = (MethodKind::Dgmpm, MethodKind::Fem);
    let coarse = dgmpm_errors(with(d, f, 2));
    let fine = dgmpm_errors(with(d, f, 4));
    let finer = dgmpm_errors(with(d, f, 8));
    let swapped = dgmpm_errors(with(f, d, 8));
    for k in 0..coarse.len() {
        let spreads = [coarse[k].1, fine[k].1, finer[k].1];
        assert!(
            spreads[1] < 0.85 * spreads[0] && spreads[2] < 0.85 * spreads[1],
            "t{k}: spreads at 2x, 4x, 8x {spreads:?}"
        );
        let (e_a, spread) = finer[k];
        let e_b = swapped[k].0;
        assert!(
            (e_a - e_b).abs() <= spread * (1.0 + e_b) + 1e-12,
            "t{k}: {e_a} against DGMPM 8x, {e_b} against FEM 8x, spread {spread}"
        );
        // the spread of the swapped pair is the same distance over FEM's norm
        assert!((swapped[k].1 - spread).abs() <= spread * spread.max(0.05) * 2.0);
    }
}

/// A stored DGMPM reference is never read as a FEM one, nor as another refinement.
#[test]
fn the_cache_keys_hold_the_reference_method_and_refinement() {
    let study = plate(Overrides::default());
    let problem: Problem<2> = study.problem().unwrap();
    let setup = impact::reference_setup::resolve(&problem, &MethodKind::ALL).unwrap();
    assert_eq!(setup.judge.method, MethodKind::Dgmpm);
    assert_eq!(setup.spread.method, MethodKind::Fem);
    let dir = common::tmp("reference-keys");
    let mut fine = problem.clone();
    for l in 0..2 {
        fine.grid.cells[l] *= 4;
        fine.grid.spacing[l] /= 4.0;
    }
    let dgmpm = impact::reference::cache_entry(&dir, &fine, (&setup.judge, 4));
    let fem = impact::reference::cache_entry(&dir, &fine, (&setup.spread, 4));
    let other = impact::reference::cache_entry(&dir, &fine, (&setup.judge, 8));
    assert_ne!(dgmpm.path(), fem.path());
    assert_ne!(dgmpm.path(), other.path());
    let cells = fine.grid.cell_count();
    let stored = impact::reference_cache::Stored {
        stress_xx: vec![vec![1.0; cells]],
        velocity_x: vec![vec![2.0; cells]],
        work: vec![3.0],
    };
    dgmpm.store(&stored).unwrap();
    assert_eq!(dgmpm.load(1, cells), Some(stored));
    assert!(fem.load(1, cells).is_none());
    assert!(other.load(1, cells).is_none());
}

/// `impact run plate --method dgmpm`: FEM judges (DGMPM is compared), DGMPM gives the
/// spread; summary.json says so, with the refinement, the fine cells, and a spread beside
/// every error.
#[test]
fn summary_json_names_the_reference_and_every_error_has_its_spread() {
    use_test_cache();
    let study = plate(Overrides::default());
    let out = common::tmp("reference-run");
    let options = RunOptions {
        out: out.to_path_buf(),
        quiet: true,
        no_files: true,
        ..Default::default()
    };
    impact::run::run_study::<2>(&study, &[MethodKind::Dgmpm], &options).unwrap();
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    let setup = &s["reference_setup"];
    assert_eq!(setup["method"], "fem", "{text}");
    assert_eq!(setup["spread"]["method"], "dgmpm", "{text}");
    assert_eq!(setup["refinement"], 8);
    assert_eq!(setup["cells"], serde_json::json!([264, 200]));
    assert!(s["reference"].as_str().unwrap().contains("FEM"), "{text}");
    for t in s["runs"][0]["times"].as_array().unwrap() {
        let (l1, spread) = (t["l1_rel"].as_f64().unwrap(), t["l1_spread"].as_f64());
        assert!(l1 > 0.0 && spread.is_some_and(|s| s > 0.0), "{t}");
    }
}

/// Bad reference options are refused, naming the field or flag and what is allowed.
#[test]
fn bad_reference_options_name_the_field_and_the_allowed_values() {
    let o = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(["run", "plate", "--no-files", "--reference", "exact"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for word in ["--reference", "exact", "dgmpm", "mpm", "fem"] {
        assert!(err.contains(word), "{word}: {err}");
    }
    let o = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(["run", "plate", "--no-files", "--reference-refinement", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--reference-refinement") && err.contains("2 to 16"),
        "{err}"
    );
    let base = std::fs::read_to_string("scenes/plate.toml").unwrap();
    for (line, field, allowed) in [
        ("reference = \"exact\"", "reference", "\"fem\""),
        (
            "reference_refinement = 1",
            "metrics.reference_refinement",
            "2 to 16",
        ),
        (
            "reference = \"fem\"\nreference_spread = \"fem\"",
            "metrics.reference_spread",
            "other than",
        ),
    ] {
        let text = format!("{base}{line}\n");
        let e = Scene::from_toml(&text, "test").unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(allowed), "{line}: {e}");
    }
}

/// `impact bench convergence` on a scene without an exact solution gives every level's
/// errors with the reference's spread in the same norm, for σ and v, L1 and L2. Swapping
/// the two references (DGMPM judges with FEM's spread, then FEM with DGMPM's) checks both
/// at once: the distance `D = ‖A − B‖` is one number, so `s = D/‖A‖` and `s' = D/‖B‖`
/// give `‖B‖/‖A‖ = s/s'`, and the triangle inequality `|‖f − A‖ − ‖f − B‖| ≤ ‖A − B‖`
/// reads `|e_A − e_B s/s'| ≤ s` in the relative errors the ladder reports (L1, and L2 by
/// Minkowski's inequality).
#[test]
fn convergence_errors_carry_the_spread_of_their_reference() {
    use impact::convergence::{ladder, FieldErrors, SpreadErrors};
    use_test_cache();
    let errors = |judge: MethodKind, spread: MethodKind| {
        let mut scene = Scene::builtin("plate").unwrap();
        let metrics = scene.metrics.get_or_insert_with(Default::default);
        metrics.reference = Some(judge);
        metrics.reference_spread = Some(spread);
        metrics.reference_refinement = Some(4);
        let configs: Vec<_> = impact::work_precision::configurations(&scene)
            .into_iter()
            .filter(|c| c.label == "fem C0.9" || c.label == "mpm 1ppc C0.5")
            .collect();
        assert_eq!(configs.len(), 2, "the ladder's FEM and MPM rows");
        ladder::<2>(&scene, &configs, 2).unwrap()
    };
    let by_dgmpm = errors(MethodKind::Dgmpm, MethodKind::Fem);
    let by_fem = errors(MethodKind::Fem, MethodKind::Dgmpm);
    assert_eq!(by_dgmpm.len(), 4);
    type Norm = (
        fn(&FieldErrors) -> f64,
        fn(&SpreadErrors) -> f64,
        &'static str,
    );
    let norms: [Norm; 4] = [
        (|e| e.l1_stress, |s| s.l1_stress_spread, "L1 σ"),
        (|e| e.l2_stress, |s| s.l2_stress_spread, "L2 σ"),
        (|e| e.l1_velocity, |s| s.l1_velocity_spread, "L1 v"),
        (|e| e.l2_velocity, |s| s.l2_velocity_spread, "L2 v"),
    ];
    for (a, b) in by_dgmpm.iter().zip(&by_fem) {
        assert_eq!((&a.config, a.cells_x), (&b.config, b.cells_x));
        let (spread_a, spread_b) = (a.errors.spread.unwrap(), b.errors.spread.unwrap());
        for (error, spread, name) in norms {
            let (s, s_swapped) = (spread(&spread_a), spread(&spread_b));
            assert!(s > 0.0 && s.is_finite(), "{name} spread {s}");
            let (e_a, e_b) = (error(&a.errors), error(&b.errors));
            assert!(
                (e_a - e_b * s / s_swapped).abs() <= s * (1.0 + 1e-12),
                "{} at {} cells, {name}: {e_a} by DGMPM, {e_b} by FEM, spreads {s}, {s_swapped}",
                a.config,
                a.cells_x
            );
        }
    }
}

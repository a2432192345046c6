//! Every bad scene value and flag gets an error naming the field, the value and what is
//! allowed; never a panic.
use impact_core::Scene;
use std::process::Command;

const BAR: &str = include_str!("../scenes/bar.toml");

fn expect_scene_error(edit: impl Fn(&str) -> String, fragments: &[&str]) {
    let text = edit(BAR);
    let err = Scene::from_toml(&text, "test.toml")
        .expect_err("must be rejected")
        .to_string();
    for f in fragments {
        assert!(err.contains(f), "error {err:?} should contain {f:?}");
    }
}

#[test]
fn bad_scene_values_are_named() {
    // (text replaced in the paper's bar, its replacement, fragments the error must hold)
    let cases: &[(&str, &str, &[&str])] = &[
        ("dim = 1", "dim = 3", &["`dim`", "3", "1 or 2"]),
        (
            "length = [6.0]",
            "length = [-6.0]",
            &["domain.length[0]", "-6", "positive"],
        ),
        (
            "cells = [150]",
            "cells = [0]",
            &["domain.cells[0]", "0", "at least 1"],
        ),
        (
            "cells = [150]",
            "cells = [150, 4]",
            &["domain.cells", "1 cell counts"],
        ),
        (
            "poisson = 0.3",
            "poisson = 0.5",
            &["material.poisson", "0.5", "(-1, 0.5)"],
        ),
        (
            "density = 7800.0",
            "density = 0.0",
            &["material.density", "0", "positive"],
        ),
        (
            "young = 2.0e11",
            "young = -1.0",
            &["material.young", "-1", "positive"],
        ),
        (
            "\"linear-elastic\"",
            "\"plastic\"",
            &["material.model", "plastic", "linear-elastic"],
        ),
        (
            "[dgmpm]\ncourant = 1.0",
            "[dgmpm]\ncourant = 2.5",
            &["dgmpm.courant", "2.5", "(0, 2]"],
        ),
        (
            "[mpm]\ncourant = 0.5",
            "[mpm]\ncourant = 0.0",
            &["mpm.courant", "0", "(0, 2]"],
        ),
        (
            "points_per_cell = 1 ",
            "points_per_cell = 0 ",
            &["domain.points_per_cell", "0", "1 to 64"],
        ),
        (
            "{ kind = \"free\" }",
            "{ kind = \"clamped\" }",
            &["boundary.right.kind", "clamped", "\"free\""],
        ),
        (
            "kind = \"pressure\", value = 1.0e9",
            "kind = \"pressure\"",
            &["boundary.left.value", "missing", "finite"],
        ),
        (
            "right = { kind = \"free\" }",
            "right = { kind = \"free\" }\nbottom = { kind = \"free\" }",
            &["boundary.bottom", "only `left` and `right` in 1D"],
        ),
        (
            "[50, 100, 200]",
            "[100, 50]",
            &["time.output_transits", "increasing"],
        ),
        (
            "output_transits = [50, 100, 200]",
            "output_transits = [50]\noutput_times = [1e-3]",
            &["`time`", "one of"],
        ),
        (
            "integrator = \"euler\"",
            "integrator = \"rk4\"",
            &["dgmpm.integrator", "rk4", "\"euler\" or \"rk2\""],
        ),
        (
            "update = \"nodal\"",
            "update = \"flip\"",
            &["dgmpm.update", "flip", "\"nodal\" or \"increment\""],
        ),
        (
            "name = \"bar\"",
            "name = \"my bar!\"",
            &["`name`", "letters, digits"],
        ),
    ];
    assert_eq!(cases.len(), 19);
    for (from, to, fragments) in cases {
        assert!(BAR.contains(from), "the case must edit the scene: {from:?}");
        expect_scene_error(|s| s.replace(from, to), fragments);
    }
}

#[test]
fn unknown_and_malformed_fields_are_named_with_their_line() {
    let err = Scene::from_toml(&BAR.replace("young = 2.0e11", "youngs = 2.0e11"), "t.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("youngs") && err.contains("line"), "{err}");
    let err = Scene::from_toml(
        &BAR.replace("cells = [150]", "cells = [\"many\"]"),
        "t.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("t.toml") && err.contains("line"), "{err}");
}

fn cli_error(args: &[&str], fragments: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} should fail");
    assert!(!err.contains("panicked"), "{err}");
    for f in fragments {
        assert!(err.contains(f), "{args:?}: {err:?} should contain {f:?}");
    }
}

#[test]
fn bad_flags_are_named() {
    cli_error(
        &["run", "bar", "--courant", "3"],
        &["--courant", "3", "(0, 2]"],
    );
    cli_error(&["run", "bar", "--courant", "-0.5"], &["--courant"]);
    cli_error(
        &["run", "bar", "--points-per-cell", "0"],
        &["--points-per-cell", "0"],
    );
    cli_error(
        &["run", "bar", "--cells", "0"],
        &["--cells", "0", "at least 1"],
    );
    // grids that cannot fit in memory are refused before any allocation
    cli_error(
        &["run", "bar", "--cells", "99999999"],
        &["--cells", "99999999", "at most 1e7"],
    );
    cli_error(
        &["run", "plate", "--cells", "5000"],
        &["--cells", "at most 1e7"],
    );
    cli_error(
        &["run", "bar", "--integrator", "rk4"],
        &["--integrator", "rk4", "euler", "rk2"],
    );
    cli_error(
        &["run", "bar", "--method", "sph"],
        &["--method", "sph", "dgmpm"],
    );
    cli_error(
        &["run", "bar", "--output-times", "1e-3,5e-4"],
        &["--output-times", "increasing"],
    );
    cli_error(
        &["run", "bar", "--t-end", "-1"],
        &["t_end", "-1", "positive"],
    );
    cli_error(
        &["run", "plate-of-gold"],
        &["unknown scene", "plate-of-gold", "bar"],
    );
    cli_error(
        &["run", "no/such/file.toml"],
        &["cannot read scene file", "no/such/file.toml"],
    );
    cli_error(&["check", "bar", "--courant", "nan"], &["--courant", "NaN"]);
}

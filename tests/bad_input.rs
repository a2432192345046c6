//! Every bad scene value and flag gets an error naming the field, the value and what is
//! allowed, before anything is allocated or written; never a panic. Valid edge cases run.
use crate::common::impact;
use impact_core::Scene;
use std::process::Command;

const BAR: &str = include_str!("../scenes/bar.toml");

/// Every file of `tests/bad-scenes/` is refused before anything is written, with exit
/// status 2, no panic, and a message holding each fragment of its `# expect:` line
/// (fragments separated by `|`: the field path, the value, what is allowed).
#[test]
fn every_bad_scene_is_refused_with_its_field_value_and_range() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 60, "{} bad scenes", files.len());
    let out = std::env::temp_dir().join(format!("impact-bad-{}", std::process::id()));
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# expect: "))
            .unwrap_or_else(|| panic!("{}: first line must be `# expect: ...`", file.display()));
        let o = impact(&[
            "run",
            file.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        let name = file.file_name().unwrap().to_string_lossy();
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(!out.exists(), "{name}: refused input must write nothing");
        for fragment in expect.split('|').map(str::trim) {
            assert!(
                err.contains(fragment),
                "{name}: {err:?} should contain {fragment:?}"
            );
        }
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
        &["run", "bar", "--cells", "200000000"],
        &["--cells", "200000000", "at most 1e8"],
    );
    cli_error(
        &["run", "plate", "--cells", "20000"],
        &["--cells", "at most 1.5e8"],
    );
    // a rank grid (`--ranks-grid`) that does not fit the rank count or the dimension,
    // refused before any run (here on one rank)
    cli_error(
        &["run", "plate", "--method", "dgmpm", "--ranks-grid", "2,2"],
        &["--ranks-grid 2,2", "product is 4 but the run has 1 ranks"],
    );
    cli_error(
        &["run", "plate", "--ranks-grid", "1,1,1"],
        &[
            "--ranks-grid 1,1,1",
            "3 entries but the grid is 2D",
            "px,py",
        ],
    );
    cli_error(
        &["run", "plate", "--ranks-grid", "2,x"],
        &["--ranks-grid", "x"],
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
        &["--t-end", "-1", "positive"],
    );
    cli_error(
        &["run", "bar", "--t-end", "1e300"],
        &["work of dgmpm", "point-updates", "--work-budget"],
    );
    cli_error(
        &["run", "bar", "--courant", "1e-300"],
        &["work of dgmpm", "--work-budget"],
    );
    // the converged references of a 2D scene count too (8x finer: 64x the cells, 8x the
    // steps: 7.757e6 points x 1.424e5 steps)
    cli_error(
        &[
            "run", "plate", "--cells", "400", "--t-end", "3e-2", "--method", "fem",
        ],
        &["work of a converged reference", "1.105e12 point-updates"],
    );
    cli_error(
        &["run", "bar", "--work-budget", "0"],
        &["--work-budget", "0", "at least 1"],
    );
    cli_error(
        &["run", "bar", "--work-budget", "1000"],
        &["work of dgmpm", "at most 1.0e3 point-updates"],
    );
    cli_error(
        &[
            "run",
            "bar",
            "--output-times",
            "1e-4,2e-3",
            "--t-end",
            "1e-3",
        ],
        &[
            "time.output_times (with the command-line overrides)",
            "after time.t_end",
        ],
    );
    cli_error(
        &["run", "bar", "--output-times", "5e-324"],
        &["time.output_times", "5e-324", "finite normal"],
    );
    cli_error(
        &["run", "bar", "--load-magnitude", "1e11"],
        &[
            "boundary.left.value (with the command-line overrides)",
            "strain of at most 0.1",
        ],
    );
    cli_error(
        &["run", "bar", "--load-magnitude", "0"],
        &["--load-magnitude", "0", "positive"],
    );
    cli_error(
        &["run", "plate", "--load", "tension"],
        &["--load", "pressure-loaded end"],
    );
    cli_error(&["run", "bar", "--flux", "ctu"], &["--flux", "only in 2D"]);
    cli_error(
        &["run", "plate", "--points-per-cell", "2"],
        &["--points-per-cell", "2", "square number"],
    );
    cli_error(
        &["run", "bar", "--cells", "18446744073709551616"],
        &["--cells", "18446744073709551616"],
    );
    cli_error(&["run", "bar", "--courant", "inf"], &["--courant", "inf"]);
    cli_error(
        &["check", "bar", "--against", "sph"],
        &["--against", "sph", "all-mpm", "\"gimp\""],
    );
    cli_error(
        &["run", "bar", "--shape", "nurbs"],
        &["--shape", "nurbs", "bspline3"],
    );
    cli_error(
        &["stability", "--steps-1d", "99999999999"],
        &["--steps-1d", "99999999999", "1 to 1000000"],
    );
    cli_error(&["stability", "--dim", "3"], &["--dim 3", "1 and/or 2"]);
    cli_error(
        &[
            "bench",
            "work-precision",
            "--scene",
            "bar",
            "--levels",
            "50",
        ],
        &["--levels 50", "1 to 10"],
    );
    cli_error(
        &["run", "bar", "--out", "/proc/impact-cannot-write-here"],
        &[
            "cannot write /proc/.impact-cannot-write-here.lock",
            "(os error",
        ],
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

/// Edge cases at the ends of the allowed ranges run to completion (exit 0) with finite
/// metrics.
#[test]
fn valid_edge_cases_run() {
    let plate = include_str!("../scenes/plate.toml");
    let svk = include_str!("../scenes/svk-bar.toml");
    let r = |base: &str, from: &str, to: &str| {
        assert!(base.contains(from), "{from}");
        base.replacen(from, to, 1)
    };
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("one cell", r(BAR, "cells = [150]", "cells = [1]"), vec![]),
        (
            "two cells in 2D",
            r(plate, "cells = [33, 25]", "cells = [2, 2]")
                .replace("from = 0.0, to = 1.0", "from = 0.0, to = 1.5"),
            vec![],
        ),
        (
            "largest strain",
            r(BAR, "value = 1.0e9", "value = 2.0e10"),
            vec![],
        ),
        (
            "64 points per cell in 1D",
            r(BAR, "points_per_cell = 1 ", "points_per_cell = 64 "),
            vec!["--cells", "10", "--courant", "0.4"],
        ),
        (
            "64 points per cell in 2D",
            r(plate, "points_per_cell = 1 ", "points_per_cell = 64 "),
            vec!["--cells", "6", "--courant", "0.4"],
        ),
        (
            "segment of one face",
            r(plate, "from = 0.0, to = 1.0", "from = 0.0, to = 0.12"),
            vec![],
        ),
        (
            "nondimensional",
            r(
                &r(
                    &r(BAR, "young = 2.0e11", "young = 1.0"),
                    "density = 7800.0",
                    "density = 1.0",
                ),
                "value = 1.0e9",
                "value = 0.01",
            ),
            vec![],
        ),
        (
            "extreme but consistent units",
            r(
                &r(
                    &r(BAR, "young = 2.0e11", "young = 1e-30"),
                    "density = 7800.0",
                    "density = 1e-30",
                ),
                "value = 1.0e9",
                "value = 1e-33",
            ),
            vec![],
        ),
        (
            "nearly incompressible",
            r(plate, "poisson = 0.3", "poisson = 0.499"),
            vec![],
        ),
        (
            "1000 outputs",
            r(
                BAR,
                "[50, 100, 200]",
                &format!(
                    "[{}]",
                    (1..=1000)
                        .map(|k| k.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ),
            vec!["--cells", "20"],
        ),
        (
            "output at the end time",
            r(
                BAR,
                "output_transits = [50, 100, 200]",
                "output_times = [1e-4, 2e-4]\nt_end = 2e-4",
            ),
            vec![],
        ),
        (
            "fixed wall",
            r(
                BAR,
                "right = { kind = \"free\" }",
                "right = { kind = \"velocity\", value = 0.0 }",
            ),
            vec![],
        ),
        (
            "SVK at 90 % of the hyperbolicity limit",
            r(svk, "value = 8.0e8", "value = 1.7e10"),
            vec!["--method", "dgmpm"],
        ),
    ];
    assert!(cases.len() >= 10);
    let base = crate::common::tmp("edge");
    std::fs::create_dir_all(&*base).unwrap();
    for (k, (what, scene, extra)) in cases.iter().enumerate() {
        let file = base.join(format!("edge{k}.toml"));
        std::fs::write(&file, scene).unwrap();
        let out = base.join(format!("out{k}"));
        let mut args = vec![
            "run",
            file.to_str().unwrap(),
            "--quiet",
            "--no-files",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra.iter().copied());
        let o = impact(&args);
        assert!(
            o.status.success(),
            "{what}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert!(!summary.to_string().contains("null"), "{what}: {summary}");
        for run in summary["runs"].as_array().unwrap() {
            for t in run["times"].as_array().unwrap() {
                assert!(t["energy_rel"].is_number(), "{what}: {t}");
                assert!(
                    t["l1_rel"].is_number() || t["errors"] == "no-reference",
                    "{what}: {t}"
                );
            }
        }
    }
}

/// Checks before work (issue 23, item 9): an option the scene's model or dimension does not
/// take is refused before the converged reference or any run starts, within a second, with
/// exit 2 and the field, the value and what is allowed; the same for `check` and the
/// studies.
#[test]
fn incompatible_options_are_refused_before_any_work() {
    let out = std::env::temp_dir().join(format!("impact-compat-{}", std::process::id()));
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["run", "svk-plate", "--flux", "ctu", "--cells", "160"],
            &[
                "dgmpm.flux (--flux)",
                "ctu",
                "\"dcu\" with Saint-Venant-Kirchhoff",
            ],
        ),
        (
            &["check", "svk-plate", "--flux", "ctu", "--cells", "160"],
            &["dgmpm.flux (--flux)", "ctu", "\"dcu\""],
        ),
        (
            &["run", "svk-plate", "--riemann", "exact"],
            &[
                "dgmpm.riemann (--riemann)",
                "exact",
                "\"approximate\" in 2D",
            ],
        ),
        (
            &["run", "svk-bar", "--frame", "updated-lagrangian"],
            &[
                "mpm.frame (--frame)",
                "updated-lagrangian",
                "\"total-lagrangian\"",
            ],
        ),
        (
            &[
                "run",
                "ep-bar",
                "--riemann",
                "elastoplastic",
                "--points-per-cell",
                "2",
            ],
            &["--points-per-cell", "2", "1 with --riemann elastoplastic"],
        ),
        (
            &[
                "bench",
                "work-precision",
                "--scene",
                "svk-plate",
                "--frame",
                "updated-lagrangian",
            ],
            &[
                "mpm.frame (--frame)",
                "updated-lagrangian",
                "\"total-lagrangian\"",
            ],
        ),
    ];
    for (args, fragments) in cases {
        let mut all: Vec<&str> = args.to_vec();
        all.extend(["--out", out.to_str().unwrap()]);
        if args[0] == "check" {
            all.truncate(all.len() - 2);
        }
        let start = std::time::Instant::now();
        let o = impact(&all);
        let seconds = start.elapsed().as_secs_f64();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(seconds < 1.0, "{args:?}: refused after {seconds:.2} s");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        for fragment in fragments {
            assert!(
                err.contains(fragment),
                "{args:?}: {err:?} should contain {fragment:?}"
            );
        }
        assert!(!out.exists(), "{args:?}: nothing written");
    }
}

//! Provenance and studies on any scene (issue 23, items 3 and 4): every output folder says
//! what produced it (`provenance.json`, the resolved `scene.toml`), `impact run --from`
//! repeats a run exactly, and the studies (`bench work-precision`, `bench convergence`,
//! `stability`) run on scene files a user wrote, with the flags they do not vary.
use crate::common::{impact, json, text, tmp};
use impact_core::Scene;

/// A bar of another material and length than the paper's, loaded in compression at its
/// left end (an exact solution exists: the step wave).
const ALU_BAR: &str = r#"
name = "alu-bar"
dim = 1
[domain]
length = [2.0]
cells = [100]
[material]
model = "linear-elastic"
young = 7.0e10
density = 2700.0
[boundary]
left = { kind = "pressure", value = 1.0e8 }
right = { kind = "free" }
[time]
output_transits = [20, 40]
"#;

/// A 2:1 plate of aluminium hit on the middle of its left edge (no exact solution: the
/// converged reference).
const WIDE_PLATE: &str = r#"
name = "wide-plate"
dim = 2
[domain]
length = [3.0, 1.5]
cells = [20, 10]
[material]
model = "linear-elastic"
young = 7.0e10
poisson = 0.33
density = 2700.0
[boundary]
left = { kind = "normal-velocity", value = 2.0, from = 0.5, to = 1.0 }
[time]
output_transits = [6, 12]
"#;

/// The standing wave of `smooth-bar` on a 3 m aluminium bar: an exact smooth solution.
const SMOOTH_ALU: &str = r#"
name = "smooth-alu"
dim = 1
[domain]
length = [3.0]
cells = [150]
[material]
model = "linear-elastic"
young = 7.0e10
density = 2700.0
[initial]
standing_wave = { amplitude = 2.0, modes = [1] }
[boundary]
left = { kind = "symmetry" }
right = { kind = "symmetry" }
[time]
output_times = [0.2e-3, 0.4e-3]
"#;

/// Write `text` as `<dir>/<name>.toml` and return its path.
fn scene_file(dir: &std::path::Path, name: &str, text: &str) -> String {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The run of `method` in a summary.json or provenance.json `runs` array.
fn run_of<'a>(runs: &'a serde_json::Value, method: &str) -> &'a serde_json::Value {
    runs.as_array()
        .unwrap()
        .iter()
        .find(|r| r["method"] == method || r["options"]["method"] == method)
        .unwrap_or_else(|| panic!("no {method} run in {runs}"))
}

/// A run with non-default options records each of them (summary.json per run,
/// provenance.json, the resolved scene.toml); `impact run --from` its folder repeats it:
/// the same options and the same numbers, bit for bit, at every output time.
#[test]
fn run_records_its_configuration_and_from_repeats_it_exactly() {
    let root = tmp("provenance-from");
    let (a, b) = (root.join("a"), root.join("b"));
    let o = impact(&[
        "run",
        "bar",
        "--shape",
        "gimp",
        "--cells",
        "90",
        "--points-per-cell",
        "2",
        "--courant",
        "0.5",
        "--quiet",
        "--out",
        a.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let record = json(&a.join("provenance.json"));
    assert_eq!(record["command"], "run");
    assert_eq!(record["impact_version"], env!("CARGO_PKG_VERSION"));
    let commit = record["git_commit"].as_str().unwrap();
    let hash = commit.trim_end_matches("-dirty");
    assert!(
        commit == "unknown" || (hash.len() == 40 && hash.chars().all(|c| c.is_ascii_hexdigit())),
        "{commit}"
    );
    let argv: Vec<&str> = record["argv"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(
        argv.windows(2).any(|w| w == ["--shape", "gimp"]),
        "{argv:?}"
    );
    assert!(record["machine"]["cores"].as_u64().unwrap() >= 1);
    assert!(!record["machine"]["cpu_model"].as_str().unwrap().is_empty());
    assert_eq!(record["allow_unstable"], false);
    assert!(record["reference"].as_str().unwrap().contains("exact"));
    assert_eq!(record["material"]["young"], 2.0e11);
    assert_eq!(record["boundary"]["left"]["kind"], "pressure");
    assert!(record["wall_s"].as_f64().unwrap() > 0.0);
    let summary = json(&a.join("summary.json"));
    for runs in [&summary["runs"], &record["runs"]] {
        let mpm = &run_of(runs, "mpm")["options"];
        assert_eq!(mpm["shape"], "gimp");
        assert_eq!(mpm["frame"], "total-lagrangian");
        assert_eq!(mpm["stress_update"], "usl");
        assert_eq!(mpm["points_per_cell"], 2);
        assert_eq!(mpm["courant"], 0.5);
        let dgmpm = &run_of(runs, "dgmpm")["options"];
        assert_eq!(dgmpm["integrator"], "euler");
        assert_eq!(dgmpm["update"], "nodal");
        assert_eq!(dgmpm["riemann"], "approximate");
        assert!(dgmpm.get("flux").is_none(), "no flux in 1D: {dgmpm}");
        assert!(dgmpm.get("shape").is_none(), "{dgmpm}");
    }
    // the resolved scene: the overrides and every method option written out
    let scene = Scene::from_file(&a.join("scene.toml")).unwrap();
    assert_eq!(scene.domain.cells, [90]);
    assert_eq!(scene.domain.points_per_cell, 2);
    assert_eq!(scene.mpm.shape.map(|s| s.name()), Some("gimp"));
    assert_eq!(scene.dgmpm.courant, 0.5);
    assert_eq!(scene.fem.courant, 0.5);
    // the same configuration again, from the folder
    let o = impact(&[
        "run",
        "--from",
        a.to_str().unwrap(),
        "--quiet",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let again = json(&b.join("summary.json"));
    let (first, second) = (
        summary["runs"].as_array().unwrap(),
        again["runs"].as_array().unwrap(),
    );
    assert_eq!(first.len(), 3);
    assert_eq!(first.len(), second.len());
    for (x, y) in first.iter().zip(second) {
        assert_eq!(x["options"], y["options"]);
        assert_eq!(x["steps"], y["steps"]);
        assert_eq!(x["cells"], y["cells"]);
        // every metric at every output time, exactly
        assert_eq!(x["times"], y["times"], "{}", x["method"]);
    }
    let record = json(&b.join("provenance.json"));
    assert!(record["scene_source"]
        .as_str()
        .unwrap()
        .starts_with("--from"));
    // a second run with another shape is told apart from its folder
    let c = root.join("c");
    let o = impact(&[
        "run",
        "bar",
        "--method",
        "mpm",
        "--shape",
        "bspline2",
        "--cells",
        "90",
        "--no-files",
        "--quiet",
        "--out",
        c.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let other = json(&c.join("summary.json"));
    assert_eq!(
        run_of(&other["runs"], "mpm")["options"]["shape"],
        "bspline2"
    );
    // --from takes no option flags, and only an `impact run` folder
    let o = impact(&["run", "--from", a.to_str().unwrap(), "--cells", "10"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--cells") && text(&o).contains("--from"));
    let o = impact(&["run", "--from", root.join("none").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("provenance.json"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&root);
}

/// Work-precision on a bar a user wrote (another material and length) with a method flag
/// the ladder does not vary: the reference is the exact solution and is stated, every MPM
/// configuration runs MUSL, DGMPM at Courant 1 is exact to round-off (as on the paper's
/// bar) and FEM converges; the folder holds the provenance and the resolved scene.
#[test]
fn work_precision_on_a_user_bar() {
    let root = tmp("provenance-wp");
    let file = scene_file(&root, "alu-bar", ALU_BAR);
    let out = root.join("wp");
    let o = impact(&[
        "bench",
        "work-precision",
        "--scene",
        &file,
        "--levels",
        "2",
        "--stress-update",
        "musl",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("reference: exact"), "{}", text(&o));
    let record = json(&out.join("provenance.json"));
    assert!(record["reference"].as_str().unwrap().starts_with("exact"));
    assert_eq!(record["scene"], "alu-bar");
    let configs = record["configurations"].as_array().unwrap();
    let mpm: Vec<_> = configs.iter().filter(|c| c["method"] == "mpm").collect();
    assert!(!mpm.is_empty());
    assert!(mpm.iter().all(|c| c["stress_update"] == "musl"));
    let scene = Scene::from_file(&out.join("scene.toml")).unwrap();
    assert_eq!(scene.material.young, 7.0e10);
    let points = json(&out.join("work_precision.json"));
    let points = points.as_array().unwrap();
    assert_eq!(points.len(), 2 * configs.len());
    let errors = |label: &str| -> Vec<f64> {
        points
            .iter()
            .filter(|p| p["config"] == label)
            .map(|p| p["l1_rel"].as_f64().unwrap())
            .collect()
    };
    let dgmpm = errors("dgmpm euler 1ppc C1.0");
    assert!(dgmpm.iter().all(|e| *e < 1e-12), "{dgmpm:?}");
    let fem = errors("fem C0.9");
    assert!(fem[1] < fem[0], "{fem:?}");
    // flags the ladder sets itself are refused, naming the flag
    let o = impact(&[
        "bench",
        "work-precision",
        "--scene",
        &file,
        "--courant",
        "0.5",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--courant"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&root);
}

/// A 1D scene whose ends have no exact solution in this build is either measured against
/// a stated reference or refused before anything runs, saying why: never a ladder of
/// unmeasured errors.
#[test]
fn a_study_states_its_reference_or_why_it_has_none() {
    let root = tmp("provenance-noref");
    let right = ALU_BAR
        .replace("alu-bar", "right-bar")
        .replace(
            "left = { kind = \"pressure\", value = 1.0e8 }",
            "left = { kind = \"free\" }",
        )
        .replace(
            "right = { kind = \"free\" }",
            "right = { kind = \"pressure\", value = 1.0e8 }",
        );
    let file = scene_file(&root, "right-bar", &right);
    let out = root.join("wp");
    let o = impact(&[
        "bench",
        "work-precision",
        "--scene",
        &file,
        "--levels",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    match o.status.code() {
        Some(0) => {
            let record = json(&out.join("provenance.json"));
            let reference = record["reference"].as_str().unwrap();
            assert!(reference.starts_with("exact") || reference.starts_with("converged"));
        }
        Some(2) => {
            let err = text(&o);
            assert!(err.contains("right-bar") && err.contains("a scene with a reference"));
            assert!(!out.exists());
        }
        code => panic!("{code:?}: {}", text(&o)),
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// Convergence on a standing wave a user wrote (another length and material): FEM shows
/// its second order in L2 against the exact solution; on a 2:1 plate hit mid-edge (no
/// exact solution) the ladder runs against the converged reference and says so, with the
/// scene's 2:1 cells kept at each level.
#[test]
fn convergence_on_user_scenes() {
    let root = tmp("provenance-conv");
    let file = scene_file(&root, "smooth-alu", SMOOTH_ALU);
    let out = root.join("smooth");
    let o = impact(&[
        "bench",
        "convergence",
        "--scene",
        &file,
        "--levels",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let levels = json(&out.join("convergence.json"));
    let fem: Vec<f64> = levels
        .as_array()
        .unwrap()
        .iter()
        .filter(|l| l["config"] == "fem C0.9")
        .map(|l| l["l2_stress"].as_f64().unwrap())
        .collect();
    assert_eq!(fem.len(), 3);
    let order = (fem[1] / fem[2]).log2();
    assert!((order - 2.0).abs() < 0.15, "FEM L2 order {order}: {fem:?}");
    assert!(json(&out.join("provenance.json"))["reference"]
        .as_str()
        .unwrap()
        .starts_with("exact"));
    let file = scene_file(&root, "wide-plate", WIDE_PLATE);
    let out = root.join("plate");
    let o = impact(&[
        "bench",
        "convergence",
        "--scene",
        &file,
        "--levels",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("reference: converged"), "{}", text(&o));
    let cells = impact::convergence::level_cells(
        &Scene::from_file(out.join("scene.toml").as_path()).unwrap(),
        2,
    );
    assert_eq!(cells, [64, 32]);
    let _ = std::fs::remove_dir_all(&root);
}

/// The stability sweep on a user's bar finds DGMPM's von Neumann limits, which depend on
/// the scheme and not the material (1 at one point per cell; 0.686 with two points per cell
/// and Euler); on a user's plate it keeps the cell size and applies `--shape`.
#[test]
fn stability_on_user_scenes() {
    let root = tmp("provenance-stab");
    let file = scene_file(&root, "alu-bar", ALU_BAR);
    let out = root.join("bar");
    let o = impact(&[
        "stability",
        "--scene",
        &file,
        "--steps-1d",
        "1000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let rows = json(&out.join("stability.json"));
    let limit = |ppc: u64, integrator: &str| {
        rows.as_array()
            .unwrap()
            .iter()
            .find(|r| {
                r["method"] == "dgmpm"
                    && r["points_per_cell"] == ppc
                    && r["integrator"] == integrator
                    && r["update"] == "nodal"
            })
            .unwrap()["von_neumann"]
            .as_f64()
            .unwrap()
    };
    assert!((limit(1, "euler") - 1.0).abs() < 1e-4);
    assert!(
        (limit(2, "euler") - 0.6862).abs() < 1e-3,
        "{}",
        limit(2, "euler")
    );
    assert!(rows.as_array().unwrap().iter().all(|r| r["dim"] == 1));
    let file = scene_file(&root, "wide-plate", WIDE_PLATE);
    let out = root.join("plate");
    let o = impact(&[
        "stability",
        "--scene",
        &file,
        "--steps-2d",
        "50",
        "--shape",
        "gimp",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let scene = Scene::from_file(&out.join("scene.toml")).unwrap();
    // cut along x (20 -> 16) and widened along y (10 -> 12): a sweep body holds the 2D
    // sweep's 16×12 cells whatever the scene's extent (`impact::stability::cut_scene`)
    assert_eq!(scene.domain.cells, [16, 12]);
    // the cell size kept: 0.15 m by 0.15 m
    assert!((scene.domain.length[0] - 2.4).abs() < 1e-12);
    assert!((scene.domain.length[1] - 1.8).abs() < 1e-12);
    let record = json(&out.join("provenance.json"));
    let configs = record["configurations"].as_array().unwrap();
    assert!(configs
        .iter()
        .filter(|c| c["method"] == "mpm")
        .all(|c| c["shape"] == "gimp"));
    // the sweep's own variables are refused as flags
    let o = impact(&["stability", "--scene", &file, "--courant", "0.5"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--courant"));
    // a Saint-Venant-Kirchhoff plate: the CTU configurations are skipped, each with its
    // reason, and the others measured
    let svk = WIDE_PLATE
        .replace("linear-elastic", "svk")
        .replace("wide-plate", "svk-wide");
    let file = scene_file(&root, "svk-wide", &svk);
    let out = root.join("svk");
    let o = impact(&[
        "stability",
        "--scene",
        &file,
        "--steps-2d",
        "30",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains(
            "skipped: 2D dgmpm 1ppc euler ctu: invalid scene value for `dgmpm.flux (--flux)`"
        ),
        "{}",
        text(&o)
    );
    let rows = json(&out.join("stability.json"));
    let rows = rows.as_array().unwrap();
    assert!(rows.iter().all(|r| r["flux"] != "ctu"));
    assert!(rows
        .iter()
        .any(|r| r["method"] == "dgmpm" && r["flux"] == "dcu"));
    let _ = std::fs::remove_dir_all(&root);
}

/// `impact check --json` (no output folder) carries the provenance inline: command line,
/// commit, the options of both runs and the resolved scene.
#[test]
fn check_json_carries_its_provenance() {
    let root = tmp("provenance-check");
    std::fs::create_dir_all(&root).unwrap();
    let file = root.join("check.json");
    let o = impact(&[
        "check",
        "bar",
        "--against",
        "gimp",
        "--mpm-points-per-cell",
        "2",
        "--quiet",
        "--json",
        file.to_str().unwrap(),
    ]);
    assert!(o.status.code().is_some_and(|c| c <= 1), "{}", text(&o));
    let doc = json(&file);
    let record = &doc["provenance"];
    assert_eq!(record["command"], "check");
    assert!(record["git_commit"].as_str().is_some());
    assert!(record["reference"].as_str().unwrap().starts_with("exact"));
    let mpm = &run_of(&record["runs"], "mpm")["options"];
    assert_eq!(mpm["shape"], "gimp");
    assert_eq!(mpm["points_per_cell"], 2);
    assert_eq!(doc["reports"][0]["mpm"]["options"], *mpm);
    assert_eq!(record["resolved_scene"]["name"], "bar");
    let _ = std::fs::remove_dir_all(&root);
}

//! `impact bench work-precision` on a short ladder: every configuration is run at every
//! level with its own process, errors behave as the methods do (DGMPM at Courant 1 is exact
//! on the bar; the others converge), and the files are written.
use std::process::Command;

#[test]
fn work_precision_ladder_on_the_bar() {
    let out = std::env::temp_dir().join(format!("impact-wp-{}", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args([
            "bench",
            "work-precision",
            "--scene",
            "bar",
            "--levels",
            "3",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(stdout.contains("is reached fastest by"), "{stdout}");
    let points: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("work_precision.json")).unwrap())
            .unwrap();
    let points = points.as_array().unwrap();
    let configs =
        impact::work_precision::configurations(&impact_core::Scene::builtin("bar").unwrap());
    assert_eq!(points.len(), 3 * configs.len());
    for c in &configs {
        let mine: Vec<&serde_json::Value> = points
            .iter()
            .filter(|p| p["config"] == c.label.as_str())
            .collect();
        assert_eq!(mine.len(), 3);
        let errors: Vec<f64> = mine.iter().map(|p| p["l1_rel"].as_f64().unwrap()).collect();
        for p in &mine {
            assert!(p["error"].is_null(), "{}: {}", c.label, p["error"]);
            assert!(
                p["peak_rss_mib"].as_f64().unwrap() > 0.0
                    && p["updates_per_s"].as_f64().unwrap() > 0.0
            );
        }
        // DGMPM at Courant 1 is exact on the bar: Euler with one point per cell, RK2 with any
        if c.label.starts_with("dgmpm") && c.label.ends_with("C1.0") {
            assert!(errors.iter().all(|e| *e < 1e-12), "{}: {errors:?}", c.label);
        } else {
            assert!(errors[2] < errors[0], "{}: {errors:?}", c.label);
        }
    }
    let csv = std::fs::read_to_string(out.join("work_precision.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3 * configs.len());
    assert_eq!(
        &std::fs::read(out.join("work_precision.png")).unwrap()[..4],
        b"\x89PNG"
    );
    // the summary of the ladder on disk: the same sentence as the run printed, and (the bar
    // has exact configurations) a second one without them
    let again = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(["bench", "work-precision", "--summarize"])
        .arg(&out)
        .output()
        .unwrap();
    let summary = String::from_utf8_lossy(&again.stdout);
    assert!(again.status.success());
    assert!(stdout.contains(summary.trim()), "{stdout}\n{summary}");
    assert!(
        summary.contains("Without the configurations that are exact on this scene"),
        "{summary}"
    );
    std::fs::remove_dir_all(&out).unwrap();
}

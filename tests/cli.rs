//! The `impact` binary as a user runs it: outputs, overrides, the CI gate, blow-ups.
use crate::common::{impact, json, text, tmp, vtu_text};
use std::path::Path;

#[test]
fn run_bar_writes_every_output_and_the_table() {
    let out = tmp("run");
    let o = impact(&["run", "bar", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    // one row per method and output time
    for m in ["dgmpm", "mpm", "fem"] {
        assert_eq!(
            stdout.lines().filter(|l| l.starts_with(m)).count(),
            3,
            "{stdout}"
        );
    }
    let s = json(&out.join("summary.json"));
    assert_eq!(s["scene"], "bar");
    assert_eq!(s["dim"], 1);
    let runs = s["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    for r in runs {
        for key in [
            "method",
            "courant",
            "points_per_cell",
            "integrator",
            "cells",
            "steps",
            "wall_s",
            "times",
        ] {
            assert!(!r[key].is_null(), "missing {key}");
        }
        let times = r["times"].as_array().unwrap();
        assert_eq!(times.len(), 3);
        for t in times {
            for key in [
                "t",
                "l1_rel",
                "linf_rel",
                "front_width_cells",
                "overshoot_pct",
                "energy_rel",
            ] {
                assert!(t[key].is_number(), "{key} in {t}");
            }
        }
    }
    // DGMPM is exact: the summary says so
    assert!(runs[0]["times"][2]["l1_rel"].as_f64().unwrap() < 1e-12);
    for m in ["dgmpm", "mpm", "fem"] {
        for k in 0..3 {
            let csv = std::fs::read_to_string(out.join(format!("{m}_t{k}.csv"))).unwrap();
            assert!(csv.starts_with(
                "x,x_current,cauchy_stress_xx,velocity_x,reference_cauchy_stress_xx,reference_velocity_x"
            ));
            assert_eq!(csv.lines().count(), 151);
            let vtu = vtu_text(out.join(format!("{m}_t{k}.vtu")));
            assert!(
                vtu.contains("NumberOfPoints=\"150\"") && vtu.contains("Name=\"cauchy_stress\"")
            );
        }
        assert!(out.join(format!("{m}.pvd")).exists());
        assert!(out.join(format!("{m}_grid.pvd")).exists());
        let grid = vtu_text(out.join(format!("{m}_grid_t0.vtu")));
        assert!(grid.contains("NumberOfCells=\"150\""));
    }
    let png = std::fs::read(out.join("stress.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // nothing half-written left behind
    for entry in std::fs::read_dir(&out).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        assert!(!name.contains(".tmp"), "{name}");
    }
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn scene_file_and_flags_override() {
    let out = tmp("file");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bar.toml");
    let o = impact(&[
        "run",
        scene,
        "--quiet",
        "--method",
        "dgmpm,fem",
        "--cells",
        "300",
        "--courant",
        "0.8",
        "--points-per-cell",
        "2",
        "--integrator",
        "rk2",
        "--output-times",
        "1e-4,2e-4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let s = json(&out.join("summary.json"));
    let runs = s["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[0]["method"], "dgmpm");
    assert_eq!(runs[0]["cells"], 300);
    assert_eq!(runs[0]["courant"], 0.8);
    assert_eq!(runs[0]["points_per_cell"], 2);
    assert_eq!(runs[0]["integrator"], "rk2");
    assert_eq!(runs[1]["method"], "fem");
    let t = runs[0]["times"].as_array().unwrap();
    assert_eq!(t.len(), 2);
    assert!((t[1]["t"].as_f64().unwrap() - 2e-4).abs() < 1e-15);
    // --t-end alone truncates the default schedule and ends there
    let o = impact(&[
        "run",
        "bar",
        "--quiet",
        "--method",
        "dgmpm",
        "--t-end",
        "6e-4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let s = json(&out.join("summary.json"));
    let t = s["runs"][0]["times"].as_array().unwrap();
    assert_eq!(t.len(), 2, "0.395 ms kept, 0.79 ms dropped, 0.6 ms added");
    assert!((t[1]["t"].as_f64().unwrap() - 6e-4).abs() < 1e-15);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn check_bar_passes() {
    let o = impact(&["check", "bar"]);
    let out = text(&o);
    assert!(o.status.success(), "{out}");
    assert_eq!(
        out.lines()
            .filter(|l| l.trim_end().ends_with("pass"))
            .count(),
        3,
        "{out}"
    );
    assert!(out.contains("PASS"));
}

/// With DGMPM forced to a smeared setting the gate prints the same figures as the
/// in-process metrics and exits according to its verdict.
#[test]
fn check_prints_the_figures_of_a_smeared_dgmpm() {
    use impact_core::method::{Integrator, MethodKind};
    let o = impact(&[
        "check",
        "bar",
        "--quiet",
        "--dgmpm-points-per-cell",
        "4",
        "--integrator",
        "rk2",
        "--dgmpm-courant",
        "0.3",
    ]);
    let out = text(&o);
    let (scene, problem, reference) = crate::common::bar(150, None);
    let (dg, _) = crate::common::run(
        &problem,
        crate::common::dgmpm(&scene, 0.3, 4, Integrator::Rk2),
        &reference,
    );
    let (mpm, _) = crate::common::run(&problem, scene.method_config(MethodKind::Mpm), &reference);
    let rows: Vec<Vec<String>> = out
        .lines()
        .filter(|l| l.trim_start().starts_with("0.") || l.trim_start().starts_with("1."))
        .map(|l| l.split_whitespace().map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 3, "{out}");
    let mut all_pass = true;
    for (k, row) in rows.iter().enumerate() {
        let parse = |i: usize| row[i].parse::<f64>().unwrap();
        assert!((parse(1) - dg.times[k].front_width_cells.unwrap()).abs() < 1e-3);
        assert!((parse(2) - mpm.times[k].front_width_cells.unwrap()).abs() < 1e-3);
        assert!((parse(3) - dg.times[k].overshoot_pct.unwrap()).abs() < 1e-3);
        assert!((parse(4) - mpm.times[k].overshoot_pct.unwrap()).abs() < 1e-3);
        all_pass &= row[5] == "pass";
    }
    assert!(!all_pass, "a smeared DGMPM front is wider than MPM's");
    assert_eq!(o.status.code(), Some(1), "{out}");
}

/// MPM at Courant 1: refused before any work (its measured limit is 0.708); run anyway
/// (`--allow-unstable`), stopped with method, step, time and place; the frames written
/// before are kept, the summary records the error, and no NaN is written.
#[test]
fn mpm_blow_up_stops_cleanly_and_keeps_frames() {
    let out = tmp("blowup");
    let refused = impact(&["run", "bar", "--quiet", "--method", "mpm", "--courant", "1"]);
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused));
    assert!(text(&refused).contains("measured stable up to Courant 0.70"));
    let o = impact(&[
        "run",
        "bar",
        "--quiet",
        "--allow-unstable",
        "--method",
        "mpm",
        "--courant",
        "1",
        "--output-times",
        "2e-5,4e-4,8e-4",
        "--out",
        out.to_str().unwrap(),
    ]);
    let all = text(&o);
    // exit 3: a blow-up, told apart from bad input (2)
    assert_eq!(o.status.code(), Some(3), "{all}");
    assert!(
        all.contains("mpm blew up at step") && all.contains("t = ") && all.contains("near x = "),
        "{all}"
    );
    let s = json(&out.join("summary.json"));
    assert!(s["runs"][0]["error"].as_str().unwrap().contains("blew up"));
    let csv = std::fs::read_to_string(out.join("mpm_t0.csv")).unwrap();
    assert!(!csv.to_lowercase().contains("nan") && !csv.contains("inf"));
    assert!(!out.join("mpm_t1.csv").exists());
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn check_plate_passes() {
    let o = impact(&["check", "plate"]);
    let out = text(&o);
    assert!(o.status.success(), "{out}");
    assert_eq!(
        out.lines()
            .filter(|l| l.trim_end().ends_with("pass"))
            .count(),
        3,
        "{out}"
    );
}

/// The plate writes the bottom-row profiles, the samples, the grid cells / FEM mesh, the
/// colour map, and states its converged reference.
#[test]
fn run_plate_writes_the_2d_outputs() {
    let out = tmp("plate");
    let o = impact(&["run", "plate", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let s = json(&out.join("summary.json"));
    assert_eq!(s["dim"], 2);
    assert!(s["reference"].as_str().unwrap().contains("264x200"));
    for m in ["dgmpm", "mpm", "fem"] {
        let csv = std::fs::read_to_string(out.join(format!("{m}_t2.csv"))).unwrap();
        assert_eq!(
            csv.lines().count(),
            34,
            "33 cells along the bottom row + header"
        );
        // the measured line with its coordinates and every component
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(
            header,
            [
                "x",
                "y",
                "x_current",
                "y_current",
                "cauchy_stress_xx",
                "cauchy_stress_yy",
                "cauchy_stress_zz",
                "cauchy_stress_xy",
                "velocity_x",
                "velocity_y",
                "reference_cauchy_stress_xx",
                "reference_velocity_x"
            ]
        );
        let (nu, dy) = (0.3, 3.0 / 25.0);
        for row in lines {
            let v: Vec<f64> = row.split(',').map(|c| c.parse().unwrap()).collect();
            // the bottom row's centres
            assert!((v[1] - 0.5 * dy).abs() < 1e-12, "{m}: y = {}", v[1]);
            // plane strain: σ_zz = ν (σ_xx + σ_yy)
            let scale = v[4].abs().max(v[5].abs()).max(1.0);
            assert!(
                (v[6] - nu * (v[4] + v[5])).abs() <= 1e-9 * scale,
                "{m}: {row}"
            );
        }
        let samples = vtu_text(out.join(format!("{m}_t2.vtu")));
        for name in [
            "reference_position",
            "reference_cauchy_stress_xx",
            "reference_velocity_x",
        ] {
            assert!(samples.contains(&format!("Name=\"{name}\"")), "{m}: {name}");
        }
        let grid = vtu_text(out.join(format!("{m}_grid_t2.vtu")));
        assert!(grid.contains("NumberOfPoints=\"884\"") && grid.contains("NumberOfCells=\"825\""));
        let times = s["runs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["method"] == m)
            .unwrap()["times"]
            .clone();
        let t = &times[2];
        assert!(
            (t["front_position"].as_f64().unwrap() - t["front_exact"].as_f64().unwrap()).abs()
                < 0.25
        );
    }
    // the FEM mesh carries nodal velocities, named apart from the cell averages
    let fem = vtu_text(out.join("fem_grid_t2.vtu"));
    assert!(
        fem.contains("<PointData>\n        <DataArray type=\"Float64\" Name=\"nodal_velocity\"")
    );
    assert!(fem.contains("<CellData>") && fem.matches("Name=\"velocity\"").count() == 1);
    for png in ["stress.png", "stress_map.png"] {
        let bytes = std::fs::read(out.join(png)).unwrap();
        assert_eq!(&bytes[..4], b"\x89PNG");
    }
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn flux_is_refused_in_1d() {
    let o = impact(&["run", "bar", "--flux", "ctu"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("--flux") && text(&o).contains("only in 2D"));
}

/// A plate too fine for its 4× converged reference runs without one (errors not computed)
/// instead of exhausting memory.
#[test]
fn a_fine_plate_runs_without_a_reference_it_cannot_afford() {
    let out = tmp("fine");
    let o = impact(&[
        "run",
        "plate",
        "--cells",
        "1000",
        "--method",
        "fem",
        "--t-end",
        "1e-6",
        "--no-files",
        "--out",
        out.to_str().unwrap(),
    ]);
    let all = text(&o);
    assert!(o.status.success(), "{all}");
    assert!(
        all.contains("no converged reference") && all.contains("exceeds"),
        "{all}"
    );
    let s = json(&out.join("summary.json"));
    assert!(s["reference"].as_str().unwrap().starts_with("none"));
    assert_eq!(s["runs"][0]["cells"], 1000 * 758);
    std::fs::remove_dir_all(&out).unwrap();
}

/// `check --against all-mpm` prints one verdict per MPM shape function with FLIP (the
/// scene's transfer), then per shape with PIC and with APIC (not CPDI), and the MPM front
/// widths it prints are those `impact run --method mpm --shape <shape> --transfer <t>`
/// records against the same reference.
#[test]
fn check_against_all_mpm_prints_every_variant_with_the_run_figures() {
    for scene in ["bar", "svk-bar", "plate"] {
        let o = impact(&["check", scene, "--against", "all-mpm"]);
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(!stdout.is_empty(), "{}", text(&o));
        let verdicts: Vec<&str> = stdout
            .lines()
            .filter(|l| l.starts_with("PASS") || l.starts_with("FAIL"))
            .collect();
        let shapes = impact_core::method::MpmShape::NAMES;
        let variants: Vec<(&str, &str)> = ["flip", "pic", "apic"]
            .into_iter()
            .flat_map(|t| shapes.iter().map(move |s| (*s, t)))
            .filter(|&(s, t)| !(t == "apic" && s == "cpdi"))
            .collect();
        assert_eq!(verdicts.len(), variants.len(), "{stdout}");
        // the exit status is the conjunction of the verdicts
        assert_eq!(
            o.status.success(),
            verdicts.iter().all(|v| v.starts_with("PASS")),
            "{stdout}"
        );
        let blocks: Vec<&str> = stdout.split("check ").skip(1).collect();
        for (block, (shape, transfer)) in blocks.iter().zip(variants.iter().copied()) {
            let label = match transfer {
                "flip" => shape.to_string(),
                t => format!("{shape} {t}"),
            };
            assert!(block.contains(&format!("usl, {label})")), "{block}");
            let printed: Vec<String> = block
                .lines()
                .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()))
                .map(|l| l.split_whitespace().nth(2).unwrap().to_string())
                .collect();
            let out = tmp(&format!("against-{scene}-{shape}-{transfer}"));
            // the same judge as the check's (FEM where there is no exact solution: the
            // default of a run of MPM alone would be DGMPM)
            let r = impact(&[
                "run",
                scene,
                "--method",
                "mpm",
                "--shape",
                shape,
                "--reference",
                "fem",
                "--transfer",
                transfer,
                "--no-files",
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(r.status.success(), "{}", text(&r));
            let s = json(&out.join("summary.json"));
            let recorded: Vec<String> = s["runs"][0]["times"]
                .as_array()
                .unwrap()
                .iter()
                .map(|t| {
                    t["front_width_cells"]
                        .as_f64()
                        .map_or("-".into(), |w| format!("{w:.3}"))
                })
                .collect();
            assert_eq!(printed, recorded, "{scene} {shape} {transfer}");
        }
    }
}

/// `--order 2 --limiter <l>` runs DGMPM's second-order scheme, recorded in provenance.json
/// and the resolved scene.toml, and re-running that scene file gives the same fields; at
/// Courant 0.5 it differs from order 1. A limiter with order 1 is refused with the field and
/// the reason.
#[test]
fn order_two_runs_is_recorded_and_a_limiter_needs_it() {
    let (a, b, c) = (tmp("order2"), tmp("order2-again"), tmp("order1"));
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["run", "--method", "dgmpm", "--courant", "0.5", "--quiet"];
        args.extend_from_slice(extra);
        args.extend(["--out", out.to_str().unwrap()]);
        let o = impact(&args);
        assert!(o.status.success(), "{}", text(&o));
        std::fs::read_to_string(out.join("dgmpm_t2.csv")).unwrap()
    };
    let second = run(&["bar", "--order", "2", "--limiter", "superbee"], &a);
    let p = json(&a.join("provenance.json"));
    let options = &p["runs"][0]["options"];
    assert_eq!(
        (options["order"].as_u64(), options["limiter"].as_str()),
        (Some(2), Some("superbee"))
    );
    let scene = a.join("scene.toml");
    assert_eq!(run(&[scene.to_str().unwrap()], &b), second);
    assert_ne!(run(&["bar"], &c), second);
    let o = impact(&[
        "run",
        "block-wave",
        "--limiter",
        "mc",
        "--quiet",
        "--out",
        c.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("dgmpm.limiter (--limiter)") && text(&o).contains("order = 2"),
        "{}",
        text(&o)
    );
}

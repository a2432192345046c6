//! Faults while `impact run` writes its folder: SIGTERM and SIGINT leave the previous
//! complete folder and no temporary file; `kill -9` leaves no partial file under a final
//! name and the next run cleans up; a second run into a folder being written is refused;
//! a re-run leaves no file of the earlier run. Each folder that exists holds exactly the
//! files its `manifest.json` lists.
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn impact() -> Command {
    Command::new(env!("CARGO_BIN_EXE_impact"))
}

/// A fresh folder for test `name`, removed when dropped (kept if the test fails).
fn scratch(name: &str) -> crate::common::TmpPath {
    let dir = crate::common::tmp(&format!("faults-{name}"));
    std::fs::create_dir_all(&*dir).unwrap();
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The folder holds exactly the files its manifest lists, with their sizes, and a
/// summary that names `methods`.
fn assert_complete(dir: &Path, methods: &[&str]) {
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
    let mut listed: Vec<String> = manifest["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let name = f["name"].as_str().unwrap().to_string();
            let size = std::fs::metadata(dir.join(&name)).unwrap().len();
            assert_eq!(size, f["bytes"].as_u64().unwrap(), "{name}");
            name
        })
        .collect();
    listed.push("manifest.json".into());
    listed.sort();
    assert_eq!(names(dir), listed);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let ran: Vec<&str> = summary["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["method"].as_str().unwrap())
        .collect();
    assert_eq!(ran, methods);
    for entry in names(dir) {
        assert!(!entry.contains(".tmp"), "{entry}");
    }
}

/// Nothing but the target folder and its lock file beside it.
fn assert_clean(root: &Path) {
    assert_eq!(names(root), [".out.lock", "out"]);
}

/// A quick complete run of the bar into `out`.
fn quick_run(out: &Path, methods: &str) {
    let o = impact()
        .args(["run", "bar", "--quiet", "--method", methods, "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A run of several seconds (the bar at 20,000 cells to 1 ms, three methods).
fn slow_run(out: &Path) -> Child {
    impact()
        .args([
            "run", "bar", "--quiet", "--cells", "20000", "--t-end", "1e-3", "--out",
        ])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Wait until the run's staging folder holds a file (it is writing).
fn wait_for_writing(root: &Path) {
    let start = Instant::now();
    loop {
        let staging = names(root)
            .into_iter()
            .find(|n| n.starts_with(".out.staging-"));
        if let Some(s) = staging {
            if std::fs::read_dir(root.join(s))
                .map(|mut d| d.next().is_some())
                .unwrap_or(false)
            {
                return;
            }
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the run never started writing"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([format!("-{name}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

fn wait(mut child: Child, limit: Duration) -> (Option<i32>, String) {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            if let Some(mut e) = child.stderr.take() {
                let _ = e.read_to_string(&mut err);
            }
            return (status.code(), err);
        }
        assert!(start.elapsed() < limit, "the run did not stop");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn sigterm_and_sigint_keep_the_previous_complete_folder() {
    for name in ["TERM", "INT"] {
        let root = scratch(&format!("signal-{name}"));
        let out = root.join("out");
        quick_run(&out, "dgmpm");
        assert_complete(&out, &["dgmpm"]);
        let before = std::fs::read(out.join("summary.json")).unwrap();
        let child = slow_run(&out);
        wait_for_writing(&root);
        signal(&child, name);
        let (code, err) = wait(child, Duration::from_secs(30));
        assert_eq!(code, Some(130), "{err}");
        assert!(err.contains("stopped by a signal"), "{err}");
        assert_clean(&root);
        assert_complete(&out, &["dgmpm"]);
        assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), before);
    }
}

#[test]
fn kill_nine_leaves_no_partial_file_and_the_next_run_cleans_up() {
    let root = scratch("kill9");
    let out = root.join("out");
    quick_run(&out, "dgmpm,fem");
    let child = slow_run(&out);
    wait_for_writing(&root);
    signal(&child, "KILL");
    let (code, _) = wait(child, Duration::from_secs(30));
    assert_eq!(code, None, "killed by a signal");
    // the target is the previous complete run; the staging folder is left behind
    assert_complete(&out, &["dgmpm", "fem"]);
    assert!(names(&root).iter().any(|n| n.starts_with(".out.staging-")));
    quick_run(&out, "mpm");
    assert_clean(&root);
    assert_complete(&out, &["mpm"]);
}

#[test]
fn a_second_run_into_a_folder_being_written_is_refused() {
    let root = scratch("concurrent");
    let out = root.join("out");
    let first = slow_run(&out);
    wait_for_writing(&root);
    let second = impact()
        .args(["run", "bar", "--quiet", "--method", "dgmpm", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(2), "{err}");
    assert!(err.contains("another impact run is writing"), "{err}");
    let (code, err) = wait(first, Duration::from_secs(300));
    assert_eq!(code, Some(0), "{err}");
    assert_clean(&root);
    assert_complete(&out, &["dgmpm", "mpm", "fem"]);
}

#[test]
fn a_rerun_with_fewer_methods_or_outputs_leaves_nothing_of_the_earlier_run() {
    let root = scratch("rerun");
    let out = root.join("out");
    quick_run(&out, "dgmpm,mpm,fem");
    assert!(out.join("fem_t2.csv").exists());
    let o = impact()
        .args([
            "run",
            "bar",
            "--quiet",
            "--method",
            "dgmpm",
            "--output-times",
            "1e-4",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_clean(&root);
    assert_complete(&out, &["dgmpm"]);
    assert!(!out.join("fem_t0.csv").exists() && !out.join("dgmpm_t1.csv").exists());
    assert!(out.join("dgmpm_t0.csv").exists());
}

#[test]
fn a_folder_that_is_not_an_impact_output_is_never_replaced() {
    let root = scratch("foreign");
    let out = root.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = impact()
        .args(["run", "bar", "--quiet", "--method", "dgmpm", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("not an impact output folder"), "{err}");
    assert_eq!(names(&out), ["notes.txt"]);
}

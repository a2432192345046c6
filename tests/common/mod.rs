//! Helpers shared by the integration tests.
#![allow(dead_code)]
use impact::convergence::{ladder, orders, FieldErrors, Level};
use impact::run::{run_method, RunRecord, Silent};
use impact::work_precision::configurations;
use impact_core::method::{Integrator, MethodConfig, MethodKind};
use impact_core::reference::Reference;
use impact_core::{Blowup, Problem, Scene};

/// The paper's bar with `cells` cells and output times in seconds.
pub fn bar(cells: usize, times: Option<Vec<f64>>) -> (Scene, Problem<1>, Reference) {
    let mut scene = Scene::builtin("bar").unwrap();
    scene.domain.cells = vec![cells];
    let mut problem = Problem::<1>::from_scene(&scene).unwrap();
    if let Some(t) = times {
        problem.set_schedule(Some(t), None).unwrap();
    }
    let reference = Reference::for_problem(&problem).unwrap();
    (scene, problem, reference)
}

/// A configuration of `kind` from the scene, changed by `f`.
pub fn config(scene: &Scene, kind: MethodKind, f: impl FnOnce(&mut MethodConfig)) -> MethodConfig {
    let mut c = scene.method_config(kind);
    f(&mut c);
    c
}

/// Run and return the record and the blow-up, if any.
pub fn run(
    problem: &Problem<1>,
    config: MethodConfig,
    reference: &Reference,
) -> (RunRecord, Option<Blowup>) {
    run_method(problem, config, Some(reference), &mut Silent).unwrap()
}

/// DGMPM configuration shortcut.
pub fn dgmpm(scene: &Scene, courant: f64, ppc: usize, integrator: Integrator) -> MethodConfig {
    config(scene, MethodKind::Dgmpm, |c| {
        c.courant = courant;
        c.points_per_cell = ppc;
        if let Some(o) = c.dgmpm_mut() {
            o.integrator = integrator;
        }
    })
}

/// The `impact` binary run on `args`.
pub fn impact(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(args)
        .output()
        .expect("run impact")
}

/// A fresh (removed if present) temporary path for test `name` of this process, removed
/// again when the guard is dropped, unless the test is panicking (then kept to inspect).
pub fn tmp(name: &str) -> TmpPath {
    let dir = std::env::temp_dir().join(format!("impact-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_file(&dir);
    TmpPath(dir)
}

/// Point the reference cache (read from `IMPACT_CACHE_DIR`) at folder `name` in Cargo's
/// scratch folder for tests (`target/tmp`), emptied at the first call of this test
/// binary's run, so no run leaves a cache behind in `/tmp` and each run starts empty.
pub fn use_fresh_cache(name: &str) {
    static FRESH: std::sync::Once = std::sync::Once::new();
    let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    FRESH.call_once(|| {
        let _ = std::fs::remove_dir_all(&cache);
    });
    std::env::set_var("IMPACT_CACHE_DIR", &cache);
}

/// A temporary path of [`tmp`] (a folder or a file): what is there is removed when it is
/// dropped (not while the thread panics).
pub struct TmpPath(pub std::path::PathBuf);

impl Drop for TmpPath {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = match self.0.is_dir() {
                true => std::fs::remove_dir_all(&self.0),
                false => std::fs::remove_file(&self.0),
            };
        }
    }
}

impl std::ops::Deref for TmpPath {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for TmpPath {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::ffi::OsStr> for TmpPath {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.as_os_str()
    }
}

/// A run's stdout and stderr, for assertion messages.
pub fn text(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A `.vtu` as text (its raw appended binary section read lossily).
pub fn vtu_text(path: std::path::PathBuf) -> String {
    String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned()
}

/// A JSON file, parsed.
pub fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Which error of a run (the convergence suites: `smooth.rs`, `oblique.rs`).
pub type Error = fn(&FieldErrors) -> f64;

pub fn measured<const D: usize>(scene: &str, labels: &[&str], levels: usize) -> Vec<Level> {
    let scene = Scene::builtin(scene).unwrap();
    let configs: Vec<_> = configurations(&scene)
        .into_iter()
        .filter(|c| labels.contains(&c.label.as_str()))
        .collect();
    assert_eq!(
        configs.len(),
        labels.len(),
        "unknown label among {labels:?}"
    );
    let runs = ladder::<D>(&scene, &configs, levels).unwrap();
    print!("{}", impact::convergence::table(&runs));
    runs
}

/// Mean observed order of the last two refinements of `label`'s `error`.
pub fn order(runs: &[Level], label: &str, error: Error) -> f64 {
    let levels: Vec<&Level> = runs.iter().filter(|r| r.config == label).collect();
    let o = orders(&levels, error);
    assert!(o.len() >= 2, "{label}: {} levels measured", levels.len());
    let tail = &o[o.len() - 2..];
    tail.iter().sum::<f64>() / 2.0
}

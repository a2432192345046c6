//! What produced an output folder: `provenance.json` and `scene.toml`, written into the
//! staging folder before it is committed (so they appear with the results or not at all).
//!
//! - `scene.toml`: the resolved scene: every field after the scene file's defaults and the
//!   command-line overrides (cells, load, schedule, plasticity), edges not given written as
//!   free, the point layout, with each method's section holding the options its run used (the sections of methods not run keep the scene's).
//!   `Scene::parse_toml` reads it back to the same scene: floats are written in Rust's
//!   shortest round-trip form.
//! - `provenance.json`: the command line, impact's version and git commit (`-dirty` when the
//!   tracked tree had changes at build time, `unknown` without git), the options of every
//!   run ([`MethodOptionsRecord`]), the material and boundary conditions, the reference
//!   used (or why none), `allow_unstable`, the machine and the wall times.
//!
//! `impact run --from <folder>` reads both back ([`Provenance::read`], [`replay_study`]) and
//! runs the same configuration.
use crate::study::Study;
use anyhow::{Context, Result};
use impact_core::method::{
    EdgeTreatment, Integrator, MethodConfig, MethodKind, MethodOptions, MpmFrame, MpmShape,
    MpmTransfer, PointUpdate, RiemannSolver, SchemeOrder, StressUpdate, TransverseFlux,
    WaveLimiter,
};
use impact_core::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// File name of the provenance record.
pub const PROVENANCE_FILE: &str = "provenance.json";
/// File name of the resolved scene.
pub const SCENE_FILE: &str = "scene.toml";

/// impact's git commit at build time (`build.rs`).
pub const GIT_COMMIT: &str = env!("IMPACT_GIT_COMMIT");

/// The options one run used: the method, the shared Courant number and points per cell,
/// and the method's own options (absent for the other methods; DGMPM's `flux` and `edges`
/// only in 2D). Names are those of scene files and flags.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodOptionsRecord {
    /// Method.
    pub method: MethodKind,
    /// Courant number.
    pub courant: f64,
    /// Points per cell (FEM has none: 1).
    pub points_per_cell: usize,
    /// DGMPM time integrator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<Integrator>,
    /// DGMPM point update.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub update: Option<PointUpdate>,
    /// DGMPM transverse flux (2D).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flux: Option<TransverseFlux>,
    /// DGMPM Riemann solver.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub riemann: Option<RiemannSolver>,
    /// DGMPM CTU edge treatment (2D).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edges: Option<EdgeTreatment>,
    /// DGMPM spatial order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order: Option<SchemeOrder>,
    /// DGMPM wave limiter (order 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limiter: Option<WaveLimiter>,
    /// MPM stress update.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stress_update: Option<StressUpdate>,
    /// MPM frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<MpmFrame>,
    /// MPM shape functions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<MpmShape>,
    /// MPM velocity transfer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transfer: Option<MpmTransfer>,
    /// MPM's FLIP share (`transfer = "blend"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip_fraction: Option<f64>,
}

impl MethodOptionsRecord {
    /// The record of `config` in dimension `dim`.
    pub fn of(config: &MethodConfig, dim: usize) -> Self {
        let mut r = Self {
            method: config.kind(),
            courant: config.courant,
            points_per_cell: match config.kind() {
                MethodKind::Fem => 1,
                _ => config.points_per_cell,
            },
            integrator: None,
            update: None,
            flux: None,
            riemann: None,
            edges: None,
            order: None,
            limiter: None,
            stress_update: None,
            frame: None,
            shape: None,
            transfer: None,
            flip_fraction: None,
        };
        match config.options {
            MethodOptions::Dgmpm(o) => {
                r.integrator = Some(o.integrator);
                r.update = Some(o.update);
                r.riemann = Some(o.riemann);
                r.order = Some(o.order);
                r.limiter = o.wave_limiter();
                if dim > 1 {
                    r.flux = Some(o.flux);
                    r.edges = Some(o.edges);
                }
            }
            MethodOptions::Mpm(o) => {
                r.stress_update = Some(o.stress_update);
                r.frame = Some(o.frame);
                r.shape = Some(o.shape);
                r.transfer = Some(o.transfer);
                r.flip_fraction = o.flip_fraction;
            }
            MethodOptions::Fem(_) => {}
        }
        r
    }
}

/// The machine a command ran on.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Machine {
    /// Logical cores available to the process.
    pub cores: usize,
    /// CPU model (`model name` of `/proc/cpuinfo`), or `unknown`.
    pub cpu_model: String,
    /// Operating system (`PRETTY_NAME` of `/etc/os-release`, else Rust's OS name).
    pub os: String,
    /// Kernel release (`/proc/sys/kernel/osrelease`), if known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kernel: Option<String>,
    /// CPU architecture.
    pub arch: String,
    /// `RAYON_NUM_THREADS` if set (the worker threads of the parallel loops).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rayon_num_threads: Option<String>,
}

impl Machine {
    /// This machine.
    pub fn detect() -> Self {
        let cpu_model = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split_once(':'))
                    .map(|(_, v)| v.trim().to_string())
            })
            .unwrap_or_else(|| "unknown".into());
        let os = std::fs::read_to_string("/etc/os-release")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find_map(|l| l.strip_prefix("PRETTY_NAME="))
                    .map(|v| v.trim_matches('"').to_string())
            })
            .unwrap_or_else(|| std::env::consts::OS.to_string());
        Self {
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            cpu_model,
            os,
            kernel: std::fs::read_to_string("/proc/sys/kernel/osrelease")
                .ok()
                .map(|s| s.trim().to_string()),
            arch: std::env::consts::ARCH.to_string(),
            rayon_num_threads: std::env::var("RAYON_NUM_THREADS").ok(),
        }
    }
}

/// The flags of `impact run` that are not scene or method options, kept for
/// `impact run --from`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunFlags {
    /// Methods, in the order run.
    pub methods: Vec<MethodKind>,
    /// `--no-reference`.
    pub no_reference: bool,
    /// `--no-files`.
    pub no_files: bool,
    /// `--vtu` (`binary` or `ascii`).
    pub vtu: String,
}

/// One run's options and times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunEntry {
    /// The options used.
    pub options: MethodOptionsRecord,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// The blow-up that stopped it, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// `provenance.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Provenance {
    /// The command (`run`, `bench work-precision`, ...).
    pub command: String,
    /// The command line, as the process received it.
    pub argv: Vec<String>,
    /// impact's version (`CARGO_PKG_VERSION`).
    pub impact_version: String,
    /// impact's git commit at build time (`-dirty`: tracked files had changes; `unknown`:
    /// built without git).
    pub git_commit: String,
    /// Scene name (absent for commands that take no scene).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// The scene as given on the command line (a shipped name or a file path).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_source: Option<String>,
    /// The resolved scene's file in this folder ([`SCENE_FILE`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<String>,
    /// The resolved scene itself, for outputs without a folder (`impact check --json`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolved_scene: Option<Scene>,
    /// The command-line overrides given (flag names as typed).
    #[serde(default)]
    pub overrides: Vec<String>,
    /// The material of the resolved scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<impact_core::scene::MaterialSpec>,
    /// The boundary conditions (loads, histories, segments) of the resolved scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary: Option<impact_core::scene::BoundarySpec>,
    /// Output times in seconds.
    #[serde(default)]
    pub output_times_s: Vec<f64>,
    /// The reference the errors are measured against, or why there is none.
    pub reference: String,
    /// Whether `--allow-unstable` let a configuration above its stability limit run.
    #[serde(default)]
    pub allow_unstable: bool,
    /// `impact run`'s own flags (for `impact run --from`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunFlags>,
    /// Every run: options and times.
    #[serde(default)]
    pub runs: Vec<RunEntry>,
    /// The options of a study's configurations (ladders and sweeps), when it has no runs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub configurations: Vec<MethodOptionsRecord>,
    /// What else the command reported (configurations skipped, with their reasons).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The machine.
    pub machine: Machine,
    /// Start of the command (seconds since the Unix epoch).
    pub started_unix_s: u64,
    /// Wall time of the whole command until the folder was written (s).
    pub wall_s: f64,
}

/// Seconds since the Unix epoch.
pub fn unix_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

impl Provenance {
    /// A record of `command` started at `started` (argv, version, commit, machine); the
    /// caller fills the scene, runs and reference.
    pub fn new(command: &str, started: &Clock) -> Self {
        Self {
            command: command.to_string(),
            argv: std::env::args().collect(),
            impact_version: env!("CARGO_PKG_VERSION").to_string(),
            git_commit: GIT_COMMIT.to_string(),
            scene: None,
            scene_source: None,
            scene_file: None,
            resolved_scene: None,
            overrides: Vec::new(),
            material: None,
            boundary: None,
            output_times_s: Vec::new(),
            reference: "none".into(),
            allow_unstable: false,
            run: None,
            runs: Vec::new(),
            configurations: Vec::new(),
            notes: Vec::new(),
            machine: Machine::detect(),
            started_unix_s: started.unix_s,
            wall_s: 0.0,
        }
    }

    /// Fill the scene fields from `study` (`source`: the scene as given) and write the
    /// resolved scene ([`resolved_scene`]) as `scene.toml` into `dir`.
    pub fn with_study(
        self,
        study: &Study,
        source: &str,
        kinds: &[MethodKind],
        dir: &Path,
    ) -> Result<Self> {
        let scene = resolved_scene(study, kinds);
        write_scene(&dir.join(SCENE_FILE), &scene)?;
        let mut record = self.describe(&scene, study, source);
        record.scene_file = Some(SCENE_FILE.into());
        Ok(record)
    }

    /// Fill the scene fields from `study` without writing a file (`impact check`, whose
    /// JSON report holds the resolved scene itself in `resolved_scene`).
    pub fn with_study_inline(self, study: &Study, source: &str, kinds: &[MethodKind]) -> Self {
        let scene = resolved_scene(study, kinds);
        let mut record = self.describe(&scene, study, source);
        record.resolved_scene = Some(scene);
        record
    }

    fn describe(mut self, scene: &Scene, study: &Study, source: &str) -> Self {
        self.scene = Some(scene.name.clone());
        self.scene_source = Some(source.to_string());
        self.overrides = study.overrides.given();
        self.material = Some(scene.material.clone());
        self.boundary = Some(scene.boundary.clone());
        self.output_times_s = scene.schedule_seconds().0;
        self
    }

    /// Set the wall time since `clock`.
    pub fn finish(&mut self, clock: &Clock) {
        self.wall_s = clock.start.elapsed().as_secs_f64();
    }

    /// Write `provenance.json` into `dir` (atomically), with the wall time since `clock`.
    pub fn write(mut self, dir: &Path, clock: &Clock) -> Result<()> {
        self.wall_s = clock.start.elapsed().as_secs_f64();
        impact_io::write_json(&dir.join(PROVENANCE_FILE), &self)?;
        Ok(())
    }

    /// Read `provenance.json` of `folder`.
    pub fn read(folder: &Path) -> Result<Self> {
        let path = folder.join(PROVENANCE_FILE);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "--from {}: no {PROVENANCE_FILE} in it (allowed: an output folder of `impact \
                 run` written by this version)",
                folder.display()
            )
        })?;
        serde_json::from_str(&text).with_context(|| {
            format!(
                "--from {}: {} is not a provenance record",
                folder.display(),
                path.display()
            )
        })
    }
}

/// When a command started: wall clock and Unix time.
#[derive(Debug, Clone, Copy)]
pub struct Clock {
    start: std::time::Instant,
    unix_s: u64,
}

impl Clock {
    /// Now.
    pub fn start() -> Self {
        Self {
            start: std::time::Instant::now(),
            unix_s: unix_now(),
        }
    }
}

impl Default for Clock {
    fn default() -> Self {
        Self::start()
    }
}

mod scene_file;
pub use scene_file::{replay_study, resolved_scene, write_scene};

//! Scene files (TOML). Unknown fields are rejected by the parser, whose errors name the
//! field path and the expected type; every value is then checked by [`Scene::validate`]
//! (file `validate.rs`), whose errors name the field, the value and what is allowed.
//! A new scene is a TOML file under `scenes/`, listed in [`BUILTIN`].
//!
//! ```toml
//! name = "bar"
//! dim = 1
//! [domain]
//! length = [6.0]
//! cells = [150]
//! points_per_cell = 1
//! [material]
//! model = "linear-elastic"
//! young = 2.0e11
//! poisson = 0.3
//! density = 7800.0
//! [boundary]
//! left = { kind = "pressure", value = 1.0e9 }
//! right = { kind = "free" }
//! [time]
//! output_transits = [50, 100, 200]
//! [dgmpm]
//! courant = 1.0
//! integrator = "euler"
//! ```
use crate::error::CoreError;
use crate::options::{EdgeKind, LayoutKind, LoadShape, MaterialModel, SegmentCover};

mod boundary;
mod sides;
pub use sides::{BoundarySpec, Coordinates, SidesSpec, AXIS_NAMES};
mod initial;
mod layout;
mod metrics;
mod plane_wave;
pub use plane_wave::{PlaneWaveKind, PlaneWaveSpec};
mod method_specs;
mod validate;
pub use method_specs::{DgmpmSpec, FemSpec, MpmSpec};
pub use metrics::{
    check_reference_refinement, LineSpec, MetricsSpec, ReferenceOptions, REFERENCE_REFINEMENTS,
};
use serde::{Deserialize, Serialize};
pub use validate::{
    check_courant, check_output_times, check_points_per_cell, check_work, points_per_axis,
    WorkEstimate, COURANT_RANGE, DEFAULT_WORK_BUDGET, MAX_POINTS, MAX_STRAIN, SI_RANGE,
};

/// A whole scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Scene name (used for the output folder).
    pub name: String,
    /// Spatial dimension, 1, 2 or 3.
    pub dim: usize,
    /// Geometry and discretisation.
    pub domain: Domain,
    /// Material.
    pub material: MaterialSpec,
    /// Boundary conditions per edge.
    pub boundary: BoundarySpec,
    /// Time and output schedule.
    pub time: TimeSpec,
    /// State at `t = 0` (default: at rest).
    #[serde(default)]
    pub initial: Option<InitialSpec>,
    /// DGMPM options.
    #[serde(default)]
    pub dgmpm: DgmpmSpec,
    /// MPM options.
    #[serde(default)]
    pub mpm: MpmSpec,
    /// FEM options.
    #[serde(default)]
    pub fem: FemSpec,
    /// Where profiles and fronts are measured (default: inferred from the loads).
    #[serde(default)]
    pub metrics: Option<MetricsSpec>,
}

/// Geometry: a box `[0, length]` meshed by `cells` regular cells.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// Edge lengths (m), one per axis.
    pub length: Vec<f64>,
    /// Cells per axis.
    pub cells: Vec<usize>,
    /// Material points per cell (`n^dim` for an `n`-per-axis layout).
    #[serde(default = "one")]
    pub points_per_cell: usize,
    /// Where the points sit in a cell: `centred` (default), `shifted` (by `shift`) or
    /// `given` (at `positions`).
    #[serde(default)]
    pub layout: Option<LayoutKind>,
    /// Shift of every point in sub-cell widths, `|shift| < ½` (`layout = "shifted"`).
    #[serde(default)]
    pub shift: Option<f64>,
    /// Local positions in `(0, 1)^dim`, one per point of a cell (`layout = "given"`).
    #[serde(default)]
    pub positions: Option<Vec<Vec<f64>>>,
}

fn one() -> usize {
    1
}

/// Material parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Constitutive model: `linear-elastic` or `svk` (Saint-Venant–Kirchhoff, large strain).
    pub model: MaterialModel,
    /// Young's modulus (Pa).
    pub young: f64,
    /// Poisson's ratio (unused by the 1D bar, which is in uniaxial stress).
    #[serde(default)]
    pub poisson: f64,
    /// Density (kg/m³).
    pub density: f64,
    /// Initial yield stress `σ_y` (Pa; `j2` only).
    #[serde(default)]
    pub yield_stress: Option<f64>,
    /// Hardening modulus `H` (Pa; `j2` only): equivalent stress against accumulated plastic
    /// strain.
    #[serde(default)]
    pub hardening: Option<f64>,
}

/// One edge's condition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgeSpec {
    /// `free`, `pressure` (normal pressure, positive in compression), `velocity` (normal
    /// velocity into the body) or `symmetry` (zero normal velocity and shear traction).
    pub kind: EdgeKind,
    /// Magnitude for `pressure` (Pa) and `velocity` (m/s).
    #[serde(default)]
    pub value: Option<f64>,
    /// Start of the loaded patch along each tangential axis of the face, in increasing
    /// axis order: a number along a 2D edge, `[s1, s2]` on a 3D face (e.g. `[x, y]` on a
    /// face normal to `z`; default: the face's start).
    #[serde(default)]
    pub from: Option<Coordinates>,
    /// End of the loaded patch (as `from`; default: the face's end).
    #[serde(default)]
    pub to: Option<Coordinates>,
    /// Centre of a loaded disc on a 3D face, `[s1, s2]` in tangential coordinates.
    #[serde(default)]
    pub centre: Option<Vec<f64>>,
    /// Radius of a loaded disc on a 3D face (m).
    #[serde(default)]
    pub radius: Option<f64>,
    /// Where a segment end cuts a face: `centre` (default) or `fraction`.
    #[serde(default)]
    pub cover: Option<SegmentCover>,
    /// Time history of the load: `step` (default), `ramp`, `smooth-ramp`, `sine` or `pulse`.
    #[serde(default)]
    pub history: Option<LoadShape>,
    /// Time scale of the history (s): rise time, period or pulse length.
    #[serde(default)]
    pub duration: Option<f64>,
}

/// The state at `t = 0` ([`crate::initial`]): a standing P mode or a travelling plane
/// pulse with an exact solution, or velocity and stress by formula; one of them.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// The standing P mode of [`crate::exact::StandingWave`] (exact with `symmetry` edges).
    #[serde(default)]
    pub standing_wave: Option<StandingWaveSpec>,
    /// A travelling plane pulse, [`crate::exact::PlaneWave`] (exact in the clean interior,
    /// [`crate::interior`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane_wave: Option<PlaneWaveSpec>,
    /// Velocity components (m/s) as formulas of `x` (and `y`, `z`), one per axis.
    #[serde(default)]
    pub velocity: Option<Vec<String>>,
    /// Stress components (Pa) as formulas: `[xx]` in 1D, `[xx, yy, xy]` in 2D,
    /// `[xx, yy, zz, yz, xz, xy]` in 3D
    /// (linear elasticity, DGMPM and MPM).
    #[serde(default)]
    pub stress: Option<Vec<String>>,
}

/// A standing P mode: peak speed and mode numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StandingWaveSpec {
    /// Peak speed `U` (m/s).
    pub amplitude: f64,
    /// Half wavelengths along each axis, `[m]` in 1D, `[m, n]` in 2D, `[m, n, q]` in 3D
    /// (`m ≥ 1`, `n, q ≥ 0`).
    pub modes: Vec<u32>,
}

/// Output schedule: give `output_times` (s) or `output_transits` (multiples of the
/// time a P wave takes to cross the smallest cell, `Δx/c_p`), not both.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// Output times in seconds.
    #[serde(default)]
    pub output_times: Option<Vec<f64>>,
    /// Output times as whole numbers of cell transits `n·Δx/c_p`.
    #[serde(default)]
    pub output_transits: Option<Vec<f64>>,
    /// End time (default: the last output time).
    #[serde(default)]
    pub t_end: Option<f64>,
}

impl Scene {
    /// Parse and validate a scene from TOML text; `origin` names the source in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, CoreError> {
        let scene = Self::parse_toml(text, origin)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Parse a scene from TOML text without checking its values (callers that change the
    /// scene before use validate it once afterwards, as [`Scene::validate`]).
    pub fn parse_toml(text: &str, origin: &str) -> Result<Self, CoreError> {
        let parse_error = |message: String| CoreError::Parse {
            path: origin.to_string(),
            message,
        };
        let deserializer = toml::Deserializer::new(text);
        serde_path_to_error::deserialize(deserializer).map_err(|e| {
            let mut field = e.path().to_string();
            let inner = e.into_inner();
            let line_number = inner
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            if field == "." || field.is_empty() {
                // the parser failed before serde saw a field: name the key on that line
                field = line_number
                    .and_then(|n| key_at_line(text, n))
                    .unwrap_or_default();
            }
            let line = line_number
                .map(|n| format!(" (line {n})"))
                .unwrap_or_default();
            let at = if field.is_empty() {
                String::new()
            } else {
                format!("`{field}`: ")
            };
            let value = line_number
                .and_then(|n| text.lines().nth(n - 1))
                .and_then(|l| l.split_once('='))
                .map(|(_, v)| v.split('#').next().unwrap_or("").trim())
                .filter(|v| !v.is_empty() && v.len() <= 80)
                .map(|v| format!(" (written {v})"))
                .unwrap_or_default();
            parse_error(format!("{at}{}{value}{line}", inner.message()))
        })
    }

    /// Read, parse and validate a scene file.
    pub fn from_file(path: &std::path::Path) -> Result<Self, CoreError> {
        let scene = Self::parse_file(path)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Read and parse a scene file without checking its values (see [`Self::parse_toml`]).
    pub fn parse_file(path: &std::path::Path) -> Result<Self, CoreError> {
        let text = std::fs::read_to_string(path).map_err(|source| CoreError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::parse_toml(&text, &path.display().to_string())
    }
}

/// The dotted path of the key written on line `number` (1-based) of a TOML text: the key
/// before its `=`, under the last `[section]` header above it.
fn key_at_line(text: &str, number: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let line = lines.get(number.checked_sub(1)?)?;
    let (key, _) = line.split_once('=')?;
    let key = key.trim();
    if key.is_empty() || key.contains(['[', '"', ' ']) {
        return None;
    }
    let section = lines[..number - 1]
        .iter()
        .rev()
        .map(|l| l.trim())
        .find(|l| l.starts_with('[') && l.ends_with(']'))
        .map(|l| l.trim_matches(|c| c == '[' || c == ']').trim().to_string());
    Some(match section {
        Some(section) if !section.is_empty() => format!("{section}.{key}"),
        _ => key.to_string(),
    })
}

/// Names of the scenes shipped with impact (files under `scenes/`).
pub const BUILTIN: &[&str] = &[
    "bar",
    "plate",
    "plate-wave",
    "svk-bar",
    "svk-plate",
    "smooth-bar",
    "smooth-plate",
    "ep-bar",
    "ep-plate-wave",
    "ep-plate",
    "block-wave",
    "smooth-block",
    "block",
    "ep-block",
    "lamb",
    "oblique-wave",
    "oblique-plate-wave",
];

/// TOML text of a shipped scene.
pub fn builtin(name: &str) -> Option<&'static str> {
    match name {
        "bar" => Some(include_str!("../../../../scenes/bar.toml")),
        "smooth-bar" => Some(include_str!("../../../../scenes/smooth-bar.toml")),
        "ep-bar" => Some(include_str!("../../../../scenes/ep-bar.toml")),
        "ep-plate-wave" => Some(include_str!("../../../../scenes/ep-plate-wave.toml")),
        "ep-plate" => Some(include_str!("../../../../scenes/ep-plate.toml")),
        "smooth-plate" => Some(include_str!("../../../../scenes/smooth-plate.toml")),
        "plate" => Some(include_str!("../../../../scenes/plate.toml")),
        "plate-wave" => Some(include_str!("../../../../scenes/plate-wave.toml")),
        "svk-bar" => Some(include_str!("../../../../scenes/svk-bar.toml")),
        "svk-plate" => Some(include_str!("../../../../scenes/svk-plate.toml")),
        "block-wave" => Some(include_str!("../../../../scenes/block-wave.toml")),
        "smooth-block" => Some(include_str!("../../../../scenes/smooth-block.toml")),
        "block" => Some(include_str!("../../../../scenes/block.toml")),
        "ep-block" => Some(include_str!("../../../../scenes/ep-block.toml")),
        "lamb" => Some(include_str!("../../../../scenes/lamb.toml")),
        "oblique-wave" => Some(include_str!("../../../../scenes/oblique-wave.toml")),
        "oblique-plate-wave" => Some(include_str!("../../../../scenes/oblique-plate-wave.toml")),
        _ => None,
    }
}

impl Scene {
    /// A shipped scene by name (see [`BUILTIN`]).
    pub fn builtin(name: &str) -> Option<Self> {
        builtin(name).map(|text| {
            Self::from_toml(text, &format!("scenes/{name}.toml"))
                .expect("internal: shipped scenes are valid")
        })
    }
}

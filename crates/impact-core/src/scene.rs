//! Scene files (TOML). Unknown fields are rejected; every value is checked by
//! [`Scene::validate`], whose errors name the field, the value and what is allowed.
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
use crate::error::{CoreError, SceneError};
use crate::options::{
    DgmpmOptions, Integrator, MethodConfig, MethodKind, MethodOptions, MpmFrame, MpmOptions,
    PointUpdate, RiemannSolver, StressUpdate, TransverseFlux,
};
use serde::{Deserialize, Serialize};

/// A whole scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Scene name (used for the output folder).
    pub name: String,
    /// Spatial dimension, 1 or 2.
    pub dim: usize,
    /// Geometry and discretisation.
    pub domain: Domain,
    /// Material.
    pub material: MaterialSpec,
    /// Boundary conditions per edge.
    pub boundary: BoundarySpec,
    /// Time and output schedule.
    pub time: TimeSpec,
    /// DGMPM options.
    #[serde(default)]
    pub dgmpm: DgmpmSpec,
    /// MPM options.
    #[serde(default)]
    pub mpm: MpmSpec,
    /// FEM options.
    #[serde(default)]
    pub fem: FemSpec,
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
}

fn one() -> usize {
    1
}

/// Material parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Model name: `linear-elastic` or `svk` (Saint-Venant–Kirchhoff, large strain).
    pub model: String,
    /// Young's modulus (Pa).
    pub young: f64,
    /// Poisson's ratio (unused by the 1D bar, which is in uniaxial stress).
    #[serde(default)]
    pub poisson: f64,
    /// Density (kg/m³).
    pub density: f64,
}

/// One edge's condition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgeSpec {
    /// `free`, `pressure` (normal pressure, positive in compression), `velocity` (normal
    /// velocity into the body) or `symmetry` (zero normal velocity and shear traction).
    pub kind: String,
    /// Magnitude for `pressure` (Pa) and `velocity` (m/s).
    #[serde(default)]
    pub value: Option<f64>,
    /// Start of the loaded segment along the edge (2D; default: whole edge).
    #[serde(default)]
    pub from: Option<f64>,
    /// End of the loaded segment along the edge (2D; default: whole edge).
    #[serde(default)]
    pub to: Option<f64>,
}

/// Conditions on each edge; edges not given are free.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Edge `x = 0`.
    pub left: Option<EdgeSpec>,
    /// Edge `x = length[0]`.
    pub right: Option<EdgeSpec>,
    /// Edge `y = 0` (2D).
    pub bottom: Option<EdgeSpec>,
    /// Edge `y = length[1]` (2D).
    pub top: Option<EdgeSpec>,
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

/// DGMPM's section: Courant number and options (each absent option takes its default,
/// [`DgmpmOptions::default`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DgmpmSpec {
    /// Courant number `c_p Δt / Δx_min` (default 1, the paper's).
    #[serde(default = "courant_one")]
    pub courant: f64,
    /// Time integrator.
    #[serde(default)]
    pub integrator: Option<Integrator>,
    /// Point update after the nodal solve.
    #[serde(default)]
    pub update: Option<PointUpdate>,
    /// Transverse flux (2D only).
    #[serde(default)]
    pub flux: Option<TransverseFlux>,
    /// Riemann solver (Saint-Venant–Kirchhoff).
    #[serde(default)]
    pub riemann: Option<RiemannSolver>,
}

/// MPM's section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpmSpec {
    /// Courant number (default 0.5, the paper's).
    #[serde(default = "courant_half")]
    pub courant: f64,
    /// Stress update.
    #[serde(default)]
    pub stress_update: Option<StressUpdate>,
    /// Frame of the shape functions.
    #[serde(default)]
    pub frame: Option<MpmFrame>,
}

/// FEM's section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FemSpec {
    /// Courant number (default 0.9, the paper's).
    #[serde(default = "courant_fem")]
    pub courant: f64,
}

fn courant_one() -> f64 {
    1.0
}
fn courant_half() -> f64 {
    0.5
}
fn courant_fem() -> f64 {
    0.9
}

impl Default for DgmpmSpec {
    fn default() -> Self {
        Self {
            courant: courant_one(),
            integrator: None,
            update: None,
            flux: None,
            riemann: None,
        }
    }
}

impl Default for MpmSpec {
    fn default() -> Self {
        Self {
            courant: courant_half(),
            stress_update: None,
            frame: None,
        }
    }
}

impl Default for FemSpec {
    fn default() -> Self {
        Self {
            courant: courant_fem(),
        }
    }
}

impl Scene {
    /// The configuration of `kind` written in this scene (absent options at their
    /// defaults).
    pub fn method_config(&self, kind: MethodKind) -> MethodConfig {
        let ppc = self.domain.points_per_cell;
        match kind {
            MethodKind::Dgmpm => {
                let s = &self.dgmpm;
                let d = DgmpmOptions::default();
                MethodConfig {
                    courant: s.courant,
                    points_per_cell: ppc,
                    options: MethodOptions::Dgmpm(DgmpmOptions {
                        integrator: s.integrator.unwrap_or(d.integrator),
                        update: s.update.unwrap_or(d.update),
                        flux: s.flux.unwrap_or(d.flux),
                        riemann: s.riemann.unwrap_or(d.riemann),
                    }),
                }
            }
            MethodKind::Mpm => {
                let s = &self.mpm;
                let d = MpmOptions::default();
                MethodConfig {
                    courant: s.courant,
                    points_per_cell: ppc,
                    options: MethodOptions::Mpm(MpmOptions {
                        stress_update: s.stress_update.unwrap_or(d.stress_update),
                        frame: s.frame.unwrap_or(d.frame),
                    }),
                }
            }
            MethodKind::Fem => MethodConfig::new(MethodKind::Fem, self.fem.courant, ppc),
        }
    }
}

/// Largest number of cells × points per cell a scene may ask for.
pub const MAX_POINTS: f64 = 1e7;

/// Allowed range of the Courant number.
pub const COURANT_RANGE: &str = "a number in (0, 2]";

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
            let field = e.path().to_string();
            let inner = e.into_inner();
            let line = inner
                .span()
                .map(|s| format!(" (line {})", text[..s.start].matches('\n').count() + 1))
                .unwrap_or_default();
            let at = if field == "." || field.is_empty() {
                String::new()
            } else {
                format!("`{field}`: ")
            };
            parse_error(format!("{at}{}{line}", inner.message()))
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

    /// Check every value; the first problem found is returned.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.name.is_empty()
            || !self
                .name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(SceneError::new(
                "name",
                format!("{:?}", self.name),
                "a non-empty name of letters, digits, '-' and '_'",
            ));
        }
        if !(self.dim == 1 || self.dim == 2) {
            return Err(SceneError::new("dim", self.dim, "1 or 2"));
        }
        let d = &self.domain;
        if d.length.len() != self.dim {
            return Err(SceneError::new(
                "domain.length",
                format!("{:?}", d.length),
                format!("{} positive lengths (one per axis)", self.dim),
            ));
        }
        for (l, &len) in d.length.iter().enumerate() {
            positive(
                &format!("domain.length[{l}]"),
                len,
                "a positive finite length in m",
            )?;
        }
        if d.cells.len() != self.dim {
            return Err(SceneError::new(
                "domain.cells",
                format!("{:?}", d.cells),
                format!("{} cell counts (one per axis)", self.dim),
            ));
        }
        for (l, &n) in d.cells.iter().enumerate() {
            if n == 0 || n > 100_000_000 {
                return Err(SceneError::new(
                    format!("domain.cells[{l}]"),
                    n,
                    "at least 1 cell (at most 1e8)",
                ));
            }
        }
        check_points_per_cell(self.dim, d.points_per_cell)?;
        let total = d.cells.iter().map(|&n| n as f64).product::<f64>() * d.points_per_cell as f64;
        if total > MAX_POINTS {
            return Err(SceneError::new(
                "domain.cells",
                format!("{:?} × {} points per cell", d.cells, d.points_per_cell),
                format!(
                    "at most {MAX_POINTS:.0e} cells × points per cell in total (about 1.2 kB per cell \
                     in 2D: larger grids do not fit in memory here)"
                ),
            ));
        }
        let m = &self.material;
        if !(m.model == "linear-elastic" || m.model == "svk") {
            return Err(SceneError::new(
                "material.model",
                format!("{:?}", m.model),
                "\"linear-elastic\" or \"svk\" (Saint-Venant-Kirchhoff)",
            ));
        }
        positive("material.young", m.young, "a positive finite modulus in Pa")?;
        positive(
            "material.density",
            m.density,
            "a positive finite density in kg/m³",
        )?;
        if !(m.poisson > -1.0 && m.poisson < 0.5) {
            return Err(SceneError::new(
                "material.poisson",
                m.poisson,
                "a number in (-1, 0.5)",
            ));
        }
        let edges = [
            ("left", &self.boundary.left, 1),
            ("right", &self.boundary.right, 1),
            ("bottom", &self.boundary.bottom, 2),
            ("top", &self.boundary.top, 2),
        ];
        for (name, edge, min_dim) in edges {
            let Some(edge) = edge else { continue };
            let field = format!("boundary.{name}");
            if self.dim < min_dim {
                return Err(SceneError::new(
                    field,
                    &edge.kind,
                    "only `left` and `right` in 1D",
                ));
            }
            check_edge(&field, edge, self.dim)?;
        }
        let t = &self.time;
        let times = match (&t.output_times, &t.output_transits) {
            (Some(_), Some(_)) => {
                return Err(SceneError::new(
                    "time",
                    "both output_times and output_transits",
                    "one of `output_times` and `output_transits`",
                ))
            }
            (Some(v), None) => ("time.output_times", v),
            (None, Some(v)) => ("time.output_transits", v),
            (None, None) => {
                return Err(SceneError::new(
                    "time",
                    "no output times",
                    "`output_times` (s) or `output_transits` (multiples of Δx/c)",
                ))
            }
        };
        check_output_times(times.0, times.1)?;
        if let Some(t_end) = t.t_end {
            positive("time.t_end", t_end, "a positive finite time in s")?;
        }
        check_courant("dgmpm.courant", self.dgmpm.courant)?;
        check_courant("mpm.courant", self.mpm.courant)?;
        check_courant("fem.courant", self.fem.courant)?;
        if let (Some(f), 1) = (self.dgmpm.flux, self.dim) {
            return Err(SceneError::new(
                "dgmpm.flux",
                format!("{:?}", f.name()),
                "no transverse flux in 1D (DGMPM in 2D only)",
            ));
        }
        Ok(())
    }
}

fn positive(field: &str, value: f64, allowed: &str) -> Result<(), SceneError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SceneError::new(field, value, allowed))
    }
}

/// Check a Courant number (also used for CLI flags).
pub fn check_courant(field: &str, courant: f64) -> Result<(), SceneError> {
    if courant.is_finite() && courant > 0.0 && courant <= 2.0 {
        Ok(())
    } else {
        Err(SceneError::new(field, courant, COURANT_RANGE))
    }
}

/// Check a points-per-cell count for dimension `dim` (also used for CLI flags).
pub fn check_points_per_cell(dim: usize, ppc: usize) -> Result<(), SceneError> {
    let per_axis = points_per_axis(dim, ppc);
    if ppc == 0 || ppc > 64 || per_axis.is_none() {
        let allowed = if dim == 1 {
            "a whole number from 1 to 64".to_string()
        } else {
            "a square number (1, 4, 9, 16, ...) up to 64 in 2D".to_string()
        };
        return Err(SceneError::new("domain.points_per_cell", ppc, allowed));
    }
    Ok(())
}

/// Points per axis for `ppc` points per cell, if `ppc` is an exact `dim`-th power.
pub fn points_per_axis(dim: usize, ppc: usize) -> Option<usize> {
    (1..=64usize).find(|n| n.pow(dim as u32) == ppc)
}

/// Check output times (also used for CLI flags): positive, finite, strictly increasing.
pub fn check_output_times(field: &str, times: &[f64]) -> Result<(), SceneError> {
    if times.is_empty() {
        return Err(SceneError::new(field, "[]", "at least one output time"));
    }
    let mut last = 0.0;
    for &t in times {
        if !(t.is_finite() && t > last) {
            return Err(SceneError::new(
                field,
                format!("{times:?}"),
                "positive, finite, strictly increasing times",
            ));
        }
        last = t;
    }
    Ok(())
}

fn check_edge(field: &str, edge: &EdgeSpec, dim: usize) -> Result<(), SceneError> {
    match edge.kind.as_str() {
        "free" | "symmetry" => {
            if edge.value.is_some() {
                return Err(SceneError::new(
                    format!("{field}.value"),
                    edge.value.unwrap_or_default(),
                    format!("no value for a `{}` edge", edge.kind),
                ));
            }
        }
        "pressure" | "velocity" => {
            let Some(v) = edge.value else {
                return Err(SceneError::new(
                    format!("{field}.value"),
                    "missing",
                    format!("a finite number for a `{}` edge", edge.kind),
                ));
            };
            if !v.is_finite() {
                return Err(SceneError::new(
                    format!("{field}.value"),
                    v,
                    "a finite number",
                ));
            }
        }
        other => {
            return Err(SceneError::new(
                format!("{field}.kind"),
                format!("{other:?}"),
                "\"free\", \"pressure\", \"velocity\" or \"symmetry\"",
            ))
        }
    }
    if dim == 1 && (edge.from.is_some() || edge.to.is_some()) {
        return Err(SceneError::new(
            format!("{field}.from"),
            "a segment",
            "no segment in 1D (an end is a point)",
        ));
    }
    if let (Some(a), Some(b)) = (edge.from, edge.to) {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(SceneError::new(
                format!("{field}.from/to"),
                format!("{a}..{b}"),
                "finite `from` < `to` along the edge",
            ));
        }
    }
    Ok(())
}

/// Names of the scenes shipped with impact (files under `scenes/`).
pub const BUILTIN: &[&str] = &["bar", "plate", "plate-wave", "svk-bar", "svk-plate"];

/// TOML text of a shipped scene.
pub fn builtin(name: &str) -> Option<&'static str> {
    match name {
        "bar" => Some(include_str!("../../../scenes/bar.toml")),
        "plate" => Some(include_str!("../../../scenes/plate.toml")),
        "plate-wave" => Some(include_str!("../../../scenes/plate-wave.toml")),
        "svk-bar" => Some(include_str!("../../../scenes/svk-bar.toml")),
        "svk-plate" => Some(include_str!("../../../scenes/svk-plate.toml")),
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

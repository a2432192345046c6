//! The boundary part of [`Scene::validate`]: each edge's kind and value against the
//! model's bounds (module doc of `validate.rs`), and loaded segments.
use super::validate::MAX_STRAIN;
use super::{Coordinates, EdgeSpec, Scene, AXIS_NAMES};
use crate::error::SceneError;
use crate::material::Svk;
use crate::options::{EdgeKind, LoadShape, MaterialModel};

impl Scene {
    pub(super) fn check_boundaries(&self) -> Result<(), SceneError> {
        let b = &self.boundary;
        let aliases = [
            ("left", b.left.is_some(), 0, 0),
            ("right", b.right.is_some(), 0, 1),
            ("bottom", b.bottom.is_some(), 1, 0),
            ("top", b.top.is_some(), 1, 1),
        ];
        for (name, given, axis, side) in aliases {
            let named = [&b.x, &b.y][axis]
                .as_ref()
                .and_then(|s| [&s.low, &s.high][side].as_ref());
            if given && named.is_some() {
                let full = format!("{}.{}", AXIS_NAMES[axis], ["low", "high"][side]);
                return Err(SceneError::new(
                    format!("boundary.{name}"),
                    "given twice",
                    format!("one of `{name}` and its name `{full}`"),
                ));
            }
        }
        for axis in 0..3 {
            for side in 0..2 {
                let Some((field, edge)) = b.side(axis, side) else {
                    continue;
                };
                if axis >= self.dim {
                    let allowed = match self.dim {
                        1 => "only `x.low`/`x.high` (`left`/`right`) in 1D".to_string(),
                        d => format!(
                            "sides of the axes {} only in {d}D",
                            AXIS_NAMES[..d].join(", ")
                        ),
                    };
                    return Err(SceneError::new(field, edge.kind, allowed));
                }
                self.check_edge_value(&field, edge)?;
                self.check_patch(&field, edge, axis)?;
                check_history(&field, edge)?;
            }
        }
        Ok(())
    }

    fn check_edge_value(&self, field: &str, edge: &EdgeSpec) -> Result<(), SceneError> {
        let value_field = format!("{field}.value");
        let value = match (edge.kind, edge.value) {
            (EdgeKind::Free | EdgeKind::Symmetry, None) => return Ok(()),
            (EdgeKind::Free | EdgeKind::Symmetry, Some(v)) => {
                return Err(SceneError::new(
                    value_field,
                    v,
                    format!("no value for a `{}` edge", edge.kind),
                ))
            }
            (kind, None) => {
                return Err(SceneError::new(
                    value_field,
                    "missing",
                    format!("a finite number for a `{kind}` edge"),
                ))
            }
            (_, Some(v)) => v,
        };
        if edge.kind == EdgeKind::Pressure && value == 0.0 {
            return Err(SceneError::new(
                value_field,
                value,
                "a nonzero pressure (a zero pressure is a `free` edge)",
            ));
        }
        let (allowed, fits) = self.load_bound(edge.kind, value);
        if !(value.is_finite() && fits) {
            return Err(SceneError::new(value_field, value, allowed));
        }
        Ok(())
    }

    /// What a load of `kind` and `value` may be under this scene's model, and whether
    /// `value` is within it.
    fn load_bound(&self, kind: EdgeKind, value: f64) -> (String, bool) {
        let (material, modulus) = self.p_modulus();
        let speed = (modulus / material.density).sqrt();
        match (self.material.model, kind) {
            (MaterialModel::LinearElastic | MaterialModel::J2, EdgeKind::Pressure) => {
                let limit = MAX_STRAIN * modulus;
                (
                    format!(
                        "|p| ≤ {limit:.4e} Pa: a strain of at most {MAX_STRAIN} under small-strain \
                         linear elasticity (|p|/M, M = {modulus:.4e} Pa; use model = \"svk\" beyond)"
                    ),
                    value.abs() <= limit,
                )
            }
            (MaterialModel::LinearElastic | MaterialModel::J2, _) => {
                let limit = MAX_STRAIN * speed;
                (
                    format!(
                        "|v| ≤ {limit:.4e} m/s: a strain of at most {MAX_STRAIN} under small-strain \
                         linear elasticity (|v|/c_p, c_p = {speed:.4e} m/s; use model = \"svk\" beyond)"
                    ),
                    value.abs() <= limit,
                )
            }
            (MaterialModel::Svk, EdgeKind::Pressure) => {
                let svk = Svk::new(material);
                let (f_lim, pi_lim) = svk.hyperbolicity_limit_1d();
                let tension = 3.0 * self.material.young;
                (
                    format!(
                        "a compression below the SVK hyperbolicity limit E/(3√3) = {:.4e} Pa \
                         (uniaxial F = 1/√3 = {f_lim:.4}, where Π' = 0) and a tension of at most \
                         Π(F = 2) = 3E = {tension:.4e} Pa",
                        -pi_lim
                    ),
                    value < -pi_lim && value >= -tension,
                )
            }
            (MaterialModel::Svk, _) => {
                let limit = 0.4 * speed;
                (
                    format!(
                        "|v| ≤ 0.4 c_p = {limit:.4e} m/s (a uniaxial stretch above 0.6, clear of \
                         the SVK hyperbolicity limit F = 1/√3)"
                    ),
                    value.abs() <= limit,
                )
            }
        }
    }

    /// A patch lies on its face (2D: a segment `from..to`; 3D: a box `from..to` with one
    /// coordinate per tangential axis, or a disc `centre`, `radius`), is not empty, and
    /// loads at least one face: by centre, a face centre lies in it.
    fn check_patch(&self, field: &str, edge: &EdgeSpec, axis: usize) -> Result<(), SceneError> {
        let boxed = edge.from.is_some() || edge.to.is_some();
        let disc = edge.centre.is_some() || edge.radius.is_some();
        if !boxed && !disc {
            if let Some(cover) = edge.cover {
                return Err(SceneError::new(
                    format!("{field}.cover"),
                    cover,
                    "no `cover` without a patch (`from`/`to`, or `centre`/`radius` in 3D)",
                ));
            }
            return Ok(());
        }
        if self.dim == 1 {
            return Err(SceneError::new(
                format!("{field}.{}", if boxed { "from" } else { "centre" }),
                "a patch",
                "no patch in 1D (an end is a point)",
            ));
        }
        if !matches!(
            edge.kind,
            EdgeKind::Pressure | EdgeKind::Velocity | EdgeKind::NormalVelocity
        ) {
            return Err(SceneError::new(
                format!("{field}.{}", if boxed { "from" } else { "centre" }),
                "a patch",
                format!("no patch on a `{}` side (only loads have one)", edge.kind),
            ));
        }
        if boxed && disc {
            return Err(SceneError::new(
                format!("{field}.centre"),
                "a disc and a box",
                "either a box (`from`, `to`) or a disc (`centre`, `radius`)",
            ));
        }
        let tangents: Vec<usize> = (0..self.dim).filter(|&k| k != axis).collect();
        let names: Vec<&str> = tangents.iter().map(|&k| AXIS_NAMES[k]).collect();
        let extent = |k: usize| self.domain.length[k];
        let spacing = |k: usize| self.domain.length[k] / self.domain.cells[k] as f64;
        if disc {
            if self.dim != 3 {
                return Err(SceneError::new(
                    format!("{field}.centre"),
                    "a disc",
                    "a disc only on a 3D face (a 2D edge takes a segment `from`, `to`)",
                ));
            }
            let centre = edge.centre.as_ref().ok_or_else(|| {
                SceneError::new(
                    format!("{field}.centre"),
                    "missing",
                    "[s1, s2] with `radius`",
                )
            })?;
            if centre.len() != 2 {
                return Err(SceneError::new(
                    format!("{field}.centre"),
                    format!("{centre:?}"),
                    format!(
                        "2 coordinates [{}] (one per tangential axis)",
                        names.join(", ")
                    ),
                ));
            }
            for (slot, &k) in tangents.iter().enumerate() {
                if !(centre[slot].is_finite() && (0.0..=extent(k)).contains(&centre[slot])) {
                    return Err(SceneError::new(
                        format!("{field}.centre"),
                        format!("{centre:?}"),
                        format!(
                            "a point of the face: {} in [0, {}] m",
                            names[slot],
                            extent(k)
                        ),
                    ));
                }
            }
            let radius = edge.radius.unwrap_or(f64::NAN);
            let smallest = tangents
                .iter()
                .map(|&k| spacing(k))
                .fold(f64::INFINITY, f64::min);
            if !(radius.is_finite() && radius >= 0.5 * smallest) {
                return Err(SceneError::new(
                    format!("{field}.radius"),
                    edge.radius.map_or("missing".to_string(), |r| r.to_string()),
                    format!(
                        "a finite radius of at least half a cell ({:e} m): a smaller disc \
                         loads at most one face",
                        0.5 * smallest
                    ),
                ));
            }
            return Ok(());
        }
        let dims = tangents.len();
        let read = |key: &str, given: &Option<Coordinates>, default: &dyn Fn(usize) -> f64| {
            let values = match given {
                None => return Ok(tangents.iter().map(|&k| default(k)).collect::<Vec<_>>()),
                Some(c) => c.to_vec(),
            };
            if values.len() != dims {
                return Err(SceneError::new(
                    format!("{field}.{key}"),
                    format!("{values:?}"),
                    if dims == 1 {
                        format!("one number: a position along {}", names[0])
                    } else {
                        format!(
                            "{dims} coordinates [{}] (one per tangential axis)",
                            names.join(", ")
                        )
                    },
                ));
            }
            for (slot, &k) in tangents.iter().enumerate() {
                let v = values[slot];
                if !(v.is_finite() && (0.0..=extent(k)).contains(&v)) {
                    return Err(SceneError::new(
                        format!("{field}.{key}"),
                        if dims == 1 {
                            v.to_string()
                        } else {
                            format!("{values:?}")
                        },
                        format!(
                            "a position on the face: {} in [0, {}] m",
                            names[slot],
                            extent(k)
                        ),
                    ));
                }
            }
            Ok(values)
        };
        let from = read("from", &edge.from, &|_| 0.0)?;
        let to = read("to", &edge.to, &|k| extent(k))?;
        for (slot, &k) in tangents.iter().enumerate() {
            let (from, to) = (from[slot], to[slot]);
            if from >= to {
                return Err(SceneError::new(
                    format!("{field}.to"),
                    to,
                    format!("a position after `from` = {from} m along {}", names[slot]),
                ));
            }
            let h = spacing(k);
            let first = ((from / h) - 0.5).ceil().max(0.0);
            if (first + 0.5) * h > to * (1.0 + 1e-12) + 1e-12 * h {
                return Err(SceneError::new(
                    format!("{field}.from/to"),
                    format!("{from}..{to} m along {}", names[slot]),
                    format!(
                        "a patch that covers at least one face centre (faces are {h:e} m wide); \
                         a shorter patch loads no face"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A load history (`history`, `duration`) only on a loaded edge; `duration` exactly when
/// the shape needs one, positive and finite.
fn check_history(field: &str, edge: &EdgeSpec) -> Result<(), SceneError> {
    let loaded = matches!(
        edge.kind,
        EdgeKind::Pressure | EdgeKind::Velocity | EdgeKind::NormalVelocity
    );
    if !loaded {
        if let Some(shape) = edge.history {
            return Err(SceneError::new(
                format!("{field}.history"),
                shape,
                format!("no history for a `{}` edge", edge.kind),
            ));
        }
    }
    let shape = edge.history.unwrap_or(LoadShape::Step);
    let duration_field = format!("{field}.duration");
    match (shape, edge.duration) {
        (LoadShape::Step, None) => Ok(()),
        (LoadShape::Step, Some(d)) => Err(SceneError::new(
            duration_field,
            d,
            "no duration for a step load (give `history = \"ramp\"`, \"smooth-ramp\", \"sine\" or \"pulse\")",
        )),
        (shape, None) => Err(SceneError::new(
            duration_field,
            "missing",
            format!("a positive time in s: the {shape} load's time scale"),
        )),
        (shape, Some(d)) => {
            if d.is_finite() && d > 0.0 && d <= 1e30 {
                Ok(())
            } else {
                Err(SceneError::new(
                    duration_field,
                    d,
                    format!("a positive finite time in s (the {shape} load's time scale)"),
                ))
            }
        }
    }
}

//! The boundary part of [`Scene::validate`]: each edge's kind and value against the
//! model's bounds (module doc of `validate.rs`), and loaded segments.
use super::validate::MAX_STRAIN;
use super::{EdgeSpec, Scene};
use crate::error::SceneError;
use crate::material::Svk;
use crate::options::{EdgeKind, LoadShape, MaterialModel};

impl Scene {
    fn edges(&self) -> [(&'static str, &Option<EdgeSpec>, usize); 4] {
        let b = &self.boundary;
        [
            ("left", &b.left, 1),
            ("right", &b.right, 1),
            ("bottom", &b.bottom, 0),
            ("top", &b.top, 0),
        ]
    }

    pub(super) fn check_boundaries(&self) -> Result<(), SceneError> {
        for (name, edge, tangent) in self.edges() {
            let Some(edge) = edge else { continue };
            let field = format!("boundary.{name}");
            if self.dim == 1 && matches!(name, "bottom" | "top") {
                return Err(SceneError::new(
                    field,
                    edge.kind,
                    "only `left` and `right` in 1D",
                ));
            }
            self.check_edge_value(&field, edge)?;
            self.check_segment(&field, edge, tangent)?;
            check_history(&field, edge)?;
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

    /// A segment lies on its edge (2D), `from < to`, and covers a face centre.
    fn check_segment(
        &self,
        field: &str,
        edge: &EdgeSpec,
        tangent: usize,
    ) -> Result<(), SceneError> {
        if edge.from.is_none() && edge.to.is_none() {
            if let Some(cover) = edge.cover {
                return Err(SceneError::new(
                    format!("{field}.cover"),
                    cover,
                    "no `cover` without a segment (`from` or `to`)",
                ));
            }
            return Ok(());
        }
        if self.dim == 1 {
            return Err(SceneError::new(
                format!("{field}.from"),
                "a segment",
                "no segment in 1D (an end is a point)",
            ));
        }
        let extent = self.domain.length[tangent];
        let (from, to) = (edge.from.unwrap_or(0.0), edge.to.unwrap_or(extent));
        for (key, v) in [("from", from), ("to", to)] {
            if !(v.is_finite() && (0.0..=extent).contains(&v)) {
                return Err(SceneError::new(
                    format!("{field}.{key}"),
                    v,
                    format!("a position along the edge, in [0, {extent}] m"),
                ));
            }
        }
        if from >= to {
            return Err(SceneError::new(
                format!("{field}.to"),
                to,
                format!("a position after `from` = {from} m"),
            ));
        }
        let cells = self.domain.cells[tangent];
        let h = extent / cells as f64;
        let first = ((from / h) - 0.5).ceil().max(0.0);
        if (first + 0.5) * h > to * (1.0 + 1e-12) + 1e-12 * h {
            return Err(SceneError::new(
                format!("{field}.from/to"),
                format!("{from}..{to} m"),
                format!(
                    "a segment that covers at least one face centre (faces are {h:e} m wide); \
                     a shorter segment loads no face"
                ),
            ));
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

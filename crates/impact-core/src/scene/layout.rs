//! The point-layout part of [`Scene::validate`] and its typed form
//! ([`Scene::point_layout`]).
use super::Scene;
use crate::error::SceneError;
use crate::options::LayoutKind;
use crate::points::PointLayout;

impl Scene {
    pub(super) fn check_layout(&self) -> Result<(), SceneError> {
        let d = &self.domain;
        let kind = d.layout.unwrap_or(LayoutKind::Centred);
        if kind != LayoutKind::Shifted {
            if let Some(shift) = d.shift {
                return Err(SceneError::new(
                    "domain.shift",
                    shift,
                    "a shift only with `layout = \"shifted\"`",
                ));
            }
        }
        if kind != LayoutKind::Given && d.positions.is_some() {
            return Err(SceneError::new(
                "domain.positions",
                "given",
                "positions only with `layout = \"given\"`",
            ));
        }
        match kind {
            LayoutKind::Centred => Ok(()),
            LayoutKind::Shifted => {
                let shift = d.shift.ok_or_else(|| {
                    SceneError::new(
                        "domain.shift",
                        "missing",
                        "a shift in (-0.5, 0.5) sub-cells",
                    )
                })?;
                if shift.is_finite() && shift.abs() < 0.5 {
                    Ok(())
                } else {
                    Err(SceneError::new(
                        "domain.shift",
                        shift,
                        "a shift in (-0.5, 0.5) sub-cell widths (points stay in their sub-cells)",
                    ))
                }
            }
            LayoutKind::Given => {
                let positions = d.positions.as_ref().ok_or_else(|| {
                    SceneError::new(
                        "domain.positions",
                        "missing",
                        "one local position per point of a cell",
                    )
                })?;
                if positions.len() != d.points_per_cell {
                    return Err(SceneError::new(
                        "domain.positions",
                        format!("{} positions", positions.len()),
                        format!("{} (points_per_cell)", d.points_per_cell),
                    ));
                }
                for (k, p) in positions.iter().enumerate() {
                    let inside = p.iter().all(|u| u.is_finite() && *u > 0.0 && *u < 1.0);
                    if p.len() != self.dim || !inside {
                        return Err(SceneError::new(
                            format!("domain.positions[{k}]"),
                            format!("{p:?}"),
                            format!("{} local coordinates in (0, 1)", self.dim),
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// The typed layout of a scene that [`Scene::validate`] accepted.
    pub fn point_layout(&self) -> PointLayout {
        let d = &self.domain;
        match d.layout.unwrap_or(LayoutKind::Centred) {
            LayoutKind::Centred => PointLayout::Centred,
            LayoutKind::Shifted => PointLayout::Shifted(d.shift.unwrap_or(0.0)),
            LayoutKind::Given => PointLayout::Given(d.positions.clone().unwrap_or_default()),
        }
    }
}

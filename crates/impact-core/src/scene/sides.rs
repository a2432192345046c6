//! The `[boundary]` section's types: the sides by axis and their 1D/2D aliases
//! ([`BoundarySpec::side`]), and coordinates on a face ([`Coordinates`]).
use super::EdgeSpec;
use serde::{Deserialize, Serialize};

/// Conditions on each side of each axis; sides not given are free. A side is named by
/// axis and side, `x.low`, `x.high`, `y.low`, ..., `z.high` (in TOML `[boundary]` then
/// `x.low = { ... }`); the 1D/2D names `left` (`x.low`), `right` (`x.high`), `bottom`
/// (`y.low`) and `top` (`y.high`) are aliases. Giving a side under both names is refused.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Edge `x = 0` (alias of `x.low`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub left: Option<EdgeSpec>,
    /// Edge `x = length[0]` (alias of `x.high`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub right: Option<EdgeSpec>,
    /// Edge `y = 0` (alias of `y.low`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bottom: Option<EdgeSpec>,
    /// Edge `y = length[1]` (alias of `y.high`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<EdgeSpec>,
    /// The two sides of axis x.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<SidesSpec>,
    /// The two sides of axis y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<SidesSpec>,
    /// The two sides of axis z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<SidesSpec>,
}

/// The two sides of one axis.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidesSpec {
    /// The side at coordinate 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub low: Option<EdgeSpec>,
    /// The side at coordinate `length`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub high: Option<EdgeSpec>,
}

/// A number (along a 2D edge) or one number per tangential axis (on a 3D face).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Coordinates {
    /// One coordinate.
    One(f64),
    /// One per tangential axis.
    Many(Vec<f64>),
}

impl Coordinates {
    /// The coordinates as a list.
    pub fn to_vec(&self) -> Vec<f64> {
        match self {
            Coordinates::One(v) => vec![*v],
            Coordinates::Many(v) => v.clone(),
        }
    }
}

/// Axis names in scene files.
pub const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

impl BoundarySpec {
    /// The spec of side `side` (0 low, 1 high) of axis `axis`, under either name, with the
    /// name it was given under.
    pub fn side(&self, axis: usize, side: usize) -> Option<(String, &EdgeSpec)> {
        let sides = [&self.x, &self.y, &self.z][axis].as_ref();
        let named = sides.and_then(|s| [&s.low, &s.high][side].as_ref());
        if let Some(edge) = named {
            return Some((
                format!("boundary.{}.{}", AXIS_NAMES[axis], ["low", "high"][side]),
                edge,
            ));
        }
        let alias = match (axis, side) {
            (0, 0) => ("left", &self.left),
            (0, 1) => ("right", &self.right),
            (1, 0) => ("bottom", &self.bottom),
            (1, 1) => ("top", &self.top),
            _ => return None,
        };
        alias
            .1
            .as_ref()
            .map(|edge| (format!("boundary.{}", alias.0), edge))
    }

    /// The slot of side `side` of axis `axis` to edit: the named one (`x.low`, ...) if
    /// given there, else the 1D/2D alias (`left`, ...) for x and y, else `z.low`/`z.high`.
    pub fn side_mut(&mut self, axis: usize, side: usize) -> &mut Option<EdgeSpec> {
        let named_given = [&self.x, &self.y, &self.z][axis]
            .as_ref()
            .is_some_and(|s| [&s.low, &s.high][side].is_some());
        if axis < 2 && !named_given {
            return match (axis, side) {
                (0, 0) => &mut self.left,
                (0, _) => &mut self.right,
                (_, 0) => &mut self.bottom,
                _ => &mut self.top,
            };
        }
        let sides =
            [&mut self.x, &mut self.y, &mut self.z][axis].get_or_insert_with(SidesSpec::default);
        if side == 0 {
            &mut sides.low
        } else {
            &mut sides.high
        }
    }
}

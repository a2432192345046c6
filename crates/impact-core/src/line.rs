//! Where profiles, errors and fronts are measured: a straight line through the body along
//! one axis, from the face a front enters by to the opposite face.
//!
//! A scene states it (`[metrics] line = { from = [x, y], to = [x, y] }`, parallel to an
//! axis) or impact infers it from the loads ([`MeasureLine::infer`]):
//! - the first loaded edge (a pressure or a velocity of non-zero magnitude; order left,
//!   right, bottom, top) sets the axis, its normal, and the start, on that edge;
//! - in 2D and 3D the line runs through the middle of the loaded patch (the middle of the
//!   face when no patch is given; the centre of a disc), where a normal impact sends the
//!   strongest plane-like front;
//! - with no load the line is the bottom row along x (as the paper's plate), and fronts
//!   are not measured (nothing sends one).
//!
//! The paper measures its plate "along the bottom boundary" (Fig. 5): the shipped plates
//! state that line. A researcher hitting the middle of an edge wants the line through the
//! impact; along the bottom row the front there is a weak diffracted wave whose jump is a
//! few % of the load, and an overshoot relative to it is meaningless.
//!
//! The samples on the line are those whose region contains the line (in 2D, the row of
//! samples with `lo ≤ offset < hi` across the line along each other axis; `hi` included
//! on the body's high face), ordered along it; the measured component is the normal stress along the line,
//! `σ_aa` (`σ_xx` along x, `σ_yy` along y), and the velocity `v_a`.
use crate::problem::{Boundary, Problem};
use crate::Vector;

/// How a line was chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LineOrigin {
    /// Stated by the scene (`[metrics] line`).
    Stated,
    /// Normal to the loaded edge `(axis, side)` (side 0: low, 1: high).
    LoadedEdge(usize, usize),
    /// No load: the bottom row along x.
    NoLoad,
}

/// A measuring line along axis `axis` (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasureLine {
    /// Axis the line runs along (0: x, 1: y).
    pub axis: usize,
    /// Coordinate along the axis where the line starts: the face a front enters by.
    pub start: f64,
    /// Coordinate along the axis where it ends.
    pub end: f64,
    /// The other coordinates, in increasing axis order (`Grid::tangent_axes(axis)`): the
    /// line is `X_k = offset[slot]` for its other axes `k` (unused entries 0).
    pub offset: [f64; 2],
    /// How it was chosen.
    pub origin: LineOrigin,
}

/// Names of the edges by `(axis, side)`: `left`, `right`, `bottom`, `top` for x and y,
/// `z.low`, `z.high` for z (the scene file's names).
pub fn edge_name(axis: usize, side: usize) -> &'static str {
    match (axis, side) {
        (0, 0) => "left",
        (0, _) => "right",
        (1, 0) => "bottom",
        (1, _) => "top",
        (_, 0) => "z.low",
        _ => "z.high",
    }
}

impl MeasureLine {
    /// The line of `problem`: the stated one, else inferred from its loads (module doc).
    pub fn of<const D: usize>(problem: &Problem<D>) -> Self {
        problem.line.unwrap_or_else(|| Self::infer(problem))
    }

    /// The line inferred from the loads of `problem` (module doc).
    pub fn infer<const D: usize>(problem: &Problem<D>) -> Self {
        let lo = problem.grid.origin;
        let hi = problem.grid.upper();
        for axis in 0..D {
            for side in 0..2 {
                let load = match problem.boundaries[axis][side] {
                    Boundary::Pressure(load) | Boundary::Velocity { load, .. } => load,
                    Boundary::Free | Boundary::Symmetry => continue,
                };
                if load.value == 0.0 {
                    continue; // a fixed wall, not a load
                }
                let (start, end) = if side == 0 {
                    (lo[axis], hi[axis])
                } else {
                    (hi[axis], lo[axis])
                };
                let mut offset = [0.0; 2];
                for (slot, k) in crate::Grid::<D>::tangent_axes(axis).enumerate() {
                    offset[slot] = 0.5 * (lo[k] + hi[k]);
                }
                match load.patch.map(|p| p.shape) {
                    Some(crate::PatchShape::Box { lo: from, hi: to }) => {
                        for (slot, k) in crate::Grid::<D>::tangent_axes(axis).enumerate() {
                            offset[slot] = 0.5 * (from[slot].max(lo[k]) + to[slot].min(hi[k]));
                        }
                    }
                    Some(crate::PatchShape::Disc { centre, .. }) => offset = centre,
                    None => {}
                }
                return Self {
                    axis,
                    start,
                    end,
                    offset,
                    origin: LineOrigin::LoadedEdge(axis, side),
                };
            }
        }
        Self::bottom_row(&problem.grid)
    }

    /// The bottom row along x of `grid` (the line of a body with no load; in 3D the edge
    /// `y = z = 0`).
    pub fn bottom_row<const D: usize>(grid: &crate::Grid<D>) -> Self {
        Self {
            axis: 0,
            start: grid.origin[0],
            end: grid.upper()[0],
            offset: [
                if D > 1 { grid.origin[1] } else { 0.0 },
                if D > 2 { grid.origin[2] } else { 0.0 },
            ],
            origin: LineOrigin::NoLoad,
        }
    }

    /// `+1` if the line runs towards larger coordinates, `-1` otherwise.
    pub fn direction(&self) -> f64 {
        if self.end >= self.start {
            1.0
        } else {
            -1.0
        }
    }

    /// Length of the line.
    pub fn length(&self) -> f64 {
        (self.end - self.start).abs()
    }

    /// The interval of the axis the line covers, `(low, high)`.
    pub fn span(&self) -> (f64, f64) {
        (self.start.min(self.end), self.start.max(self.end))
    }

    /// Whether the region `[lo, hi]` of a sample lies on the line (module doc): in 1D
    /// every sample; else those with `lo ≤ offset < hi` across it along every other axis
    /// (`hi` included when the offset is on the body's high face, `upper`), and within the
    /// line's span along it.
    pub fn holds<const D: usize>(&self, lo: &Vector<D>, hi: &Vector<D>, upper: &Vector<D>) -> bool {
        let (a, b) = self.span();
        let tol = 1e-9 * (hi[self.axis] - lo[self.axis]).abs().max(1e-300);
        let centre = 0.5 * (lo[self.axis] + hi[self.axis]);
        if centre < a - tol || centre > b + tol {
            return false;
        }
        crate::Grid::<D>::tangent_axes(self.axis)
            .enumerate()
            .all(|(slot, other)| {
                let tol = 1e-9 * (hi[other] - lo[other]).abs().max(1e-300);
                let c = self.offset[slot];
                lo[other] <= c + tol
                    && (c < hi[other] - tol
                        || (hi[other] >= upper[other] - tol && c <= hi[other] + tol))
            })
    }

    /// The point of the line at coordinate `s` along it.
    pub fn point<const D: usize>(&self, s: f64) -> Vector<D> {
        let mut x = Vector::<D>::zeros();
        x[self.axis] = s;
        for (slot, k) in crate::Grid::<D>::tangent_axes(self.axis).enumerate() {
            x[k] = self.offset[slot];
        }
        x
    }

    /// One sentence: where the line runs and why.
    pub fn describe<const D: usize>(&self) -> String {
        let point = |s: f64| {
            let x = self.point::<D>(s);
            let parts: Vec<String> = x.iter().map(|v| v.to_string()).collect();
            format!("({})", parts.join(", "))
        };
        let why = match self.origin {
            LineOrigin::Stated => "stated by the scene ([metrics] line)".to_string(),
            LineOrigin::LoadedEdge(axis, side) => format!(
                "inferred: normal to the loaded {} edge{}",
                edge_name(axis, side),
                if D == 1 {
                    ""
                } else {
                    ", through the middle of its loaded patch"
                }
            ),
            LineOrigin::NoLoad => "inferred: no load, the bottom row along x".to_string(),
        };
        format!(
            "along {} from {} to {} m, {why}",
            ["x", "y", "z"][self.axis],
            point(self.start),
            point(self.end)
        )
    }
}

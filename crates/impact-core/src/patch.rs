//! Where on a face a load acts: a box of the face (a segment of an edge in 2D, a rectangle
//! in 3D) or a disc (3D), in the face's tangential coordinates, and the share of a cut
//! face, cell side or tributary area that it covers.
//!
//! A face normal to axis `l` has the `D - 1` tangential axes [`crate::Grid::tangent_axes`]
//! (increasing); a patch stores its extent along each of them in that order, so the
//! first tangential coordinate of a face normal to `z` is `x` and the second `y`.
//!
//! **Coverage** of the rectangle `centre ± half` (tangential coordinates):
//! - [`SegmentCover::Centre`]: 1 if the centre lies in the patch (1e-12 tolerance), else 0
//!   (Clawpack's and the paper's rule for a cell face);
//! - [`SegmentCover::Fraction`]: the covered area over the rectangle's area, exact for a
//!   box (a product of the covered lengths) and for a disc (the closed-form area of a disc
//!   cut by a rectangle, [`disc_rectangle_area`]), so the load's resultant equals
//!   `value × patch area` on any grid. A zero half width falls back to the centre rule
//!   along that axis.
use crate::options::SegmentCover;
use crate::{Grid, Vector};

/// The shape of a loaded patch in tangential coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PatchShape {
    /// `lo[k] ≤ s_k ≤ hi[k]` along each tangential axis `k` (unused entries are
    /// `-∞..∞`: a 2D edge has one tangential axis).
    Box {
        /// Lower ends (m).
        lo: [f64; 2],
        /// Upper ends (m).
        hi: [f64; 2],
    },
    /// `|s - centre| ≤ radius` (3D).
    Disc {
        /// Centre in tangential coordinates (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
}

/// A loaded patch of a face and its rule for cut faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Box or disc.
    pub shape: PatchShape,
    /// All or nothing by centre, or by covered fraction.
    pub cover: SegmentCover,
}

impl Patch {
    /// A segment `[from, to]` of a 2D edge.
    pub fn segment(from: f64, to: f64, cover: SegmentCover) -> Self {
        Self {
            shape: PatchShape::Box {
                lo: [from, f64::NEG_INFINITY],
                hi: [to, f64::INFINITY],
            },
            cover,
        }
    }

    /// The tangential coordinates of `x` on a face normal to `l` (the first `D - 1`
    /// entries are used).
    #[inline]
    pub fn tangential<const D: usize>(l: usize, x: &Vector<D>) -> [f64; 2] {
        let mut s = [0.0; 2];
        for (slot, k) in Grid::<D>::tangent_axes(l).enumerate() {
            s[slot] = x[k];
        }
        s
    }

    /// Whether the tangential point `s` lies in the patch (1e-12 tolerance).
    #[inline]
    pub fn contains(&self, s: [f64; 2]) -> bool {
        match self.shape {
            PatchShape::Box { lo, hi } => {
                (0..2).all(|k| s[k] >= lo[k] - 1e-12 && s[k] <= hi[k] + 1e-12)
            }
            PatchShape::Disc { centre, radius } => {
                let (dx, dy) = (s[0] - centre[0], s[1] - centre[1]);
                (dx * dx + dy * dy).sqrt() <= radius * (1.0 + 1e-12) + 1e-12
            }
        }
    }

    /// The covered share of the rectangle `centre ± half` (module doc); `dims` is the
    /// number of tangential axes (`D - 1`).
    pub fn coverage(&self, centre: [f64; 2], half: [f64; 2], dims: usize) -> f64 {
        if self.cover == SegmentCover::Centre {
            return f64::from(u8::from(self.contains(centre)));
        }
        match self.shape {
            PatchShape::Box { lo, hi } => (0..dims)
                .map(|k| {
                    if half[k] <= 0.0 {
                        f64::from(u8::from(
                            centre[k] >= lo[k] - 1e-12 && centre[k] <= hi[k] + 1e-12,
                        ))
                    } else {
                        let from = (centre[k] - half[k]).max(lo[k]);
                        let to = (centre[k] + half[k]).min(hi[k]);
                        ((to - from) / (2.0 * half[k])).clamp(0.0, 1.0)
                    }
                })
                .product(),
            PatchShape::Disc { centre: c, radius } => {
                if half[0] <= 0.0 || half[1] <= 0.0 {
                    return f64::from(u8::from(self.contains(centre)));
                }
                let area = disc_rectangle_area(
                    radius,
                    [centre[0] - half[0] - c[0], centre[0] + half[0] - c[0]],
                    [centre[1] - half[1] - c[1], centre[1] + half[1] - c[1]],
                );
                (area / (4.0 * half[0] * half[1])).clamp(0.0, 1.0)
            }
        }
    }

    /// The patch's area (length in 2D), for resultants.
    pub fn measure(&self, dims: usize) -> f64 {
        match self.shape {
            PatchShape::Box { lo, hi } => (0..dims).map(|k| hi[k] - lo[k]).product(),
            PatchShape::Disc { radius, .. } => std::f64::consts::PI * radius * radius,
        }
    }
}

/// Area of the disc `x² + y² ≤ r²` inside the rectangle `[x0, x1] × [y0, y1]`:
/// `A = Q(x1, y1) - Q(x0, y1) - Q(x1, y0) + Q(x0, y0)` with `Q(x, y) = sgn x sgn y ·
/// q(|x|, |y|)` the signed area of the disc in `[0, x] × [0, y]` and, for `x, y ≥ 0`,
/// `q = y'·a + S(x') - S(a)`, `x' = min(x, r)`, `y' = min(y, r)`,
/// `a = min(x', √(r² - y'²))`, `S(t) = ∫₀ᵗ √(r² - u²) du = ½(t√(r² - t²) + r² asin(t/r))`.
pub fn disc_rectangle_area(radius: f64, x: [f64; 2], y: [f64; 2]) -> f64 {
    let quadrant = |x: f64, y: f64| -> f64 {
        let sign = x.signum() * y.signum();
        let (x, y) = (x.abs().min(radius), y.abs().min(radius));
        let a = x.min((radius * radius - y * y).max(0.0).sqrt());
        let s = |t: f64| {
            0.5 * (t * (radius * radius - t * t).max(0.0).sqrt()
                + radius * radius * (t / radius).clamp(-1.0, 1.0).asin())
        };
        sign * (y * a + s(x) - s(a))
    };
    quadrant(x[1], y[1]) - quadrant(x[0], y[1]) - quadrant(x[1], y[0]) + quadrant(x[0], y[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    #[test]
    fn disc_area_in_rectangles_sums_to_the_disc() {
        let r = 0.37;
        assert_relative_eq!(
            disc_rectangle_area(r, [-1.0, 1.0], [-1.0, 1.0]),
            PI * r * r,
            epsilon = 1e-14
        );
        // a quarter, a half, and a grid of cells tiling the disc's box
        assert_relative_eq!(
            disc_rectangle_area(r, [0.0, 1.0], [0.0, 1.0]),
            0.25 * PI * r * r,
            epsilon = 1e-14
        );
        assert_relative_eq!(
            disc_rectangle_area(r, [-1.0, 1.0], [-1.0, 0.0]),
            0.5 * PI * r * r,
            epsilon = 1e-14
        );
        let h = 0.07;
        let mut sum = 0.0;
        for i in -7..7 {
            for j in -7..7 {
                let (x0, y0) = (i as f64 * h + 0.013, j as f64 * h - 0.021);
                sum += disc_rectangle_area(r, [x0, x0 + h], [y0, y0 + h]);
            }
        }
        assert_relative_eq!(sum, PI * r * r, epsilon = 1e-13);
    }

    #[test]
    fn disc_area_matches_sampling_on_a_cut_cell() {
        let r = 1.0;
        let (x, y) = ([0.6, 0.9], [0.2, 0.7]);
        let n = 2000;
        let mut inside = 0usize;
        for i in 0..n {
            for j in 0..n {
                let px = x[0] + (i as f64 + 0.5) / n as f64 * (x[1] - x[0]);
                let py = y[0] + (j as f64 + 0.5) / n as f64 * (y[1] - y[0]);
                inside += usize::from(px * px + py * py <= r * r);
            }
        }
        let sampled = inside as f64 / (n * n) as f64 * (x[1] - x[0]) * (y[1] - y[0]);
        assert_relative_eq!(disc_rectangle_area(r, x, y), sampled, epsilon = 2e-5);
    }

    #[test]
    fn box_fraction_is_the_product_of_covered_lengths() {
        let patch = Patch {
            shape: PatchShape::Box {
                lo: [0.0, 0.0],
                hi: [0.25, 0.5],
            },
            cover: SegmentCover::Fraction,
        };
        // a cell [0.2, 0.3] × [0.45, 0.55]: half covered along each axis
        assert_relative_eq!(patch.coverage([0.25, 0.5], [0.05, 0.05], 2), 0.25);
        assert_relative_eq!(patch.coverage([0.1, 0.1], [0.05, 0.05], 2), 1.0);
        assert_eq!(patch.coverage([0.4, 0.1], [0.05, 0.05], 2), 0.0);
        let centre = Patch {
            cover: SegmentCover::Centre,
            ..patch
        };
        assert_eq!(centre.coverage([0.25, 0.5], [0.05, 0.05], 2), 1.0);
        assert_eq!(centre.coverage([0.26, 0.5], [0.05, 0.05], 2), 0.0);
        // a segment (2D) ignores the second axis
        let seg = Patch::segment(0.0, 0.25, SegmentCover::Fraction);
        assert_relative_eq!(seg.coverage([0.25, 0.0], [0.05, 0.0], 1), 0.5);
    }
}

//! Regular Cartesian grid of `D`-dimensional cells with multilinear (tensor-product)
//! shape functions. Cell `c` has `2^D` local nodes; local node `a` sits at the corner whose
//! bit `l` of `a` tells low (0) or high (1) along axis `l`.
use crate::Vector;

/// A regular grid: `cells[l]` cells of size `spacing[l]` from `origin` along each axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid<const D: usize> {
    /// Lower corner.
    pub origin: Vector<D>,
    /// Cell size along each axis.
    pub spacing: Vector<D>,
    /// Number of cells along each axis.
    pub cells: [usize; D],
}

impl<const D: usize> Grid<D> {
    /// Number of local nodes of a cell, `2^D`.
    pub const NODES_PER_CELL: usize = 1 << D;

    /// Total number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells.iter().product()
    }

    /// Cell volume (length in 1D, area in 2D; unit thickness/cross-section).
    pub fn cell_volume(&self) -> f64 {
        self.spacing.iter().product()
    }

    /// Smallest cell size.
    pub fn min_spacing(&self) -> f64 {
        self.spacing.min()
    }

    /// Linear index of the cell with multi-index `idx` (axis 0 fastest).
    #[inline]
    pub fn cell_index(&self, idx: [usize; D]) -> usize {
        let mut lin = 0;
        for l in (0..D).rev() {
            lin = lin * self.cells[l] + idx[l];
        }
        lin
    }

    /// Index along axis `l` of the layer of cells holding the coordinate `x`, a coordinate
    /// within 1e-9 of a cell below a face counted in the cell above it (the rule of
    /// `MeasureLine::holds`: `lo ≤ x < hi`), clamped to the grid.
    #[inline]
    pub fn layer_of(&self, l: usize, x: f64) -> usize {
        let h = self.spacing[l];
        (((x - self.origin[l]) / h + 1e-9).floor().max(0.0) as usize).min(self.cells[l] - 1)
    }

    /// Multi-index of cell `c`.
    #[inline]
    pub fn cell_multi_index(&self, mut c: usize) -> [usize; D] {
        let mut idx = [0; D];
        for l in 0..D {
            idx[l] = c % self.cells[l];
            c /= self.cells[l];
        }
        idx
    }

    /// Lower corner of cell `c`.
    pub fn cell_lower(&self, c: usize) -> Vector<D> {
        let idx = self.cell_multi_index(c);
        Vector::<D>::from_fn(|l, _| self.origin[l] + idx[l] as f64 * self.spacing[l])
    }

    /// Centre of cell `c`.
    pub fn cell_centre(&self, c: usize) -> Vector<D> {
        self.cell_lower(c) + self.spacing * 0.5
    }

    /// The `count` layers of cells along the last axis from layer `first` on (a rank's
    /// slab; `count` may reach past the grid, e.g. into padding): the same spacing, the
    /// origin moved to the first layer, `x_0 + first · h`.
    pub fn layers(&self, first: usize, count: usize) -> Self {
        let mut cells = self.cells;
        cells[D - 1] = count;
        self.cut(
            std::array::from_fn(|k| if k == D - 1 { first } else { 0 }),
            cells,
        )
    }

    /// The box of `cells` cells per axis from cell `first` on (a rank's box; it may reach
    /// past the grid): the same spacing, the origin moved to the first cell,
    /// `x_0 + first · h` per axis (the same arithmetic on every axis, none on an uncut one).
    pub fn cut(&self, first: [usize; D], cells: [usize; D]) -> Self {
        let mut grid = self.clone();
        grid.cells = cells;
        for k in (0..D).filter(|&k| first[k] > 0) {
            grid.origin[k] += first[k] as f64 * self.spacing[k];
        }
        grid
    }

    /// Upper corner of the grid.
    pub fn upper(&self) -> Vector<D> {
        Vector::<D>::from_fn(|l, _| self.origin[l] + self.cells[l] as f64 * self.spacing[l])
    }

    /// The cell containing `x` (clamped to the grid) and the local coordinates in `[0,1]^D`.
    /// Returns `None` when `x` lies outside the grid.
    #[inline]
    pub fn locate(&self, x: &Vector<D>) -> Option<(usize, Vector<D>)> {
        let mut idx = [0usize; D];
        let mut xi = Vector::<D>::zeros();
        for l in 0..D {
            let s = (x[l] - self.origin[l]) / self.spacing[l];
            if !(s >= 0.0 && s <= self.cells[l] as f64) {
                return None;
            }
            let i = (s.floor() as usize).min(self.cells[l] - 1);
            idx[l] = i;
            xi[l] = s - i as f64;
        }
        Some((self.cell_index(idx), xi))
    }

    /// Number of grid vertices along each axis (`cells + 1`).
    pub fn vertex_counts(&self) -> [usize; D] {
        let mut n = self.cells;
        for v in n.iter_mut() {
            *v += 1;
        }
        n
    }

    /// Total number of grid vertices (shared nodes, used by MPM and FEM).
    pub fn vertex_count(&self) -> usize {
        self.vertex_counts().iter().product()
    }

    /// Vertex index of local node `a` of cell `c` (the shared-node numbering).
    #[inline]
    pub fn vertex_of(&self, c: usize, a: usize) -> usize {
        let idx = self.cell_multi_index(c);
        let n = self.vertex_counts();
        let mut lin = 0;
        for l in (0..D).rev() {
            lin = lin * n[l] + idx[l] + ((a >> l) & 1);
        }
        lin
    }

    /// Position of vertex `v`.
    pub fn vertex_position(&self, mut v: usize) -> Vector<D> {
        let n = self.vertex_counts();
        let mut x = self.origin;
        for l in 0..D {
            x[l] += (v % n[l]) as f64 * self.spacing[l];
            v /= n[l];
        }
        x
    }

    /// Tangential axes of a face normal to axis `l` (`D - 1` of them, increasing).
    #[inline]
    pub fn tangent_axes(l: usize) -> impl Iterator<Item = usize> {
        (0..D).filter(move |&k| k != l)
    }

    /// The axis along which a loaded segment of an edge normal to `l` is measured: the
    /// first tangential axis (`None` in 1D, where an edge is a point). Segments are a 2D
    /// notion; a 3D patch would need every tangential axis.
    #[inline]
    pub fn segment_axis(l: usize) -> Option<usize> {
        // closed form of `tangent_axes(l).next()` (a per-face call in the flux loops)
        match D {
            0 | 1 => None,
            _ => Some(usize::from(l == 0)),
        }
    }

    /// Dimensions of the array of faces normal to axis `l` (`cells + 1` along `l`).
    pub fn face_dims(&self, l: usize) -> [usize; D] {
        std::array::from_fn(|k| self.cells[k] + usize::from(k == l))
    }

    /// Number of faces normal to axis `l`.
    pub fn face_count(&self, l: usize) -> usize {
        self.face_dims(l).iter().product()
    }

    /// Multilinear shape functions `S_a(ξ)` and their physical gradients `∇S_a` at local
    /// coordinates `xi` in `[0,1]^D`: `S_a = Π_l (ξ_l if bit l of a else 1-ξ_l)`.
    #[inline]
    pub fn shape(&self, xi: &Vector<D>, values: &mut [f64], gradients: &mut [Vector<D>]) {
        for a in 0..Self::NODES_PER_CELL {
            let mut s = 1.0;
            let mut g = Vector::<D>::from_element(1.0);
            for l in 0..D {
                let high = (a >> l) & 1 == 1;
                let f = if high { xi[l] } else { 1.0 - xi[l] };
                let df = if high { 1.0 } else { -1.0 } / self.spacing[l];
                s *= f;
                for k in 0..D {
                    g[k] *= if k == l { df } else { f };
                }
            }
            values[a] = s;
            gradients[a] = g;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn shape_functions_partition_unity_and_reproduce_linear_fields() {
        let grid = Grid::<2> {
            origin: Vector::<2>::new(0.0, 0.0),
            spacing: Vector::<2>::new(0.5, 0.25),
            cells: [4, 3],
        };
        let x = Vector::<2>::new(1.3, 0.6);
        let (c, xi) = grid.locate(&x).unwrap();
        let mut s = [0.0; 4];
        let mut g = [Vector::<2>::zeros(); 4];
        grid.shape(&xi, &mut s, &mut g);
        assert_relative_eq!(s.iter().sum::<f64>(), 1.0, epsilon = 1e-14);
        let lower = grid.cell_lower(c);
        // reproduce f(x) = 3x + 2y and its gradient
        let mut f = 0.0;
        let mut df = Vector::<2>::zeros();
        for a in 0..4 {
            let node = lower
                + Vector::<2>::new(
                    (a & 1) as f64 * grid.spacing[0],
                    ((a >> 1) & 1) as f64 * grid.spacing[1],
                );
            let fa = 3.0 * node[0] + 2.0 * node[1];
            f += s[a] * fa;
            df += g[a] * fa;
            assert_relative_eq!(grid.vertex_position(grid.vertex_of(c, a)), node);
        }
        assert_relative_eq!(f, 3.0 * 1.3 + 2.0 * 0.6, epsilon = 1e-12);
        assert_relative_eq!(df, Vector::<2>::new(3.0, 2.0), epsilon = 1e-12);
    }
}

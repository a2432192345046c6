//! MPM shape functions: one-dimensional weights `φ(d)` of a node at signed distance `d`
//! (in cells) from the point, and their tensor products over the `w^D` nodes of a point's
//! stencil (`w` nodes per axis from the base node `s_k`).
//!
//! - Linear hat (Sulsky, Chen & Schreyer 1994), `w = 2`, `s = ⌊u⌋`:
//!   `φ(d) = 1 − |d|` for `|d| < 1`.
//! - Uniform GIMP (Bardenhagen & Kober 2004, eq. 45 for the 1D weight), the hat averaged over
//!   the point's domain of half-width `ℓ` cells (`ℓ = 1/(2 n)` for `n` points per cell and
//!   axis, kept fixed: uGIMP), `w = 3`, `s = ⌊u − ½⌋`:
//!   `φ = 1 − (d² + ℓ²)/(2ℓ)` for `|d| < ℓ`; `1 − |d|` for `ℓ ≤ |d| < 1 − ℓ`;
//!   `(1 + ℓ − |d|)²/(4ℓ)` for `1 − ℓ ≤ |d| < 1 + ℓ`; 0 beyond.
//! - Quadratic B-spline (Steffen, Kirby & Berzins 2008), `w = 3`, `s = ⌊u − ½⌋`:
//!   `φ = ¾ − d²` for `|d| < ½`; `½ (³⁄₂ − |d|)²` for `½ ≤ |d| < ³⁄₂`.
//! - Cubic B-spline, `w = 4`, `s = ⌊u⌋ − 1`:
//!   `φ = ½|d|³ − d² + ⅔` for `|d| < 1`; `(2 − |d|)³/6` for `1 ≤ |d| < 2`.
//!
//! Here `u = (x − x_0)/h` is the point's grid coordinate. Boundary treatment: the background
//! grid is padded by [`crate::PADDING`] cells on every side, so every stencil lies on the
//! uniform grid and the weights keep the partition of unity `Σ φ = 1` and linear
//! completeness `Σ φ_i x_i = x` up to the body's edges (tested). Nodes outside the body then
//! carry mass, as in any padded-grid B-spline MPM; velocity and symmetry edges prescribe the
//! nodes on and beyond the edge. A pressure load is still spread over the nodes of the cell
//! holding its application point with the hat's weights, whatever the shape (the whole force
//! reaches the body either way).
use impact_core::method::MpmShape;
use impact_core::{Grid, Vector};

/// Most nodes per axis of a stencil.
pub const MAX_WIDTH: usize = 4;

/// The weight `φ(d)` and `dφ/dd` of a node at signed distance `d` (cells) for `shape`, with
/// GIMP's half domain `half` (cells).
#[inline]
pub fn weight(shape: MpmShape, half: f64, d: f64) -> (f64, f64) {
    let a = d.abs();
    let sign = if d < 0.0 { -1.0 } else { 1.0 };
    match shape {
        // CPDI evaluates hats at its domain's corners (`crate::cpdi`); alone, a hat
        MpmShape::Linear | MpmShape::Cpdi => {
            // `≤`: a point on a node takes the one-sided slopes of the cell it lies in
            // (its stencil's nodes at d = 0 and d = -1)
            if a <= 1.0 {
                (1.0 - a, -sign)
            } else {
                (0.0, 0.0)
            }
        }
        MpmShape::Gimp => {
            let l = half;
            if a < l {
                (1.0 - (d * d + l * l) / (2.0 * l), -d / l)
            } else if a < 1.0 - l {
                (1.0 - a, -sign)
            } else if a < 1.0 + l {
                let r = 1.0 + l - a;
                (r * r / (4.0 * l), -sign * r / (2.0 * l))
            } else {
                (0.0, 0.0)
            }
        }
        MpmShape::Bspline2 => {
            if a < 0.5 {
                (0.75 - d * d, -2.0 * d)
            } else if a < 1.5 {
                let r = 1.5 - a;
                (0.5 * r * r, -sign * r)
            } else {
                (0.0, 0.0)
            }
        }
        MpmShape::Bspline3 => {
            if a < 1.0 {
                (
                    0.5 * a * a * a - d * d + 2.0 / 3.0,
                    sign * 1.5 * a * a - 2.0 * d,
                )
            } else if a < 2.0 {
                let r = 2.0 - a;
                (r * r * r / 6.0, -sign * 0.5 * r * r)
            } else {
                (0.0, 0.0)
            }
        }
    }
}

/// The stencil of a shape function on a grid: nodes per axis, node offsets from the base
/// node, GIMP's half domain.
#[derive(Debug, Clone)]
pub struct Stencil<const D: usize> {
    /// The shape function.
    pub shape: MpmShape,
    /// Nodes per axis.
    pub width: usize,
    /// Nodes of a stencil, `width^D`.
    pub nodes: usize,
    /// Linear index offset of local node `a` (first axis fastest) from the base node.
    pub offsets: Vec<usize>,
    /// Linear index offset of each row's first node from the base node: a row is `width`
    /// consecutive nodes along the first axis (stride 1), local nodes `r·width ..
    /// (r + 1)·width`, so `offsets[r·width + c] = row_offsets[r] + c`. 32 bits: a row's
    /// end `row_offsets[r] + width` cannot overflow, so the scatter and gather check a row
    /// against the nodes from the point's base node on with one comparison.
    pub(crate) row_offsets: Vec<u32>,
    /// Linear index stride of each axis.
    pub(crate) strides: [usize; D],
    /// Position of local node `a` relative to the base node, `(k_0 h_0, …)` for its
    /// per-axis index `k` (APIC's `x_i − x_p`: `crate::affine`).
    pub(crate) steps: Vec<Vector<D>>,
    /// GIMP's half domain in cells, `1/(2 n)` for `n` points per cell and axis.
    half: f64,
}

impl<const D: usize> Stencil<D> {
    /// The stencil of `shape` on `grid` for `points_per_axis` points per cell and axis.
    pub fn new(grid: &Grid<D>, shape: MpmShape, points_per_axis: usize) -> Self {
        let width: usize = match shape {
            MpmShape::Linear => 2,
            MpmShape::Gimp | MpmShape::Bspline2 => 3,
            MpmShape::Bspline3 | MpmShape::Cpdi => 4,
        };
        let counts = grid.vertex_counts();
        let mut strides = [1usize; D];
        for k in 1..D {
            strides[k] = strides[k - 1] * counts[k - 1];
        }
        let nodes = width.pow(D as u32);
        let offsets = (0..nodes)
            .map(|a| {
                let mut rest = a;
                (0..D).fold(0, |sum, k| {
                    let local = rest % width;
                    rest /= width;
                    sum + local * strides[k]
                })
            })
            .collect::<Vec<usize>>();
        let row_offsets = (offsets.iter().step_by(width))
            .map(|&o| u32::try_from(o).expect("a stencil spans fewer than 2^32 nodes"))
            .collect();
        let mut stencil = Self {
            shape,
            width,
            nodes,
            offsets,
            row_offsets,
            strides,
            steps: Vec::new(),
            half: 0.5 / points_per_axis.max(1) as f64,
        };
        stencil.steps = (0..nodes)
            .map(|a| {
                let local = stencil.local_index(a);
                Vector::<D>::from_fn(|k, _| local[k] as f64 * grid.spacing[k])
            })
            .collect();
        stencil
    }

    /// The per-axis position (first axis fastest) of local node `a` in the stencil.
    #[inline]
    pub(crate) fn local_index(&self, a: usize) -> [usize; D] {
        let mut local = [0usize; D];
        let mut rest = a;
        for l in local.iter_mut() {
            *l = rest % self.width;
            rest /= self.width;
        }
        local
    }

    /// A CPDI domain at rest: half a point spacing along each axis, `diag(ℓ h)`.
    pub fn rest_domain(&self, grid: &Grid<D>) -> impact_core::Tensor<D> {
        impact_core::Tensor::<D>::from_diagonal(&(grid.spacing * self.half))
    }

    /// The first node of the stencil along an axis at grid coordinate `u`, if the stencil
    /// lies on the `cells` cells of that axis.
    #[inline]
    fn start(&self, u: f64, cells: usize) -> Option<f64> {
        let start = match self.width {
            2 => u.floor(),
            3 => (u - 0.5).floor(),
            _ => u.floor() - 1.0,
        };
        (start >= 0.0 && start + (self.width - 1) as f64 <= cells as f64).then_some(start)
    }

    /// Whether the stencil of a point at `x` lies on the grid.
    pub fn fits(&self, grid: &Grid<D>, x: &Vector<D>) -> bool {
        if self.shape == MpmShape::Cpdi {
            return self.fits_domain(grid, x, &self.rest_domain(grid));
        }
        (0..D).all(|k| {
            let u = (x[k] - grid.origin[k]) / grid.spacing[k];
            self.start(u, grid.cells[k]).is_some()
        })
    }

    /// Weights and gradients of the stencil's nodes at `x` into `values` and `gradients`
    /// (`nodes` entries each); returns the base node's linear index and its layer along
    /// the last axis, or `None` if the stencil leaves the grid.
    pub fn evaluate(
        &self,
        grid: &Grid<D>,
        x: &Vector<D>,
        values: &mut [f64],
        gradients: &mut [Vector<D>],
    ) -> Option<(usize, usize)> {
        if self.shape == MpmShape::Cpdi {
            return self.evaluate_domain(grid, x, &self.rest_domain(grid), values, gradients);
        }
        let mut phi = [[0.0; MAX_WIDTH]; D];
        let mut dphi = [[0.0; MAX_WIDTH]; D];
        let mut base = [0usize; D];
        for k in 0..D {
            let u = (x[k] - grid.origin[k]) / grid.spacing[k];
            let start = self.start(u, grid.cells[k])?;
            base[k] = start as usize;
            for j in 0..self.width {
                let (w, dw) = weight(self.shape, self.half, u - (start + j as f64));
                phi[k][j] = w;
                // d/dx of φ(u − i) = φ'(d) / h
                dphi[k][j] = dw / grid.spacing[k];
            }
        }
        for a in 0..self.nodes {
            let local = self.local_index(a);
            let mut value = 1.0;
            let mut gradient = Vector::<D>::from_element(1.0);
            for k in 0..D {
                value *= phi[k][local[k]];
                for (m, g) in gradient.iter_mut().enumerate() {
                    *g *= if m == k {
                        dphi[k][local[k]]
                    } else {
                        phi[k][local[k]]
                    };
                }
            }
            values[a] = value;
            gradients[a] = gradient;
        }
        let index = (0..D).map(|k| base[k] * self.strides[k]).sum();
        Some((index, base[D - 1]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid2() -> Grid<2> {
        Grid {
            origin: Vector::<2>::new(-0.4, -0.3),
            spacing: Vector::<2>::new(0.1, 0.075),
            cells: [20, 16],
        }
    }

    /// Partition of unity, linear completeness and zero-sum gradients at points anywhere
    /// in the grid (edges of the padded grid excepted, where the stencil leaves it).
    #[test]
    fn every_shape_is_a_partition_of_unity_and_linearly_complete() {
        let grid = grid2();
        for shape in MpmShape::ALL {
            for per_axis in [1, 2, 3] {
                let stencil = Stencil::new(&grid, shape, per_axis);
                let mut values = vec![0.0; stencil.nodes];
                let mut gradients = vec![Vector::<2>::zeros(); stencil.nodes];
                let mut tested = 0;
                for i in 0..400 {
                    // a deterministic spread of points, including cell faces and nodes
                    let x = Vector::<2>::new(
                        -0.4 + 2.0 * ((i as f64 * 0.6180339887) % 1.0),
                        -0.3 + 1.2 * ((i as f64 * 0.4142135623) % 1.0),
                    );
                    let x = if i % 7 == 0 {
                        Vector::<2>::new((x[0] * 10.0).round() / 10.0, x[1])
                    } else {
                        x
                    };
                    let evaluated = stencil.evaluate(&grid, &x, &mut values, &mut gradients);
                    assert_eq!(
                        evaluated.is_some(),
                        stencil.fits(&grid, &x),
                        "{shape:?} at {x}"
                    );
                    let Some((base, _)) = evaluated else {
                        continue;
                    };
                    tested += 1;
                    let sum: f64 = values.iter().sum();
                    let mut first = Vector::<2>::zeros();
                    let mut gradient_sum = Vector::<2>::zeros();
                    let mut jacobian = nalgebra::Matrix2::<f64>::zeros();
                    for a in 0..stencil.nodes {
                        let node = grid.vertex_position(base + stencil.offsets[a]);
                        first += node * values[a];
                        gradient_sum += gradients[a];
                        jacobian += node * gradients[a].transpose();
                    }
                    assert!(
                        (sum - 1.0).abs() < 1e-14,
                        "{shape:?} {per_axis}: Σφ = {sum}"
                    );
                    assert!(
                        (first - x).norm() < 1e-14,
                        "{shape:?}: Σφx = {first} at {x}"
                    );
                    assert!(
                        gradient_sum.norm() < 1e-12,
                        "{shape:?}: Σ∇φ = {gradient_sum}"
                    );
                    // Σ x_i ⊗ ∇φ_i = I: the gradient of the position is exact
                    assert!(
                        (jacobian - nalgebra::Matrix2::identity()).norm() < 1e-12,
                        "{shape:?}: {jacobian}"
                    );
                }
                assert!(tested > 300, "{shape:?}: {tested} points inside");
            }
        }
    }

    /// 3D: every shape's 8-, 27- or 64-node stencil is a partition of unity, linearly
    /// complete, with zero-sum gradients and `Σ x_i ⊗ ∇φ_i = I`; and its weights are the
    /// products of the 1D ones (the 3D stencil of a point is the tensor product of its 1D
    /// stencils along each axis).
    #[test]
    fn every_shape_is_a_partition_of_unity_and_linearly_complete_in_3d() {
        let grid = Grid::<3> {
            origin: Vector::<3>::new(-0.4, -0.3, -0.2),
            spacing: Vector::<3>::new(0.1, 0.075, 0.05),
            cells: [20, 16, 14],
        };
        for shape in MpmShape::ALL {
            for per_axis in [1, 2] {
                let stencil = Stencil::new(&grid, shape, per_axis);
                let line = |k: usize| Grid::<1> {
                    origin: Vector::<1>::new(grid.origin[k]),
                    spacing: Vector::<1>::new(grid.spacing[k]),
                    cells: [grid.cells[k]],
                };
                let lines: Vec<_> = (0..3)
                    .map(|k| Stencil::new(&line(k), shape, per_axis))
                    .collect();
                let mut values = vec![0.0; stencil.nodes];
                let mut gradients = vec![Vector::<3>::zeros(); stencil.nodes];
                let (mut v1, mut g1) = (
                    vec![vec![0.0; 4]; 3],
                    vec![vec![Vector::<1>::zeros(); 4]; 3],
                );
                let mut tested = 0;
                for i in 0..150 {
                    let x = Vector::<3>::new(
                        -0.4 + 2.0 * ((i as f64 * 0.618_033_988_7) % 1.0),
                        -0.3 + 1.2 * ((i as f64 * 0.414_213_562_3) % 1.0),
                        -0.2 + 0.7 * ((i as f64 * 0.732_050_807_6) % 1.0),
                    );
                    let Some((base, _)) = stencil.evaluate(&grid, &x, &mut values, &mut gradients)
                    else {
                        continue;
                    };
                    tested += 1;
                    let mut sum = 0.0;
                    let mut first = Vector::<3>::zeros();
                    let mut gradient_sum = Vector::<3>::zeros();
                    let mut jacobian = nalgebra::Matrix3::<f64>::zeros();
                    for a in 0..stencil.nodes {
                        let node = grid.vertex_position(base + stencil.offsets[a]);
                        sum += values[a];
                        first += node * values[a];
                        gradient_sum += gradients[a];
                        jacobian += node * gradients[a].transpose();
                    }
                    assert!((sum - 1.0).abs() < 1e-14, "{shape:?}: Σφ = {sum}");
                    assert!((first - x).norm() < 1e-14, "{shape:?}: Σφx = {first}");
                    assert!(
                        gradient_sum.norm() < 1e-9,
                        "{shape:?}: Σ∇φ = {gradient_sum}"
                    );
                    assert!((jacobian - nalgebra::Matrix3::identity()).norm() < 1e-12);
                    if shape == MpmShape::Cpdi {
                        continue;
                    }
                    for k in 0..3 {
                        let xk = Vector::<1>::new(x[k]);
                        lines[k]
                            .evaluate(&line(k), &xk, &mut v1[k], &mut g1[k])
                            .unwrap();
                    }
                    for a in 0..stencil.nodes {
                        let l = stencil.local_index(a);
                        let product = v1[0][l[0]] * v1[1][l[1]] * v1[2][l[2]];
                        assert!((values[a] - product).abs() < 1e-15, "{shape:?}");
                        let dx = g1[0][l[0]][0] * v1[1][l[1]] * v1[2][l[2]];
                        assert!((gradients[a][0] - dx).abs() <= 1e-12 * dx.abs().max(1.0));
                    }
                }
                assert!(tested > 60, "{shape:?}: {tested} points inside");
            }
        }
    }

    /// The rows the scatter and gather read (`row_offsets`): `width` consecutive nodes
    /// each, together the stencil's nodes in its order, in 2D and 3D.
    #[test]
    fn rows_of_consecutive_nodes_cover_the_stencil_in_order() {
        fn check<const D: usize>(grid: &Grid<D>) {
            for shape in MpmShape::ALL {
                let stencil = Stencil::new(grid, shape, 2);
                assert_eq!(stencil.row_offsets.len() * stencil.width, stencil.nodes);
                for (a, &offset) in stencil.offsets.iter().enumerate() {
                    let (row, column) = (a / stencil.width, a % stencil.width);
                    let first = stencil.row_offsets[row] as usize;
                    assert_eq!(offset, first + column, "{shape:?} {a}");
                }
            }
        }
        check(&grid2());
        check(&Grid::<3> {
            origin: Vector::<3>::zeros(),
            spacing: Vector::<3>::new(0.1, 0.075, 0.05),
            cells: [20, 16, 14],
        });
    }

    /// The derivative of each 1D weight agrees with a central difference.
    #[test]
    fn weight_derivatives_match_finite_differences() {
        for shape in MpmShape::ALL {
            for half in [0.5, 0.25] {
                for k in 0..200 {
                    let d = -2.2 + 4.4 * k as f64 / 199.0 + 1e-3;
                    let h = 1e-6;
                    let numeric =
                        (weight(shape, half, d + h).0 - weight(shape, half, d - h).0) / (2.0 * h);
                    let (_, analytic) = weight(shape, half, d);
                    assert!(
                        (numeric - analytic).abs() < 1e-6,
                        "{shape:?} ℓ = {half} d = {d}: {numeric} vs {analytic}"
                    );
                }
            }
        }
    }

    /// At cell centres (one point per cell, total Lagrangian), uGIMP and the quadratic
    /// B-spline give each node the linear hat's weight and gradient.
    #[test]
    fn smooth_shapes_equal_the_hat_at_cell_centres() {
        let grid = grid2();
        let linear = Stencil::new(&grid, MpmShape::Linear, 1);
        let (mut lv, mut lg) = (vec![0.0; 4], vec![Vector::<2>::zeros(); 4]);
        for shape in [MpmShape::Gimp, MpmShape::Bspline2] {
            let smooth = Stencil::new(&grid, shape, 1);
            let (mut sv, mut sg) = (vec![0.0; 9], vec![Vector::<2>::zeros(); 9]);
            for (i, j) in [(3usize, 4usize), (10, 2), (17, 13)] {
                let x = Vector::<2>::new(
                    grid.origin[0] + (i as f64 + 0.5) * grid.spacing[0],
                    grid.origin[1] + (j as f64 + 0.5) * grid.spacing[1],
                );
                let (lb, _) = linear.evaluate(&grid, &x, &mut lv, &mut lg).unwrap();
                let (sb, _) = smooth.evaluate(&grid, &x, &mut sv, &mut sg).unwrap();
                for a in 0..4 {
                    let node = lb + linear.offsets[a];
                    let b = (0..9).find(|&b| sb + smooth.offsets[b] == node).unwrap();
                    assert!((lv[a] - sv[b]).abs() < 1e-14, "{shape:?} value at {x}");
                    assert!(
                        (lg[a] - sg[b]).norm() < 1e-10,
                        "{shape:?}: {} vs {}",
                        lg[a],
                        sg[b]
                    );
                }
            }
        }
    }
}

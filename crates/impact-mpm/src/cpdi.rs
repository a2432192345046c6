//! CPDI1 weights (Sadeghirad, Brannon & Burghardt 2011, eq. 21-22): the point's domain is
//! the parallelogram (parallelepiped in 3D, segment in 1D) `x_p + Σ_k ξ_k r_k`,
//! `ξ ∈ [-1, 1]^D`, with edge half-vectors `r_k` (the columns of `R`; `R = diag(ℓ)` at
//! the start, `ℓ` the half-size, and `R ← (I + Δt ∇v) R` in the updated Lagrangian frame).
//! The hat `N_i` is replaced by its multilinear interpolant from the domain's `2^D`
//! corners `x_c = x_p + Σ_k s_ck r_k` (`s_ck = ±1`), whose average and average gradient
//! over the domain are
//!
//! `S_ip = 2^{-D} Σ_c N_i(x_c)`,  `∇S_ip = 2^{-D} Σ_c N_i(x_c) R^{-T} s_c`
//!
//! (`∫ ∇Q_c dV = det R · R^{-T} s_c` for the corner function `Q_c` and `V = 2^D det R`;
//! in 2D this is the paper's eq. 22; in 1D `∇S = (N(x_+) − N(x_−)) / (2r)`). Both keep the
//! partition of unity and linear completeness (tested here and in `shape.rs`, 1D to 3D).
//! An undeformed box gives the product of the 1D corner means, the trapezoidal rule of the
//! hat over the domain along each axis (close to uGIMP's exact average, not equal to it).
//! The stencil is 4 nodes per axis from the node below the lowest corner, so a domain may
//! grow to two cells along each axis.
use crate::shape::Stencil;
use impact_core::{Grid, Tensor, Vector};

/// Most corners of a domain (`2^D`, 3D).
const MAX_CORNERS: usize = 8;

impl<const D: usize> Stencil<D> {
    /// The stencil's first node along each axis for the domain `domain` around `x`, if
    /// all its corners' hats lie on the grid.
    pub(crate) fn domain_start(
        &self,
        grid: &Grid<D>,
        x: &Vector<D>,
        domain: &Tensor<D>,
    ) -> Option<[usize; D]> {
        let mut start = [0usize; D];
        for k in 0..D {
            let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
            for c in 0..1usize << D {
                let u = (corner(x, domain, c)[k] - grid.origin[k]) / grid.spacing[k];
                low = low.min(u);
                high = high.max(u);
            }
            let first = low.floor();
            // the highest corner's hat needs nodes ⌊u⌋ and ⌊u⌋ + 1 within the 4
            let fits = first >= 0.0
                && high.floor() <= first + 2.0
                && first + (self.width - 1) as f64 <= grid.cells[k] as f64;
            if !(fits && low.is_finite() && high.is_finite()) {
                return None;
            }
            start[k] = first as usize;
        }
        Some(start)
    }

    /// Whether the domain's stencil lies on the grid.
    pub fn fits_domain(&self, grid: &Grid<D>, x: &Vector<D>, domain: &Tensor<D>) -> bool {
        self.domain_start(grid, x, domain).is_some()
    }

    /// CPDI1 weights and gradients (module doc) of the stencil's nodes into `values` and
    /// `gradients`; returns the base node's linear index and its layer along the last axis,
    /// or `None` if the stencil leaves the grid or the domain is degenerate.
    pub fn evaluate_domain(
        &self,
        grid: &Grid<D>,
        x: &Vector<D>,
        domain: &Tensor<D>,
        values: &mut [f64],
        gradients: &mut [Vector<D>],
    ) -> Option<(usize, usize)> {
        let start = self.domain_start(grid, x, domain)?;
        let inverse_transpose = domain.try_inverse()?.transpose();
        let corners = 1usize << D;
        let share = 1.0 / corners as f64;
        // per corner: the hat of each stencil node along each axis, and R^{-T} s_c
        let mut hats = [[[0.0; crate::shape::MAX_WIDTH]; D]; MAX_CORNERS];
        let mut directions = [Vector::<D>::zeros(); MAX_CORNERS];
        for c in 0..corners {
            let xc = corner(x, domain, c);
            for k in 0..D {
                let u = (xc[k] - grid.origin[k]) / grid.spacing[k];
                for j in 0..self.width {
                    let d = u - (start[k] + j) as f64;
                    hats[c][k][j] = (1.0 - d.abs()).max(0.0);
                }
            }
            directions[c] = inverse_transpose * signs::<D>(c);
        }
        for a in 0..self.nodes {
            let local = self.local_index(a);
            let mut value = 0.0;
            let mut gradient = Vector::<D>::zeros();
            for c in 0..corners {
                let hat: f64 = (0..D).map(|k| hats[c][k][local[k]]).product();
                value += hat * share;
                gradient += directions[c] * (hat * share);
            }
            values[a] = value;
            gradients[a] = gradient;
        }
        let index = (0..D).map(|k| start[k] * self.strides[k]).sum();
        Some((index, start[D - 1]))
    }
}

/// The signs `s_c` of corner `c` (bit `k` set: `+1` along `r_k`).
#[inline]
fn signs<const D: usize>(c: usize) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| if (c >> k) & 1 == 1 { 1.0 } else { -1.0 })
}

/// Corner `c` of the domain `R` around `x`: `x + R s_c`.
#[inline]
fn corner<const D: usize>(x: &Vector<D>, domain: &Tensor<D>, c: usize) -> Vector<D> {
    x + domain * signs::<D>(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_core::method::MpmShape;

    /// Partition of unity, linear completeness, zero-sum gradients and an exact position
    /// gradient (`Σ x_i ⊗ ∇S_i = I`) for sheared, stretched and rotated domains anywhere
    /// in the grid.
    #[test]
    fn cpdi_weights_are_a_partition_of_unity_and_linearly_complete() {
        let grid = Grid::<2> {
            origin: Vector::<2>::new(-0.4, -0.3),
            spacing: Vector::<2>::new(0.1, 0.075),
            cells: [20, 16],
        };
        let stencil = Stencil::new(&grid, MpmShape::Cpdi, 2);
        let (mut values, mut gradients) = (vec![0.0; 16], vec![Vector::<2>::zeros(); 16]);
        let mut tested = 0;
        for i in 0..300 {
            let x = Vector::<2>::new(
                -0.2 + 1.6 * ((i as f64 * 0.618_033_988_7) % 1.0),
                -0.15 + 0.9 * ((i as f64 * 0.414_213_562_3) % 1.0),
            );
            let angle = i as f64 * 0.37;
            let (c, s) = (angle.cos(), angle.sin());
            let shear = 0.3 * ((i % 5) as f64 - 2.0) / 2.0;
            let stretch = Tensor::<2>::new(
                0.025 * (1.0 + 0.1 * (i % 3) as f64),
                0.025 * shear,
                0.0,
                0.019,
            );
            let domain = Tensor::<2>::new(c, -s, s, c) * stretch;
            let Some((base, _)) =
                stencil.evaluate_domain(&grid, &x, &domain, &mut values, &mut gradients)
            else {
                continue;
            };
            tested += 1;
            let sum: f64 = values.iter().sum();
            let mut first = Vector::<2>::zeros();
            let mut gradient_sum = Vector::<2>::zeros();
            let mut jacobian = Tensor::<2>::zeros();
            for a in 0..16 {
                let node = grid.vertex_position(base + stencil.offsets[a]);
                first += node * values[a];
                gradient_sum += gradients[a];
                jacobian += node * gradients[a].transpose();
            }
            assert!((sum - 1.0).abs() < 1e-14, "Σ S = {sum}");
            assert!((first - x).norm() < 1e-14, "Σ S x = {first} at {x}");
            assert!(gradient_sum.norm() < 1e-10, "Σ ∇S = {gradient_sum}");
            assert!(
                (jacobian - Tensor::<2>::identity()).norm() < 1e-12,
                "{jacobian}"
            );
        }
        assert!(tested > 250, "{tested} inside");
    }

    /// 3D (hexahedral domains, 8 corners, 64-node stencils): partition of unity, linear
    /// completeness, zero-sum gradients and `Σ x_i ⊗ ∇S_i = I` for rotated, sheared and
    /// stretched parallelepipeds; and an undeformed domain gives uGIMP's weights (the hat
    /// averaged over a box is the tensor product of the 1D averages).
    #[test]
    fn three_dimensional_cpdi_is_a_partition_of_unity_and_linearly_complete() {
        let grid = Grid::<3> {
            origin: Vector::<3>::new(-0.4, -0.3, -0.2),
            spacing: Vector::<3>::new(0.1, 0.075, 0.05),
            cells: [20, 16, 14],
        };
        let stencil = Stencil::new(&grid, MpmShape::Cpdi, 2);
        let (mut values, mut gradients) = (vec![0.0; 64], vec![Vector::<3>::zeros(); 64]);
        let mut tested = 0;
        for i in 0..200 {
            let x = Vector::<3>::new(
                -0.2 + 1.6 * ((i as f64 * 0.618_033_988_7) % 1.0),
                -0.15 + 0.9 * ((i as f64 * 0.414_213_562_3) % 1.0),
                -0.1 + 0.5 * ((i as f64 * 0.732_050_807_6) % 1.0),
            );
            let (a, b) = (i as f64 * 0.37, i as f64 * 0.23);
            let rz = Tensor::<3>::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0);
            let rx = Tensor::<3>::new(1.0, 0.0, 0.0, 0.0, b.cos(), -b.sin(), 0.0, b.sin(), b.cos());
            let shear = 0.3 * ((i % 5) as f64 - 2.0) / 2.0;
            let stretch = Tensor::<3>::new(
                0.025 * (1.0 + 0.1 * (i % 3) as f64),
                0.025 * shear,
                0.0,
                0.0,
                0.019,
                0.01 * shear,
                0.0,
                0.0,
                0.0125,
            );
            let domain = rz * rx * stretch;
            let Some((base, _)) =
                stencil.evaluate_domain(&grid, &x, &domain, &mut values, &mut gradients)
            else {
                continue;
            };
            tested += 1;
            let mut sum = 0.0;
            let mut first = Vector::<3>::zeros();
            let mut gradient_sum = Vector::<3>::zeros();
            let mut jacobian = Tensor::<3>::zeros();
            for a in 0..64 {
                let node = grid.vertex_position(base + stencil.offsets[a]);
                sum += values[a];
                first += node * values[a];
                gradient_sum += gradients[a];
                jacobian += node * gradients[a].transpose();
            }
            assert!((sum - 1.0).abs() < 1e-14, "Σ S = {sum}");
            assert!((first - x).norm() < 1e-14, "Σ S x = {first} at {x}");
            assert!(gradient_sum.norm() < 1e-9, "Σ ∇S = {gradient_sum}");
            assert!(
                (jacobian - Tensor::<3>::identity()).norm() < 1e-12,
                "{jacobian}"
            );
        }
        assert!(tested > 150, "{tested} inside");
        // an undeformed box: the product of the 1D corner means (trapezoidal rule of the
        // hat along each axis)
        let x = Vector::<3>::new(0.513, 0.271, 0.137);
        let r = stencil.rest_domain(&grid);
        let (base, _) = stencil
            .evaluate_domain(&grid, &x, &r, &mut values, &mut gradients)
            .unwrap();
        for a in 0..64 {
            let node = grid.vertex_position(base + stencil.offsets[a]);
            let hat = |k: usize, at: f64| (1.0 - ((at - node[k]) / grid.spacing[k]).abs()).max(0.0);
            let mean = |k: usize| 0.5 * (hat(k, x[k] - r[(k, k)]) + hat(k, x[k] + r[(k, k)]));
            let expected = mean(0) * mean(1) * mean(2);
            assert!(
                (values[a] - expected).abs() < 1e-15,
                "{} vs {expected}",
                values[a]
            );
        }
    }

    /// In 1D `∇S = (N(x + r) − N(x − r)) / (2r)` and `S` is the corners' mean.
    #[test]
    fn one_dimensional_cpdi_is_the_segment_average() {
        let grid = Grid::<1> {
            origin: Vector::<1>::new(0.0),
            spacing: Vector::<1>::new(0.5),
            cells: [10],
        };
        let stencil = Stencil::new(&grid, MpmShape::Cpdi, 1);
        let (mut values, mut gradients) = (vec![0.0; 4], vec![Vector::<1>::zeros(); 4]);
        let (x, r) = (Vector::<1>::new(1.9), 0.3);
        let (base, _) = stencil
            .evaluate_domain(&grid, &x, &Tensor::<1>::new(r), &mut values, &mut gradients)
            .unwrap();
        let hat = |node: f64, at: f64| (1.0 - ((at - node) / 0.5).abs()).max(0.0);
        for a in 0..4 {
            let node = grid.vertex_position(base + a)[0];
            let (low, high) = (hat(node, 1.9 - r), hat(node, 1.9 + r));
            assert!((values[a] - 0.5 * (low + high)).abs() < 1e-15);
            assert!((gradients[a][0] - (high - low) / (2.0 * r)).abs() < 1e-13);
        }
    }
}

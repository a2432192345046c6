//! Order 2 with the approximate Saint-Venant–Kirchhoff solver in 2D and 3D (donor-cell;
//! [`crate::riemann::svk_approximate`]). The solver links each side to the star state `q*`
//! by `t* − t_L = Z_L (v* − v_L)` and `t* − t_R = −Z_R (v* − v_R)`, `Z = sqrt(ρ₀ A(F, n))`
//! (Toro 2009, §9.3). `Z` shares the eigenvectors of the side's acoustic tensor `A`, so the
//! jump of each side splits exactly into a P part and a shear part: with `e_P` the unit
//! eigenvector of the largest eigenvalue `λ_P` of `A` (the P wave, `c_P = sqrt(λ_P/ρ₀)`),
//! `a = e_P·(v* − v_L)` and the state `m_L = (t_L + Z_P a e_P, v_L + a e_P)`,
//! `Z_P = sqrt(ρ₀ λ_P)`, between the waves, the left f-waves (LeVeque 2002, §15.5; flux
//! `F_n(q) = −(v ⊗ n, Π n)`) are
//!
//! - P: `Z¹ = F_n(m_L) − F_n(q_L) = −(a e_P ⊗ n, Z_P a e_P)` at `−c_P`,
//! - S: `Z³ = F_n(q*) − F_n(m_L)` at `−c_S`,
//!
//! and the mirror on the right (`a = e_P·(v_R − v*)`, `m_R = (t_R + Z_P a e_P, v_R − a e_P)`,
//! `Z⁴ = F_n(m_R) − F_n(q*)` at `+c_S`, `Z⁶ = F_n(q_R) − F_n(m_R)` at `+c_P`), the families
//! P and S of [`WAVES`](super::WAVES) (the linear solver's slots). They sum to the flux jump
//! and the left-going ones to `F_n(q*) − F_n(q_L)`, so the Godunov flux is unchanged.
//!
//! **Why the shear waves are one family.** The shear part of the jump lies in the
//! eigenspace orthogonal to `e_P`: one direction in 2D, two in 3D. Near `F = 1` the two
//! shear eigenvalues of the 3D acoustic tensor coincide (both `μ`), so their eigenvectors
//! are not defined by the data and would swap from face to face, and a limiter that
//! compares a family with its upwind neighbour's needs a family that varies continuously.
//! The shear part is therefore one wave, at the speed of its own Rayleigh quotient
//! `c_S² = w·A w/(ρ₀ w·w)`, `w = Δv − a e_P` (the shear eigenvalue exactly in 2D and for
//! any wave along one shear eigenvector; between the two shear speeds otherwise). The P
//! eigenvalue stays apart from the shear ones (`λ + 2μ` against `μ` at `F = 1`), so `e_P`
//! is continuous. At `F = 1` these are the linear solver's waves (`linear_waves`).
//!
//! **Ends.** As in 1D (`svk.rs`): an end face's star state is the flux's own half problem
//! (`acoustic_boundary`), its wave into the body is split as above about the interior
//! side, and each wave into the ghost is the mirror image `M Z` of the wave into the body
//! of the same family: `M` is the linear part of the edge's ghost rule
//! ([`crate::riemann::ghost_state`], any condition, a partly covered face's blend
//! included) applied to the wave's jump `(Δv, Δt)`, with the order of the states reversed.
//! The face beyond the end is the mirror of the first interior face (left- and right-going
//! families swapped through `M`). The limiter then gives the two waves at the end face the
//! same `θ`, so the end's condition holds at order 2 as at order 1.
use super::{FaceWaves, LAST};
use crate::faces::Fields;
use crate::riemann::{ghost_state, Conserved, FaceState, FullState};
use crate::{unit, DgmpmSolver};
use impact_core::material::Svk;
use impact_core::{Tensor, Vector};

/// Slots of the left-going P and S families and their right-going mirrors.
const P_LEFT: usize = 0;
const S_LEFT: usize = 2;

impl<const D: usize> DgmpmSolver<D> {
    /// The f-waves of padded face `j` of the row of axis `l` through `idx` (the parent
    /// module's numbering: the ghost faces `0` and `n + 2`, the end faces `1` and `n + 1`)
    /// under the approximate SVK solver in 2D and 3D (module doc).
    pub(crate) fn svk_padded_waves_nd(
        &self,
        svk: &Svk,
        l: usize,
        idx: [usize; D],
        j: usize,
        fields: Fields<'_, D>,
    ) -> FaceWaves<D> {
        let n = self.grid.cells[l];
        let e = unit::<D>(l);
        let state = |i: usize, high: bool| {
            let mut at = idx;
            at[l] = i;
            fields.side(self.grid.cell_index(at), l, high)
        };
        let star = |f: usize, left: Option<FullState<D>>, right: Option<FullState<D>>| {
            let mut at = idx;
            at[l] = f;
            let crate::Physics::Svk { riemann, .. } = self.physics else {
                unreachable!("internal: the SVK waves without SVK")
            };
            self.svk_star(svk, riemann, l, left, right, self.edge_coordinate(l, &at))
        };
        // the mirror through end `end` (module doc)
        let mirror = |end: usize, w: &Conserved<D>| -> Conserved<D> {
            let mut at = idx;
            at[l] = end * n;
            let condition = self.ghost_condition(l, end, self.edge_coordinate(l, &at));
            let outward = if end == 0 { -e } else { e };
            let jump = FaceState {
                traction: -w.momentum,
                velocity: -(w.tensor * e),
            };
            let zero = FaceState {
                traction: Vector::<D>::zeros(),
                velocity: Vector::<D>::zeros(),
            };
            let (g, g0) = (
                ghost_state(&jump, &outward, condition),
                ghost_state(&zero, &outward, condition),
            );
            // the reversed jump −L(Δ), as a wave −(Δv ⊗ e, Δt)
            let (dv, dt) = (g0.velocity - g.velocity, g0.traction - g.traction);
            Conserved {
                tensor: -(dv * e.transpose()),
                momentum: -dt,
            }
        };
        // `out` with the waves of `from` at the mirrored slots through end `end`
        let mirrored =
            |end: usize, from: &FaceWaves<D>, out: &mut FaceWaves<D>, slots: &[usize]| {
                for &p in slots {
                    out.wave[LAST - p] = mirror(end, &from.wave[p]);
                    out.speed[LAST - p] = -from.speed[p];
                }
            };
        let right_slots = [LAST - S_LEFT, LAST - P_LEFT];
        let left_slots = [P_LEFT, S_LEFT];
        match j {
            j if j == 0 || j == n + 2 => {
                let (end, inner) = if j == 0 { (0, 2) } else { (1, n) };
                let w = self.svk_padded_waves_nd(svk, l, idx, inner, fields);
                let mut out = FaceWaves::default();
                mirrored(end, &w, &mut out, &left_slots);
                mirrored(end, &w, &mut out, &right_slots);
                out
            }
            1 => {
                let inner = state(0, false);
                let q = star(0, None, Some(inner));
                let mut out = FaceWaves::default();
                self.svk_split(svk, l, &inner, &q, false, &mut out);
                let body = out;
                mirrored(0, &body, &mut out, &right_slots);
                out
            }
            j if j == n + 1 => {
                let inner = state(n - 1, true);
                let q = star(n, Some(inner), None);
                let mut out = FaceWaves::default();
                self.svk_split(svk, l, &inner, &q, true, &mut out);
                let body = out;
                mirrored(1, &body, &mut out, &left_slots);
                out
            }
            j => {
                let (left, right) = (state(j - 2, true), state(j - 1, false));
                let q = star(j - 1, Some(left), Some(right));
                let mut out = FaceWaves::default();
                self.svk_split(svk, l, &left, &q, true, &mut out);
                self.svk_split(svk, l, &right, &q, false, &mut out);
                out
            }
        }
    }

    /// The P and S f-waves between `side` and the star state `star` normal to `e_l`, into
    /// the left-going slots of `out` if `side` is on the left, the right-going ones
    /// otherwise (module doc).
    fn svk_split(
        &self,
        svk: &Svk,
        l: usize,
        side: &FullState<D>,
        star: &FaceState<D>,
        left: bool,
        out: &mut FaceWaves<D>,
    ) {
        let e = unit::<D>(l);
        let rho = svk.linear.density;
        let a = svk.acoustic_tensor(&side.tensor, &e);
        let (lambda, dir) = largest_eigen(&a);
        let z_p = (rho * lambda.max(0.0)).sqrt();
        let traction = svk.piola(&side.tensor) * e;
        // the velocity jump from the side's state towards the star state
        let dv = star.velocity - side.velocity;
        let amp = dir.dot(&dv);
        let shear = dv - dir * amp;
        let ww = shear.dot(&shear);
        let c_s2 = if ww > 0.0 {
            shear.dot(&(a * shear)) / (rho * ww)
        } else {
            (a.trace() - lambda) / ((D - 1) as f64 * rho)
        };
        let (c_p, c_s) = ((lambda / rho).max(0.0).sqrt(), c_s2.max(0.0).sqrt());
        // the P wave's jump of (v, t) from the side's state to m: (a e_P, ±Z_P a e_P)
        let p_dv = dir * amp;
        let p_dt = dir * (z_p * amp * if left { 1.0 } else { -1.0 });
        let flux = |dv: Vector<D>, dt: Vector<D>| Conserved {
            tensor: -(dv * e.transpose()),
            momentum: -dt,
        };
        let total = flux(dv, star.traction - traction);
        let p_wave = flux(p_dv, p_dt);
        if left {
            // q_L → m_L → q*
            out.wave[P_LEFT] = p_wave;
            out.wave[S_LEFT] = total.add_scaled(&p_wave, -1.0);
            out.speed[P_LEFT] = -c_p;
            out.speed[S_LEFT] = -c_s;
        } else {
            // q* → m_R → q_R: the jumps are the negatives of side → star's
            let p_wave = Conserved::<D>::zeros().add_scaled(&p_wave, -1.0);
            let total = Conserved::<D>::zeros().add_scaled(&total, -1.0);
            out.wave[LAST - P_LEFT] = p_wave;
            out.wave[LAST - S_LEFT] = total.add_scaled(&p_wave, -1.0);
            out.speed[LAST - P_LEFT] = c_p;
            out.speed[LAST - S_LEFT] = c_s;
        }
    }
}

/// The largest eigenvalue of the symmetric 2×2 or 3×3 tensor `a` and its unit eigenvector
/// (2D: the closed form `λ = (a₀₀ + a₁₁)/2 + sqrt(((a₀₀ − a₁₁)/2)² + a₀₁²)`; 3D: an axis
/// decoupled from the other two takes the 2×2 form on the coupled block, as `spd_sqrt`,
/// otherwise nalgebra's symmetric eigen decomposition).
fn largest_eigen<const D: usize>(a: &Tensor<D>) -> (f64, Vector<D>) {
    if D == 1 {
        return (a[(0, 0)], unit::<D>(0));
    }
    let two = |a00: f64, a01: f64, a11: f64| -> (f64, [f64; 2]) {
        let (mean, half) = (0.5 * (a00 + a11), 0.5 * (a00 - a11));
        let lambda = mean + half.hypot(a01);
        let v = if a01 == 0.0 {
            if a00 >= a11 {
                [1.0, 0.0]
            } else {
                [0.0, 1.0]
            }
        } else if a00 >= a11 {
            [lambda - a11, a01]
        } else {
            [a01, lambda - a00]
        };
        let norm = v[0].hypot(v[1]);
        (lambda, [v[0] / norm, v[1] / norm])
    };
    if D == 2 {
        let (lambda, v) = two(a[(0, 0)], a[(0, 1)], a[(1, 1)]);
        return (lambda, Vector::<D>::from_fn(|k, _| v[k]));
    }
    let decoupled =
        (0..3).find(|&j| (0..3).all(|p| p == j || (a[(j, p)] == 0.0 && a[(p, j)] == 0.0)));
    if let Some(j) = decoupled {
        let (p, q) = ((j + 1) % 3, (j + 2) % 3);
        let (lambda, v) = two(a[(p, p)], a[(p, q)], a[(q, q)]);
        if lambda >= a[(j, j)] {
            let mut out = Vector::<D>::zeros();
            (out[p], out[q]) = (v[0], v[1]);
            return (lambda, out);
        }
        return (a[(j, j)], unit::<D>(j));
    }
    let m = nalgebra::Matrix3::from_fn(|i, k| a[(i, k)]);
    let eigen = m.symmetric_eigen();
    let top = eigen.eigenvalues.imax();
    let v = eigen.eigenvectors.column(top);
    (eigen.eigenvalues[top], Vector::<D>::from_fn(|k, _| v[k]))
}

#[cfg(test)]
mod tests {
    use super::largest_eigen;
    use approx::assert_relative_eq;
    use impact_core::Tensor;

    /// The eigenpair solves `A e = λ e` with a unit `e`, and `λ` is the largest eigenvalue
    /// (2D; 3D coupled, through nalgebra; 3D with a decoupled axis, both orders).
    #[test]
    fn largest_eigenpair() {
        let a2 = Tensor::<2>::new(3.0, 1.2, 1.2, 5.0);
        let (l, e) = largest_eigen(&a2);
        assert_relative_eq!(a2 * e, e * l, max_relative = 1e-14);
        assert_relative_eq!(
            l,
            a2.symmetric_eigen().eigenvalues.max(),
            max_relative = 1e-14
        );
        let a3 = Tensor::<3>::new(4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0);
        let (l, e) = largest_eigen(&a3);
        assert_relative_eq!(e.norm(), 1.0, max_relative = 1e-14);
        assert_relative_eq!(a3 * e, e * l, max_relative = 1e-12);
        assert_relative_eq!(
            l,
            a3.symmetric_eigen().eigenvalues.max(),
            max_relative = 1e-14
        );
        for zz in [1.0, 9.0] {
            let a = Tensor::<3>::new(4.0, 1.0, 0.0, 1.0, 3.0, 0.0, 0.0, 0.0, zz);
            let (l, e) = largest_eigen(&a);
            assert_relative_eq!(a * e, e * l, max_relative = 1e-14);
            assert_relative_eq!(
                l,
                a.symmetric_eigen().eigenvalues.max(),
                max_relative = 1e-14
            );
        }
    }
}

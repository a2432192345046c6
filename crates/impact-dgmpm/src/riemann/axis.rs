//! The linear-elastic solvers with the normal along a grid axis, written out component by
//! component: the Godunov flux of `super::linear` and the transverse solver of
//! `super::transverse` for `n = e_L` (1D and 2D small strain). They are the same
//! formulas with every product by a zero or unit component of `n` left out, which the
//! general functions (a normal known only at run time) cannot skip; the fused cell path
//! ([`crate::fused`]) calls them on interior faces. Tested equal to the general functions
//! to round-off.
//!
//! With `L` the normal axis and `T` the other one (2D), a state's traction on the face is
//! the column `σ e_L = (σ_LL, σ_TL)`; the star state (paper §4, eqs. 18-21) is
//! `t_L* = ½(t_Ll + t_Lr) + ½ Z_p (v_Lr - v_Ll)`, `v_L* = ½(v_Ll + v_Lr) + (t_Lr - t_Ll)/(2 Z_p)`,
//! the same along `T` with `Z_s`, and the flux is
//! `F_{e_L}(q*) = -(C : sym(v* ⊗ e_L), t*)`, i.e. `σ`-part `-(λ+2μ) v_L*` (`LL`),
//! `-λ v_L*` (`TT`), `-μ v_T*` (`LT`, `TL`).
use super::{Conserved, Elastic, FullState};
use impact_core::{Tensor, Vector};

/// The constants of the axis solvers, formed once from [`Elastic`] (the same products and
/// quotients the general functions form on every call).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisConstants {
    lambda: f64,
    zp: f64,
    zs: f64,
    half_zp: f64,
    half_zs: f64,
    half_over_zp: f64,
    half_over_zs: f64,
    inv_zp: f64,
    inv_zs: f64,
    inv_rho: f64,
    /// `-λ`, `-μ`, `-2μ` and `-(λ+2μ)`: the fluxes' negated stress parts as products by a
    /// negated constant, `-(c x) = (-c) x` exactly (sign of zero included), so no
    /// negation is left to do per face.
    neg_lambda: f64,
    neg_mu: f64,
    neg_two_mu: f64,
    neg_lambda_two_mu: f64,
}

impl AxisConstants {
    /// The constants of `m`.
    pub fn new(m: &Elastic) -> Self {
        Self {
            lambda: m.lambda,
            zp: m.z.p,
            zs: m.z.s,
            half_zp: 0.5 * m.z.p,
            half_zs: 0.5 * m.z.s,
            half_over_zp: 0.5 / m.z.p,
            half_over_zs: if m.z.s > 0.0 { 0.5 / m.z.s } else { 0.0 },
            inv_zp: 1.0 / m.z.p,
            inv_zs: if m.z.s > 0.0 { 1.0 / m.z.s } else { 0.0 },
            inv_rho: 1.0 / m.density,
            neg_lambda: -m.lambda,
            neg_mu: -m.mu,
            neg_two_mu: -(2.0 * m.mu),
            neg_lambda_two_mu: -(m.lambda + 2.0 * m.mu),
        }
    }
}

/// Godunov flux through a face normal to `e_L` between `left` and `right` (2D): the module
/// doc's formulas, equal to `normal_flux(linear_elastic_star(…))` for `n = e_L`.
#[inline(always)]
pub fn axis_flux_2d<const L: usize>(
    left: &FullState<2>,
    right: &FullState<2>,
    c: &AxisConstants,
) -> Conserved<2> {
    let t = 1 - L;
    let (tl_n, tl_t) = (left.tensor[(L, L)], left.tensor[(t, L)]);
    let (tr_n, tr_t) = (right.tensor[(L, L)], right.tensor[(t, L)]);
    let (vl_n, vl_t) = (left.velocity[L], left.velocity[t]);
    let (vr_n, vr_t) = (right.velocity[L], right.velocity[t]);
    let traction_n = 0.5 * (tl_n + tr_n) + c.half_zp * (vr_n - vl_n);
    let velocity_n = 0.5 * (vl_n + vr_n) + (tr_n - tl_n) * c.half_over_zp;
    let traction_t = (tl_t + tr_t) * 0.5 + (vr_t - vl_t) * c.half_zs;
    let velocity_t = (vl_t + vr_t) * 0.5 + (tr_t - tl_t) * c.half_over_zs;
    // `-(a + b) = (-a) - b` and `-(c x) = (-c) x` exactly, zeros' signs included (no
    // term cancels another: both carry the sign of `v_L*`)
    let mut tensor = Tensor::<2>::zeros();
    tensor[(L, L)] = velocity_n * c.neg_two_mu - c.lambda * velocity_n;
    tensor[(t, t)] = c.neg_lambda * velocity_n;
    tensor[(L, t)] = velocity_t * c.neg_mu;
    tensor[(t, L)] = velocity_t * c.neg_mu;
    let mut momentum = Vector::<2>::zeros();
    momentum[L] = -traction_n;
    momentum[t] = -traction_t;
    Conserved { tensor, momentum }
}

/// The normal flux of a state through a face normal to `e_L` (2D):
/// `F_{e_L}(q) = -(C : sym(v ⊗ e_L), σ e_L)`, equal to `normal_flux(q.on_face(e_L))`; the
/// nodal sweep applies it to the difference of a cell's two side states.
#[inline(always)]
pub fn axis_normal_flux_2d<const L: usize>(
    state: &FullState<2>,
    c: &AxisConstants,
) -> Conserved<2> {
    let t = 1 - L;
    let (v_n, v_t) = (state.velocity[L], state.velocity[t]);
    let mut tensor = Tensor::<2>::zeros();
    tensor[(L, L)] = v_n * c.neg_two_mu - c.lambda * v_n;
    tensor[(t, t)] = c.neg_lambda * v_n;
    tensor[(L, t)] = v_t * c.neg_mu;
    tensor[(t, L)] = v_t * c.neg_mu;
    let mut momentum = Vector::<2>::zeros();
    momentum[L] = -state.tensor[(L, L)];
    momentum[t] = -state.tensor[(t, L)];
    Conserved { tensor, momentum }
}

/// Godunov flux through a face of the bar (1D, `Z = sqrt(ρE)`, `C = E`):
/// `F = -(E v*, σ*)`.
#[inline(always)]
pub fn axis_flux_1d(left: &FullState<1>, right: &FullState<1>, c: &AxisConstants) -> Conserved<1> {
    let (tl, tr) = (left.tensor[(0, 0)], right.tensor[(0, 0)]);
    let (vl, vr) = (left.velocity[0], right.velocity[0]);
    let traction = 0.5 * (tl + tr) + c.half_zp * (vr - vl);
    let velocity = 0.5 * (vl + vr) + (tr - tl) * c.half_over_zp;
    Conserved {
        tensor: Tensor::<1>::new(velocity * c.neg_two_mu),
        momentum: Vector::<1>::new(-traction),
    }
}

/// What the transverse solver sends into a face normal to `e_K` (2D) from the cells below
/// and above it: `B⁺ w_below + B⁻ w_above` ([`super::transverse_into_face`], LeVeque 2002
/// §21.2) for `n = e_K`, with `O` the other axis:
/// `α_P+ = ½(m_K/ρ - W_KK/Z_p)` (below), `α_P- = ½(m_K/ρ + W_KK/Z_p)` (above),
/// `α_S± = ½(m_O/ρ ∓ W_OK/Z_s)`; stress `-(λ+2μ)(α_P+ + α_P-)` (`KK`),
/// `-λ(α_P+ + α_P-)` (`OO`), `-μ(α_S+ + α_S-)` (`KO`, `OK`); momentum
/// `Z_p(α_P+ - α_P-)` along `K`, `Z_s(α_S+ - α_S-)` along `O`.
#[inline(always)]
pub fn axis_transverse_2d<const K: usize>(
    below: &Conserved<2>,
    above: &Conserved<2>,
    c: &AxisConstants,
) -> Conserved<2> {
    let o = 1 - K;
    let ap = 0.5 * (below.momentum[K] * c.inv_rho - below.tensor[(K, K)] * c.inv_zp);
    let am = 0.5 * (above.momentum[K] * c.inv_rho + above.tensor[(K, K)] * c.inv_zp);
    let sp = (below.momentum[o] * c.inv_rho - below.tensor[(o, K)] * c.inv_zs) * 0.5;
    let sm = (above.momentum[o] * c.inv_rho + above.tensor[(o, K)] * c.inv_zs) * 0.5;
    let (p, s) = (ap + am, sp + sm);
    let mut tensor = Tensor::<2>::zeros();
    tensor[(K, K)] = c.neg_lambda_two_mu * p;
    tensor[(o, o)] = c.neg_lambda * p;
    tensor[(K, o)] = s * c.neg_mu;
    tensor[(o, K)] = s * c.neg_mu;
    let mut momentum = Vector::<2>::zeros();
    momentum[K] = c.zp * (ap - am);
    momentum[o] = (sp - sm) * c.zs;
    Conserved { tensor, momentum }
}

/// [`axis_transverse_2d`] in any dimension, the normal axis `k` known at run time: the
/// same formulas with every tangent `o ≠ k` (two in 3D) taking the 2D `O`'s terms,
/// `α_S±(o) = ½(m_o/ρ ∓ W_ok/Z_s)`; stress `-(λ+2μ)(α_P+ + α_P-)` (`kk`),
/// `-λ(α_P+ + α_P-)` (`oo`), `-μ(α_S+(o) + α_S-(o))` (`ko`, `ok`), zero between two
/// tangents; momentum `Z_p(α_P+ - α_P-)` along `k`, `Z_s(α_S+(o) - α_S-(o))` along `o`
/// (LeVeque 2002 §21.2; `super::transverse_into_face` for `n = e_k`). The 3D CTU's solver.
#[inline(always)]
pub fn axis_transverse<const D: usize>(
    k: usize,
    below: &Conserved<D>,
    above: &Conserved<D>,
    c: &AxisConstants,
) -> Conserved<D> {
    let ap = 0.5 * (below.momentum[k] * c.inv_rho - below.tensor[(k, k)] * c.inv_zp);
    let am = 0.5 * (above.momentum[k] * c.inv_rho + above.tensor[(k, k)] * c.inv_zp);
    let p = ap + am;
    let mut tensor = Tensor::<D>::zeros();
    let mut momentum = Vector::<D>::zeros();
    for o in (0..D).filter(|&o| o != k) {
        let sp = (below.momentum[o] * c.inv_rho - below.tensor[(o, k)] * c.inv_zs) * 0.5;
        let sm = (above.momentum[o] * c.inv_rho + above.tensor[(o, k)] * c.inv_zs) * 0.5;
        let shear = (sp + sm) * c.neg_mu;
        tensor[(o, o)] = c.neg_lambda * p;
        tensor[(k, o)] = shear;
        tensor[(o, k)] = shear;
        momentum[o] = (sp - sm) * c.zs;
    }
    tensor[(k, k)] = c.neg_lambda_two_mu * p;
    momentum[k] = c.zp * (ap - am);
    Conserved { tensor, momentum }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::riemann::test_support::{sample, steel};
    use crate::riemann::{linear_elastic_star, normal_flux, transverse_into_face};
    use approx::assert_relative_eq;

    fn close<const D: usize>(a: &Conserved<D>, b: &Conserved<D>) {
        let scale = b.tensor.abs().max().max(1.0);
        assert_relative_eq!(a.tensor, b.tensor, epsilon = 1e-14 * scale);
        let scale = b.momentum.abs().max().max(1.0);
        assert_relative_eq!(a.momentum, b.momentum, epsilon = 1e-14 * scale);
    }

    fn states() -> (FullState<2>, FullState<2>) {
        (
            FullState {
                tensor: Tensor::<2>::new(-1.0e8, 2.0e7, 2.0e7, 3.0e7),
                velocity: Vector::<2>::new(3.0, -1.0),
            },
            FullState {
                tensor: Tensor::<2>::new(5.0e7, -4.0e7, -4.0e7, 0.0),
                velocity: Vector::<2>::new(-1.0, 0.5),
            },
        )
    }

    /// The axis flux is the general star state's flux for `n = e_x` and `n = e_y`.
    #[test]
    fn axis_flux_equals_the_general_flux() {
        let m = steel();
        let c = AxisConstants::new(&m);
        let (l, r) = states();
        for axis in 0..2 {
            let n = crate::unit::<2>(axis);
            let star = linear_elastic_star(&l.on_face(&n), &r.on_face(&n), &n, m.z);
            let general = normal_flux(&star, &n, &m);
            let fast = match axis {
                0 => axis_flux_2d::<0>(&l, &r, &c),
                _ => axis_flux_2d::<1>(&l, &r, &c),
            };
            close(&fast, &general);
        }
    }

    /// The axis normal flux is the general normal flux for `n = e_x` and `n = e_y`.
    #[test]
    fn axis_normal_flux_equals_the_general_flux() {
        let m = steel();
        let c = AxisConstants::new(&m);
        let (state, _) = states();
        for axis in 0..2 {
            let n = crate::unit::<2>(axis);
            let general = normal_flux(&state.on_face(&n), &n, &m);
            let fast = match axis {
                0 => axis_normal_flux_2d::<0>(&state, &c),
                _ => axis_normal_flux_2d::<1>(&state, &c),
            };
            close(&fast, &general);
        }
    }

    /// A pure velocity jump on the bar (worked by hand): `v_L = 1`, `v_R = -1`, unstressed,
    /// `Z = 2`, `E = 4`: `v* = 0`, `σ* = -2`, so `F = (0, 2)`.
    #[test]
    fn bar_flux_by_hand() {
        let m = Elastic {
            lambda: 0.0,
            mu: 2.0,
            density: 1.0,
            z: crate::riemann::Impedances { p: 2.0, s: 0.0 },
        };
        let state = |v: f64| FullState {
            tensor: Tensor::<1>::new(0.0),
            velocity: Vector::<1>::new(v),
        };
        let f = axis_flux_1d(&state(1.0), &state(-1.0), &AxisConstants::new(&m));
        assert_eq!((f.tensor[(0, 0)], f.momentum[0]), (0.0, 2.0));
        let n = Vector::<1>::new(1.0);
        let (l, r) = (state(0.3).on_face(&n), state(-0.7).on_face(&n));
        let general = normal_flux(&linear_elastic_star(&l, &r, &n, m.z), &n, &m);
        close(
            &axis_flux_1d(&state(0.3), &state(-0.7), &AxisConstants::new(&m)),
            &general,
        );
    }

    /// The axis transverse solver is `transverse_into_face` for `n = e_x` and `n = e_y`.
    #[test]
    fn axis_transverse_equals_the_general_solver() {
        let m = steel();
        let c = AxisConstants::new(&m);
        let below = sample();
        let above = Conserved {
            tensor: Tensor::<2>::new(-2.0e8, 7.0e7, 7.0e7, 1.0e8),
            momentum: Vector::<2>::new(-4.0e3, 9.0e3),
        };
        for axis in 0..2 {
            let n = crate::unit::<2>(axis);
            let general = transverse_into_face(&below, &above, &n, &m);
            let fast = match axis {
                0 => axis_transverse_2d::<0>(&below, &above, &c),
                _ => axis_transverse_2d::<1>(&below, &above, &c),
            };
            close(&fast, &general);
        }
    }

    /// The run-time axis solver is `transverse_into_face` for every axis in 3D.
    #[test]
    fn axis_transverse_equals_the_general_solver_in_3d() {
        let m = steel();
        let c = AxisConstants::new(&m);
        let below = Conserved {
            tensor: Tensor::<3>::new(
                -2.0e8, 7.0e7, 3.0e7, 7.0e7, 1.0e8, -5.0e7, 3.0e7, -5.0e7, 4.0e7,
            ),
            momentum: Vector::<3>::new(-4.0e3, 9.0e3, 2.0e3),
        };
        let above = Conserved {
            tensor: below.tensor.transpose() * -0.6 + Tensor::<3>::identity() * 2e7,
            momentum: Vector::<3>::new(1.0e3, -3.0e3, 5.0e3),
        };
        for axis in 0..3 {
            let n = crate::unit::<3>(axis);
            let general = transverse_into_face(&below, &above, &n, &m);
            close(&axis_transverse(axis, &below, &above, &c), &general);
        }
    }
}

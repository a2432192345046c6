//! The exact linear-elastic Riemann solver normal to a face (paper §4, eqs. 18-21). The
//! Jacobian `Σ_p n_p A^p` has eigenvalues `±c_p` (P waves, impedance `Z_p = ρ c_p`),
//! `±c_s` (S waves, `Z_s = ρ c_s`) and 0. The star state at `ξ = X·n = 0` is
//!
//! `t_n* = (t_nL + t_nR)/2 + Z_p (v_nR - v_nL)/2`, `v_n* = (v_nL + v_nR)/2 + (t_nR - t_nL)/(2 Z_p)`
//!
//! and the same for the tangential parts with `Z_s`. The Godunov flux `F_n(q*)`
//! (paper eq. 7) only needs `v*` and `t*`: `F_n = -(C : sym(v* ⊗ n), t*)`.
//! In 1D (the bar) there is only the P wave, with `Z = sqrt(ρ E)`.
use super::{sym, Conserved, Elastic, FaceState, Impedances};
use impact_core::Vector;

#[inline]
pub fn linear_elastic_star<const D: usize>(
    left: &FaceState<D>,
    right: &FaceState<D>,
    normal: &Vector<D>,
    z: Impedances,
) -> FaceState<D> {
    let tl = left.traction.dot(normal);
    let tr = right.traction.dot(normal);
    let vl = left.velocity.dot(normal);
    let vr = right.velocity.dot(normal);
    let t_n = 0.5 * (tl + tr) + 0.5 * z.p * (vr - vl);
    let v_n = 0.5 * (vl + vr) + (tr - tl) * (0.5 / z.p);
    let mut traction = normal * t_n;
    let mut velocity = normal * v_n;
    if D > 1 && z.s > 0.0 {
        let ttl = left.traction - normal * tl;
        let ttr = right.traction - normal * tr;
        let vtl = left.velocity - normal * vl;
        let vtr = right.velocity - normal * vr;
        traction += (ttl + ttr) * 0.5 + (vtr - vtl) * (0.5 * z.s);
        velocity += (vtl + vtr) * 0.5 + (ttr - ttl) * (0.5 / z.s);
    }
    FaceState { traction, velocity }
}

/// The Godunov flux of a face state (paper eq. 7 and 20): `F_n = -(C : sym(v ⊗ n), t)`
/// with the traction `t = σ n`.
#[inline]
pub fn normal_flux<const D: usize>(
    face: &FaceState<D>,
    normal: &Vector<D>,
    m: &Elastic,
) -> Conserved<D> {
    Conserved {
        tensor: -m.stress(&sym(&face.velocity, normal)),
        momentum: -face.traction,
    }
}

/// Fluctuations of the face Riemann problem (LeVeque 2002, §4.12): `A⁻Δq = F_n(q*) - F_n(q_L)`
/// goes into the left cell, `A⁺Δq = F_n(q_R) - F_n(q*)` into the right cell.
#[inline]
pub fn fluctuations<const D: usize>(
    left: &FaceState<D>,
    right: &FaceState<D>,
    star: &FaceState<D>,
    normal: &Vector<D>,
    m: &Elastic,
) -> (Conserved<D>, Conserved<D>) {
    let fl = normal_flux(left, normal, m);
    let fr = normal_flux(right, normal, m);
    let fs = normal_flux(star, normal, m);
    (fs.add_scaled(&fl, -1.0), fr.add_scaled(&fs, -1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::riemann::test_support::steel;
    use approx::assert_relative_eq;

    fn s1(t: f64, v: f64) -> FaceState<1> {
        FaceState {
            traction: Vector::<1>::new(t),
            velocity: Vector::<1>::new(v),
        }
    }
    const Z1: Impedances = Impedances { p: 2.0, s: 0.0 };
    fn n1() -> Vector<1> {
        Vector::<1>::new(1.0)
    }

    #[test]
    fn equal_states_are_their_own_star_state() {
        let s = s1(-3.0, 1.5);
        assert_eq!(linear_elastic_star(&s, &s, &n1(), Z1), s);
        let s2 = FaceState {
            traction: Vector::<2>::new(1.0, -2.0),
            velocity: Vector::<2>::new(0.3, 0.7),
        };
        let n = Vector::<2>::new(0.6, 0.8);
        let star = linear_elastic_star(&s2, &s2, &n, Impedances { p: 3.0, s: 1.0 });
        assert_relative_eq!(star.traction, s2.traction, epsilon = 1e-14);
        assert_relative_eq!(star.velocity, s2.velocity, epsilon = 1e-14);
    }

    #[test]
    fn pure_traction_jump() {
        // σ_L = -2, σ_R = 0, at rest, Z = 2: σ* = -1, v* = 0.5 (worked by hand)
        let star = linear_elastic_star(&s1(-2.0, 0.0), &s1(0.0, 0.0), &n1(), Z1);
        assert_relative_eq!(star.traction[0], -1.0);
        assert_relative_eq!(star.velocity[0], 0.5);
    }

    #[test]
    fn colliding_velocities_compress() {
        // v_L = 1, v_R = -1, unstressed, Z = 2: v* = 0, σ* = -2
        let star = linear_elastic_star(&s1(0.0, 1.0), &s1(0.0, -1.0), &n1(), Z1);
        assert_relative_eq!(star.velocity[0], 0.0);
        assert_relative_eq!(star.traction[0], -2.0);
    }

    #[test]
    fn jumps_satisfy_rankine_hugoniot_across_each_wave() {
        // 2D, oblique normal: the jump from L to * is a left-going P wave plus S wave:
        // Δt_n = Z_p Δv_n, Δt_t = Z_s Δv_t; from * to R: Δt_n = -Z_p Δv_n, Δt_t = -Z_s Δv_t.
        let l = FaceState {
            traction: Vector::<2>::new(1.0, -2.0),
            velocity: Vector::<2>::new(0.3, 0.7),
        };
        let r = FaceState {
            traction: Vector::<2>::new(-0.5, 0.25),
            velocity: Vector::<2>::new(-0.1, 0.2),
        };
        let n = Vector::<2>::new(0.6, 0.8);
        let z = Impedances { p: 3.0, s: 1.2 };
        let s = linear_elastic_star(&l, &r, &n, z);
        let split = |t: Vector<2>, v: Vector<2>| {
            (t.dot(&n), v.dot(&n), t - n * t.dot(&n), v - n * v.dot(&n))
        };
        let (tnl, vnl, ttl, vtl) = split(s.traction - l.traction, s.velocity - l.velocity);
        let (tnr, vnr, ttr, vtr) = split(r.traction - s.traction, r.velocity - s.velocity);
        assert_relative_eq!(tnl, z.p * vnl, epsilon = 1e-12);
        assert_relative_eq!(ttl, vtl * z.s, epsilon = 1e-12);
        assert_relative_eq!(tnr, -z.p * vnr, epsilon = 1e-12);
        assert_relative_eq!(ttr, -vtr * z.s, epsilon = 1e-12);
    }

    /// Fluctuations add up to the flux difference, and vanish for equal states.
    #[test]
    fn fluctuations_add_up_to_the_flux_difference() {
        let m = steel();
        let n = Vector::<2>::new(1.0, 0.0);
        let l = FaceState {
            traction: Vector::<2>::new(-1e8, 2e7),
            velocity: Vector::<2>::new(3.0, -1.0),
        };
        let r = FaceState {
            traction: Vector::<2>::new(5e7, 0.0),
            velocity: Vector::<2>::new(-1.0, 0.5),
        };
        let star = linear_elastic_star(&l, &r, &n, m.z);
        let (am, ap) = fluctuations(&l, &r, &star, &n, &m);
        let diff = normal_flux(&r, &n, &m).add_scaled(&normal_flux(&l, &n, &m), -1.0);
        assert_relative_eq!(am.tensor + ap.tensor, diff.tensor, max_relative = 1e-12);
        assert_relative_eq!(
            am.momentum + ap.momentum,
            diff.momentum,
            max_relative = 1e-12
        );
        let (am, ap) = fluctuations(&l, &l, &l, &n, &m);
        assert_eq!((am.momentum.norm(), ap.tensor.norm()), (0.0, 0.0));
    }
}

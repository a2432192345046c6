//! Riemann solvers: pure functions with fixed signatures, tested alone.
//!
//! Linear elasticity normal to a face (paper §4, eqs. 18-21). With `n` the unit normal
//! pointing from the left state to the right state, traction `t = σ n`, normal parts
//! `t_n = n·t`, `v_n = n·v` and tangential parts `t_t = t - t_n n`, `v_t = v - v_n n`, the
//! Jacobian `Σ_p n_p A^p` has eigenvalues `±c_p` (P waves, impedance `Z_p = ρ c_p`),
//! `±c_s` (S waves, `Z_s = ρ c_s`) and 0. The star state at `ξ = X·n = 0` is
//!
//! `t_n* = (t_nL + t_nR)/2 + Z_p (v_nR - v_nL)/2`, `v_n* = (v_nL + v_nR)/2 + (t_nR - t_nL)/(2 Z_p)`
//!
//! and the same for the tangential parts with `Z_s`. The Godunov flux `F_n(q*)`
//! (paper eq. 7) only needs `v*` and `t*`: `F_n = -(C : sym(v* ⊗ n), t*)`.
//! In 1D (the bar) there is only the P wave, with `Z = sqrt(ρ E)`.
use impact_core::Vector;

/// Traction and velocity of one side of a face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceState<const D: usize> {
    /// Traction `σ n` on the face, with `n` from left to right.
    pub traction: Vector<D>,
    /// Velocity.
    pub velocity: Vector<D>,
}

/// Acoustic impedances of the two wave families.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedances {
    /// `Z_p = ρ c_p`.
    pub p: f64,
    /// `Z_s = ρ c_s` (0 in 1D: no shear wave).
    pub s: f64,
}

/// Star state of the exact linear-elastic Riemann problem normal to `normal` (module doc).
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
    let v_n = 0.5 * (vl + vr) + (tr - tl) / (2.0 * z.p);
    let mut traction = normal * t_n;
    let mut velocity = normal * v_n;
    if D > 1 && z.s > 0.0 {
        let ttl = left.traction - normal * tl;
        let ttr = right.traction - normal * tr;
        let vtl = left.velocity - normal * vl;
        let vtr = right.velocity - normal * vr;
        traction += (ttl + ttr) * 0.5 + (vtr - vtl) * (0.5 * z.s);
        velocity += (vtl + vtr) * 0.5 + (ttr - ttl) / (2.0 * z.s);
    }
    FaceState { traction, velocity }
}

/// Boundary condition at a face, as seen by [`ghost_state`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GhostCondition<const D: usize> {
    /// Prescribed traction `t_d` (traction-free: `t_d = 0`).
    Traction(Vector<D>),
    /// Prescribed normal velocity `v_n` along the outward normal, zero shear traction.
    NormalVelocity(f64),
}

/// Ghost state outside a boundary face (LeVeque 2002, §7.3): with `n` the outward normal
/// and the interior state on the left, the ghost state on the right makes the star state
/// satisfy the condition exactly:
/// - traction `t_d`: `t_g = 2 t_d - t_i`, `v_g = v_i` (then `t* = t_d`);
/// - normal velocity `v_d`: `v_gn = 2 v_d - v_in`, `t_gn = t_in`, and `t_gt = -t_it`,
///   `v_gt = v_it` (then `v_n* = v_d`, `t_t* = 0`).
#[inline]
pub fn ghost_state<const D: usize>(
    interior: &FaceState<D>,
    outward: &Vector<D>,
    condition: GhostCondition<D>,
) -> FaceState<D> {
    match condition {
        GhostCondition::Traction(t_d) => FaceState {
            traction: t_d * 2.0 - interior.traction,
            velocity: interior.velocity,
        },
        GhostCondition::NormalVelocity(v_d) => {
            let t_n = interior.traction.dot(outward);
            let v_n = interior.velocity.dot(outward);
            let t_t = interior.traction - outward * t_n;
            let v_t = interior.velocity - outward * v_n;
            FaceState {
                traction: outward * t_n - t_t,
                velocity: outward * (2.0 * v_d - v_n) + v_t,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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

    #[test]
    fn ghost_states_enforce_their_condition() {
        let n = Vector::<2>::new(-1.0, 0.0);
        let z = Impedances { p: 3.0, s: 1.2 };
        let inner = FaceState {
            traction: Vector::<2>::new(0.4, -0.9),
            velocity: Vector::<2>::new(1.1, 0.3),
        };
        let t_d = Vector::<2>::new(5.0, 0.0);
        let g = ghost_state(&inner, &n, GhostCondition::Traction(t_d));
        let s = linear_elastic_star(&inner, &g, &n, z);
        assert_relative_eq!(s.traction, t_d, epsilon = 1e-12);
        let g = ghost_state(&inner, &n, GhostCondition::NormalVelocity(-5.0));
        let s = linear_elastic_star(&inner, &g, &n, z);
        assert_relative_eq!(s.velocity.dot(&n), -5.0, epsilon = 1e-12);
        assert_relative_eq!(
            (s.traction - n * s.traction.dot(&n)).norm(),
            0.0,
            epsilon = 1e-12
        );
    }
}

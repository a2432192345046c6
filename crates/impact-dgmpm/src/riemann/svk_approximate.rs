//! Approximate (acoustic) Saint-Venant–Kirchhoff Riemann solver (Toro 2009, §9.3): each
//! wave linearised about its own side with the impedance tensor `Z = sqrt(ρ₀ A(F, n))`.
use super::{FaceState, GhostCondition};
use impact_core::material::Svk;
use impact_core::{Tensor, Vector};
/// Determinant of a 1×1 or 2×2 tensor.
fn small_det<const D: usize>(a: &Tensor<D>) -> f64 {
    match D {
        1 => a[(0, 0)],
        2 => a[(0, 0)] * a[(1, 1)] - a[(0, 1)] * a[(1, 0)],
        _ => unreachable!("internal: impact runs in 1D and 2D"),
    }
}

/// Inverse of a 1×1 or 2×2 tensor (`None` if singular).
fn small_inverse<const D: usize>(a: &Tensor<D>) -> Option<Tensor<D>> {
    let det = small_det(a);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let mut inv = Tensor::<D>::zeros();
    if D == 1 {
        inv[(0, 0)] = 1.0 / det;
    } else {
        inv[(0, 0)] = a[(1, 1)] / det;
        inv[(1, 1)] = a[(0, 0)] / det;
        inv[(0, 1)] = -a[(0, 1)] / det;
        inv[(1, 0)] = -a[(1, 0)] / det;
    }
    Some(inv)
}

/// Square root of a symmetric positive definite 1×1 or 2×2 tensor (closed form:
/// `√M = (M + √det M 1)/sqrt(tr M + 2 √det M)` in 2D).
pub fn spd_sqrt<const D: usize>(a: &Tensor<D>) -> Tensor<D> {
    if D == 1 {
        return a.map(|x| x.max(0.0).sqrt());
    }
    let det = small_det(a).max(0.0).sqrt();
    let norm = (a.trace() + 2.0 * det).max(0.0).sqrt();
    (a + Tensor::<D>::identity() * det) / norm
}

/// Approximate (acoustic) Riemann solver: each wave is linearised about its own side,
/// `t* - t_L = Z_L (v* - v_L)`, `t* - t_R = -Z_R (v* - v_R)`, with the impedance tensors
/// `Z = sqrt(ρ₀ A(F, n))` from the acoustic tensor (Toro 2009, §9.3; exact for linear
/// elasticity, where it is [`super::linear_elastic_star`]). `None` if an acoustic tensor
/// is not positive definite (hyperbolicity lost).
pub fn acoustic_star<const D: usize>(
    m: &Svk,
    (fl, vl): (&Tensor<D>, &Vector<D>),
    (fr, vr): (&Tensor<D>, &Vector<D>),
    n: &Vector<D>,
) -> Option<FaceState<D>> {
    let (zl, zr) = (impedance(m, fl, n), impedance(m, fr, n));
    let left = FaceState {
        traction: m.piola(fl) * n,
        velocity: *vl,
    };
    let right = FaceState {
        traction: m.piola(fr) * n,
        velocity: *vr,
    };
    acoustic_star_tv(&zl, &left, &zr, &right)
}

/// Acoustic boundary half problem: the interior state on the left of the outward normal
/// `n`, the waves entering the interior obey `t* = t_i + Z (v* - v_i)`. A traction
/// condition fixes `t* = t_d` (`v* = v_i + Z⁻¹ (t_d - t_i)`); a normal-velocity condition
/// fixes `v*·n = v_d` and zero shear traction, which leaves the tangential velocity and the
/// normal traction to solve for (exact for any symmetric `Z`, also when shear and normal
/// waves couple at finite strain); a velocity-vector condition fixes `v* = v_d`.
pub fn acoustic_boundary<const D: usize>(
    z: &Tensor<D>,
    interior: &FaceState<D>,
    n: &Vector<D>,
    condition: GhostCondition<D>,
) -> Option<FaceState<D>> {
    if let Some((full, share)) = condition.split(n) {
        let covered = acoustic_boundary(z, interior, n, full)?;
        let free = acoustic_boundary(z, interior, n, GhostCondition::free())?;
        return Some(FaceState {
            traction: covered.traction * share + free.traction * (1.0 - share),
            velocity: covered.velocity * share + free.velocity * (1.0 - share),
        });
    }
    let state = match condition {
        GhostCondition::Traction(t_d) => FaceState {
            traction: t_d,
            velocity: interior.velocity + small_inverse(z)? * (t_d - interior.traction),
        },
        GhostCondition::NormalVelocity(v_d) => {
            let dvn = v_d - interior.velocity.dot(n);
            let mut velocity = interior.velocity + n * dvn;
            if D > 1 {
                let t = Vector::<D>::from_fn(|k, _| match k {
                    0 => -n[1 % D],
                    _ => n[0],
                });
                let (ztt, ztn) = (t.dot(&(z * t)), t.dot(&(z * n)));
                if ztt <= 0.0 {
                    return None;
                }
                // 0 = t·t_i + Z_tn Δv_n + Z_tt Δv_t
                let dvt = -(t.dot(&interior.traction) + ztn * dvn) / ztt;
                velocity += t * dvt;
            }
            let traction = interior.traction + z * (velocity - interior.velocity);
            // keep only the normal part: the shear traction is zero by construction
            FaceState {
                traction: n * n.dot(&traction),
                velocity,
            }
        }
        GhostCondition::Velocity(v_d) => FaceState {
            traction: interior.traction + z * (v_d - interior.velocity),
            velocity: v_d,
        },
        GhostCondition::PartialVelocity { .. } => unreachable!("internal: split above"),
    };
    (state
        .traction
        .iter()
        .chain(state.velocity.iter())
        .all(|x| x.is_finite()))
    .then_some(state)
}

/// Impedance tensor `Z = sqrt(ρ₀ A(F, n))`.
pub fn impedance<const D: usize>(m: &Svk, f: &Tensor<D>, n: &Vector<D>) -> Tensor<D> {
    spd_sqrt(&(m.acoustic_tensor(f, n) * m.linear.density))
}

/// The acoustic star state from traction/velocity pairs and impedance tensors:
/// `v* = (Z_L + Z_R)⁻¹ (Z_L v_L + Z_R v_R + t_R - t_L)`, `t* = t_L + Z_L (v* - v_L)`.
pub fn acoustic_star_tv<const D: usize>(
    zl: &Tensor<D>,
    left: &FaceState<D>,
    zr: &Tensor<D>,
    right: &FaceState<D>,
) -> Option<FaceState<D>> {
    let sum = small_inverse(&(zl + zr))?;
    let v = sum * (zl * left.velocity + zr * right.velocity + right.traction - left.traction);
    let state = FaceState {
        traction: left.traction + zl * (v - left.velocity),
        velocity: v,
    };
    (state.traction.iter().all(|x| x.is_finite()) && zl.iter().all(|x| x.is_finite()))
        .then_some(state)
}

#[cfg(test)]
mod svk_tests {
    use crate::riemann::svk::*;
    use crate::riemann::{linear_elastic_star, FaceState, Impedances};
    use approx::assert_relative_eq;
    use impact_core::material::{LinearElastic, Svk};
    use impact_core::{Tensor, Vector};

    fn m() -> Svk {
        Svk::new(LinearElastic::new(2e11, 0.3, 7800.0))
    }

    /// At F = 1 the acoustic solver is the linear one.
    #[test]
    fn acoustic_solver_is_linear_at_rest() {
        let svk = m();
        let (f, n) = (Tensor::<2>::identity(), Vector::<2>::new(0.0, 1.0));
        let (vl, vr) = (Vector::<2>::new(1.0, -2.0), Vector::<2>::new(-0.5, 3.0));
        let s = acoustic_star(&svk, (&f, &vl), (&f, &vr), &n).unwrap();
        let (zp, zs) = svk.linear.impedances::<2>();
        let zero = Vector::<2>::zeros();
        let lin = linear_elastic_star(
            &FaceState {
                traction: zero,
                velocity: vl,
            },
            &FaceState {
                traction: zero,
                velocity: vr,
            },
            &n,
            Impedances { p: zp, s: zs },
        );
        assert_relative_eq!(s.velocity, lin.velocity, max_relative = 1e-12);
        assert_relative_eq!(s.traction, lin.traction, max_relative = 1e-12);
        let a = Tensor::<2>::new(4.0, 1.0, 1.0, 3.0);
        let r = spd_sqrt(&a);
        assert_relative_eq!(r * r, a, max_relative = 1e-12);
    }
}

#[cfg(test)]
mod acoustic_boundary_tests {
    use super::acoustic_boundary;
    use crate::riemann::{FaceState, GhostCondition};
    use approx::assert_relative_eq;
    use impact_core::{Tensor, Vector};

    /// With a coupled (non-diagonal) impedance the boundary state still meets the condition
    /// exactly and lies on the interior's wave relation.
    #[test]
    fn boundary_state_meets_its_condition_with_coupled_impedance() {
        let z = Tensor::<2>::new(4.0e7, 0.6e7, 0.6e7, 2.2e7);
        let inner = FaceState {
            traction: Vector::<2>::new(-3e8, 4e7),
            velocity: Vector::<2>::new(2.0, -0.7),
        };
        let n = Vector::<2>::new(-1.0, 0.0);
        let s = acoustic_boundary(&z, &inner, &n, GhostCondition::NormalVelocity(-100.0)).unwrap();
        assert_relative_eq!(s.velocity.dot(&n), -100.0, max_relative = 1e-12);
        assert_eq!(s.traction[1], 0.0);
        let rel = inner.traction + z * (s.velocity - inner.velocity);
        assert_relative_eq!(rel, s.traction, max_relative = 1e-12);
        let t_d = Vector::<2>::new(1e8, 0.0);
        let s = acoustic_boundary(&z, &inner, &n, GhostCondition::Traction(t_d)).unwrap();
        assert_eq!(s.traction, t_d);
        assert_relative_eq!(
            inner.traction + z * (s.velocity - inner.velocity),
            t_d,
            max_relative = 1e-12,
            epsilon = 1e-6
        );
    }
}

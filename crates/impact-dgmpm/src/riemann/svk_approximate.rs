//! Approximate (acoustic) Saint-Venant–Kirchhoff Riemann solver (Toro 2009, §9.3): each
//! wave linearised about its own side with the impedance tensor `Z = sqrt(ρ₀ A(F, n))`.
use super::{FaceState, GhostCondition};
use impact_core::material::Svk;
use impact_core::{Tensor, Vector};
/// The 3×3 matrix of a tensor (3D only: the closed forms below are written for it).
#[inline]
fn as_matrix3<const D: usize>(a: &Tensor<D>) -> nalgebra::Matrix3<f64> {
    nalgebra::Matrix3::from_fn(|i, j| if i < D && j < D { a[(i, j)] } else { 0.0 })
}

/// The tensor of a 3×3 matrix (3D only).
#[inline]
fn from_matrix3<const D: usize>(m: &nalgebra::Matrix3<f64>) -> Tensor<D> {
    Tensor::<D>::from_fn(|i, j| m[(i, j)])
}

/// Determinant of a 1×1, 2×2 or 3×3 tensor (3D: the rule of Sarrus, through nalgebra).
fn small_det<const D: usize>(a: &Tensor<D>) -> f64 {
    match D {
        1 => a[(0, 0)],
        2 => a[(0, 0)] * a[(1, 1)] - a[(0, 1)] * a[(1, 0)],
        _ => as_matrix3(a).determinant(),
    }
}

/// Inverse of a 1×1, 2×2 or 3×3 tensor (`None` if singular; 3D: the adjugate over the
/// determinant, through nalgebra).
fn small_inverse<const D: usize>(a: &Tensor<D>) -> Option<Tensor<D>> {
    let det = small_det(a);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let mut inv = Tensor::<D>::zeros();
    if D == 1 {
        inv[(0, 0)] = 1.0 / det;
    } else if D == 2 {
        inv[(0, 0)] = a[(1, 1)] / det;
        inv[(1, 1)] = a[(0, 0)] / det;
        inv[(0, 1)] = -a[(0, 1)] / det;
        inv[(1, 0)] = -a[(1, 0)] / det;
    } else {
        inv = from_matrix3(&as_matrix3(a).try_inverse()?);
    }
    Some(inv)
}

/// Square root of a symmetric positive definite tensor (closed form:
/// `√M = (M + √det M 1)/sqrt(tr M + 2 √det M)` in 2D; in 3D through the eigen
/// decomposition `M = Q Λ Qᵀ`, `√M = Q √Λ Qᵀ`, negative round-off eigenvalues taken as 0).
pub fn spd_sqrt<const D: usize>(a: &Tensor<D>) -> Tensor<D> {
    if D == 1 {
        return a.map(|x| x.max(0.0).sqrt());
    }
    if D == 3 {
        // an axis decoupled from the other two (a plane-strain state on an axis-aligned
        // face): the 2×2 closed form on the coupled block, the root of the decoupled entry
        let decoupled =
            (0..3).find(|&j| (0..3).all(|p| p == j || (a[(j, p)] == 0.0 && a[(p, j)] == 0.0)));
        if let Some(j) = decoupled {
            let (p, q) = ((j + 1) % 3, (j + 2) % 3);
            let block = Tensor::<2>::new(a[(p, p)], a[(p, q)], a[(q, p)], a[(q, q)]);
            let root = spd_sqrt(&block);
            let mut out = Tensor::<D>::zeros();
            for (r, x) in [p, q].into_iter().enumerate() {
                for (c, y) in [p, q].into_iter().enumerate() {
                    out[(x, y)] = root[(r, c)];
                }
            }
            out[(j, j)] = a[(j, j)].max(0.0).sqrt();
            return out;
        }
        let eigen = as_matrix3(a).symmetric_eigen();
        let root = eigen.eigenvalues.map(|x| x.max(0.0).sqrt());
        let q = eigen.eigenvectors;
        return from_matrix3(&(q * nalgebra::Matrix3::from_diagonal(&root) * q.transpose()));
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
            if D == 3 {
                // two tangents: 0 = t_a·(t_i + Z Δv_n n + Z Σ_b Δv_b t_b), a = 1, 2
                let t = tangents(n);
                let rhs = t.map(|ta| -ta.dot(&(interior.traction + z * n * dvn)));
                let g = |a: usize, b: usize| t[a].dot(&(z * t[b]));
                let det = g(0, 0) * g(1, 1) - g(0, 1) * g(1, 0);
                if g(0, 0) <= 0.0 || det <= 0.0 {
                    return None;
                }
                let dv0 = (rhs[0] * g(1, 1) - g(0, 1) * rhs[1]) / det;
                let dv1 = (g(0, 0) * rhs[1] - g(1, 0) * rhs[0]) / det;
                velocity += t[0] * dv0 + t[1] * dv1;
            } else if D > 1 {
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

/// Two unit tangents orthogonal to the unit vector `n` and to each other (3D): `t_1` from
/// the axis least aligned with `n`, `t_2 = n × t_1`.
fn tangents<const D: usize>(n: &Vector<D>) -> [Vector<D>; 2] {
    let j = (0..D)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let e = Vector::<D>::from_fn(|k, _| f64::from(u8::from(k == j)));
    let t1 = (e - n * n.dot(&e)).normalize();
    let c = |a: usize| (a % D, (a + 1) % D, (a + 2) % D);
    let t2 = Vector::<D>::from_fn(|k, _| {
        let (_, p, q) = c(k);
        n[p] * t1[q] - n[q] * t1[p]
    });
    [t1, t2]
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

#[cfg(test)]
mod svk_3d_tests {
    use super::*;
    use crate::riemann::{linear_elastic_star, Impedances};
    use approx::assert_relative_eq;
    use impact_core::material::LinearElastic;

    /// 3D: at `F = 1` the acoustic solver is the linear one for an oblique normal; the
    /// square root squares back; a frictionless boundary meets its normal velocity with
    /// zero shear traction and stays on the interior's wave relation.
    #[test]
    fn acoustic_solver_in_3d() {
        let svk = Svk::new(LinearElastic::new(2e11, 0.3, 7800.0));
        let f = Tensor::<3>::identity();
        let n = Vector::<3>::new(0.48, -0.6, 0.64);
        let (vl, vr) = (
            Vector::<3>::new(1.0, -2.0, 0.5),
            Vector::<3>::new(-0.5, 3.0, -1.0),
        );
        let s = acoustic_star(&svk, (&f, &vl), (&f, &vr), &n).unwrap();
        let (zp, zs) = svk.linear.impedances::<3>();
        let face = |v: Vector<3>| FaceState {
            traction: Vector::<3>::zeros(),
            velocity: v,
        };
        let lin = linear_elastic_star(&face(vl), &face(vr), &n, Impedances { p: zp, s: zs });
        assert_relative_eq!(s.velocity, lin.velocity, max_relative = 1e-12);
        assert_relative_eq!(
            s.traction,
            lin.traction,
            max_relative = 1e-10,
            epsilon = 1e-3
        );
        let a = Tensor::<3>::new(4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0);
        let r = spd_sqrt(&a);
        assert_relative_eq!(r * r, a, max_relative = 1e-12);
        let block = Tensor::<3>::new(4.0, 0.0, 1.0, 0.0, 2.5, 0.0, 1.0, 0.0, 3.0);
        let r = spd_sqrt(&block);
        assert_relative_eq!(r * r, block, max_relative = 1e-14);
        assert_relative_eq!(small_det(&a), a.determinant(), max_relative = 1e-14);
        assert_relative_eq!(
            small_inverse(&a).unwrap() * a,
            Tensor::<3>::identity(),
            epsilon = 1e-14
        );
        let z = impedance(
            &svk,
            &Tensor::<3>::new(1.01, 0.02, 0.0, 0.01, 0.99, 0.03, 0.0, 0.0, 1.0),
            &n,
        );
        let inner = FaceState {
            traction: Vector::<3>::new(-3e8, 4e7, 1e7),
            velocity: Vector::<3>::new(2.0, -0.7, 0.3),
        };
        let b = acoustic_boundary(&z, &inner, &n, GhostCondition::NormalVelocity(-100.0)).unwrap();
        assert_relative_eq!(b.velocity.dot(&n), -100.0, max_relative = 1e-12);
        let rel = inner.traction + z * (b.velocity - inner.velocity);
        assert_relative_eq!(rel, b.traction, max_relative = 1e-9, epsilon = 1e-3);
    }
}

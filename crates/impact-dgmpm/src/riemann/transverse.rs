//! The transverse Riemann solver of corner transport upwind (LeVeque 2002, §21.2).
use super::{Conserved, Elastic};
use impact_core::{Tensor, Vector};

/// Transverse Riemann solver (LeVeque 2002, §21.2): split `w` into the waves of the
/// Jacobian `B` normal to `normal` and keep those moving along `+normal` (`B⁺w`) and
/// along `-normal` (`B⁻w`). With `n` the normal, `t` a tangent, `m` the momentum part and
/// `W` the stress part of `w`, the P- and S-wave strengths are
/// `α_P± = ½ (m·n/ρ ∓ n·W n/Z_p)`, `α_S± = ½ (m·t/ρ ∓ t·W n/Z_s)`, the eigenvectors
/// `r_P± = (∓(λ 1 + 2μ n⊗n)/c_p, ρ n)`, `r_S± = (∓μ (t⊗n + n⊗t)/c_s, ρ t)`, and
/// `B⁺w = c_p α_P+ r_P+ + c_s α_S+ r_S+`, `B⁻w = -c_p α_P- r_P- - c_s α_S- r_S-`.
/// The stationary wave (a jump of `σ_tt`) moves neither way.
#[inline]
pub fn transverse_split<const D: usize>(
    w: &Conserved<D>,
    normal: &Vector<D>,
    m: &Elastic,
) -> (Conserved<D>, Conserved<D>) {
    let n = normal;
    let rho = m.density;
    let (zp, zs) = (m.z.p, m.z.s);
    let inv_rho = 1.0 / rho;
    let wn = w.tensor * n;
    let p_sum = w.momentum.dot(n) * inv_rho;
    let p_diff = -n.dot(&wn) / zp;
    let (ap, am) = (0.5 * (p_sum + p_diff), 0.5 * (p_sum - p_diff));
    // c_p α r_P± = ∓(λ 1 + 2μ n⊗n) α, ±Z_p α n
    let pstress = Tensor::<D>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu);
    let mut plus = Conserved {
        tensor: -pstress * ap,
        momentum: n * (zp * ap),
    };
    let mut minus = Conserved {
        tensor: -pstress * am,
        momentum: n * (-zp * am),
    };
    if D > 1 && zs > 0.0 {
        // tangential unit vectors: the component of wn and m normal to n
        let mt = w.momentum - n * w.momentum.dot(n);
        let tt = wn - n * wn.dot(n);
        // S waves act on the tangential plane; in 2D it is one direction
        let s_sum = mt * inv_rho;
        let s_diff = tt * (-1.0 / zs);
        let (sp, sm) = ((s_sum + s_diff) * 0.5, (s_sum - s_diff) * 0.5);
        // c_s r_S±(a) = (∓μ(a⊗n + n⊗a), ±Z_s a) for a tangential amplitude vector a
        let shear = |a: &Vector<D>| (a * n.transpose() + n * a.transpose()) * m.mu;
        plus.tensor -= shear(&sp);
        plus.momentum += sp * zs;
        minus.tensor -= shear(&sm);
        minus.momentum -= sm * zs;
    }
    (plus, minus)
}

/// What the transverse solver sends into a face normal to `normal` from the cells on its
/// two sides: `B⁺ w_below + B⁻ w_above` (CTU, LeVeque 2002 §21.2), with the wave strengths
/// of [`transverse_split`] taken only where they are used:
/// `α_P+ = ½ (m_b·n/ρ - n·W_b n/Z_p)`, `α_P- = ½ (m_a·n/ρ + n·W_a n/Z_p)`,
/// `α_S+ = ½ (m_b·t/ρ - t·W_b n/Z_s)`, `α_S- = ½ (m_a·t/ρ + t·W_a n/Z_s)`, giving
/// stress `-(λ 1 + 2μ n⊗n)(α_P+ + α_P-) - μ (a⊗n + n⊗a)` with `a = (α_S+ + α_S-) t`, and
/// momentum `Z_p (α_P+ - α_P-) n + Z_s (α_S+ - α_S-) t`. Half the work of splitting both.
#[inline]
pub fn transverse_into_face<const D: usize>(
    below: &Conserved<D>,
    above: &Conserved<D>,
    normal: &Vector<D>,
    m: &Elastic,
) -> Conserved<D> {
    let n = normal;
    let (zp, zs) = (m.z.p, m.z.s);
    let inv_rho = 1.0 / m.density;
    let inv_zp = 1.0 / zp;
    let (wn_b, wn_a) = (below.tensor * n, above.tensor * n);
    let (mn_b, mn_a) = (below.momentum.dot(n), above.momentum.dot(n));
    let (tn_b, tn_a) = (n.dot(&wn_b), n.dot(&wn_a));
    let ap = 0.5 * (mn_b * inv_rho - tn_b * inv_zp);
    let am = 0.5 * (mn_a * inv_rho + tn_a * inv_zp);
    let pstress = Tensor::<D>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu);
    let mut out = Conserved {
        tensor: -pstress * (ap + am),
        momentum: n * (zp * (ap - am)),
    };
    if D > 1 && zs > 0.0 {
        let inv_zs = 1.0 / zs;
        // tangential parts of the momentum and of the traction W n
        let (mt_b, mt_a) = (below.momentum - n * mn_b, above.momentum - n * mn_a);
        let (tt_b, tt_a) = (wn_b - n * tn_b, wn_a - n * tn_a);
        let sp = (mt_b * inv_rho - tt_b * inv_zs) * 0.5;
        let sm = (mt_a * inv_rho + tt_a * inv_zs) * 0.5;
        let a = sp + sm;
        out.tensor -= (a * n.transpose() + n * a.transpose()) * m.mu;
        out.momentum += (sp - sm) * zs;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::riemann::test_support::{sample, steel};
    use crate::riemann::{normal_flux, FaceState};
    use approx::assert_relative_eq;

    /// `transverse_into_face(b, a) = B⁺b + B⁻a` from the full split.
    #[test]
    fn transverse_into_face_is_the_used_half_of_two_splits() {
        let m = steel();
        let below = sample();
        let above = Conserved {
            tensor: below.tensor.transpose() * -0.7 + Tensor::<2>::identity() * 3e7,
            momentum: Vector::<2>::new(-4.0e3, 9.0e3),
        };
        for n in [
            Vector::<2>::new(1.0, 0.0),
            Vector::<2>::new(0.0, 1.0),
            Vector::<2>::new(0.6, -0.8),
        ] {
            let (up, _) = transverse_split(&below, &n, &m);
            let (_, down) = transverse_split(&above, &n, &m);
            let got = transverse_into_face(&below, &above, &n, &m);
            assert_relative_eq!(
                got.tensor,
                up.tensor + down.tensor,
                max_relative = 1e-12,
                epsilon = 1e-3
            );
            assert_relative_eq!(
                got.momentum,
                up.momentum + down.momentum,
                max_relative = 1e-12,
                epsilon = 1e-6
            );
        }
    }

    /// `B⁺w + B⁻w = Bw`, the normal flux Jacobian applied to `w`.
    #[test]
    fn transverse_split_sums_to_the_jacobian() {
        let m = steel();
        let w = sample();
        for n in [
            Vector::<2>::new(1.0, 0.0),
            Vector::<2>::new(0.0, 1.0),
            Vector::<2>::new(0.6, -0.8),
        ] {
            let (plus, minus) = transverse_split(&w, &n, &m);
            let bw = normal_flux(
                &FaceState {
                    traction: w.tensor * n,
                    velocity: w.momentum / m.density,
                },
                &n,
                &m,
            );
            assert_relative_eq!(
                plus.tensor + minus.tensor,
                bw.tensor,
                max_relative = 1e-10,
                epsilon = 1e-3
            );
            assert_relative_eq!(
                plus.momentum + minus.momentum,
                bw.momentum,
                max_relative = 1e-10,
                epsilon = 1e-3
            );
        }
    }

    /// A pure right-going P wave has no left-going part, and `B⁺ r = c_p r`.
    #[test]
    fn transverse_split_of_an_eigenvector() {
        let m = steel();
        let n = Vector::<2>::new(0.0, 1.0);
        let cp = m.z.p / m.density;
        let r = Conserved {
            tensor: -(Tensor::<2>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu)) / cp,
            momentum: n * m.density,
        };
        let (plus, minus) = transverse_split(&r, &n, &m);
        assert_relative_eq!(
            minus.tensor.norm() + minus.momentum.norm(),
            0.0,
            epsilon = 1e-6
        );
        assert_relative_eq!(plus.tensor, r.tensor * cp, max_relative = 1e-12);
        assert_relative_eq!(plus.momentum, r.momentum * cp, max_relative = 1e-12);
    }
}

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
use impact_core::{Tensor, Vector};

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

/// A vector of conserved quantities `q = (σ, ρ v)` (paper eq. 7), or a flux or fluctuation
/// in that space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conserved<const D: usize> {
    /// Stress part.
    pub stress: Tensor<D>,
    /// Momentum part `ρ v`.
    pub momentum: Vector<D>,
}

impl<const D: usize> Conserved<D> {
    /// Zero.
    pub fn zeros() -> Self {
        Self {
            stress: Tensor::<D>::zeros(),
            momentum: Vector::<D>::zeros(),
        }
    }
    /// `self + other * s`.
    #[inline]
    pub fn add_scaled(&self, other: &Self, s: f64) -> Self {
        Self {
            stress: self.stress + other.stress * s,
            momentum: self.momentum + other.momentum * s,
        }
    }
}

/// A full state: stress and velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullState<const D: usize> {
    /// Stress `σ`.
    pub stress: Tensor<D>,
    /// Velocity `v`.
    pub velocity: Vector<D>,
}

impl<const D: usize> FullState<D> {
    /// Traction and velocity on a face of normal `normal`.
    #[inline]
    pub fn on_face(&self, normal: &Vector<D>) -> FaceState<D> {
        FaceState {
            traction: self.stress * normal,
            velocity: self.velocity,
        }
    }
}

/// Isotropic linear elasticity as the flux functions need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// `λ` (unused in 1D).
    pub lambda: f64,
    /// `μ` (in 1D the bar's `E/2`, so that `C(ε) = 2μ ε = E ε`).
    pub mu: f64,
    /// Density `ρ`.
    pub density: f64,
    /// Impedances.
    pub z: Impedances,
}

impl Elastic {
    /// `C : ε` (1D: `E ε`; 2D: `λ tr ε 1 + 2μ ε`).
    #[inline]
    pub fn stress<const D: usize>(&self, strain: &Tensor<D>) -> Tensor<D> {
        let mut s = strain * (2.0 * self.mu);
        if D > 1 {
            s += Tensor::<D>::identity() * (self.lambda * strain.trace());
        }
        s
    }
}

fn sym<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> Tensor<D> {
    let outer = a * b.transpose();
    (outer + outer.transpose()) * 0.5
}

/// Normal flux `F_n(q) = -(C : sym(v ⊗ n), σ n)` of a face state given by its velocity and
/// traction `σ n` (paper eq. 7 and 20).
#[inline]
pub fn normal_flux<const D: usize>(
    face: &FaceState<D>,
    normal: &Vector<D>,
    m: &Elastic,
) -> Conserved<D> {
    Conserved {
        stress: -m.stress(&sym(&face.velocity, normal)),
        momentum: -face.traction,
    }
}

/// Fluctuations of the face Riemann problem (LeVeque 2002, eq. 4.?): `A⁻Δq = F_n(q*) - F_n(q_L)`
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

/// Transverse Riemann solver (LeVeque 2002, §21.2): split `w` into the waves of the
/// Jacobian `B` normal to `normal` and keep those moving along `+normal` (`B⁺w`) and
/// along `-normal` (`B⁻w`). With `n` the normal, `t` a tangent, `m = ρ v`-part and
/// `W` the stress part of `w`, the P- and S-wave strengths are
/// `α_P± = ½ (m·n/ρ ∓ n·Wn/Z_p)`, `α_S± = ½ (m·t/ρ ∓ t·Wn/Z_s)`, with eigenvectors
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
    let wn = w.stress * n;
    let p_sum = w.momentum.dot(n) * inv_rho;
    let p_diff = -n.dot(&wn) / zp;
    let (ap, am) = (0.5 * (p_sum + p_diff), 0.5 * (p_sum - p_diff));
    // c_p α r_P± = ∓(λ 1 + 2μ n⊗n) α, ±Z_p α n
    let pstress = Tensor::<D>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu);
    let mut plus = Conserved {
        stress: -pstress * ap,
        momentum: n * (zp * ap),
    };
    let mut minus = Conserved {
        stress: -pstress * am,
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
        plus.stress -= shear(&sp);
        plus.momentum += sp * zs;
        minus.stress -= shear(&sm);
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
    let (wn_b, wn_a) = (below.stress * n, above.stress * n);
    let (mn_b, mn_a) = (below.momentum.dot(n), above.momentum.dot(n));
    let (tn_b, tn_a) = (n.dot(&wn_b), n.dot(&wn_a));
    let ap = 0.5 * (mn_b * inv_rho - tn_b * inv_zp);
    let am = 0.5 * (mn_a * inv_rho + tn_a * inv_zp);
    let pstress = Tensor::<D>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu);
    let mut out = Conserved {
        stress: -pstress * (ap + am),
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
        out.stress -= (a * n.transpose() + n * a.transpose()) * m.mu;
        out.momentum += (sp - sm) * zs;
    }
    out
}

/// Full-state ghost transform (the state of the mirror cell behind a boundary), in the
/// normal/tangential basis of the outward normal `n`:
/// traction `t_d`: `σ_nn' = 2 t_d·n - σ_nn`, `σ_nt' = 2 t_d·t - σ_nt`, `σ_tt' = σ_tt`, `v' = v`;
/// normal velocity `v_d`: `v_n' = 2 v_d - v_n`, `v_t' = v_t`, `σ_nn' = σ_nn`,
/// `σ_nt' = -σ_nt`, `σ_tt' = σ_tt`. On the face it agrees with [`ghost_state`].
pub fn ghost_full<const D: usize>(
    interior: &FullState<D>,
    outward: &Vector<D>,
    condition: GhostCondition<D>,
) -> FullState<D> {
    let n = outward;
    let t_i = interior.stress * n;
    let g = ghost_state(&interior.on_face(n), n, condition);
    // replace the traction part of σ: σ' = σ + (Δt ⊗ n + n ⊗ Δt) - (Δt·n) n⊗n, Δt = t' - t
    let dt = g.traction - t_i;
    let stress =
        interior.stress + dt * n.transpose() + n * dt.transpose() - n * n.transpose() * dt.dot(n);
    FullState {
        stress,
        velocity: g.velocity,
    }
}

/// Restrict a transverse flux correction on a boundary face (outward normal `n`) to what
/// the edge's condition leaves free. A correction is of the form `(-C : sym(Δv ⊗ n), -Δt)`
/// (the range of the normal Jacobian). Under a traction condition the traction is
/// prescribed: `Δt = 0`. Under a normal-velocity condition the normal velocity and the
/// shear traction are prescribed: the parts of the stress correction made by `Δv_n`
/// (`nn` and `tt` components) and the tangential `Δt` vanish.
pub fn constrain_correction<const D: usize>(
    correction: &Conserved<D>,
    n: &Vector<D>,
    condition: GhostCondition<D>,
) -> Conserved<D> {
    match condition {
        GhostCondition::Traction(_) => Conserved {
            stress: correction.stress,
            momentum: Vector::<D>::zeros(),
        },
        GhostCondition::NormalVelocity(_) => {
            // keep only the shear (nt) part of the stress correction
            let s = correction.stress;
            let sn = s * n;
            let nt = sn - n * n.dot(&sn);
            Conserved {
                stress: nt * n.transpose() + n * nt.transpose(),
                momentum: n * n.dot(&correction.momentum),
            }
        }
    }
}

#[cfg(test)]
mod flux_tests {
    use super::*;
    use approx::assert_relative_eq;

    fn steel() -> Elastic {
        let (e, nu, rho): (f64, f64, f64) = (2e11, 0.3, 7800.0);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        Elastic {
            lambda,
            mu,
            density: rho,
            z: Impedances {
                p: (rho * (lambda + 2.0 * mu)).sqrt(),
                s: (rho * mu).sqrt(),
            },
        }
    }

    fn sample() -> Conserved<2> {
        Conserved {
            stress: Tensor::<2>::new(3.0e8, -1.0e8, -1.0e8, 2.0e8),
            momentum: Vector::<2>::new(4.0e4, -2.5e4),
        }
    }

    /// `transverse_into_face(b, a) = B⁺b + B⁻a` from the full split.
    #[test]
    fn transverse_into_face_is_the_used_half_of_two_splits() {
        let m = steel();
        let below = sample();
        let above = Conserved {
            stress: below.stress.transpose() * -0.7 + Tensor::<2>::identity() * 3e7,
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
                got.stress,
                up.stress + down.stress,
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
                    traction: w.stress * n,
                    velocity: w.momentum / m.density,
                },
                &n,
                &m,
            );
            assert_relative_eq!(
                plus.stress + minus.stress,
                bw.stress,
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
            stress: -(Tensor::<2>::identity() * m.lambda + n * n.transpose() * (2.0 * m.mu)) / cp,
            momentum: n * m.density,
        };
        let (plus, minus) = transverse_split(&r, &n, &m);
        assert_relative_eq!(
            minus.stress.norm() + minus.momentum.norm(),
            0.0,
            epsilon = 1e-6
        );
        assert_relative_eq!(plus.stress, r.stress * cp, max_relative = 1e-12);
        assert_relative_eq!(plus.momentum, r.momentum * cp, max_relative = 1e-12);
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
        assert_relative_eq!(am.stress + ap.stress, diff.stress, max_relative = 1e-12);
        assert_relative_eq!(
            am.momentum + ap.momentum,
            diff.momentum,
            max_relative = 1e-12
        );
        let (am, ap) = fluctuations(&l, &l, &l, &n, &m);
        assert_eq!((am.momentum.norm(), ap.stress.norm()), (0.0, 0.0));
    }

    /// The full ghost state's traction on the face is the face ghost state's.
    #[test]
    fn ghost_full_agrees_with_the_face_ghost() {
        let inner = FullState {
            stress: Tensor::<2>::new(1e8, 3e7, 3e7, -2e8),
            velocity: Vector::<2>::new(2.0, -1.0),
        };
        for n in [Vector::<2>::new(-1.0, 0.0), Vector::<2>::new(0.0, 1.0)] {
            for c in [
                GhostCondition::Traction(Vector::<2>::new(5e7, 0.0)),
                GhostCondition::NormalVelocity(-5.0),
            ] {
                let g = ghost_full(&inner, &n, c);
                let face = ghost_state(&inner.on_face(&n), &n, c);
                assert_relative_eq!(g.stress * n, face.traction, max_relative = 1e-12);
                assert_relative_eq!(g.velocity, face.velocity, max_relative = 1e-12);
                assert_eq!(g.stress, g.stress.transpose());
                // the tangential normal stress is untouched
                let t = Vector::<2>::new(n[1], -n[0]);
                assert_relative_eq!(
                    t.dot(&(g.stress * t)),
                    t.dot(&(inner.stress * t)),
                    max_relative = 1e-12
                );
            }
        }
    }
}

/// Saint-Venant–Kirchhoff Riemann solvers (paper §4, §5.3), for the total Lagrangian system
/// `q = (F, ρ₀ v)`, `F_n(q) = -(v ⊗ n, Π(F) n)` (paper eq. 6).
pub mod svk {
    use super::{FaceState, GhostCondition};
    use impact_core::material::Svk;
    use impact_core::{Tensor, Vector};

    /// Velocity behind a wave of the 1D system reaching the stress `pi` from the state
    /// `(f, v)`: a left-going (1-) wave if `left` (the state on its left), else a
    /// right-going (2-) wave. Rarefaction (the Riemann invariant `v ∓ φ(F)` holds) when
    /// the stretch decreases across it, shock (Rankine–Hugoniot,
    /// `[v]² = [Π][F]/ρ₀`) otherwise. `None` beyond the hyperbolicity limit.
    pub fn wave_velocity_1d(m: &Svk, f: f64, v: f64, pi: f64, left: bool) -> Option<f64> {
        let f_star = m.stretch_for_1d(pi)?;
        let pi_side = m.piola_1d(f);
        let jump = if f_star < f {
            m.riemann_phi_1d(f_star) - m.riemann_phi_1d(f)
        } else {
            ((pi - pi_side) * (f_star - f) / m.linear.density)
                .max(0.0)
                .sqrt()
        };
        Some(if left { v + jump } else { v - jump })
    }

    /// Root of the increasing function `g` on `(lo, ∞)`: bracket by doubling from `guess`,
    /// then Newton with slope `slope(π)` safeguarded by bisection. `None` when `g(lo) > 0`.
    fn solve_increasing(
        g: impl Fn(f64) -> Option<f64>,
        slope: impl Fn(f64) -> f64,
        lo: f64,
        guess: f64,
        scale: f64,
    ) -> Option<f64> {
        let (mut a, mut b) = (lo, guess.max(lo + 1e-9 * scale));
        if g(a)? > 0.0 {
            return None;
        }
        let mut width = scale.max(1.0);
        let mut gb = g(b)?;
        let mut tries = 0;
        while gb < 0.0 {
            a = b;
            b += width;
            width *= 2.0;
            gb = g(b)?;
            tries += 1;
            if tries > 200 {
                return None;
            }
        }
        let mut x = guess.clamp(a, b);
        for _ in 0..200 {
            let gx = g(x)?;
            if gx == 0.0 {
                return Some(x);
            }
            if gx < 0.0 {
                a = x;
            } else {
                b = x;
            }
            let mut next = x - gx / slope(x);
            if !(next > a && next < b) {
                next = 0.5 * (a + b);
            }
            if (next - x).abs() <= 1e-14 * (x.abs() + 1e-6 * scale)
                || b - a <= 1e-14 * (x.abs() + scale * 1e-6)
            {
                return Some(next);
            }
            x = next;
        }
        Some(x)
    }

    fn slope_1d(m: &Svk, pi: f64) -> f64 {
        let f = m.stretch_for_1d(pi).unwrap_or(1.0);
        1.0 / (m.linear.density * m.wave_speed_1d(f)).max(1e-300)
    }

    /// Exact 1D star state `(v*, Π*)` between `(F_L, v_L)` and `(F_R, v_R)`:
    /// `v₁(Π*) = v₂(Π*)` with [`wave_velocity_1d`]. `None` if no admissible star state
    /// exists (hyperbolicity lost).
    pub fn exact_star_1d(m: &Svk, left: (f64, f64), right: (f64, f64)) -> Option<(f64, f64)> {
        let (_, pi_min) = m.hyperbolicity_limit_1d();
        let lo = pi_min * (1.0 - 1e-9);
        let (pl, pr) = (m.piola_1d(left.0), m.piola_1d(right.0));
        let (zl, zr) = (
            m.linear.density * m.wave_speed_1d(left.0),
            m.linear.density * m.wave_speed_1d(right.0),
        );
        let guess = (zr * pl + zl * pr + zl * zr * (right.1 - left.1)) / (zl + zr);
        let g = |pi: f64| {
            Some(
                wave_velocity_1d(m, left.0, left.1, pi, true)?
                    - wave_velocity_1d(m, right.0, right.1, pi, false)?,
            )
        };
        let pi = solve_increasing(
            g,
            |p| 2.0 * slope_1d(m, p),
            lo,
            guess.max(lo),
            m.linear.elastic.young * 1e-3,
        )?;
        Some((wave_velocity_1d(m, left.0, left.1, pi, true)?, pi))
    }

    /// Exact 1D boundary problem: the interior state `(F, v)`, the outward normal sign
    /// `outward` (±1) and the condition give `(v*, Π*)`: a traction `t_d` fixes
    /// `Π* = t_d · outward` and `v*` follows from the interior's wave curve; a normal velocity
    /// fixes `v* = v_n · outward` and `Π*` is solved on that curve.
    pub fn exact_boundary_1d(
        m: &Svk,
        interior: (f64, f64),
        outward: f64,
        condition: GhostCondition<1>,
    ) -> Option<(f64, f64)> {
        // the interior is on the left of a right boundary (1-wave), on the right of a left one
        let interior_left = outward > 0.0;
        match condition {
            GhostCondition::Traction(t) => {
                let pi = t[0] * outward;
                Some((
                    wave_velocity_1d(m, interior.0, interior.1, pi, interior_left)?,
                    pi,
                ))
            }
            GhostCondition::NormalVelocity(vn) => {
                let v = vn * outward;
                let (_, pi_min) = m.hyperbolicity_limit_1d();
                let sign = if interior_left { 1.0 } else { -1.0 };
                let g = |pi: f64| {
                    Some(
                        sign * (wave_velocity_1d(m, interior.0, interior.1, pi, interior_left)?
                            - v),
                    )
                };
                let guess = m.piola_1d(interior.0);
                let pi = solve_increasing(
                    g,
                    |p| slope_1d(m, p),
                    pi_min * (1.0 - 1e-9),
                    guess,
                    m.linear.elastic.young * 1e-3,
                )?;
                Some((v, pi))
            }
        }
    }

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
    /// waves couple at finite strain).
    pub fn acoustic_boundary<const D: usize>(
        z: &Tensor<D>,
        interior: &FaceState<D>,
        n: &Vector<D>,
        condition: GhostCondition<D>,
    ) -> Option<FaceState<D>> {
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
}

#[cfg(test)]
mod svk_tests {
    use super::svk::*;
    use super::{linear_elastic_star, FaceState, GhostCondition, Impedances};
    use approx::assert_relative_eq;
    use impact_core::material::{LinearElastic, Svk};
    use impact_core::{Tensor, Vector};

    fn m() -> Svk {
        Svk::new(LinearElastic::new(2e11, 0.3, 7800.0))
    }

    #[test]
    fn equal_states_are_their_own_star_state() {
        let f = 0.995;
        let (v, pi) = exact_star_1d(&m(), (f, 3.0), (f, 3.0)).unwrap();
        assert_relative_eq!(v, 3.0, max_relative = 1e-10);
        assert_relative_eq!(pi, m().piola_1d(f), max_relative = 1e-10);
    }

    /// A pure fan: the left state is the star state of a compressive load reached through
    /// a rarefaction from rest; the solver returns it.
    #[test]
    fn pure_fan() {
        let f = m().stretch_for_1d(-8e8).unwrap();
        let v = -m().riemann_phi_1d(f);
        let (vs, pis) = exact_star_1d(&m(), (f, v), (1.0, 0.0)).unwrap();
        assert_relative_eq!(vs, v, max_relative = 1e-9);
        assert_relative_eq!(pis, -8e8, max_relative = 1e-9);
    }

    /// A pure shock: a tensile state behind a Rankine–Hugoniot shock into rest.
    #[test]
    fn pure_shock() {
        let f = m().stretch_for_1d(8e8).unwrap();
        let s = (m().piola_1d(f) / (7800.0 * (f - 1.0))).sqrt();
        let v = -s * (f - 1.0);
        let (vs, pis) = exact_star_1d(&m(), (f, v), (1.0, 0.0)).unwrap();
        assert_relative_eq!(vs, v, max_relative = 1e-9);
        assert_relative_eq!(pis, 8e8, max_relative = 1e-9);
    }

    /// Hand-worked colliding state: two halves at ±10 m/s meet; by symmetry v* = 0. The
    /// compression lowers the wave speed (Π'' > 0), so both waves are rarefactions (Lax):
    /// the invariant v - φ(F) across the 1-wave gives φ(F*) = -10 m/s.
    #[test]
    fn colliding_halves() {
        let (vs, pis) = exact_star_1d(&m(), (1.0, 10.0), (1.0, -10.0)).unwrap();
        assert!(vs.abs() < 1e-9);
        let f = m().stretch_for_1d(pis).unwrap();
        assert!(f < 1.0);
        assert_relative_eq!(m().riemann_phi_1d(f), -10.0, max_relative = 1e-9);
        // pulling apart instead gives two shocks: [v]² = [Π][F]/ρ₀
        let (vs, pis) = exact_star_1d(&m(), (1.0, -10.0), (1.0, 10.0)).unwrap();
        assert!(vs.abs() < 1e-9 && pis > 0.0);
        let f = m().stretch_for_1d(pis).unwrap();
        assert_relative_eq!(100.0, pis * (f - 1.0) / 7800.0, max_relative = 1e-9);
        let (_, pis) = exact_star_1d(&m(), (1.0, 10.0), (1.0, -10.0)).unwrap();
        // weak waves: close to the acoustic value Z v
        assert_relative_eq!(-pis, (7800.0 * 2e11f64).sqrt() * 10.0, max_relative = 0.01);
    }

    #[test]
    fn boundary_problems_enforce_their_condition() {
        let (v, pi) = exact_boundary_1d(
            &m(),
            (1.0, 0.0),
            -1.0,
            GhostCondition::Traction(Vector::<1>::new(8e8)),
        )
        .unwrap();
        assert_relative_eq!(pi, -8e8, max_relative = 1e-12);
        assert_relative_eq!(
            v,
            -m().riemann_phi_1d(m().stretch_for_1d(-8e8).unwrap()),
            max_relative = 1e-9
        );
        let (v, pi) =
            exact_boundary_1d(&m(), (1.0, 0.0), -1.0, GhostCondition::NormalVelocity(-5.0))
                .unwrap();
        assert_relative_eq!(v, 5.0, max_relative = 1e-12);
        assert!(pi < 0.0);
        // loads beyond the hyperbolicity limit have no star state
        let (_, pi_min) = m().hyperbolicity_limit_1d();
        assert!(exact_boundary_1d(
            &m(),
            (1.0, 0.0),
            -1.0,
            GhostCondition::Traction(Vector::<1>::new(-pi_min * 1.01))
        )
        .is_none());
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
    use super::svk::acoustic_boundary;
    use super::{FaceState, GhostCondition};
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

//! Ghost states behind boundary faces (LeVeque 2002, §7.3) and the restriction of CTU
//! corrections on boundary faces.
use super::{Conserved, FaceState, FullState};
use impact_core::Vector;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GhostCondition<const D: usize> {
    /// Prescribed traction `t_d` (traction-free: `t_d = 0`).
    Traction(Vector<D>),
    /// Prescribed normal velocity `v_n` along the outward normal, zero shear traction
    /// (a frictionless impactor or wall).
    NormalVelocity(f64),
    /// Prescribed velocity vector `v_d` (a bonded impactor: no slip).
    Velocity(Vector<D>),
    /// An impactor that covers the share `share` ∈ (0, 1) of the face (a segment end under
    /// `cover = "fraction"`): the ghost state is `share · ghost(impactor) + (1 - share) ·
    /// ghost(free)`. The linear Riemann flux is linear in the ghost state, so the face then
    /// carries the share-weighted average of the impactor's and the free face's fluxes.
    PartialVelocity {
        /// The impactor's velocity vector `v_d` (bonded) or `v_d n` (frictionless).
        velocity: Vector<D>,
        /// Bonded (the whole vector) or frictionless (its normal component).
        bonded: bool,
        /// Covered share of the face.
        share: f64,
    },
}

impl<const D: usize> GhostCondition<D> {
    /// A partial condition as its full impactor condition and its share; `None` otherwise.
    #[inline]
    pub fn split(self, outward: &Vector<D>) -> Option<(GhostCondition<D>, f64)> {
        match self {
            GhostCondition::PartialVelocity {
                velocity,
                bonded,
                share,
            } => Some((
                if bonded {
                    GhostCondition::Velocity(velocity)
                } else {
                    GhostCondition::NormalVelocity(velocity.dot(outward))
                },
                share,
            )),
            _ => None,
        }
    }

    /// The free condition (zero traction).
    #[inline]
    pub fn free() -> Self {
        GhostCondition::Traction(Vector::<D>::zeros())
    }
}

/// Ghost state outside a boundary face (LeVeque 2002, §7.3): with `n` the outward normal
/// and the interior state on the left, the ghost state on the right makes the star state
/// satisfy the condition exactly:
/// - traction `t_d`: `t_g = 2 t_d - t_i`, `v_g = v_i` (then `t* = t_d`);
/// - normal velocity `v_d`: `v_gn = 2 v_d - v_in`, `t_gn = t_in`, and `t_gt = -t_it`,
///   `v_gt = v_it` (then `v_n* = v_d`, `t_t* = 0`);
/// - velocity vector `v_d`: `v_g = 2 v_d - v_i`, `t_g = t_i` (then `v* = v_d`).
#[inline]
pub fn ghost_state<const D: usize>(
    interior: &FaceState<D>,
    outward: &Vector<D>,
    condition: GhostCondition<D>,
) -> FaceState<D> {
    if let Some((full, share)) = condition.split(outward) {
        let covered = ghost_state(interior, outward, full);
        let free = ghost_state(interior, outward, GhostCondition::free());
        return FaceState {
            traction: covered.traction * share + free.traction * (1.0 - share),
            velocity: covered.velocity * share + free.velocity * (1.0 - share),
        };
    }
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
        GhostCondition::Velocity(v_d) => FaceState {
            traction: interior.traction,
            velocity: v_d * 2.0 - interior.velocity,
        },
        GhostCondition::PartialVelocity { .. } => unreachable!("internal: split above"),
    }
}

/// traction `t_d`: `σ_nn' = 2 t_d·n - σ_nn`, `σ_nt' = 2 t_d·t - σ_nt`, `σ_tt' = σ_tt`, `v' = v`;
/// normal velocity `v_d`: `v_n' = 2 v_d - v_n`, `v_t' = v_t`, `σ_nn' = σ_nn`,
/// `σ_nt' = -σ_nt`, `σ_tt' = σ_tt`. On the face it agrees with [`ghost_state`].
pub fn ghost_full<const D: usize>(
    interior: &FullState<D>,
    outward: &Vector<D>,
    condition: GhostCondition<D>,
) -> FullState<D> {
    let n = outward;
    let t_i = interior.tensor * n;
    let g = ghost_state(&interior.on_face(n), n, condition);
    // replace the traction part of σ: σ' = σ + (Δt ⊗ n + n ⊗ Δt) - (Δt·n) n⊗n, Δt = t' - t
    let dt = g.traction - t_i;
    let stress =
        interior.tensor + dt * n.transpose() + n * dt.transpose() - n * n.transpose() * dt.dot(n);
    FullState {
        tensor: stress,
        velocity: g.velocity,
    }
}

/// Restrict a transverse flux correction on a boundary face (outward normal `n`) to what
/// the edge's condition leaves free. A correction is of the form `(-C : sym(Δv ⊗ n), -Δt)`
/// (the range of the normal Jacobian). Under a traction condition the traction is
/// prescribed: `Δt = 0`. Under a normal-velocity condition the normal velocity and the
/// shear traction are prescribed: the parts of the stress correction made by `Δv_n`
/// (`nn` and `tt` components) and the tangential `Δt` vanish. Under a velocity-vector
/// condition the whole velocity is prescribed: the stress correction vanishes, `Δt` stays.
pub fn constrain_correction<const D: usize>(
    correction: &Conserved<D>,
    n: &Vector<D>,
    condition: GhostCondition<D>,
) -> Conserved<D> {
    if let Some((full, share)) = condition.split(n) {
        let covered = constrain_correction(correction, n, full);
        let free = constrain_correction(correction, n, GhostCondition::free());
        return covered
            .add_scaled(&covered, share - 1.0)
            .add_scaled(&free, 1.0 - share);
    }
    match condition {
        GhostCondition::Traction(_) => Conserved {
            tensor: correction.tensor,
            momentum: Vector::<D>::zeros(),
        },
        GhostCondition::NormalVelocity(_) => {
            // keep only the shear (nt) part of the stress correction
            let s = correction.tensor;
            let sn = s * n;
            let nt = sn - n * n.dot(&sn);
            Conserved {
                tensor: nt * n.transpose() + n * nt.transpose(),
                momentum: n * n.dot(&correction.momentum),
            }
        }
        GhostCondition::Velocity(_) => Conserved {
            tensor: impact_core::Tensor::<D>::zeros(),
            momentum: correction.momentum,
        },
        GhostCondition::PartialVelocity { .. } => unreachable!("internal: split above"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::riemann::{linear_elastic_star, Impedances};
    use approx::assert_relative_eq;
    use impact_core::Tensor;

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
        // a bonded impactor: the whole star velocity is the impactor's, and the star
        // traction is the interior's plus the impedance times the velocity jump
        let v_d = Vector::<2>::new(5.0, 0.0);
        let g = ghost_state(&inner, &n, GhostCondition::Velocity(v_d));
        let s = linear_elastic_star(&inner, &g, &n, z);
        assert_relative_eq!(s.velocity, v_d, epsilon = 1e-12);
        // outward n = -e_x: waves enter the interior to the right; t* = t_i + Z (v* - v_i)
        let dv = v_d - inner.velocity;
        let expected = inner.traction + Vector::<2>::new(z.p * dv[0], z.s * dv[1]);
        assert_relative_eq!(s.traction, expected, epsilon = 1e-12);
    }

    /// The full ghost state's traction on the face is the face ghost state's.
    #[test]
    fn ghost_full_agrees_with_the_face_ghost() {
        let inner = FullState {
            tensor: Tensor::<2>::new(1e8, 3e7, 3e7, -2e8),
            velocity: Vector::<2>::new(2.0, -1.0),
        };
        for n in [Vector::<2>::new(-1.0, 0.0), Vector::<2>::new(0.0, 1.0)] {
            for c in [
                GhostCondition::Traction(Vector::<2>::new(5e7, 0.0)),
                GhostCondition::NormalVelocity(-5.0),
                GhostCondition::Velocity(Vector::<2>::new(-5.0, 0.0)),
            ] {
                let g = ghost_full(&inner, &n, c);
                let face = ghost_state(&inner.on_face(&n), &n, c);
                assert_relative_eq!(g.tensor * n, face.traction, max_relative = 1e-12);
                assert_relative_eq!(g.velocity, face.velocity, max_relative = 1e-12);
                assert_eq!(g.tensor, g.tensor.transpose());
                // the tangential normal stress is untouched
                let t = Vector::<2>::new(n[1], -n[0]);
                assert_relative_eq!(
                    t.dot(&(g.tensor * t)),
                    t.dot(&(inner.tensor * t)),
                    max_relative = 1e-12
                );
            }
        }
    }
}

//! APIC, the affine particle-in-cell transfer (Jiang, Schroeder, Selle, Teran & Stomakhin
//! 2015, "The affine particle-in-cell method", ACM TOG 34(4); Jiang, Schroeder & Teran
//! 2017, "An angular momentum conserving affine-particle-in-cell method", JCP 338):
//! each point carries, besides `v_p`, an affine velocity `C_p = B_p D_p⁻¹` (a `D×D`
//! matrix per point, [`crate::MpmState::affine`], struct of arrays).
//!
//! - Particles to grid (phase 1 and the MUSL remap, `transfer.rs`):
//!   `m_i v_i = Σ_p w_ip m_p (v_p + C_p (x_i − x_p))`.
//! - Grid to particles (phase 3, here): `v_p = Σ_i w_ip v_i`,
//!   `B_p = Σ_i w_ip v_i (x_i − x_p)ᵀ`, `C_p = B_p D_p⁻¹` with the inertia-like tensor
//!   `D_p = Σ_i w_ip (x_i − x_p)(x_i − x_p)ᵀ` of the weights, and `x_p += Δt v_p`.
//!
//! `D_p` by shape function (tensor products: `D_p` is diagonal, as `Σ_i w_ip (x_i − x_p) = 0`):
//! - quadratic B-spline: `D_p = h²/4` per axis, cubic: `h²/3` (Jiang et al. 2015);
//! - uniform GIMP: not constant; its own sum `D_aa = Σ_i w_ip (x_i − x_p)_a²` per point
//!   (Jiang et al.'s general definition; positive: GIMP gives every
//!   node of its 3-node stencil weight, so it is never singular);
//! - multilinear hats: `D_aa = ξ_a (1 − ξ_a) h_a²` (`ξ` the point's place in its cell),
//!   singular on a node, but per node and axis `w_ip (x_i − x_p)_a / D_aa = ∂_a w_ip`, so
//!   `C_p = Σ_i v_i ∇w_ipᵀ` (the velocity gradient, as Jiang et al. take it for multilinear
//!   weights) — finite everywhere;
//! - CPDI is refused (`Problem::check_config`): its domain-averaged weights are not
//!   tensor products and no affine transfer is implemented for them.
//!
//! `x_i − x_p` is taken from the weights themselves, `x_i − x_base − Σ_j w_jp (x_j − x_base)`
//! (linear completeness), so `Σ_i w_ip (x_i − x_p) = 0` holds to round-off. In the total
//! Lagrangian frame the grid is the reference configuration: `x` is `X`, `C_p = ∂v/∂X`.
//!
//! What is conserved (Jiang et al. 2015 and 2017; tested in `tests/transfers.rs`): linear
//! momentum `Σ_p m_p v_p` through both transfers, and, with `D_p` the same in the scatter
//! and the gather (B-splines; any shape in the total Lagrangian frame, where `D_p` does not
//! change), the angular momentum `L = Σ_p m_p (x_p × v_p + ε : (C_p D_p)ᵀ)` (in 2D the
//! scalar `Σ_p m_p (x_p × v_p + B_p,yx − B_p,xy)`): the scatter gives the grid
//! `Σ_i x_i × m_i v_i = L`, torque-free forces (a symmetric stress: `Σ_i x_i ⊗ ∇w_ip = I`)
//! leave it, and the gather with `x_p ← x_p + Δt v_p` gives it back, to round-off. With
//! hats or GIMP in the updated Lagrangian frame `D_p` moves with the point, so `L` is
//! conserved by each transfer but not exactly over a step.
use crate::transfer::CHUNK;
use crate::MpmSolver;
use impact_core::method::{MpmFrame, MpmShape};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};

impl<const D: usize> MpmSolver<D> {
    /// APIC's gather (module doc): `v_p`, `C_p` and `x_p`, and with `STRESS` phase 5 (small
    /// strain, as [`MpmSolver::grid_to_particles_and_stress`]). No allocation.
    pub(crate) fn gather_affine<const STRESS: bool>(
        &self,
        points: &mut MaterialPoints<D>,
        affine: &mut [Tensor<D>],
        dt: f64,
    ) {
        let stencil_nodes = self.stencil.nodes;
        let steps = &self.stencil.steps;
        let nodes = &self.nodes;
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        let spacing = self.grid.spacing;
        // `D_p⁻¹` per axis where it is constant (B-splines), `None` otherwise
        let constant = match self.stencil.shape {
            MpmShape::Bspline2 => Some(spacing.map(|h| 4.0 / (h * h))),
            MpmShape::Bspline3 => Some(spacing.map(|h| 3.0 / (h * h))),
            _ => None,
        };
        let hats = self.stencil.shape == MpmShape::Linear;
        let parts = (
            (
                chunks(&mut points.velocity, CHUNK),
                chunks(&mut points.position, CHUNK),
                chunks(affine, CHUNK),
            ),
            (
                chunks(&mut points.stress, CHUNK),
                chunks(&mut points.volume, CHUNK),
            ),
        );
        for_each_chunk(
            self.parallel,
            1,
            parts,
            |r, ((velocity, position, affine), (stress, volume))| {
                for j in 0..velocity.len() {
                    let p = r * CHUNK + j;
                    let base = self.point_base[p];
                    let row = self.weight_row_start(p);
                    // the point relative to its base node (linear completeness)
                    let mut centre = Vector::<D>::zeros();
                    for a in 0..stencil_nodes {
                        centre += steps[a] * self.shape[row + a];
                    }
                    let mut v = Vector::<D>::zeros();
                    let mut b = Tensor::<D>::zeros();
                    let mut inertia = Vector::<D>::zeros();
                    let mut l = Tensor::<D>::zeros();
                    for a in 0..stencil_nodes {
                        let i = base + self.stencil.offsets[a];
                        let s = self.shape[row + a];
                        let node_velocity = nodes.velocity[i];
                        v += node_velocity * s;
                        if STRESS || hats {
                            l += node_velocity * self.shape_gradient[row + a].transpose();
                        }
                        if !hats {
                            let d = steps[a] - centre;
                            b += node_velocity * (d * s).transpose();
                            if constant.is_none() {
                                inertia += d.component_mul(&d) * s;
                            }
                        }
                    }
                    velocity[j] = v;
                    position[j] += v * dt;
                    affine[j] = if hats {
                        l
                    } else {
                        let inverse = constant.unwrap_or_else(|| inertia.map(|x| 1.0 / x));
                        b * Tensor::<D>::from_diagonal(&inverse)
                    };
                    if STRESS {
                        stress[j] += self.material.stress(&((l + l.transpose()) * 0.5)) * dt;
                        if moving {
                            volume[j] *= 1.0 + dt * l.trace();
                        }
                    }
                }
            },
        );
    }
}

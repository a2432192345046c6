//! Heun's second stage at one point per cell on the fused nodal sweep, reduced to a cell
//! update (1D and 2D, one source for both).
//!
//! With one point per cell, every `S_i = S_i(X_p) > 0` (the point strictly inside its
//! cell) and `M_i = S_i m_p`, the second stage's phases 3-5,
//! `q_p ← Σ_i S_i [a q_p + (1 - a)(q¹_i + Δt q̇¹_i)]` (`a = ½`, `q¹_i` the first stage's
//! nodal fields, `q̇¹_i` the rates at them), need no nodal rate:
//!
//! - `Σ_i S_i q̇¹_i = (ρ/m_p) Σ_i [C : sym(-V_p v_h ⊗ ∇S_i) + Σ_f ∫_f S_i sym(v* ⊗ n)]`:
//!   the volume terms sum to zero because `Σ_i ∇S_i = 0`, and each face's flux reaches its
//!   `2^{D-1}` nodes with weight `|Γ_f| 2/2^D`, so
//!   `Σ_i S_i q̇¹_i = -(ρV/m_p) Σ_l (F_l,high - F_l,low)/Δx_l` (momentum part without `ρ`),
//!   the cell path's update ([`crate::cell_path`]) with the second stage's final fluxes;
//! - `Σ_i S_i = 1`, so `q_p ← q_p + (1 - a)(Σ_i S_i (q¹_i - q_p) + Δt Σ_i S_i q̇¹_i)`.
//!
//! The face fluxes of the stage are unchanged (the averages of each side's face nodes
//! `q¹_i`, paper §4, and their CTU corrections); only the rates of the `2^D` nodes (the
//! volume term's interpolation at the point and the `2^D` divisions by `M_i`) and the
//! nodal update are gone. The increment update (`PointUpdate::Increment`) gives the same
//! formula at one point per cell (`Σ_i S_i (q_i - q_p)` with `Σ_i S_i = 1`), so both take
//! it. The sums are associated differently from the phase-by-phase path
//! ([`crate::StepPath::SinglePoint`]): `Σ_i ∇S_i` and `Σ_i S_i - 1` are zero only to
//! round-off, so the two agree to round-off (`tests/fused.rs`, 1e-13), not bit for bit.
use super::nodal::{NodalIn, NodalOut};
use super::UpdateConstants;
use crate::riemann::Conserved;
use crate::DgmpmSolver;
use impact_core::{Grid, Tensor, Vector};

impl<const D: usize> DgmpmSolver<D> {
    /// Whether Heun's second stage takes the cell update ([`self`](self) module doc): one
    /// point per cell, every point strictly inside its cell.
    pub(super) fn heun_on_cells(&self) -> bool {
        self.fused_nodal_single() && self.inside
    }

    /// Heun's second stage for cell `cell` (entry `local` of its band's points) from its
    /// faces' final fluxes `[low, high]` per axis, `start_weight` being `a`:
    /// `q_p ← q_p + (1 - a)(Σ_i S_i (q¹_i - q_p) - Δt (ρV/m_p) Σ_l (F_l,high - F_l,low)/Δx_l)`
    /// (velocity: `V/m_p`, no `ρ`), and the move `x ← x + Δt v`. Reads the point's state
    /// before writing it.
    #[inline(always)]
    pub(super) fn heun_cell_update(
        &self,
        u: &UpdateConstants<D>,
        (cell, local): (usize, usize),
        faces: [[&Conserved<D>; 2]; D],
        inputs: NodalIn<'_, D>,
        start_weight: f64,
        out: &mut NodalOut<'_, D>,
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let range = cell * nodes_per_cell..(cell + 1) * nodes_per_cell;
        let (tensor, velocity, position) = match out {
            NodalOut::Points {
                tensor,
                velocity,
                position,
            } => (tensor, velocity, position),
            NodalOut::Nodes { .. } => {
                unreachable!("internal: Heun's second stage writes the points")
            }
        };
        let (q0, v0) = (tensor[local], velocity[local]);
        let (nq, nv) = inputs.nodes(range.clone());
        let s = &self.shape[range];
        // Σ_i S_i (q¹_i - q_p): the first stage's increment at the point
        let mut dq = Tensor::<D>::zeros();
        let mut dv = Vector::<D>::zeros();
        for a in 0..nodes_per_cell {
            dq += (nq[a] - q0) * s[a];
            dv += (nv[a] - v0) * s[a];
        }
        // -Σ_l (F_l,high - F_l,low)/Δx_l
        let mut fq = Tensor::<D>::zeros();
        let mut fm = Vector::<D>::zeros();
        for (l, [low, high]) in faces.iter().enumerate() {
            fq -= (high.tensor - low.tensor) * u.inv_spacing[l];
            fm -= (high.momentum - low.momentum) * u.inv_spacing[l];
        }
        let inv_mass = 1.0 / inputs.point_mass(cell);
        let weight = 1.0 - start_weight;
        tensor[local] = q0 + (dq + fq * (u.tensor_scale * inv_mass)) * weight;
        velocity[local] = v0 + (dv + fm * (u.velocity_scale * inv_mass)) * weight;
        position[local] += velocity[local] * u.dt;
    }
}

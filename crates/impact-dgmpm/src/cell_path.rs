//! The cell path: with one point per cell and forward Euler, phases 3-5 reduce exactly to
//! the cell-centred Godunov update (derivation on [`DgmpmSolver::cell_update`]).
use crate::{DgmpmSolver, Physics, CHUNK};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};

impl<const D: usize> DgmpmSolver<D> {
    /// Cell path, phases 3-5 in one (one point per cell, forward Euler): the point update
    /// `q_p ← q_p + Δt Σ_i S_i(X_p) q̇_i` of phases 3-5 with `M_i = S_i m_p` and
    /// `q_i = q_p` on every node reduces exactly to the cell-centred Godunov update
    /// `q_p ← q_p - Δt (ρ V/m_p) Σ_l (F_l(high) - F_l(low))/Δx_l` (momentum part divided
    /// by `ρ`): `Σ_i S_i q̇_i = (ρ/m_p) Σ_i (…)_i`, the volume terms cancel because
    /// `Σ_i ∇S_i = 0`, and each face flux reaches its `2^{D-1}` nodes with weight
    /// `|Γ_f| 2/2^D`. Tested equal to phases 1-5 to round-off.
    pub fn cell_update(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let grid = &self.grid;
        let face_flux = &self.face_flux;
        let (density, volume) = (self.material.density, grid.cell_volume());
        let (tensor_scale, velocity_scale) = (dt * density * volume, dt * volume);
        let MaterialPoints {
            stress,
            deformation,
            velocity,
            mass,
            ..
        } = points;
        let target = match self.physics {
            Physics::Linear => stress,
            Physics::Svk { .. } => deformation,
        };
        // stride along l of the l-face array: the high face of a cell is this far on
        let high_offset: [usize; D] = std::array::from_fn(|l| grid.cells[..l].iter().product());
        let kernel = |c: usize, idx: [usize; D], q: &mut Tensor<D>, v: &mut Vector<D>| {
            let mut dq = Tensor::<D>::zeros();
            let mut dm = Vector::<D>::zeros();
            for l in 0..D {
                let lo = Self::face_index(grid, l, idx);
                let hi = lo + high_offset[l];
                let (a, b) = (face_flux[l][lo], face_flux[l][hi]);
                let inv = 1.0 / grid.spacing[l];
                dq -= (b.tensor - a.tensor) * inv;
                dm -= (b.momentum - a.momentum) * inv;
            }
            // Δt ρ V/m and, for the velocity (momentum / ρ), Δt V/m: one division
            let inv_mass = 1.0 / mass[c];
            *q += dq * (tensor_scale * inv_mass);
            *v += dm * (velocity_scale * inv_mass);
        };
        for_each_chunk(
            self.parallel,
            1,
            (chunks(target, CHUNK), chunks(velocity, CHUNK)),
            |r, (q, v)| {
                let start = r * CHUNK;
                let mut idx = Self::multi_index(grid.cells, start);
                for (j, (q, v)) in q.iter_mut().zip(v.iter_mut()).enumerate() {
                    kernel(start + j, idx, q, v);
                    Self::advance(&mut idx, &grid.cells);
                }
            },
        );
        self.piola_at_points(points);
    }
}

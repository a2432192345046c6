//! The fused path in 1D (the bar): each chunk of cells solves its low face, then per cell
//! its high face and the update.
use super::{Next, CHUNK};
use crate::riemann::axis::{axis_flux_1d, AxisConstants};
use crate::riemann::FullState;
use crate::DgmpmSolver;
use impact_core::points::MaterialPoints;
use impact_core::Vector;

impl DgmpmSolver<1> {
    /// The 1D sweep: each chunk of cells solves its low face, then per cell its high face
    /// and the update.
    pub(super) fn sweep_1d(&mut self, points: &mut MaterialPoints<1>, dt: f64) -> (f64, Vector<1>) {
        let constants = AxisConstants::new(&self.elastic);
        let count = self.grid.cells[0];
        let u = self.update_constants(dt);
        self.sweep_bands(
            points,
            CHUNK,
            |this, b, band, fields, inverse_mass, next| {
                let start = b * CHUNK;
                let len = next.tensor.len();
                band.power = 0.0;
                band.force = Vector::<1>::zeros();
                // the chunk's low face is counted by the chunk below it (or here at i = 0)
                let mut low = match start {
                    0 => this.boundary_flux(0, [0], fields, band),
                    _ => axis_flux_1d(&fields.cell(start - 1), &fields.cell(start), &constants),
                };
                // cells whose high face is interior: all but the bar's last
                let interior = if start + len == count { len - 1 } else { len };
                // slices of equal, known lengths: the loop indexes them without bounds checks
                let (tensor, velocity) = fields.slices();
                let (q, v) = (&tensor[start..start + len], &velocity[start..start + len]);
                let (q_right, v_right) = (
                    &tensor[start + 1..start + 1 + interior],
                    &velocity[start + 1..start + 1 + interior],
                );
                let inverse_mass = &inverse_mass[start..start + len];
                let Next {
                    tensor: next_q,
                    velocity: next_v,
                    position,
                } = next;
                let (next_q, next_v, position) =
                    (&mut next_q[..len], &mut next_v[..len], &mut position[..len]);
                let mut state = fields.cell(start);
                for j in 0..interior {
                    let right = FullState {
                        tensor: q_right[j],
                        velocity: v_right[j],
                    };
                    let high = axis_flux_1d(&state, &right, &constants);
                    let old = (&q[j], &v[j], inverse_mass[j]);
                    let out = (&mut next_q[j], &mut next_v[j], &mut position[j]);
                    Self::update_cell(&u, [[&low, &high]], old, out);
                    (low, state) = (high, right);
                }
                if interior < len {
                    // the bar's last cell: its high face is the boundary
                    let j = interior;
                    let high = this.boundary_flux(0, [count], fields, band);
                    let out = (&mut next_q[j], &mut next_v[j], &mut position[j]);
                    Self::update_cell(&u, [[&low, &high]], (&q[j], &v[j], inverse_mass[j]), out);
                }
            },
        )
    }
}

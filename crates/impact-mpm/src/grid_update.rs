//! Phase 2: the grid update `p_i += Δt f_i` and the prescribed nodal velocities.
use crate::MpmSolver;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::Vector;

/// Nodes per chunk of the node loops.
const CHUNK: usize = 4096;

impl<const D: usize> MpmSolver<D> {
    /// Phase 2: `p_i += Δt f_i` (nodes with mass), then the prescribed nodal velocities.
    /// Returns the work done in the step by the velocity constraints, `Δt Σ r · v_d`, and
    /// the impulse of the reaction forces, `Δt Σ r`.
    pub fn grid_update(&mut self, dt: f64) -> (f64, Vector<D>) {
        let nodes = &mut self.nodes;
        let floor = self.empty_mass;
        let (mass, force) = (&nodes.mass, &nodes.force);
        for_each_chunk(
            self.parallel,
            1,
            chunks(&mut nodes.momentum, CHUNK),
            |r, momentum| {
                for (j, p) in momentum.iter_mut().enumerate() {
                    let i = r * CHUNK + j;
                    if mass[i] > floor {
                        *p += force[i] * dt;
                    }
                }
            },
        );
        let mut work = 0.0;
        let mut impulse = Vector::<D>::zeros();
        for &(v, axis, value) in &self.node_constraints {
            let m = nodes.mass[v];
            if m > floor {
                let old = nodes.momentum[v][axis];
                nodes.momentum[v][axis] = value * m;
                // reaction force of the constraint, kept in the force for the FLIP update
                let reaction = (value * m - old) / dt;
                nodes.force[v][axis] += reaction;
                work += dt * reaction * value;
                impulse[axis] += dt * reaction;
            }
        }
        (work, impulse)
    }

    /// The prescribed nodal velocities on the momentum (after the MUSL remap).
    pub(crate) fn constrain_momentum(&mut self) {
        let (nodes, floor) = (&mut self.nodes, self.empty_mass);
        for &(v, axis, value) in &self.node_constraints {
            if nodes.mass[v] > floor {
                nodes.momentum[v][axis] = value * nodes.mass[v];
            }
        }
    }
}

//! The surface loads' nodal forces and power and the prescribed point velocities: the
//! edge conditions' share of a step (`edges.rs` finds them).
use crate::{MpmSolver, MAX_NODES};
use impact_core::method::MpmFrame;
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Vector};

impl<const D: usize> MpmSolver<D> {
    /// External surface loads as nodal forces at the current surface positions, at their
    /// step average over `window` (`impact_core::load`): a load is spread over the nodes of
    /// its cell that carry mass (renormalised shape functions), so the whole force reaches
    /// the body.
    pub(crate) fn external_forces(&mut self, points: &MaterialPoints<D>, window: (f64, f64)) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut s = [0.0; MAX_NODES];
        let mut g = [Vector::<D>::zeros(); MAX_NODES];
        'loads: for load in &self.loads {
            let x = match self.options.frame {
                MpmFrame::TotalLagrangian => points.reference[load.point],
                MpmFrame::UpdatedLagrangian => points.position[load.point],
            } + load.offset;
            // on the whole grid, shifted to this one's nodes (`crate::Place`)
            let whole = &self.place.whole;
            let Some((c, xi)) = whole.locate(&x) else {
                continue;
            };
            whole.shape(&xi, &mut s[..npc], &mut g[..npc]);
            // this solver's numbers of the cell's nodes (all stored for a stored point's
            // cell, `crate::build`; a cell reaching past them carries no load here)
            let mut node = [0usize; MAX_NODES];
            for (a, n) in node[..npc].iter_mut().enumerate() {
                match self.place.local_node(whole.vertex_of(c, a)) {
                    Some(v) => *n = v,
                    None => continue 'loads,
                }
            }
            let with_mass = |a: usize| self.empty.holds(node[a], self.nodes.mass[node[a]]);
            let total: f64 = (0..npc).filter(|&a| with_mass(a)).map(|a| s[a]).sum();
            if total <= 0.0 {
                continue;
            }
            let force = load.force * load.history.mean(window.0, window.1);
            for a in 0..npc {
                let i = node[a];
                if self.empty.holds(i, self.nodes.mass[i]) {
                    self.nodes.force[i] += force * (s[a] / total);
                }
            }
        }
    }

    /// Power of the surface loads over the step `window`, `Σ F ḡ · v_p` with `ḡ` the step
    /// average of `g` and `v_p` the velocity of the loaded point (own points only).
    pub(crate) fn load_power(&self, points: &MaterialPoints<D>, window: (f64, f64)) -> f64 {
        self.loads
            .iter()
            .filter(|l| self.place.owns(l.point))
            .map(|l| l.history.mean(window.0, window.1) * l.force.dot(&points.velocity[l.point]))
            .sum()
    }

    /// Points on a velocity edge take the prescribed velocity (as the paper does), its
    /// average over the step `window` (its value at `t0` for an empty window, the state at
    /// `t = 0`). Returns the impulse this gives them, `Σ m_p Δv_p` (over the own points:
    /// a slab's halo points are its neighbours').
    pub(crate) fn impose_point_velocities(
        &self,
        points: &mut MaterialPoints<D>,
        window: (f64, f64),
    ) -> Vector<D> {
        let mut kick = Vector::<D>::zeros();
        for c in &self.point_constraints {
            let (p, axis, value) = (c.carrier, c.axis, c.mean(window));
            if self.place.owns(p) {
                kick[axis] += points.mass[p] * (value - points.velocity[p][axis]);
            }
            points.velocity[p][axis] = value;
        }
        kick
    }
}

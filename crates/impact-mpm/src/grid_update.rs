//! Phase 2: the grid update `p_i += Δt f_i` and the prescribed nodal velocities.
use crate::MpmSolver;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::Vector;

/// Nodes per chunk of the node loops.
const CHUNK: usize = 4096;

impl<const D: usize> MpmSolver<D> {
    /// Phase 2: `p_i += Δt f_i` and `1/m_i` (nodes with mass; 0 for empty ones), then the
    /// prescribed nodal velocities, their averages over the step `window` (the velocity
    /// that moves the points over it: the displacement of the loaded face is exact), and
    /// the nodal velocity `v_i = p_i (1/m_i)` and velocity increment
    /// `Δv_i = f_i (Δt (1/m_i))` the gathers read (formed once per node, after the
    /// constraints: on every node in the pass, again on each constrained node).
    /// Returns the work done in the step by the velocity constraints, `Δt Σ r · v_d`, and
    /// the impulse of the reaction forces, `Δt Σ r` (over the own nodes).
    pub fn grid_update(&mut self, dt: f64, window: (f64, f64)) -> (f64, Vector<D>) {
        self.fold_padding(window, true);
        let nodes = &mut self.nodes;
        let empty = &self.empty;
        let (mass, force) = (&nodes.mass, &nodes.force);
        let parts = (
            chunks(&mut nodes.momentum, CHUNK),
            chunks(&mut nodes.increment, CHUNK),
            chunks(&mut nodes.velocity, CHUNK),
        );
        nodes.increment_dt = dt;
        for_each_chunk(
            self.parallel,
            1,
            parts,
            |r, (momentum, increment, velocity)| {
                // the chunk's nodes sliced once (no bounds check per node)
                let chunk = r * CHUNK..r * CHUNK + momentum.len();
                let (mass, force) = (&mass[chunk.clone()], &force[chunk.clone()]);
                let walls = empty.walls_of(chunk);
                let nodes = mass.iter().zip(force).zip(walls);
                let sums = momentum.iter_mut().zip(increment).zip(velocity);
                for (((p, dv), v), ((&m, f), &w)) in sums.zip(nodes) {
                    let inv = if empty.holds_on(w, m) {
                        *p += f * dt;
                        1.0 / m
                    } else {
                        0.0
                    };
                    (*v, *dv) = velocity_and_increment(p, f, inv, dt);
                }
            },
        );
        let mut work = 0.0;
        let mut impulse = Vector::<D>::zeros();
        // a slab counts its own nodes' reactions (`crate::Place`)
        let place = &self.place;
        let mut hold = |nodes: &mut crate::NodeSums<D>, v: usize, axis: usize, value: f64| {
            let m = nodes.mass[v];
            if empty.holds(v, m) {
                let old = nodes.momentum[v][axis];
                nodes.momentum[v][axis] = value * m;
                // reaction force of the constraint, kept in the force for the FLIP update
                let reaction = (value * m - old) / dt;
                nodes.force[v][axis] += reaction;
                // `1/m_i` as the node pass formed it (the node holds mass)
                let (momentum, force) = (&nodes.momentum[v], &nodes.force[v]);
                (nodes.velocity[v], nodes.increment[v]) =
                    velocity_and_increment(momentum, force, 1.0 / m, dt);
                if place.owns_node(v) {
                    work += dt * reaction * value;
                    impulse[axis] += dt * reaction;
                }
            }
        };
        for c in &self.node_constraints {
            hold(nodes, c.carrier, c.axis, c.mean(window));
        }
        // the padding from the interior it mirrors (never itself constrained)
        for c in &self.mirror_constraints {
            let value = c.offset(window) + c.sign * velocity_of(nodes, c.mirror, c.axis, empty);
            hold(nodes, c.node, c.axis, value);
        }
        (work, impulse)
    }

    /// Fold the sums of the padding nodes beyond velocity and symmetry edges onto the
    /// interior nodes they mirror (`edges` module doc): what the real points give node
    /// `-j` is what their mirror images would give node `+j`, so node `+j` gains the mass,
    /// and the momentum and force reflected like the velocity (odd normal component about
    /// the wall's velocity `V`: `p_n += 2 V m - p_n`; even or odd tangential ones). Near
    /// the wall the interior nodes then hold the full sums of a body mirrored across it.
    /// The mass and the momentum, and with `force` the force (phase 2; the MUSL remap
    /// maps and folds the mass and the momentum again: a padding node that mirrors another
    /// one, at a corner of two walls, holds folded mass after phase 2).
    pub(crate) fn fold_padding(&mut self, window: (f64, f64), force: bool) {
        let (nodes, empty) = (&mut self.nodes, &self.empty);
        for c in &self.mirror_constraints {
            let (from, to, axis) = (c.node, c.mirror, c.axis);
            let mass = nodes.mass[from];
            if axis == 0 {
                nodes.mass[to] += mass;
            }
            nodes.momentum[to][axis] +=
                c.offset(window) * mass + c.sign * nodes.momentum[from][axis];
            if force {
                nodes.force[to][axis] += c.sign * nodes.force[from][axis];
            }
        }
        // the padding then starts from the mirror of the folded interior, so its update is
        // the mirror of the interior's (no kick to the points near the wall when the
        // constraints set it after the update)
        for c in &self.mirror_constraints {
            let (from, to, axis) = (c.node, c.mirror, c.axis);
            let (m, m_to) = (nodes.mass[from], nodes.mass[to]);
            if empty.holds(from, m) && empty.holds(to, m_to) {
                let velocity = c.offset(window) + c.sign * nodes.momentum[to][axis] / m_to;
                nodes.momentum[from][axis] = velocity * m;
                if force {
                    nodes.force[from][axis] = c.sign * nodes.force[to][axis] * (m / m_to);
                }
            }
        }
    }

    /// The prescribed nodal velocities (step averages over `window`) on the momentum
    /// (after the MUSL remap).
    pub(crate) fn constrain_momentum(&mut self, window: (f64, f64)) {
        let (nodes, empty) = (&mut self.nodes, &self.empty);
        for c in &self.mirror_constraints {
            let value = c.offset(window) + c.sign * velocity_of(nodes, c.mirror, c.axis, empty);
            if empty.holds(c.node, nodes.mass[c.node]) {
                nodes.momentum[c.node][c.axis] = value * nodes.mass[c.node];
            }
        }
        for c in &self.node_constraints {
            let (v, axis, value) = (c.carrier, c.axis, c.mean(window));
            if empty.holds(v, nodes.mass[v]) {
                nodes.momentum[v][axis] = value * nodes.mass[v];
            }
        }
    }
}

/// Velocity component `p_i/m_i` of node `i` (0 for an empty node).
#[inline]
fn velocity_of<const D: usize>(
    nodes: &crate::NodeSums<D>,
    i: usize,
    axis: usize,
    empty: &crate::EmptyNodes,
) -> f64 {
    if empty.holds(i, nodes.mass[i]) {
        nodes.momentum[i][axis] / nodes.mass[i]
    } else {
        0.0
    }
}

/// A node's velocity `v_i = p_i (1/m_i)` and velocity increment `Δv_i = f_i (Δt (1/m_i))`
/// from its momentum, force and `1/m_i` (0 for an empty node): what the gathers read, formed
/// alike in the node pass and on each constrained node.
#[inline(always)]
fn velocity_and_increment<const D: usize>(
    momentum: &Vector<D>,
    force: &Vector<D>,
    inv_mass: f64,
    dt: f64,
) -> (Vector<D>, Vector<D>) {
    (momentum * inv_mass, force * (dt * inv_mass))
}

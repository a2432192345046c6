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
    /// the impulse of the reaction forces, `Δt Σ r` (over the own nodes), with the wall's
    /// share of the nodes the padding fold changed (`FoldChange`).
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
        for change in &self.fold_changes {
            let (v, axis) = (change.node, change.axis);
            // (an unchanged node, e.g. beyond hats' reach, adds nothing)
            let changed = change.mass != 0.0 || change.force != 0.0;
            if changed && empty.holds(v, nodes.mass[v]) {
                let share = change.wall_impulse(nodes.increment[v][axis], dt);
                impulse[axis] += share;
                work += share * nodes.velocity[v][axis];
            }
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
    /// With `force`, the changes it makes are kept ([`FoldChange`]).
    pub(crate) fn fold_padding(&mut self, window: (f64, f64), force: bool) {
        let (nodes, empty) = (&mut self.nodes, &self.empty);
        if force {
            for change in &mut self.fold_changes {
                (change.mass, change.force) = (
                    nodes.mass[change.node],
                    nodes.force[change.node][change.axis],
                );
            }
        }
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
        if force {
            for change in &mut self.fold_changes {
                change.mass = nodes.mass[change.node] - change.mass;
                change.force = nodes.force[change.node][change.axis] - change.force;
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

/// What the padding fold changed on one component of a node next to a velocity or symmetry
/// edge (a padding node or the interior node it mirrors): `Δm_i` and `Δf_i`, the mass and
/// force of the mirrored body, which are the wall's.
///
/// The wall's impulse on the body at node `i` is `J_i = m_i^r Δv_i - Δt f_i^r`, with the
/// real points' mass and force `m_i^r`, `f_i^r` (before the fold; the body's momentum
/// changes by `Σ_i m_i^r Δv_i` in FLIP, and `Σ_i f_i^r = 0`). A node's constraint counts
/// `r Δt = m_i Δv_i - Δt f_i` with the folded sums (0 on a node no constraint holds), so
/// the rest is [`Self::wall_impulse`], `Δt Δf_i - Δm_i Δv_i`, and its work
/// `J_i · v_i` (new velocities). On a padding pair `(-j, +j)` the pair's work is then
/// `2 V̄ J_(-j)` on the odd (normal) component and 0 on an even one: the mirror forces do
/// work only through the wall's motion. Without it a smooth stencil counted the wall's
/// layer alone: `N_0(0)/(N_0(0) + 2 N_pad(0))` of the work and impulse, 3/4 with
/// quadratic B-splines (`tests/bar_ends.rs`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FoldChange {
    /// The node.
    pub node: usize,
    /// Its component.
    pub axis: usize,
    /// `Δm_i` (during the fold: the mass before it).
    pub mass: f64,
    /// `Δf_i` (during the fold: the force before it).
    pub force: f64,
}

impl FoldChange {
    /// Every component the fold changes, once: the padding nodes and the nodes they mirror
    /// that this solver owns (`crate::Place`: a slab counts its own nodes).
    pub(crate) fn of<const D: usize>(
        mirrors: &[crate::edges::MirrorConstraint],
        place: &crate::build::Place<D>,
    ) -> Vec<Self> {
        let mut touched: Vec<(usize, usize)> = mirrors
            .iter()
            .flat_map(|c| [(c.node, c.axis), (c.mirror, c.axis)])
            .filter(|&(node, _)| place.owns_node(node))
            .collect();
        touched.sort_unstable();
        touched.dedup();
        touched
            .into_iter()
            .map(|(node, axis)| Self {
                node,
                axis,
                mass: 0.0,
                force: 0.0,
            })
            .collect()
    }

    /// The wall's impulse at the node beyond what its constraint counted,
    /// `Δt Δf_i - Δm_i Δv_i`, with the node's velocity increment `Δv_i` over `Δt`.
    #[inline]
    pub(crate) fn wall_impulse(&self, increment: f64, dt: f64) -> f64 {
        dt * self.force - self.mass * increment
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

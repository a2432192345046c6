//! The surface loads' nodal forces and power and the prescribed point velocities: the
//! edge conditions' share of a step (`edges.rs` finds them).
use crate::{MpmSolver, MAX_NODES};
use impact_core::method::MpmFrame;
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Vector};

impl<const D: usize> MpmSolver<D> {
    /// External surface loads as nodal forces at the current surface positions, at their
    /// step average over `window` (`impact_core::load`): a load is spread over the nodes of
    /// its cell that carry mass ([`Self::load_split`]), so the whole force reaches the body.
    pub(crate) fn external_forces(&mut self, points: &MaterialPoints<D>, window: (f64, f64)) {
        for k in 0..self.loads.len() {
            let load = &self.loads[k];
            let mut split = self.load_split(points, load).unwrap_or_default();
            split.point_velocity = points.velocity[load.point];
            let force = load.force * load.history.mean(window.0, window.1);
            for (&i, &share) in split.node[..split.count].iter().zip(&split.share) {
                self.nodes.force[i] += force * share;
            }
            // kept for the load's power after the grid update
            self.load_splits[k] = split;
        }
    }

    /// The nodes a surface load acts on and their shares: the nodes of the cell holding
    /// the surface point (its position in the step's frame plus the load's offset) that
    /// carry mass, with the cell's hat functions renormalised over them, `N_a / Σ N_b`
    /// ([`LoadSplit`]; `None` where no node of the cell carries mass or the cell reaches
    /// past this solver's nodes, `crate::Place`).
    #[inline]
    fn load_split(
        &self,
        points: &MaterialPoints<D>,
        load: &crate::edges::SurfaceLoad<D>,
    ) -> Option<LoadSplit<D>> {
        let npc = Grid::<D>::NODES_PER_CELL;
        let mut s = [0.0; MAX_NODES];
        let mut g = [Vector::<D>::zeros(); MAX_NODES];
        let x = match self.options.frame {
            MpmFrame::TotalLagrangian => points.reference[load.point],
            MpmFrame::UpdatedLagrangian => points.position[load.point],
        } + load.offset;
        // on the whole grid, shifted to this one's nodes (`crate::Place`)
        let whole = &self.place.whole;
        let (c, xi) = whole.locate(&x)?;
        whole.shape(&xi, &mut s[..npc], &mut g[..npc]);
        let mut node = [0usize; MAX_NODES];
        let mut share = [0.0; MAX_NODES];
        let mut count = 0;
        let mut total = 0.0;
        for (a, &weight) in s[..npc].iter().enumerate() {
            let v = self.place.local_node(whole.vertex_of(c, a))?;
            if self.empty.holds(v, self.nodes.mass[v]) {
                (node[count], share[count]) = (v, weight);
                count += 1;
                total += weight;
            }
        }
        if total <= 0.0 {
            return None;
        }
        for share in &mut share[..count] {
            *share /= total;
        }
        Some(LoadSplit {
            node,
            share,
            count,
            point_velocity: Vector::<D>::zeros(),
        })
    }

    /// Power of the surface loads over the step `window` (own points' loads only), after
    /// the gather (the nodes' `v_a`, `Δv_a` and the points' new velocities are at hand).
    ///
    /// Total Lagrangian: on the nodes the load acts on, `Σ F ḡ · Σ_a (N_a / Σ N_b) v̄_a`,
    /// with `v̄_a = v_a - Δv_a / 2` the node's mean velocity over the step (after the grid
    /// update, whose momentum the force changed): the work the force does on the grid,
    /// which is what the body's energy gains. The loaded point's own velocity differs from
    /// it where the stencil reaches past the edge (B-splines on the padded grid: the energy
    /// balance read 9 % and 30 % off with quadratic and cubic ones on the bar at 4 points
    /// per cell; now -1.6 % and -2.3 %, hats' count equals the exact work to 1e-4,
    /// `tests/bar_ends.rs`).
    ///
    /// Updated Lagrangian: the loaded point's mean velocity over the step,
    /// `F ḡ · (v_p^n + v_p^{n+1}) / 2`. There the points cross cells, and a loaded node's
    /// mass falls to nothing as its point leaves its cell (hats: `m_a → 0` while its share
    /// of the force stays near ½): its `v̄_a` then swings without bound and the nodes' count
    /// lost the sign of the work (the bar under a step pressure, updated Lagrangian MUSL
    /// with hats: a count of −3.5e6 J against an exact +3.3e7 J at 1.3 ms, while the
    /// body's energy followed the exact work, `tests/convergence.rs`). Where the stencil
    /// reaches past the edge the point's velocity is off as above: on the bar at the first
    /// output, USL, quadratic B-splines at 4 points per cell count 0.93 of the exact work,
    /// cubic ones 0.80 at 4 and 1.20 at one point per cell (`tests/bar_ends.rs`, printed).
    ///
    /// What the points gain exactly is `F · ṽ_a` with `ṽ_a = Σ_p m_p N_ap v̄_p / m_a`, the
    /// points' mean velocity mapped to the node: the consistent mass `Σ_p m_p N_ap N_bp`
    /// spreads the increment where `v̄_a` keeps it lumped on the loaded node. Where the
    /// load's node holds a small share of mass next to padding nodes the two part: cubic
    /// B-splines at one point per cell overcount the bar's work by 39 % (the point's
    /// velocity undercounted it by 24 %). Forming `ṽ_a` needs the points of the loaded
    /// nodes' supports after the gather; not done.
    pub(crate) fn load_power(&self, points: &MaterialPoints<D>, window: (f64, f64)) -> f64 {
        let nodes = &self.nodes;
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        self.loads
            .iter()
            .zip(&self.load_splits)
            .filter(|(load, _)| self.place.owns(load.point))
            .map(|(load, split)| {
                let force = load.force * load.history.mean(window.0, window.1);
                let velocity = if moving {
                    (split.point_velocity + points.velocity[load.point]) * 0.5
                } else {
                    let nodes_of = split.node[..split.count].iter().zip(&split.share);
                    nodes_of.fold(Vector::<D>::zeros(), |sum, (&i, &share)| {
                        sum + (nodes.velocity[i] - nodes.increment[i] * 0.5) * share
                    })
                };
                force.dot(&velocity)
            })
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

/// The nodes a surface load acts on this step and their shares (`count` entries; none
/// where the load reaches no node with mass), and the loaded point's velocity at the
/// step's start: formed by `external_forces`, read again for the load's power.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LoadSplit<const D: usize> {
    node: [usize; MAX_NODES],
    share: [f64; MAX_NODES],
    count: usize,
    point_velocity: Vector<D>,
}

impl<const D: usize> Default for LoadSplit<D> {
    /// No node (a load that reaches no node with mass), the point at rest.
    fn default() -> Self {
        Self {
            node: [0; MAX_NODES],
            share: [0.0; MAX_NODES],
            count: 0,
            point_velocity: Vector::<D>::zeros(),
        }
    }
}

//! Edge conditions of MPM on the padded background grid: surface loads of pressure edges
//! on the points that touch them, prescribed velocities of velocity and symmetry edges on
//! the nodes (and the paper's point constraints), and the mirrored padding nodes.
//!
//! A smooth stencil (GIMP, B-splines) gives mass to padding nodes beyond a wall. Holding
//! them at the wall's velocity (as a hat's edge node is held) makes the interpolated field
//! flat over a support's width next to the wall: on the standing wave with fixed ends
//! (`smooth-bar`) quadratic B-splines then converged at first order in stress (L2 2.1e-2
//! at 1200 cells, order 0.95). Instead a padding node at distance `j` beyond the wall
//! takes the mirror image of the interior node at distance `j` inside: the normal
//! component odd about the wall's velocity, `v_n = 2 V - v_n(mirror)`, the tangential ones
//! even (`v_t = v_t(mirror)`, free slip: symmetry and frictionless impactor) or odd about 0
//! (bonded impactor), the extension of a field that is smooth across a mirror plane
//! (Steffen, Kirby & Berzins 2008 discuss the loss of accuracy at boundaries; the
//! reflection is the ghost-node treatment of finite differences, LeVeque 2002 §7.3).
//! The wall's own node layer is held at `V` as before.
use crate::build::Place;
use crate::PADDING;
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::{Constraint, Grid, Load, LoadHistory, Problem, Vector};

/// A padding node's velocity component from its mirror node:
/// `v = offset + sign · v(mirror)`, `offset = 2V` for odd components (`sign = -1`)
/// about a nonzero wall velocity `V` (its step average), 0 otherwise.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MirrorConstraint {
    /// The padding node.
    pub node: usize,
    /// The interior node it mirrors.
    pub mirror: usize,
    /// Component.
    pub axis: usize,
    /// `+1` (even) or `-1` (odd).
    pub sign: f64,
    /// `V · g(t)` about which an odd component is reflected (the offset is `2 V(t)`).
    pub wall: Constraint,
}

impl MirrorConstraint {
    /// The offset over the step `window = (t0, t1)` (the wall's step-average velocity).
    #[inline]
    pub fn offset(&self, window: (f64, f64)) -> f64 {
        if self.sign < 0.0 {
            2.0 * self.wall.mean(window)
        } else {
            0.0
        }
    }
}

/// A load acting on a surface point of the body.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SurfaceLoad<const D: usize> {
    pub point: usize,
    /// Offset from the point to the surface (reference configuration).
    pub offset: Vector<D>,
    /// Force at full magnitude (pressure × area × covered share of the point's face).
    pub force: Vector<D>,
    /// Time history `g(t)` of the load.
    pub history: LoadHistory,
}

/// A prescribed normal velocity on the nodes and points near an edge.
#[derive(Debug, Clone, Copy)]
pub(crate) struct VelocityEdge {
    axis: usize,
    /// Nodes with this index along `axis` (background-grid numbering).
    node_layer: usize,
    /// The impactor's velocity, segment and history (a zero step load on a symmetry edge).
    load: Load,
    /// Whether it is a symmetry edge (zero normal velocity, points untouched).
    symmetry: bool,
    /// Bonded impactor: the tangential velocity is prescribed (zero) too.
    bonded: bool,
}

/// The surface loads of the pressure edges (on the points whose domain touches the edge,
/// at the domain's edge midpoint, force `-p A n`) and the velocity and symmetry edges.
pub(crate) fn edge_conditions<const D: usize>(
    problem: &Problem<D>,
    points: &MaterialPoints<D>,
) -> (Vec<SurfaceLoad<D>>, Vec<VelocityEdge>) {
    let mut loads = Vec::new();
    for l in 0..D {
        for side in 0..2 {
            face_loads(problem, (l, side), points, &mut loads);
        }
    }
    (loads, velocity_edges(problem))
}

/// Appends to `loads` the surface loads of the face `(axis, side)` (0: low, 1: high) if it
/// is a pressure edge: on the points of `points` whose domain touches it, in proportion to
/// the share of their face the segment covers (`Load::coverage`), force `-p A n` at the
/// domain's edge midpoint. Only points of the face's cell layer can touch it.
pub(crate) fn face_loads<const D: usize>(
    problem: &Problem<D>,
    (l, side): (usize, usize),
    points: &MaterialPoints<D>,
    loads: &mut Vec<SurfaceLoad<D>>,
) {
    let body = &problem.grid;
    let Boundary::Pressure(load) = problem.boundaries[l][side] else {
        return;
    };
    let sign = if side == 0 { -1.0 } else { 1.0 };
    let edge = if side == 0 {
        body.origin[l]
    } else {
        body.upper()[l]
    };
    let outward = Vector::<D>::from_fn(|k, _| if k == l { sign } else { 0.0 });
    for p in 0..points.len() {
        let x = points.reference[p];
        let h = points.half_size[p];
        if ((x[l] + sign * h[l]) - edge).abs() > 1e-9 * body.spacing[l] {
            continue;
        }
        let share = load.coverage(l, &x, &h);
        if share <= 0.0 {
            continue;
        }
        let area: f64 = Grid::<D>::tangent_axes(l).map(|k| 2.0 * h[k]).product();
        let mut offset = Vector::<D>::zeros();
        offset[l] = sign * h[l];
        loads.push(SurfaceLoad {
            point: p,
            offset,
            force: outward * (-load.value * area * share),
            history: load.history,
        });
    }
}

/// The velocity and symmetry edges of `problem`, face by face (axis, then low and high).
pub(crate) fn velocity_edges<const D: usize>(problem: &Problem<D>) -> Vec<VelocityEdge> {
    let body = &problem.grid;
    let mut edges = Vec::new();
    for l in 0..D {
        for side in 0..2 {
            let sign = if side == 0 { -1.0 } else { 1.0 };
            let node_layer = PADDING + side * body.cells[l];
            match problem.boundaries[l][side] {
                Boundary::Free | Boundary::Pressure(_) => {}
                Boundary::Velocity { load, bonded } => edges.push(VelocityEdge {
                    axis: l,
                    node_layer,
                    load: Load {
                        value: -sign * load.value,
                        ..load
                    },
                    symmetry: false,
                    bonded,
                }),
                Boundary::Symmetry => edges.push(VelocityEdge {
                    axis: l,
                    node_layer,
                    load: Load::step(0.0),
                    symmetry: true,
                    bonded: false,
                }),
            }
        }
    }
    edges
}

/// The prescribed nodal velocity components of the velocity and symmetry edges on the
/// nodes `place` stores (numbered as it numbers them): every node of the edge's layer
/// inside its segment, and the mirror constraints of the padding layers beyond it (module
/// doc) whose mirror node is stored too (a padding node whose mirror is not stored is read
/// by no stored point); and per stored node the number of mirror planes (wall layers of
/// those edges) it lies on (`crate::EmptyNodes`). A nodal value is imposed or not: the
/// patch is tested at the node's position on the whole padded grid under either `cover`
/// rule, reflected into the body across the symmetry planes the node lies beyond
/// ([`unfolded`]). The stored nodes keep the whole grid's relative order, so the lists are
/// the whole grid's restricted to them, in its order.
pub(crate) fn node_constraints<const D: usize>(
    place: &Place<D>,
    edges: &[VelocityEdge],
) -> (Vec<Constraint>, Vec<MirrorConstraint>, Vec<u8>) {
    let grid = &place.whole;
    let counts = grid.vertex_counts();
    let stored: usize = place.node_counts.iter().product();
    let mut walls = Vec::new();
    let mut mirrors = Vec::new();
    let mut on_walls = vec![0u8; stored];
    for e in edges {
        let stride: usize = counts[..e.axis].iter().product();
        for local in 0..stored {
            let v = place.whole_node(local);
            let along = (0..e.axis).fold(v, |rest, k| rest / counts[k]) % counts[e.axis];
            let beyond = e.beyond(along);
            if !(along == e.node_layer || beyond) {
                continue;
            }
            let position = unfolded(grid, edges, v);
            if !e.load.acts_on(e.axis, &position) {
                continue;
            }
            let constraint = |axis: usize, value: f64| Constraint {
                carrier: local,
                axis,
                value,
                history: e.load.history,
            };
            if !beyond {
                on_walls[local] += 1;
                walls.extend(
                    e.components::<D>()
                        .map(|(axis, value)| constraint(axis, value)),
                );
                continue;
            }
            // the interior node as far inside as this one is beyond
            let mirror_along = 2 * e.node_layer - along;
            let Some(mirror) = place.local_node(v - along * stride + mirror_along * stride) else {
                continue;
            };
            for axis in 0..D {
                let odd = axis == e.axis || e.bonded;
                mirrors.push(MirrorConstraint {
                    node: local,
                    mirror,
                    axis,
                    sign: if odd { -1.0 } else { 1.0 },
                    wall: constraint(axis, if axis == e.axis { e.load.value } else { 0.0 }),
                });
            }
        }
    }
    (walls, mirrors, on_walls)
}

/// The position of node `v` reflected across every symmetry plane it lies beyond
/// (`x_k ← 2 w_k − x_k`, `w_k` the plane): a padding node beyond a symmetry face is the
/// image of an interior node, so it belongs to a patch of another face where its image
/// does (the patch's image across the plane; module doc). Otherwise a patch reaching a
/// symmetry face would lose its mirrored padding nodes there, and a block invariant along
/// z would not reduce to its 2D section.
fn unfolded<const D: usize>(grid: &Grid<D>, edges: &[VelocityEdge], v: usize) -> Vector<D> {
    let counts = grid.vertex_counts();
    let mut x = grid.vertex_position(v);
    for s in edges.iter().filter(|s| s.symmetry) {
        let along = (0..s.axis).fold(v, |rest, k| rest / counts[k]) % counts[s.axis];
        if s.beyond(along) {
            let wall = grid.origin[s.axis] + s.node_layer as f64 * grid.spacing[s.axis];
            x[s.axis] = 2.0 * wall - x[s.axis];
        }
    }
    x
}

impl VelocityEdge {
    /// The face it lies on: `(axis, side)`, side 0 the low face, 1 the high one.
    pub(crate) fn face(&self) -> (usize, usize) {
        (self.axis, usize::from(self.node_layer != PADDING))
    }

    /// Whether it prescribes the velocity of the points touching it (not a symmetry edge).
    pub(crate) fn holds_points(&self) -> bool {
        !self.symmetry
    }

    /// Whether a node with index `along` on the edge's axis lies beyond the edge's wall
    /// layer (outside the body).
    fn beyond(&self, along: usize) -> bool {
        if self.node_layer == PADDING {
            along < self.node_layer
        } else {
            along > self.node_layer
        }
    }

    /// The prescribed components `(axis, value)`: the normal one, and under a bonded
    /// impactor the tangential ones (zero: no slip).
    fn components<const D: usize>(&self) -> impl Iterator<Item = (usize, f64)> {
        let tangential = self.bonded.then(|| Grid::<D>::tangent_axes(self.axis));
        std::iter::once((self.axis, self.load.value))
            .chain(tangential.into_iter().flatten().map(|k| (k, 0.0)))
    }
}

/// The prescribed point velocity components (velocity edges, as the paper does): points
/// whose domain touches the edge, their centre inside its segment.
pub(crate) fn point_constraints<const D: usize>(
    body: &Grid<D>,
    points: &MaterialPoints<D>,
    edges: &[VelocityEdge],
) -> Vec<Constraint> {
    let mut out = Vec::new();
    for e in edges.iter().filter(|e| !e.symmetry) {
        let low = e.node_layer == PADDING;
        let (edge, sign) = if low {
            (body.origin[e.axis], -1.0)
        } else {
            (body.upper()[e.axis], 1.0)
        };
        for p in 0..points.len() {
            let (x, h) = (points.reference[p], points.half_size[p]);
            let touches =
                ((x[e.axis] + sign * h[e.axis]) - edge).abs() <= 1e-9 * body.spacing[e.axis];
            if touches && e.load.acts_on(e.axis, &x) {
                out.extend(e.components::<D>().map(|(axis, value)| Constraint {
                    carrier: p,
                    axis,
                    value,
                    history: e.load.history,
                }));
            }
        }
    }
    out
}

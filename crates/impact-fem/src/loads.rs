//! The FEM's boundary conditions on the nodes of the mesh's faces: a pressure's
//! consistent nodal force `f = −p n A_trib` (`A_trib` the node's tributary area of the face,
//! a length in 2D, 1 in 1D: Hughes 1987, §3.10, for the bilinear face), times the share of
//! that area a loaded patch covers; prescribed velocity components of impactor and
//! symmetry faces.
use impact_core::method::SegmentCover;
use impact_core::problem::Boundary;
use impact_core::{Constraint, Grid, LoadHistory, Problem, Vector};

/// Nodal external forces (a pressure's consistent force: `p` times the node's tributary
/// length along the edge, or under `cover = "fraction"` the part of it inside the segment)
/// at full magnitude with their histories, and the prescribed velocity components of the
/// edges (by the node's position), of the whole mesh's nodes `nodes` (global indices,
/// recognised on the whole mesh, so a box's cut face is never an edge), numbered by their
/// place in `nodes` (the stored box's local numbering).
#[allow(clippy::type_complexity)]
pub(crate) fn boundary_loads<const D: usize>(
    problem: &Problem<D>,
    nodes: impl Iterator<Item = usize>,
) -> (Vec<(usize, Vector<D>, LoadHistory)>, Vec<Constraint>) {
    let grid = &problem.grid;
    let mut loaded = Vec::new();
    let mut constraints = Vec::new();
    let counts = grid.vertex_counts();
    for (local, v) in nodes.enumerate() {
        let x = grid.vertex_position(v);
        let mut rest = v;
        let mut idx = [0usize; D];
        for k in 0..D {
            idx[k] = rest % counts[k];
            rest /= counts[k];
        }
        for l in 0..D {
            for side in 0..2 {
                if idx[l] != side * grid.cells[l] {
                    continue;
                }
                let sign = if side == 0 { -1.0 } else { 1.0 };
                // the node's tributary area of the face (length in 2D, 1 in 1D): the box
                // `centre ± half` along each tangential axis
                let (mut centre, mut half) = (x, Vector::<D>::zeros());
                let mut tributary = 1.0;
                for k in Grid::<D>::tangent_axes(l) {
                    let h = grid.spacing[k];
                    let lo = if idx[k] == 0 { 0.0 } else { 0.5 * h };
                    let hi = if idx[k] == grid.cells[k] {
                        0.0
                    } else {
                        0.5 * h
                    };
                    centre[k] = x[k] + 0.5 * (hi - lo);
                    half[k] = 0.5 * (lo + hi);
                    tributary *= lo + hi;
                }
                match problem.boundaries[l][side] {
                    Boundary::Free => {}
                    Boundary::Pressure(load) => {
                        let by_centre = load.patch.map(|g| g.cover) == Some(SegmentCover::Centre);
                        let share = if by_centre {
                            // all or nothing by the node's own position
                            if load.acts_on(l, &x) {
                                1.0
                            } else {
                                0.0
                            }
                        } else {
                            load.coverage(l, &centre, &half)
                        };
                        if share > 0.0 {
                            let mut force = Vector::<D>::zeros();
                            force[l] = -sign * load.value * tributary * share;
                            loaded.push((local, force, load.history));
                        }
                    }
                    Boundary::Velocity { load, bonded } => {
                        if load.acts_on(l, &x) {
                            let prescribe = |axis, value| Constraint {
                                carrier: local,
                                axis,
                                value,
                                history: load.history,
                            };
                            constraints.push(prescribe(l, -sign * load.value));
                            if bonded {
                                // no slip: the tangential velocity is zero too
                                constraints
                                    .extend(Grid::<D>::tangent_axes(l).map(|k| prescribe(k, 0.0)));
                            }
                        }
                    }
                    Boundary::Symmetry => constraints.push(Constraint {
                        carrier: local,
                        axis: l,
                        value: 0.0,
                        history: LoadHistory::Step,
                    }),
                }
            }
        }
    }
    (loaded, constraints)
}

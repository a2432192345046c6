//! The whole body's surface loads and prescribed point velocities listed by the global
//! numbers of the points they act on, for MPM's updated Lagrangian frame on ranks
//! (`migrate.rs`): a loaded point may move to any rank, so every rank holds the lists.
//! They are found on the faces' cell layers only: a point whose domain touches a face lies
//! in the face's layer of cells, so the face's cells are seeded (as one rank seeds them,
//! the same bits: `Problem::material_points_of_box`) and nothing else of the body. The
//! lists come face by face (per axis, the low face then the high one) with the points of a
//! face in the order of their global numbers, the order in which one rank lists them
//! (`edges.rs`), so the loads are applied in one rank's order.
use crate::edges::{face_loads, point_constraints, velocity_edges, SurfaceLoad};
use impact_core::method::MethodConfig;
use impact_core::problem::Boundary;
use impact_core::{Constraint, CoreError, Problem};
use std::ops::Range;

/// The global number of point `p` of the points seeded in `cells` (a box of the body's
/// `counts` cells per axis): the box's cells in lexicographic order (axis 0 fastest), each
/// with `per_cell` points, numbered as one rank numbers the whole body's.
fn global_number<const D: usize>(
    counts: &[usize; D],
    cells: &[Range<usize>; D],
    per_cell: usize,
    p: usize,
) -> usize {
    let (mut rest, mut global, mut stride) = (p / per_cell, 0, 1);
    for k in 0..D {
        let n = cells[k].len();
        global += (cells[k].start + rest % n) * stride;
        rest /= n;
        stride *= counts[k];
    }
    global * per_cell + p % per_cell
}

/// The cells of the face `(axis, side)` (0: low, 1: high) of a body of `counts` cells.
fn face_layer<const D: usize>(
    counts: &[usize; D],
    (axis, side): (usize, usize),
) -> [Range<usize>; D] {
    std::array::from_fn(|k| match (k == axis, side) {
        (false, _) => 0..counts[k],
        (true, 0) => 0..1,
        (true, _) => counts[k] - 1..counts[k],
    })
}

/// The surface loads and the prescribed point velocities of `problem`'s faces, each naming
/// its point by its global number (module doc).
pub(crate) fn by_global_number<const D: usize>(
    problem: &Problem<D>,
    config: &MethodConfig,
) -> Result<(Vec<SurfaceLoad<D>>, Vec<Constraint>), CoreError> {
    let body = &problem.grid;
    let counts = body.cells;
    let seeded = |face: (usize, usize)| {
        let cells = face_layer(&counts, face);
        let points = problem.material_points_of_box(body, config, &cells)?;
        let per_cell = points.len() / cells.iter().map(Range::len).product::<usize>();
        let global = move |p: usize| global_number(&counts, &cells, per_cell, p);
        Ok::<_, CoreError>((points, global))
    };
    let mut loads = Vec::new();
    for axis in 0..D {
        for side in 0..2 {
            if !matches!(problem.boundaries[axis][side], Boundary::Pressure(_)) {
                continue;
            }
            let (points, global) = seeded((axis, side))?;
            let start = loads.len();
            face_loads(problem, (axis, side), &points, &mut loads);
            for load in &mut loads[start..] {
                load.point = global(load.point);
            }
        }
    }
    let mut constraints = Vec::new();
    for edge in velocity_edges(problem)
        .into_iter()
        .filter(|e| e.holds_points())
    {
        let (points, global) = seeded(edge.face())?;
        let start = constraints.len();
        constraints.extend(point_constraints(
            body,
            &points,
            std::slice::from_ref(&edge),
        ));
        for c in &mut constraints[start..] {
            c.carrier = global(c.carrier);
        }
    }
    Ok((loads, constraints))
}

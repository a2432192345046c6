//! The edges' ghost conditions as a table (phase 2's boundary faces and phase 2b's ghost
//! cells read it). A condition depends only on the edge (axis `l`, side), the loads' step
//! averages and the tangential position of the face, so it is formed once per step, where
//! the averages are set ([`DgmpmSolver::set_load_window`]): entry `t` of edge `(l, side)`
//! is `ghost_condition(l, side, edge_coordinate(l, idx))` for the edge cell whose
//! tangential indices (the axes of `Grid::tangent_axes(l)`, first fastest) have the linear
//! index `t`, so a lookup ([`DgmpmSolver::edge_condition`]) returns the same bits as that
//! call. The table holds one entry per edge cell: `2 Σ_l Π_{k≠l} n_k` conditions (a
//! perimeter in 2D, a surface in 3D), allocated when the solver is built.
use crate::riemann::GhostCondition;
use crate::DgmpmSolver;
use impact_core::Grid;

/// The ghost condition of every edge cell, edge by edge ([`DgmpmSolver::edge_condition`]).
#[derive(Debug, Clone)]
pub(crate) struct EdgeConditions<const D: usize> {
    /// The conditions, edge `(l, side)`'s from `start[l][side]` on.
    conditions: Vec<GhostCondition<D>>,
    /// Where each edge's entries start.
    start: [[usize; 2]; D],
}

impl<const D: usize> EdgeConditions<D> {
    /// A table for `grid`'s edges, every entry free until filled
    /// ([`DgmpmSolver::fill_edge_conditions`]).
    pub(crate) fn new(grid: &Grid<D>) -> Self {
        let mut start = [[0; 2]; D];
        let mut len = 0;
        for (l, edge) in start.iter_mut().enumerate() {
            for first in edge.iter_mut() {
                *first = len;
                len += edge_cells(grid, l);
            }
        }
        Self {
            conditions: vec![GhostCondition::free(); len],
            start,
        }
    }
}

/// The number of cells along an edge normal to axis `l`: `Π_{k≠l} n_k`.
fn edge_cells<const D: usize>(grid: &Grid<D>, l: usize) -> usize {
    Grid::<D>::tangent_axes(l).map(|k| grid.cells[k]).product()
}

impl<const D: usize> DgmpmSolver<D> {
    /// Fill the table of the edges' ghost conditions from the loads' current step
    /// averages: entry `t` of edge `(l, side)` is
    /// `ghost_condition(l, side, edge_coordinate(l, idx))`, `idx` the multi-index whose
    /// tangential entries have the linear index `t` (first tangential axis fastest). No
    /// allocation (the table is sized when the solver is built).
    pub(crate) fn fill_edge_conditions(&mut self) {
        let mut table = std::mem::take(&mut self.edge_conditions);
        for l in 0..D {
            for side in 0..2 {
                let start = table.start[l][side];
                for t in 0..edge_cells(&self.grid, l) {
                    let mut idx = [0usize; D];
                    let mut rest = t;
                    for k in Grid::<D>::tangent_axes(l) {
                        idx[k] = rest % self.grid.cells[k];
                        rest /= self.grid.cells[k];
                    }
                    let s = self.edge_coordinate(l, &idx);
                    table.conditions[start + t] = self.ghost_condition(l, side, s);
                }
            }
        }
        self.edge_conditions = table;
    }

    /// The ghost condition of the edge at side `side` of axis `l` at the tangential
    /// position of the cell or face with multi-index `idx` (its entries along
    /// `Grid::tangent_axes(l)`; entry `l` is not read): the table's entry, equal to
    /// `ghost_condition(l, side, edge_coordinate(l, idx))` bit for bit.
    #[inline(always)]
    pub(crate) fn edge_condition(
        &self,
        l: usize,
        side: usize,
        idx: &[usize; D],
    ) -> GhostCondition<D> {
        let mut t = 0;
        let mut stride = 1;
        for k in 0..D {
            if k != l {
                t += idx[k] * stride;
                stride *= self.grid.cells[k];
            }
        }
        self.edge_conditions.conditions[self.edge_conditions.start[l][side] + t]
    }
}

impl<const D: usize> Default for EdgeConditions<D> {
    /// No table (taken out while it is filled).
    fn default() -> Self {
        Self {
            conditions: Vec::new(),
            start: [[0; 2]; D],
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::riemann::GhostCondition;
    use crate::Dgmpm;
    use impact_core::method::MethodKind;
    use impact_core::{Grid, Problem, Scene};

    /// Every table entry equals a fresh `ghost_condition` call at the edge cell's
    /// coordinate, bit for bit (compared as values and as printed, so a `-0.0` would show),
    /// at several load windows (a ramp and a sine history change the averages), for each
    /// index normal to the edge (cells and faces: the lookup must not read it), on scenes
    /// whose partial patches give every kind of condition.
    #[test]
    fn the_edge_table_holds_the_ghost_conditions() {
        let scenes = [
            include_str!("../../../../benchmarks/compare/scenes/edges-partial-a.toml"),
            include_str!("../../../../benchmarks/compare/scenes/edges-partial-b.toml"),
        ];
        let mut kinds = [0usize; 4];
        let mut checked = 0;
        for text in scenes {
            let scene = Scene::from_toml(text, "test").unwrap();
            let problem = Problem::<2>::from_scene(&scene).unwrap();
            let config = scene.method_config(MethodKind::Dgmpm);
            let mut dgmpm = Dgmpm::new(&problem, config).unwrap();
            for window in [(0.0, 1e-6), (7e-6, 9e-6), (3e-5, 3.2e-5)] {
                let solver = &mut dgmpm.solver;
                solver.set_load_window(window);
                let grid = solver.grid.clone();
                for l in 0..2 {
                    for side in 0..2 {
                        let along = Grid::<2>::segment_axis(l).unwrap();
                        for t in 0..grid.cells[along] {
                            for normal in [0, grid.cells[l] - 1, grid.cells[l]] {
                                let mut idx = [0; 2];
                                idx[along] = t;
                                idx[l] = normal;
                                let s = solver.edge_coordinate(l, &idx);
                                let fresh = solver.ghost_condition(l, side, s);
                                let table = solver.edge_condition(l, side, &idx);
                                assert_eq!(table, fresh, "edge ({l}, {side}) at {idx:?}");
                                assert_eq!(format!("{table:?}"), format!("{fresh:?}"));
                                checked += 1;
                                kinds[match fresh {
                                    GhostCondition::Traction(t) if t.norm() == 0.0 => 0,
                                    GhostCondition::Traction(_) => 1,
                                    GhostCondition::NormalVelocity(_)
                                    | GhostCondition::Velocity(_) => 2,
                                    GhostCondition::PartialVelocity { .. } => 3,
                                }] += 1;
                            }
                        }
                    }
                }
            }
        }
        // the scenes give free, loaded-traction, full-impactor and partial-impactor faces
        assert!(kinds.iter().all(|&n| n > 0), "{kinds:?}");
        assert!(checked > 1000, "{checked}");
    }
}

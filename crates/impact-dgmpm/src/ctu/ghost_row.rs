//! Phase 2b: the fluctuations of the ghost cells behind an edge (LeVeque 2002, §21.2 with
//! ghost cells, §7.3), per ghost cell ([`DgmpmSolver::ghost_cell_fluctuations`], the
//! general paths and 3D) and for a whole row of them along an edge at once
//! ([`DgmpmSolver::ghost_row_fluctuations`], the fused 2D sweeps) or one after the other
//! down a column of them as a sweep visits its rows
//! ([`DgmpmSolver::ghost_column_fluctuation`], the fused 2D sweeps' x-edges), from the same
//! two pieces: a ghost cell's side state ([`DgmpmSolver::ghost_side_state`]) and the
//! fluctuations of a face between ghost cells ([`DgmpmSolver::ghost_face_fluctuations`]).
use crate::faces::Fields;
use crate::riemann::{ghost_full, Conserved, FullState, GhostCondition};
use crate::{unit, DgmpmSolver};
use impact_core::method::EdgeTreatment;

impl<const D: usize> DgmpmSolver<D> {
    /// `(A⁺Δq` through its low `l`-face, `A⁻Δq` through its high `l`-face) of the ghost
    /// cell mirroring `cell` through the edge of axis `k` at `side`: the face between the
    /// ghost cell's low (high) side state and its neighbour's high (low) one along `e_l`
    /// ([`Self::ghost_face_fluctuations`]; beyond the edge of axis `l`, the ghost of the
    /// ghost through that edge's condition).
    pub(crate) fn ghost_cell_fluctuations(
        &self,
        k: usize,
        side: usize,
        l: usize,
        cell: [usize; D],
        fields: Fields<'_, D>,
    ) -> (Conserved<D>, Conserved<D>) {
        let plus_low = self.ghost_low_face((k, side, l), cell, fields).1;
        let minus_high = self.ghost_high_face((k, side, l), cell, fields).0;
        (plus_low, minus_high)
    }

    /// `(A⁻Δq, A⁺Δq)` of the `l`-face below the ghost cell mirroring `cell` through the
    /// edge of axis `k` at `side`: between its neighbour's high side state (none at the
    /// edge of axis `l`) and its own low one ([`Self::ghost_face_fluctuations`]). (One
    /// function for both faces, the side a parameter, cost the RK2 wavefront 3.5
    /// instructions a cell, callgrind.)
    #[inline(always)]
    fn ghost_low_face(
        &self,
        (k, side, l): (usize, usize, usize),
        cell: [usize; D],
        fields: Fields<'_, D>,
    ) -> (Conserved<D>, Conserved<D>) {
        let ghost_of =
            |c: [usize; D], high: bool| self.ghost_side_state(k, side, l, c, high, fields);
        let left = (cell[l] > 0).then(|| {
            let mut c = cell;
            c[l] -= 1;
            ghost_of(c, true)
        });
        let me_low = ghost_of(cell, false);
        self.ghost_face_fluctuations(k, side, l, left, Some(me_low), cell)
    }

    /// `(A⁻Δq, A⁺Δq)` of the `l`-face above the ghost cell mirroring `cell` (as
    /// [`Self::ghost_low_face`]: its own high side state and its neighbour's low one).
    #[inline(always)]
    fn ghost_high_face(
        &self,
        (k, side, l): (usize, usize, usize),
        cell: [usize; D],
        fields: Fields<'_, D>,
    ) -> (Conserved<D>, Conserved<D>) {
        let ghost_of =
            |c: [usize; D], high: bool| self.ghost_side_state(k, side, l, c, high, fields);
        let right = (cell[l] + 1 < self.grid.cells[l]).then(|| {
            let mut c = cell;
            c[l] += 1;
            ghost_of(c, false)
        });
        let me_high = ghost_of(cell, true);
        self.ghost_face_fluctuations(k, side, l, Some(me_high), right, cell)
    }

    /// The state on its `high` (or low) side normal to `e_l` of the ghost cell mirroring
    /// cell `c` through the edge of axis `k` at `side`: `ghost_full` of the cell's side
    /// state through the edge's condition at the cell's position along it.
    #[inline(always)]
    pub(crate) fn ghost_side_state(
        &self,
        k: usize,
        side: usize,
        l: usize,
        c: [usize; D],
        high: bool,
        fields: Fields<'_, D>,
    ) -> FullState<D> {
        let outward = unit::<D>(k) * if side == 0 { -1.0 } else { 1.0 };
        let inner = fields.side(self.grid.cell_index(c), l, high);
        ghost_full(&inner, &outward, self.edge_condition(k, side, &c))
    }

    /// Fluctuations `(A⁻Δq, A⁺Δq)` of the `l`-face between the ghost side states `left`
    /// and `right` behind the edge of axis `k` at `side`, next to the ghost cell mirroring
    /// `cell`; a missing state (beyond the edge of axis `l`) is the ghost of the other
    /// through that edge's condition at `cell`'s position along it. At a corner where both
    /// edges prescribe a traction (under `restricted` edges) that face is dropped (zero):
    /// the ghost of the ghost cell (the diagonal neighbour) is not defined by either
    /// condition alone (measured: with it, CTU with free corners is unstable from Courant
    /// 0.99). Edge `k`'s condition is read at the ghost cell's own position along it (read
    /// at the position along `e_k`, the top-left corner of the plate took the impact
    /// segment's condition, since x = h/2 lies in y ∈ [0, 1]).
    #[inline(always)]
    pub(crate) fn ghost_face_fluctuations(
        &self,
        k: usize,
        side: usize,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        cell: [usize; D],
    ) -> (Conserved<D>, Conserved<D>) {
        let traction_corner = |l_side: usize| {
            self.options.edges == EdgeTreatment::Restricted
                && matches!(
                    self.edge_condition(k, side, &cell),
                    GhostCondition::Traction(_)
                )
                && matches!(
                    self.edge_condition(l, l_side, &cell),
                    GhostCondition::Traction(_)
                )
        };
        let dropped = match (&left, &right) {
            (None, _) => traction_corner(0),
            (_, None) => traction_corner(1),
            _ => false,
        };
        if dropped {
            return (Conserved::zeros(), Conserved::zeros());
        }
        self.face_fluctuations(l, left, right, &cell)
    }

    /// The fluctuations `w_i = A⁺Δq_low + A⁻Δq_high` of the row of ghost cells mirroring
    /// the cells `row` + `i e_l` (`i = 0..n_l`, `row[l] = 0`) through the edge of axis `k`
    /// at `side` into `out` (`n_l`), the sum [`Self::ghost_cell_fluctuations`] gives each
    /// (order 1: the ghost row's wave corrections are not added), with each ghost side
    /// state formed once and each face between ghost cells solved once (`n_l + 1` faces
    /// instead of `2 n_l`): face `i` (between ghost cells `i - 1` and `i`) gives cell
    /// `i - 1`'s `A⁻Δq_high` and cell `i`'s `A⁺Δq_low`. The same operations, so the same
    /// bits.
    pub(crate) fn ghost_row_fluctuations(
        &self,
        k: usize,
        side: usize,
        l: usize,
        row: [usize; D],
        fields: Fields<'_, D>,
        out: &mut [Conserved<D>],
    ) {
        let n = self.grid.cells[l];
        let at = |i: usize| {
            let mut c = row;
            c[l] = i;
            c
        };
        let mut previous_high = None;
        for i in 0..n {
            let cell = at(i);
            let low = self.ghost_side_state(k, side, l, cell, false, fields);
            let (minus, plus) =
                self.ghost_face_fluctuations(k, side, l, previous_high, Some(low), cell);
            if i > 0 {
                out[i - 1] = out[i - 1].add_scaled(&minus, 1.0);
            }
            out[i] = plus;
            previous_high = Some(self.ghost_side_state(k, side, l, cell, true, fields));
        }
        let minus = self
            .ghost_face_fluctuations(k, side, l, previous_high, None, at(n - 1))
            .0;
        out[n - 1] = out[n - 1].add_scaled(&minus, 1.0);
    }

    /// The fluctuation `w = A⁺Δq_low + A⁻Δq_high` of the ghost cell mirroring `cell`
    /// through the edge of axis `k` at `side` (the sum [`Self::ghost_cell_fluctuations`]
    /// gives, order 1) for a sweep that visits the cells `cell + j e_l` in increasing `j`:
    /// `carry` holds, from the call for the cell below (`(cell[l], A⁺Δq)`), the `A⁺Δq` of
    /// the ghost face below `cell`, and on return that of the face above, for the next
    /// cell. Each face between ghost cells is then solved once instead of twice, and each
    /// ghost side state formed once; a `carry` for another cell (or none) is formed here
    /// as `ghost_cell_fluctuations` forms it. Away from a corner a face's fluctuations do
    /// not depend on which of its ghost cells asks, so the same operations give the same
    /// bits.
    #[inline]
    pub(crate) fn ghost_column_fluctuation(
        &self,
        (k, side, l): (usize, usize, usize),
        cell: [usize; D],
        fields: Fields<'_, D>,
        carry: &mut Option<(usize, Conserved<D>)>,
    ) -> Conserved<D> {
        let plus_low = match carry.take() {
            Some((j, plus)) if j == cell[l] => plus,
            _ => self.ghost_low_face((k, side, l), cell, fields).1,
        };
        let (minus_high, plus_next) = self.ghost_high_face((k, side, l), cell, fields);
        // the face above serves the next cell, if there is one
        let next = cell[l] + 1;
        *carry = (next < self.grid.cells[l]).then_some((next, plus_next));
        plus_low.add_scaled(&minus_high, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use crate::faces::{Fields, SideState};
    use crate::test_scenes::for_partial_edge_scenes;
    use impact_core::{Grid, Vector};

    /// Down every edge's column of ghost cells, in both edge treatments, on scenes whose
    /// partial patches give every kind of condition (and traction corners), with side
    /// states that differ from side to side: each [`ghost_column_fluctuation`] equals the sum of
    /// `ghost_cell_fluctuations` bit for bit (compared as printed too, so a `-0.0` would
    /// show), whether the carry comes from the cell below or the walk starts mid-column.
    ///
    /// [`ghost_column_fluctuation`]: crate::DgmpmSolver::ghost_column_fluctuation
    #[test]
    fn a_column_of_ghost_cells_gives_each_cells_fluctuations() {
        let mut checked = 0;
        for_partial_edge_scenes(|edges, dgmpm| {
            let solver = &dgmpm.solver;
            let cells = solver.grid.cells[0] * solver.grid.cells[1];
            // side states of the load's size, different on every side of every cell
            // (a low side unlike the high one, as between Heun's stages)
            let wobble = |c: usize, k: usize| ((c * 7 + k * 3) as f64 * 0.37).sin();
            let sides: Vec<SideState<2>> = (0..4 * cells)
                .map(|c| SideState {
                    traction: Vector::<2>::new(1e6 * wobble(c, 0), 1e6 * wobble(c, 1)),
                    velocity: Vector::<2>::new(wobble(c, 4), wobble(c, 5)),
                })
                .collect();
            let fields = Fields::sides(&sides, 0);
            for k in 0..2 {
                let l = Grid::<2>::segment_axis(k).unwrap();
                for side in 0..2 {
                    let n = solver.grid.cells[l];
                    for start in [0, n / 2] {
                        let mut carry = None;
                        for j in start..n {
                            let mut cell = [0; 2];
                            cell[k] = side * (solver.grid.cells[k] - 1);
                            cell[l] = j;
                            let column = solver.ghost_column_fluctuation(
                                (k, side, l),
                                cell,
                                fields,
                                &mut carry,
                            );
                            let (m_in, p_in) =
                                solver.ghost_cell_fluctuations(k, side, l, cell, fields);
                            let each = m_in.add_scaled(&p_in, 1.0);
                            assert_eq!(column, each, "{edges:?} edge ({k}, {side}) at {j}");
                            assert_eq!(format!("{column:?}"), format!("{each:?}"));
                            checked += 1;
                        }
                    }
                }
            }
        });
        assert!(checked > 400, "{checked}");
    }
}

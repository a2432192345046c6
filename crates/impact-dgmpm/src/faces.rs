//! Faces and their states: face indexing (a multi-index odometer), the two states of a
//! face (averages of each side's face nodes, paper §4, or the cell's one state on the cell
//! path) and the ghost conditions of the boundary faces (LeVeque 2002, §7.3).
use crate::riemann::{ghost_full, FullState, GhostCondition};
use crate::{unit, DgmpmSolver, CHUNK};
use impact_core::parallel::{chunks, sum_chunks};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;
use impact_core::{Grid, Patch, Tensor, Vector};

mod edge_table;
pub(crate) use edge_table::EdgeConditions;

/// Where face states are read from (see [`DgmpmSolver::interface_fluxes`]).
#[derive(Clone, Copy)]
pub(crate) struct Fields<'a, const D: usize> {
    /// The tensor field (σ or F).
    tensor: &'a [Tensor<D>],
    velocity: &'a [Vector<D>],
    /// One value per cell (the cell path) instead of `2^D` nodes per cell.
    per_cell: bool,
    /// The `2D` side states of each cell, stored cell by cell (side `2l + h` of axis `l`,
    /// low `h = 0` or high `h = 1`) instead of its nodes: Heun's second stage at one point
    /// per cell (`fused/heun.rs`; `tensor` and `velocity` empty then).
    sides: Option<&'a [SideState<D>]>,
    /// The cell whose side states `sides` starts with (0, or a ring of rows of them: the
    /// Heun wavefront, `fused/heun/wavefront.rs`).
    first_cell: usize,
    /// Side states after which a ring of rows wraps to its start ([`Fields::ring`]);
    /// `usize::MAX` for one array.
    wrap: usize,
}

/// A cell's state on its side normal to `e_l` as far as a face normal to `e_l` reads it:
/// the traction `σ e_l` (the tensor's column `l`) and the velocity. The Godunov flux
/// (`riemann::axis`, eqs. 18-21), the normal flux `F_{e_l}` of the side terms, the ghost
/// state across an edge normal to `e_l` and, on a side normal to `e_l` next to an edge of
/// axis `k`, the ghost of the CTU corner fluctuation (`ghost_full` along `e_k`, then
/// `F_{e_l}`: its column `l` is `σ_ll` and `σ_kl + n_k Δt_l`, `Δt_l` from `σ_lk` alone) read
/// nothing else; [`Fields::side`] gives the other components as zero (Heun's second
/// stage, `fused/heun.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SideState<const D: usize> {
    /// `σ e_l`.
    pub(crate) traction: Vector<D>,
    /// `v`.
    pub(crate) velocity: Vector<D>,
}

impl<const D: usize> SideState<D> {
    /// Zero.
    pub(crate) fn zeros() -> Self {
        Self {
            traction: Vector::<D>::zeros(),
            velocity: Vector::<D>::zeros(),
        }
    }

    /// The state a face normal to `e_l` reads: the traction as column and row `l` of the
    /// tensor, the rest zero, and the velocity.
    #[inline(always)]
    pub(crate) fn full(&self, l: usize) -> FullState<D> {
        let mut tensor = Tensor::<D>::zeros();
        for k in 0..D {
            tensor[(k, l)] = self.traction[k];
            tensor[(l, k)] = self.traction[k];
        }
        FullState {
            tensor,
            velocity: self.velocity,
        }
    }
}

impl<'a, const D: usize> Fields<'a, D> {
    /// One state per cell (the cell path's points, stored in cell order).
    #[inline]
    pub(crate) fn per_cell(tensor: &'a [Tensor<D>], velocity: &'a [Vector<D>]) -> Self {
        Self {
            tensor,
            velocity,
            per_cell: true,
            sides: None,
            first_cell: 0,
            wrap: usize::MAX,
        }
    }

    /// `2^D` nodes per cell, stored cell by cell (the nodal paths).
    #[inline]
    pub(crate) fn nodal(tensor: &'a [Tensor<D>], velocity: &'a [Vector<D>]) -> Self {
        Self {
            tensor,
            velocity,
            per_cell: false,
            sides: None,
            first_cell: 0,
            wrap: usize::MAX,
        }
    }

    /// `2D` side states per cell, stored cell by cell from cell `first_cell` on
    /// (`fused/heun.rs`).
    #[inline]
    pub(crate) fn sides(sides: &'a [SideState<D>], first_cell: usize) -> Self {
        Self {
            tensor: &[],
            velocity: &[],
            per_cell: false,
            sides: Some(sides),
            first_cell,
            wrap: usize::MAX,
        }
    }

    /// Side states ([`Self::sides`]) in a ring of rows of `row_cells` cells each
    /// (`sides.len()` a whole number of rows): row `r` is stored at row `r mod R` of the
    /// ring; the fields give the rows from `first_row` on while the ring holds them (the
    /// Heun wavefront, `fused/heun/wavefront.rs`). A cell's entry is its offset from the
    /// window's first cell, less the ring's length once past its end: no division.
    #[inline]
    pub(crate) fn ring(sides: &'a [SideState<D>], row_cells: usize, first_row: usize) -> Self {
        assert!(D > 1, "internal: a ring of rows is 2D's or 3D's");
        let rows = sides.len() / (row_cells * 2 * D);
        Self {
            wrap: sides.len(),
            ..Self::sides(sides, (first_row - first_row % rows) * row_cells)
        }
    }

    /// The entry of cell `c`'s first side state in `sides` (module doc of [`Self::ring`];
    /// rings are 2D's, the Heun wavefront: in 1D no test of the wrap, which cost the bar's
    /// RK2 5 instructions a cell).
    #[inline(always)]
    fn side_entry(&self, c: usize) -> usize {
        let entry = (c - self.first_cell) * 2 * D;
        if D == 1 {
            return entry;
        }
        if entry >= self.wrap {
            entry - self.wrap
        } else {
            entry
        }
    }

    /// The side states of the `count` cells from `first` (`2D` a cell; one row of a
    /// [`Self::ring`]) where these are side fields ([`Self::sides`]), so that a sweep
    /// along a row reads them without an index check per cell; `None` for other fields.
    #[inline(always)]
    pub(crate) fn side_row(&self, first: usize, count: usize) -> Option<&'a [SideState<D>]> {
        let start = self.side_entry(first);
        self.sides.map(|sides| &sides[start..start + count * 2 * D])
    }

    /// The tensor field and the velocities (per-cell fields: one entry per cell).
    #[inline]
    pub(crate) fn slices(&self) -> (&'a [Tensor<D>], &'a [Vector<D>]) {
        (self.tensor, self.velocity)
    }

    /// The one state of cell `c` (per-cell fields only).
    #[inline(always)]
    pub(crate) fn cell(&self, c: usize) -> FullState<D> {
        FullState {
            tensor: self.tensor[c],
            velocity: self.velocity[c],
        }
    }

    /// State of cell `c` on its face normal to axis `l` (`high` side or low side): the
    /// average of the cell's nodes on that face (paper §4); on the cell path, the cell's
    /// one state (all its nodes carry it).
    #[inline]
    pub(crate) fn side(&self, c: usize, l: usize, high: bool) -> FullState<D> {
        if self.per_cell {
            return self.cell(c);
        }
        self.nodal_side(c, l, high)
    }

    /// [`Self::side`] with the kind of fields known at compile time: `NODAL`, the average
    /// of the face's nodes; otherwise the cell's one state (the fused sweeps).
    #[inline(always)]
    pub(crate) fn at<const NODAL: bool>(&self, c: usize, l: usize, high: bool) -> FullState<D> {
        match NODAL {
            true => self.nodal_side(c, l, high),
            false => self.cell(c),
        }
    }

    /// The average of cell `c`'s nodes on its face normal to `l` (nodal fields), or the
    /// stored side state (side fields: column and row `l` of the tensor, the rest zero,
    /// [`SideState`]).
    #[inline(always)]
    fn nodal_side(&self, c: usize, l: usize, high: bool) -> FullState<D> {
        if let Some(sides) = self.sides {
            return sides[self.side_entry(c) + 2 * l + usize::from(high)].full(l);
        }
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let mut q = Tensor::<D>::zeros();
        let mut v = Vector::<D>::zeros();
        // the face's 2^(D-1) nodes: bit l of the local node index set to `high`, the
        // other bits running over k (in increasing node order)
        let low_bits = (1usize << l) - 1;
        for k in 0..nodes_per_cell / 2 {
            let a = (k & low_bits) | (usize::from(high) << l) | ((k & !low_bits) << 1);
            q += self.tensor[c * nodes_per_cell + a];
            v += self.velocity[c * nodes_per_cell + a];
        }
        let inv = 2.0 / nodes_per_cell as f64;
        FullState {
            tensor: q * inv,
            velocity: v * inv,
        }
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Multi-index of entry `f` of an array with dimensions `dims` (first index fastest).
    #[inline]
    pub(crate) fn multi_index(dims: [usize; D], mut f: usize) -> [usize; D] {
        let mut idx = [0; D];
        for k in 0..D {
            idx[k] = f % dims[k];
            f /= dims[k];
        }
        idx
    }

    /// How the face loops of axis `l` are cut (chunks of [`CHUNK`] faces, each walked with
    /// [`Self::advance`] from its first multi-index), and the face array's dimensions.
    pub(crate) fn face_rows(&self, l: usize) -> (usize, [usize; D]) {
        (CHUNK, self.grid.face_dims(l))
    }

    /// `kernel(idx, face)` on every entry of `faces`, the array of faces normal to axis
    /// `l` (multi-index `idx`), in chunks of [`CHUNK`] walked with [`Self::advance`]
    /// (serially or on rayon's pool); returns the sum of what the kernel returns.
    pub(crate) fn sum_over_faces<T: Send>(
        &self,
        l: usize,
        faces: &mut [T],
        kernel: impl Fn([usize; D], &mut T) -> f64 + Sync,
    ) -> f64 {
        let (chunk, dims) = self.face_rows(l);
        sum_chunks(self.parallel, 1, chunks(faces, chunk), |r, faces| {
            let mut idx = Self::multi_index(dims, r * chunk);
            let mut sum = 0.0;
            for face in faces.iter_mut() {
                sum += kernel(idx, face);
                Self::advance(&mut idx, &dims);
            }
            sum
        })
    }

    /// Next multi-index in storage order (first index fastest): no division, and entries
    /// other than `idx[0]` are written only at the end of a row.
    #[inline(always)]
    pub(crate) fn advance(idx: &mut [usize; D], dims: &[usize; D]) {
        idx[0] += 1;
        if idx[0] == dims[0] {
            idx[0] = 0;
            for k in 1..D {
                idx[k] += 1;
                if idx[k] < dims[k] {
                    break;
                }
                idx[k] = 0;
            }
        }
    }

    /// Linear index of the face of axis `l` with multi-index `idx`.
    #[inline]
    pub(crate) fn face_index(grid: &Grid<D>, l: usize, idx: [usize; D]) -> usize {
        let mut lin = 0;
        for k in (0..D).rev() {
            lin = lin * (grid.cells[k] + usize::from(k == l)) + idx[k];
        }
        lin
    }

    /// The fields the face states are read from: the cells' DG nodes, or on the cell path
    /// the points themselves (one per cell, stored in cell order).
    #[inline]
    pub(crate) fn fields<'a>(&'a self, points: &'a MaterialPoints<D>) -> Fields<'a, D> {
        if !self.path.nodal() {
            Fields::per_cell(self.point_tensor(points), &points.velocity)
        } else {
            Fields::nodal(&self.nodes.tensor, &self.nodes.velocity)
        }
    }

    /// Tangential coordinates on a side normal to axis `l` of the cell or face with
    /// multi-index `idx` (its centre along each of [`Grid::tangent_axes`], in that order;
    /// unused entries 0): where a loaded patch is tested.
    #[inline]
    pub(crate) fn edge_coordinate(&self, l: usize, idx: &[usize; D]) -> [f64; 2] {
        let mut s = [0.0; 2];
        for (slot, k) in Grid::<D>::tangent_axes(l).enumerate() {
            let global = idx[k] + self.place.offset[k];
            s[slot] = self.place.origin[k] + (global as f64 + 0.5) * self.grid.spacing[k];
        }
        s
    }

    /// Ghost condition of the boundary at side `side` of axis `l`, for the face centred at
    /// the tangential coordinates `s` (`Grid::tangent_axes` order), with the loads at their magnitudes at
    /// their step averages ([`Self::set_load_window`]). A segment end that cuts the face
    /// decides by the face centre or, under `cover = "fraction"`, scales a pressure by the
    /// covered share and blends an impactor with the free face
    /// ([`GhostCondition::PartialVelocity`]).
    #[inline]
    pub(crate) fn ghost_condition(&self, l: usize, side: usize, s: [f64; 2]) -> GhostCondition<D> {
        let outward = unit::<D>(l) * if side == 0 { -1.0 } else { 1.0 };
        let half = Patch::tangential(l, &(self.grid.spacing * 0.5));
        let coverage = |load: &impact_core::Load| {
            load.patch
                .map_or(1.0, |patch| patch.coverage(s, half, D - 1))
        };
        let value = self.load_now[l][side];
        match self.boundaries[l][side] {
            Boundary::Free => GhostCondition::free(),
            Boundary::Pressure(load) => {
                let share = coverage(&load);
                GhostCondition::Traction(outward * (-value * share))
            }
            Boundary::Velocity { load, bonded } => {
                let share = coverage(&load);
                let velocity = outward * (-value);
                if share <= 0.0 {
                    GhostCondition::free()
                } else if share < 1.0 {
                    GhostCondition::PartialVelocity {
                        velocity,
                        bonded,
                        share,
                    }
                } else if bonded {
                    GhostCondition::Velocity(velocity)
                } else {
                    GhostCondition::NormalVelocity(-value)
                }
            }
            Boundary::Symmetry => GhostCondition::NormalVelocity(0.0),
        }
    }

    /// Set the loads' magnitudes to their step averages over `window = (t0, t1)`,
    /// `p ḡ` with `ḡ = (I(t1) - I(t0))/(t1 - t0)` (`impact_core::load`: the step delivers
    /// the load's impulse to round-off; 1 for a step load).
    /// Then the table of the edges' conditions is filled from them
    /// (`fill_edge_conditions`).
    pub fn set_load_window(&mut self, window: (f64, f64)) {
        for (now, pair) in self.load_now.iter_mut().zip(&self.boundaries) {
            for (value, bc) in now.iter_mut().zip(pair) {
                *value = bc.load().map_or(0.0, |load| load.mean(window));
            }
        }
        self.fill_edge_conditions();
    }

    /// Both states of a face normal to `e_l`; a missing side (outside the grid) is the ghost
    /// of the other through the boundary condition at tangential coordinate `s`.
    #[inline]
    pub(crate) fn face_pair(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: [f64; 2],
    ) -> (FullState<D>, FullState<D>) {
        self.face_pair_with(l, left, right, |side| self.ghost_condition(l, side, s))
    }

    /// [`Self::face_pair`] with the condition of the edge at the tangential position of the
    /// face or cell `idx`, from the table ([`Self::edge_condition`]; the same bits).
    #[inline]
    pub(crate) fn face_pair_at(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        idx: &[usize; D],
    ) -> (FullState<D>, FullState<D>) {
        self.face_pair_with(l, left, right, |side| self.edge_condition(l, side, idx))
    }

    /// Both states of a face normal to `e_l`, a missing side the ghost of the other
    /// (`ghost_full`) through `condition(side)`, the condition of the edge at that side.
    #[inline(always)]
    fn face_pair_with(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        condition: impl FnOnce(usize) -> GhostCondition<D>,
    ) -> (FullState<D>, FullState<D>) {
        match (left, right) {
            (Some(a), Some(b)) => (a, b),
            (None, Some(b)) => (ghost_full(&b, &(-unit::<D>(l)), condition(0)), b),
            (Some(a), None) => (a, ghost_full(&a, &unit::<D>(l), condition(1))),
            (None, None) => unreachable!("internal: a face has at least one cell"),
        }
    }

    /// The cells on both sides of the face of axis `l` with multi-index `idx` (`None`
    /// outside) and the face's tangential coordinate.
    #[inline]
    pub(crate) fn face_cells(
        &self,
        l: usize,
        idx: [usize; D],
    ) -> (Option<usize>, Option<usize>, [f64; 2]) {
        let grid = &self.grid;
        // index arithmetic (cell strides), no multi-index entry written at a run-time axis
        let mut cell = 0;
        let mut stride = 1;
        let mut stride_l = 1;
        for m in 0..D {
            cell += idx[m] * stride;
            if m == l {
                stride_l = stride;
            }
            stride *= grid.cells[m];
        }
        let right = (idx[l] < grid.cells[l]).then_some(cell);
        let left = (idx[l] > 0).then(|| cell - stride_l);
        (left, right, self.edge_coordinate(l, &idx))
    }
}

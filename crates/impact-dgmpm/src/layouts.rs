//! Cell layouts: the weights of the nodal paths that depend only on a cell's points'
//! reference local coordinates, masses and volumes, stored once per distinct cell.
//!
//! The points never move in the grid (total Lagrangian: the grid is the reference
//! configuration) and their masses and volumes are fixed, so a cell's shape values
//! `S_iα`, gradients `∇S_iα`, volume weights `K_ab = Σ_α V_α S_bα ∇S_aα`
//! ([`cell_volume_weights`]), phase-1 weights `W_αi = S_iα m_α / M_i` and lumped masses
//! `M_i = Σ_α S_iα m_α` ([`cell_mapping_weights`]) are formed once, at the build. Cells
//! whose points sit at the same local coordinates with the same masses and volumes have
//! the same blocks: [`CellLayouts`] stores each distinct set of blocks once (blocks equal
//! bit for bit, compared bit by bit) and a `u32` layout index per cell; the step reads
//! `table[layout[c]]`, so it reads the very values a per-cell array would hold. A uniform
//! seeding has few layouts (the seeding's local coordinates round to a handful of values
//! per axis: 16 at 200×150 cells, 11 at 1000×750, so at most 256 and 121 layouts in 2D);
//! an irregular one has up to one per cell (the memory of per-cell arrays plus 4 B per
//! cell). The table is formed cell by cell: the build never holds every cell's blocks
//! beside the table.
use crate::{unsupported, MAX_NODES};
use impact_core::distinct::DistinctBlocks;
use impact_core::points::MaterialPoints;
use impact_core::{CoreError, Grid, Vector};

/// Which blocks a layout holds besides the shape values `S_iα` (always there).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Blocks {
    /// The points' gradients `∇S_iα` (the volume term per point: no volume weights).
    pub gradient: bool,
    /// The volume weights `K_ab`, `(2^D - 1) × 2^D` (linear elasticity, `2^D` points per
    /// cell or more).
    pub volume: bool,
    /// Phase 1's weights `W_αi` and the lumped masses `M_i` (several points per cell).
    pub mapping: bool,
}

/// The per-cell weights of the nodal paths, once per distinct cell layout (module doc).
/// Empty (no layout) on the paths that read none.
#[derive(Debug, Clone, Default)]
pub(crate) struct CellLayouts<const D: usize> {
    /// The blocks held (`None`: not formed).
    blocks: Option<Blocks>,
    /// Points per cell.
    points_per_cell: usize,
    /// Each cell's layout.
    layout: Vec<u32>,
    /// `S_iα`, `points_per_cell × 2^D` per layout, point after point.
    shape: Vec<f64>,
    /// `∇S_iα`, as `shape` (where [`Blocks::gradient`]).
    gradient: Vec<Vector<D>>,
    /// `K_ab`, `(2^D - 1) × 2^D` per layout, row `a` after row (where [`Blocks::volume`]).
    volume: Vec<Vector<D>>,
    /// `W_αi`, as `shape` (where [`Blocks::mapping`]).
    mapping: Vec<f64>,
    /// `M_i`, `2^D` per layout (where [`Blocks::mapping`]).
    mass: Vec<f64>,
}

/// One cell's blocks while the table is formed.
struct Scratch<const D: usize> {
    shape: Vec<f64>,
    gradient: Vec<Vector<D>>,
    volume: Vec<Vector<D>>,
    mapping: Vec<f64>,
    mass: Vec<f64>,
}

impl<const D: usize> Scratch<D> {
    /// The blocks `blocks` keeps.
    fn blocks(&self, blocks: Blocks) -> BlockRefs<'_, D> {
        BlockRefs {
            shape: &self.shape,
            gradient: if blocks.gradient { &self.gradient } else { &[] },
            volume: if blocks.volume { &self.volume } else { &[] },
            mapping: if blocks.mapping { &self.mapping } else { &[] },
            mass: if blocks.mapping { &self.mass } else { &[] },
        }
    }
}

/// One cell's blocks (empty where not kept).
struct BlockRefs<'a, const D: usize> {
    shape: &'a [f64],
    gradient: &'a [Vector<D>],
    volume: &'a [Vector<D>],
    mapping: &'a [f64],
    mass: &'a [f64],
}

impl<const D: usize> BlockRefs<'_, D> {
    /// The bits of every block, in one stream (the key's source).
    fn bits(&self) -> impl Iterator<Item = u64> + '_ {
        fn vectors<const D: usize>(v: &[Vector<D>]) -> impl Iterator<Item = u64> + '_ {
            v.iter().flat_map(|v| v.iter().map(|x| x.to_bits()))
        }
        fn scalars(v: &[f64]) -> impl Iterator<Item = u64> + '_ {
            v.iter().map(|x| x.to_bits())
        }
        scalars(self.shape)
            .chain(vectors(self.gradient))
            .chain(vectors(self.volume))
            .chain(scalars(self.mapping))
            .chain(scalars(self.mass))
    }
}

impl<const D: usize> CellLayouts<D> {
    /// The table of `points` (stored cell by cell, `points_per_cell` each) in `grid`,
    /// holding the shape values and `blocks`, formed cell by cell (module doc).
    pub(crate) fn new(
        grid: &Grid<D>,
        points: &MaterialPoints<D>,
        points_per_cell: usize,
        blocks: Blocks,
    ) -> Result<Self, CoreError> {
        let n = Grid::<D>::NODES_PER_CELL;
        let cells = points.len() / points_per_cell;
        let per_cell = points_per_cell * n;
        let mut table = Self {
            blocks: Some(blocks),
            points_per_cell,
            layout: Vec::with_capacity(cells),
            ..Self::default()
        };
        let mut scratch = Scratch::<D> {
            shape: vec![0.0; per_cell],
            gradient: vec![Vector::<D>::zeros(); per_cell],
            volume: vec![Vector::<D>::zeros(); (n - 1) * n],
            mapping: vec![0.0; per_cell],
            mass: vec![0.0; n],
        };
        let mut index = DistinctBlocks::new();
        let mut coordinates = local_coordinates(grid, points);
        for c in 0..cells {
            let cell_points = c * points_per_cell..(c + 1) * points_per_cell;
            for k in 0..points_per_cell {
                let xi = coordinates.next().expect("points_per_cell per cell")?;
                let entries = k * n..(k + 1) * n;
                grid.shape(
                    &xi,
                    &mut scratch.shape[entries.clone()],
                    &mut scratch.gradient[entries],
                );
            }
            if blocks.volume {
                let volume = &points.volume[cell_points.clone()];
                let (s, g) = (&scratch.shape, &scratch.gradient);
                cell_volume_weights::<D>(s, g, volume, &mut scratch.volume);
            }
            if blocks.mapping {
                let mass = &points.mass[cell_points];
                let (w, m) = (&mut scratch.mapping, &mut scratch.mass);
                cell_mapping_weights::<D>(&scratch.shape, mass, w, m);
            }
            let refs = scratch.blocks(blocks);
            let holds = |table: &Self, l: u32| table.holds(l as usize, &scratch);
            let push = |table: &mut Self| table.push(&scratch);
            let layout = index.find_or_push(&mut table, refs.bits(), holds, push)?;
            table.layout.push(layout);
        }
        drop(index);
        table.shape.shrink_to_fit();
        table.gradient.shrink_to_fit();
        table.volume.shrink_to_fit();
        table.mapping.shrink_to_fit();
        table.mass.shrink_to_fit();
        Ok(table)
    }

    /// Whether layout `l` holds `scratch`'s blocks, bit for bit.
    fn holds(&self, l: usize, scratch: &Scratch<D>) -> bool {
        let blocks = self.blocks.unwrap_or_default();
        let per_cell = self.per_cell();
        let n = Grid::<D>::NODES_PER_CELL;
        let held = BlockRefs {
            shape: self.block(&self.shape, l, per_cell),
            gradient: self.block(&self.gradient, l, per_cell * usize::from(blocks.gradient)),
            volume: self.block(&self.volume, l, Self::VOLUME * usize::from(blocks.volume)),
            mapping: self.block(&self.mapping, l, per_cell * usize::from(blocks.mapping)),
            mass: self.block(&self.mass, l, n * usize::from(blocks.mapping)),
        };
        held.bits().eq(scratch.blocks(blocks).bits())
    }

    /// Append `scratch`'s blocks as a new layout; its index.
    fn push(&mut self, scratch: &Scratch<D>) -> Result<u32, CoreError> {
        let blocks = self.blocks.unwrap_or_default();
        let l = u32::try_from(self.shape.len() / self.per_cell())
            .map_err(|_| unsupported("more than 2^32 distinct cell layouts"))?;
        self.shape.extend_from_slice(&scratch.shape);
        if blocks.gradient {
            self.gradient.extend_from_slice(&scratch.gradient);
        }
        if blocks.volume {
            self.volume.extend_from_slice(&scratch.volume);
        }
        if blocks.mapping {
            self.mapping.extend_from_slice(&scratch.mapping);
            self.mass.extend_from_slice(&scratch.mass);
        }
        Ok(l)
    }

    /// Volume weights per layout.
    const VOLUME: usize = (Grid::<D>::NODES_PER_CELL - 1) * Grid::<D>::NODES_PER_CELL;

    /// Shape values (and gradients, mapping weights) per layout.
    #[inline(always)]
    fn per_cell(&self) -> usize {
        self.points_per_cell * Grid::<D>::NODES_PER_CELL
    }

    /// Block `l` of `table`, `len` entries each.
    #[inline(always)]
    fn block<'a, T>(&self, table: &'a [T], l: usize, len: usize) -> &'a [T] {
        &table[l * len..(l + 1) * len]
    }

    /// The blocks held (`None`: no table).
    pub(crate) fn blocks(&self) -> Option<Blocks> {
        self.blocks
    }

    /// The number of distinct layouts.
    #[cfg(test)]
    pub(crate) fn layout_count(&self) -> usize {
        match self.per_cell() {
            0 => 0,
            per_cell => self.shape.len() / per_cell,
        }
    }

    /// Whether the table holds the lumped masses ([`Blocks::mapping`]).
    #[inline(always)]
    pub(crate) fn has_mapping(&self) -> bool {
        !self.mass.is_empty()
    }

    /// Whether the table holds the volume weights ([`Blocks::volume`]).
    #[inline(always)]
    pub(crate) fn has_volume(&self) -> bool {
        !self.volume.is_empty()
    }

    /// Cell `cell`'s layout.
    #[inline(always)]
    pub(crate) fn layout_of(&self, cell: usize) -> usize {
        self.layout[cell] as usize
    }

    /// The layouts of the cells `cells`.
    #[inline(always)]
    pub(crate) fn layouts_of(&self, cells: std::ops::Range<usize>) -> &[u32] {
        &self.layout[cells]
    }

    /// `S_iα` of layout `l`'s points, `2^D` per point, point after point.
    #[inline(always)]
    pub(crate) fn shape_of(&self, l: usize) -> &[f64] {
        self.block(&self.shape, l, self.per_cell())
    }

    /// `∇S_iα` of layout `l`'s points, as [`Self::shape_of`].
    #[inline(always)]
    pub(crate) fn gradient_of(&self, l: usize) -> &[Vector<D>] {
        self.block(&self.gradient, l, self.per_cell())
    }

    /// `K_ab` of layout `l`, `(2^D - 1) × 2^D`, row `a` after row.
    #[inline(always)]
    pub(crate) fn volume_weights_of(&self, l: usize) -> &[Vector<D>] {
        self.block(&self.volume, l, Self::VOLUME)
    }

    /// `W_αi` of layout `l`'s points, as [`Self::shape_of`].
    #[inline(always)]
    pub(crate) fn mapping_weights_of(&self, l: usize) -> &[f64] {
        self.block(&self.mapping, l, self.per_cell())
    }

    /// `M_i` of layout `l`'s nodes.
    #[inline(always)]
    pub(crate) fn mass_of(&self, l: usize) -> &[f64] {
        self.block(&self.mass, l, Grid::<D>::NODES_PER_CELL)
    }

    /// `S_iα` of cell `cell`'s points ([`Self::shape_of`] its layout).
    #[inline(always)]
    pub(crate) fn shape(&self, cell: usize) -> &[f64] {
        self.shape_of(self.layout_of(cell))
    }
}

/// One cell's volume weights into `k` (`(2^D - 1) × 2^D`, row `a` after row),
/// `K_ab = Σ_α V_α S_bα ∇S_aα` over its points `α` (in point order from zero) from their
/// shape values `shape` and gradients `gradient` (`2^D` per point) and volumes `volume`.
/// The last node's row is not stored: `Σ_a K_ab = Σ_α V_α S_bα Σ_a ∇S_aα = 0` (the
/// partition of unity), so its terms are minus the others' sum
/// (`DgmpmSolver::rates_of_cell`).
///
/// With linear elasticity the volume term of node `a` (paper eq. 15),
/// `-Σ_α V_α σ_h(X_α) ∇S_aα` with `σ_h(X_α) = Σ_b S_bα σ_b` (and `v_h ⊗ ∇S_aα` likewise),
/// is `-Σ_b σ_b K_ab`: the points and volumes are fixed (total Lagrangian), so `K` is
/// formed once. The sums are associated differently from the per-point form, so the
/// rates agree with it to round-off, not bit for bit (`volume_weights_match_the_points`).
pub(crate) fn cell_volume_weights<const D: usize>(
    shape: &[f64],
    gradient: &[Vector<D>],
    volume: &[f64],
    k: &mut [Vector<D>],
) {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let rows = nodes_per_cell - 1;
    k.fill(Vector::<D>::zeros());
    let points = shape.chunks_exact(nodes_per_cell);
    let points = points
        .zip(gradient.chunks_exact(nodes_per_cell))
        .zip(volume);
    for ((s, g), &volume) in points {
        for a in 0..rows {
            let vg = g[a] * volume;
            for b in 0..nodes_per_cell {
                k[a * nodes_per_cell + b] += vg * s[b];
            }
        }
    }
}

/// One cell's phase-1 weights and lumped masses from its points' shape values `shape`
/// (`2^D` per point) and masses `mass`: `M_i = Σ_α S_iα m_α` (in point order from zero,
/// as `cell_sums` forms it) into `node_mass` and `W_αi = S_iα m_α / M_i` (0 where
/// `M_i = 0`) into `weights`, `2^D` per point, point after point. Phase 1 is then
/// `q_i = Σ_α W_αi q_α` ([`crate::DgmpmSolver::particles_to_nodes`]).
pub(crate) fn cell_mapping_weights<const D: usize>(
    shape: &[f64],
    mass: &[f64],
    weights: &mut [f64],
    node_mass: &mut [f64],
) {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    node_mass.fill(0.0);
    weights.fill(0.0);
    for (s, m) in shape.chunks_exact(nodes_per_cell).zip(mass) {
        for a in 0..nodes_per_cell {
            node_mass[a] += s[a] * m;
        }
    }
    let points = weights.chunks_exact_mut(nodes_per_cell);
    for ((w, s), m) in points.zip(shape.chunks_exact(nodes_per_cell)).zip(mass) {
        for a in 0..nodes_per_cell {
            if node_mass[a] > 0.0 {
                w[a] = s[a] * m / node_mass[a];
            }
        }
    }
}

/// The local coordinates of every point in its cell, or the error of a point outside the
/// grid.
fn local_coordinates<'a, const D: usize>(
    grid: &'a Grid<D>,
    points: &'a MaterialPoints<D>,
) -> impl Iterator<Item = Result<Vector<D>, CoreError>> + 'a {
    points.reference.iter().map(move |x| {
        grid.locate(x).map(|(_, xi)| xi).ok_or_else(|| {
            unsupported(&format!(
                "material point at {:?} lies outside the grid (degenerate cell sizes?)",
                x.as_slice()
            ))
        })
    })
}

/// Whether every point lies strictly inside its cell (every `S_iα > 0`), without storing
/// the shape functions.
pub(crate) fn all_inside<const D: usize>(
    grid: &Grid<D>,
    points: &MaterialPoints<D>,
) -> Result<bool, CoreError> {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let mut shape = [0.0; MAX_NODES];
    let mut gradient = [Vector::<D>::zeros(); MAX_NODES];
    let mut inside = true;
    for xi in local_coordinates(grid, points) {
        grid.shape(
            &xi?,
            &mut shape[..nodes_per_cell],
            &mut gradient[..nodes_per_cell],
        );
        inside &= shape[..nodes_per_cell].iter().all(|&w| w > 0.0);
    }
    Ok(inside)
}

/// `S_iα` and `∇S_iα` of every point's local nodes (`points × 2^D` each), at the points'
/// (fixed) reference positions (the Heun cell sweeps' weights are formed from them,
/// `fused/heun.rs`).
#[allow(clippy::type_complexity)]
pub(crate) fn shapes<const D: usize>(
    grid: &Grid<D>,
    points: &MaterialPoints<D>,
) -> Result<(Vec<f64>, Vec<Vector<D>>), CoreError> {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let mut shape = vec![0.0; points.len() * nodes_per_cell];
    let mut shape_gradient = vec![Vector::<D>::zeros(); points.len() * nodes_per_cell];
    for (p, xi) in local_coordinates(grid, points).enumerate() {
        let range = p * nodes_per_cell..(p + 1) * nodes_per_cell;
        grid.shape(&xi?, &mut shape[range.clone()], &mut shape_gradient[range]);
    }
    Ok((shape, shape_gradient))
}

#[cfg(test)]
mod tests;

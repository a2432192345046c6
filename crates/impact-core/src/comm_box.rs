//! One rank's box of a grid split over a grid of ranks (issue 27): [`RankGrid`] says how
//! many parts each axis is split into (`--ranks-grid px,py[,pz]`, or automatic), and
//! [`RankBox`] is one rank's share, its owned cells along every axis plus a halo.
//!
//! **Splitting.** Axis `k` of `n_k` cells is split into `p_k` contiguous runs, the first
//! `n_k mod p_k` one cell longer; the product of the parts is the rank count. Ranks are
//! numbered lexicographically over the rank grid with axis 0 fastest (`r = Σ_k c_k Π_{j<k}
//! p_j`), like the cells, so the slab decomposition `1 × … × 1 × N` numbers its slabs along
//! the last axis in order. **Automatic** (no `--ranks-grid`) is that slab decomposition:
//! each rank then talks to two neighbours only (the fewest messages); boxes pay off when the
//! last axis is short or the rank count large (their halo is smaller than a slab's).
//!
//! **Stored cells.** A rank stores its box plus `halo` cells of its neighbours along every
//! axis, clamped at the grid's ends: the faces, edges and corners of the box. A face of the
//! stored box is a physical edge ([`RankBox::physical_edge`]) only where the box reaches the
//! end of the grid along that axis; elsewhere it is a cut whose halo the neighbour refreshes.
//!
//! **Corners with no extra message.** The halo is exchanged axis by axis, each axis with
//! its two face neighbours only: along axis `a` a rank sends the layers of its own cells
//! next to the cut, extended across the axes `k < a` over the whole stored range (the halo
//! just received along those axes) and over the owned range along the axes `k > a`. The
//! corner and edge cells of the halo then arrive through the axis-`a` neighbour, which
//! received them from its own axis-`k` neighbour one exchange earlier: `D` exchanges of two
//! messages each fill the whole halo, instead of messages to all `3^D − 1` neighbours
//! ([`RankBox::sent`], [`RankBox::received`]).
//!
//! **Order.** A box's stored cells are numbered lexicographically (axis 0 fastest) within
//! the box, which keeps the global relative order of its cells; per-cell loops and per-node
//! sums see the same sequence as on one rank. Gathered values are put back in the global
//! order by the global cell index ([`RankBox::global_cell`]).
use crate::comm::CommError;
use std::ops::Range;

/// How many parts each axis is split into (module doc): the parts along axes `0, 1, …`
/// given by the user (`--ranks-grid px,py[,pz]`; axes not named get one part), or empty for
/// the automatic choice, slabs along the last axis.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RankGrid(pub Vec<usize>);

impl RankGrid {
    /// The automatic choice: slabs along the last axis.
    pub fn automatic() -> Self {
        Self(Vec::new())
    }

    /// Whether this grid is (or automatically becomes) slabs along the last axis on any
    /// dimension `dim`.
    pub fn is_slabs(&self, dim: usize) -> bool {
        self.0.is_empty() || self.0.iter().take(dim.saturating_sub(1)).all(|&p| p == 1)
    }

    /// The parts per axis for a `dim`-dimensional grid on `ranks` ranks. Refused: more
    /// entries than axes, a zero entry, or a product other than the rank count.
    pub fn parts(&self, dim: usize, ranks: usize) -> Result<Vec<usize>, CommError> {
        let text = || {
            self.0
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(",")
        };
        if self.0.is_empty() {
            let mut parts = vec![1; dim];
            parts[dim - 1] = ranks;
            return Ok(parts);
        }
        let bad = |why: String| CommError::RankGrid {
            grid: text(),
            message: why,
        };
        if self.0.len() > dim {
            return Err(bad(format!(
                "it has {} entries but the grid is {dim}D: give at most {dim} (px{})",
                self.0.len(),
                [",py", ",py,pz"][..dim.saturating_sub(1)].concat()
            )));
        }
        if self.0.contains(&0) {
            return Err(bad("every entry must be at least 1".into()));
        }
        let mut parts = self.0.clone();
        parts.resize(dim, 1);
        let product: usize = parts.iter().product();
        if product != ranks {
            return Err(bad(format!(
                "its product is {product} but the run has {ranks} ranks: the parts must \
                 multiply to the rank count"
            )));
        }
        Ok(parts)
    }
}

/// One rank's share of a grid split over a grid of ranks (module doc). Cell indices are
/// global unless named `local` (indices into the stored box).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RankBox {
    /// This rank.
    pub rank: usize,
    /// Number of ranks.
    pub ranks: usize,
    /// Parts per axis (their product is `ranks`).
    pub parts: Vec<usize>,
    /// This rank's place in the rank grid, per axis.
    pub coords: Vec<usize>,
    /// Cells of the whole grid per axis.
    pub cells: Vec<usize>,
    /// Halo width (cells stored from each neighbour along each axis).
    pub halo: usize,
    /// The cells this rank owns, per axis.
    pub owned: Vec<Range<usize>>,
    /// The cells it stores per axis: owned plus the halo, clamped to the grid.
    pub stored: Vec<Range<usize>>,
}

impl RankBox {
    /// Rank `rank`'s box of a grid of `cells` split as `grid` says over `ranks` ranks, with
    /// a halo of `halo` cells. Refused where the rank grid is not one for `ranks` ranks
    /// ([`RankGrid::parts`]) or an axis split in several parts has parts of fewer cells than
    /// the halo (its neighbours' halos would reach past it). Every rank refuses alike.
    pub fn new(
        cells: &[usize],
        grid: &RankGrid,
        ranks: usize,
        rank: usize,
        halo: usize,
    ) -> Result<Self, CommError> {
        let dim = cells.len();
        let parts = grid.parts(dim, ranks.max(1))?;
        let needed = halo.max(1);
        for (axis, (&n, &p)) in cells.iter().zip(&parts).enumerate() {
            if p > 1 && n / p < needed {
                return Err(CommError::TooManyRanks {
                    ranks: p,
                    layers: n,
                    axis,
                    needed,
                    most: (n / needed).max(1),
                });
            }
        }
        if ranks == 0 || rank >= ranks {
            return Err(CommError::TooManyRanks {
                ranks,
                layers: cells[dim - 1],
                axis: dim - 1,
                needed,
                most: (cells[dim - 1] / needed).max(1),
            });
        }
        let mut rest = rank;
        let coords: Vec<usize> = parts
            .iter()
            .map(|&p| {
                let c = rest % p;
                rest /= p;
                c
            })
            .collect();
        let owned: Vec<Range<usize>> = (0..dim)
            .map(|k| {
                let (base, extra) = (cells[k] / parts[k], cells[k] % parts[k]);
                let start = coords[k] * base + coords[k].min(extra);
                start..start + base + usize::from(coords[k] < extra)
            })
            .collect();
        let stored = (0..dim)
            .map(|k| owned[k].start.saturating_sub(halo)..(owned[k].end + halo).min(cells[k]))
            .collect();
        Ok(Self {
            rank,
            ranks,
            parts,
            coords,
            cells: cells.to_vec(),
            halo,
            owned,
            stored,
        })
    }

    /// [`Self::new`] for the rank of `comm` among its ranks.
    pub fn for_rank(
        cells: &[usize],
        grid: &RankGrid,
        comm: &(impl crate::comm::Comm + ?Sized),
        halo: usize,
    ) -> Result<Self, CommError> {
        Self::new(cells, grid, comm.size(), comm.rank(), halo)
    }

    /// The owned cells along `axis` in stored (local) indices.
    pub fn owned_local(&self, axis: usize) -> Range<usize> {
        let (own, stored) = (&self.owned[axis], &self.stored[axis]);
        own.start - stored.start..own.end - stored.start
    }

    /// Whether the stored box's low (`side = 0`) or high (`1`) face along `axis` is a
    /// physical edge (the body's boundary condition applies there; elsewhere it is a cut,
    /// whose halo cells the neighbour refreshes).
    pub fn physical_edge(&self, axis: usize, side: usize) -> bool {
        match side {
            0 => self.stored[axis].start == 0,
            _ => self.stored[axis].end == self.cells[axis],
        }
    }

    /// The neighbour rank along `axis` on the low (`side = 0`) or high (`1`) side, if any.
    pub fn neighbour(&self, axis: usize, side: usize) -> Option<usize> {
        let c = self.coords[axis];
        let stride: usize = self.parts[..axis].iter().product();
        match side {
            0 => (c > 0).then(|| self.rank - stride),
            _ => (c + 1 < self.parts[axis]).then(|| self.rank + stride),
        }
    }

    /// Both neighbours along `axis` (low, high).
    pub fn neighbours(&self, axis: usize) -> [Option<usize>; 2] {
        [self.neighbour(axis, 0), self.neighbour(axis, 1)]
    }

    /// Cells received along `axis` from the low (`side = 0`) or high (`1`) neighbour.
    pub fn halo_width(&self, axis: usize, side: usize) -> usize {
        match side {
            0 => self.owned[axis].start - self.stored[axis].start,
            _ => self.stored[axis].end - self.owned[axis].end,
        }
    }

    /// Stored cells per axis.
    pub fn stored_counts(&self) -> Vec<usize> {
        self.stored.iter().map(Range::len).collect()
    }

    /// The local box (per axis, local indices) sent along `axis` to the `side` neighbour:
    /// the owned cells next to the cut, across the stored range of the axes before `axis`
    /// and the owned range of those after (module doc).
    pub fn sent(&self, axis: usize, side: usize) -> Vec<Range<usize>> {
        let width = self.halo_width(axis, side);
        self.slab_across(axis, |own, _| match side {
            0 => own.start..own.start + width,
            _ => own.end - width..own.end,
        })
    }

    /// The local box received along `axis` from the `side` neighbour (its [`Self::sent`]).
    pub fn received(&self, axis: usize, side: usize) -> Vec<Range<usize>> {
        let width = self.halo_width(axis, side);
        self.slab_across(axis, |own, stored_len| match side {
            0 => 0..width,
            _ => own.end..stored_len,
        })
    }

    fn slab_across(
        &self,
        axis: usize,
        along: impl Fn(Range<usize>, usize) -> Range<usize>,
    ) -> Vec<Range<usize>> {
        (0..self.cells.len())
            .map(|k| match k.cmp(&axis) {
                std::cmp::Ordering::Less => 0..self.stored[k].len(),
                std::cmp::Ordering::Equal => along(self.owned_local(k), self.stored[k].len()),
                std::cmp::Ordering::Greater => self.owned_local(k),
            })
            .collect()
    }

    /// The local cell indices of the local box `ranges` in lexicographic order (axis 0
    /// fastest), each index into the stored box's cells.
    pub fn local_cells(&self, ranges: &[Range<usize>]) -> Vec<usize> {
        lexicographic(ranges, &self.stored_counts())
    }

    /// The global index of the stored box's local cell `local`.
    pub fn global_cell(&self, local: usize) -> usize {
        let (mut rest, mut global, mut stride) = (local, 0, 1);
        for k in 0..self.cells.len() {
            let n = self.stored[k].len();
            global += (self.stored[k].start + rest % n) * stride;
            rest /= n;
            stride *= self.cells[k];
        }
        global
    }

    /// The owned cells as runs of consecutive local cells (rows along axis 0), in order.
    pub fn owned_runs(&self) -> Vec<Range<usize>> {
        let mut rows = self.owned_local_all();
        let along = rows[0].clone();
        rows[0] = 0..1;
        lexicographic(&rows, &self.stored_counts())
            .into_iter()
            .map(|first| first + along.start..first + along.end)
            .collect()
    }

    fn owned_local_all(&self) -> Vec<Range<usize>> {
        (0..self.cells.len()).map(|k| self.owned_local(k)).collect()
    }

    /// Whether this is the slab decomposition (one part on every axis but the last).
    pub fn is_slabs(&self) -> bool {
        self.parts[..self.parts.len() - 1].iter().all(|&p| p == 1)
    }

    /// A one-line description for summaries: the rank grid, the cells and the halo.
    pub fn describe(&self) -> String {
        let join = |v: &[usize]| {
            v.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" × ")
        };
        let dim = self.cells.len();
        if self.is_slabs() {
            format!(
                "{} slabs along axis {} (rank grid {}, {} layers, halo {})",
                self.ranks,
                dim - 1,
                join(&self.parts),
                self.cells[dim - 1],
                self.halo
            )
        } else {
            format!(
                "{} boxes (rank grid {}, {} cells, halo {} along every axis)",
                self.ranks,
                join(&self.parts),
                join(&self.cells),
                self.halo
            )
        }
    }
}

/// The indices, in a box of `counts` cells per axis numbered lexicographically (axis 0
/// fastest), of the cells of the sub-box `ranges`, in that order (also the FEM's boxes of
/// nodes).
pub fn lexicographic(ranges: &[Range<usize>], counts: &[usize]) -> Vec<usize> {
    let mut out = vec![0usize];
    let mut stride = 1;
    for (range, &n) in ranges.iter().zip(counts) {
        // the earlier axes vary fastest: this axis's offsets wrap round them
        out = range
            .clone()
            .flat_map(|i| out.iter().map(move |&o| o + i * stride))
            .collect();
        stride *= n;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boxes cover every cell once; the sent boxes match the neighbours' received ones
    /// cell for cell in global indices; halos are clamped at the physical edges; bad rank
    /// grids are refused with the reason.
    #[test]
    fn boxes_partition_the_grid_and_halos_match() {
        let cells = [7usize, 5, 4];
        for parts in [vec![1, 1, 4], vec![2, 2, 1], vec![3, 1, 1], vec![1, 2, 2]] {
            let ranks: usize = parts.iter().product();
            let grid = RankGrid(parts.clone());
            let boxes: Vec<RankBox> = (0..ranks)
                .map(|r| RankBox::new(&cells, &grid, ranks, r, 1).unwrap())
                .collect();
            let mut owner = vec![usize::MAX; cells.iter().product()];
            for b in &boxes {
                for run in b.owned_runs() {
                    for local in run {
                        let g = b.global_cell(local);
                        assert_eq!(owner[g], usize::MAX, "cell {g} owned twice");
                        owner[g] = b.rank;
                    }
                }
                for axis in 0..3 {
                    for side in 0..2 {
                        // physical where the stored box reaches the grid's end (always
                        // without a neighbour; a thin neighbour's box may let the halo reach it)
                        let reach = [
                            b.owned[axis].start <= 1,
                            b.owned[axis].end + 1 >= cells[axis],
                        ];
                        assert_eq!(b.physical_edge(axis, side), reach[side]);
                        assert!(b.neighbour(axis, side).is_some() || b.physical_edge(axis, side));
                        let Some(n) = b.neighbour(axis, side) else {
                            continue;
                        };
                        let mine: Vec<usize> = b.local_cells(&b.sent(axis, side));
                        let other = &boxes[n];
                        let theirs = other.local_cells(&other.received(axis, 1 - side));
                        let g = |bx: &RankBox, v: &[usize]| -> Vec<usize> {
                            v.iter().map(|&c| bx.global_cell(c)).collect()
                        };
                        assert_eq!(g(b, &mine), g(other, &theirs));
                    }
                }
            }
            assert!(owner.iter().all(|&r| r < ranks));
        }
        let refuse = |grid: Vec<usize>, ranks: usize| {
            RankBox::new(&cells, &RankGrid(grid), ranks, 0, 2)
                .unwrap_err()
                .to_string()
        };
        assert!(refuse(vec![2, 2], 3).contains("product is 4 but the run has 3 ranks"));
        assert!(refuse(vec![1, 1, 1, 2], 2).contains("4 entries but the grid is 3D"));
        let thin = refuse(vec![1, 3], 3);
        assert!(thin.contains("3 ranks cannot share the 5 layers of cells along axis 1"));
        assert!(thin.contains("at most 2 ranks"), "{thin}");
    }
}

//! Where a solver's stored mesh lies in the whole one: all of it on one rank, a box of
//! elements (per axis a run of element layers; the slab along the last axis a special case)
//! on several (`slab.rs`). Positions are always formed from the whole mesh and global
//! indices (`global.vertex_position(global_node(i))`), never from the box's shifted origin,
//! whose sums round differently: so the loads' segments, the initial fields and the sample
//! places are the same bits as on one rank.
//!
//! Local nodes and elements are numbered lexicographically within the stored box (axis 0
//! fastest), which keeps the global relative order of the box's nodes and elements; the
//! owned ones are a run per row along axis 0, merged where consecutive (one run on one rank
//! and on slabs, so their loops are the one-rank ones).
use impact_core::comm_box::lexicographic;
use impact_core::{Grid, Vector};
use std::ops::Range;

/// The stored elements `stored` (per axis, global indices) of the whole mesh `global`, of
/// which `owned` belong to this solver (the whole ranges on one rank).
#[derive(Debug, Clone)]
pub(crate) struct Place<const D: usize> {
    /// The whole mesh.
    pub(crate) global: Grid<D>,
    /// Global index of the first stored element (and node) along each axis.
    pub(crate) offset: [usize; D],
    /// Stored elements per axis.
    stored: [usize; D],
    /// The owned nodes per axis (local indices): the node layers of the owned elements'
    /// lower faces, and the top face too where the owned elements end the mesh.
    owned_node_axes: [Range<usize>; D],
    /// The owned nodes (local indices) as runs of consecutive nodes, in order.
    pub(crate) owned_nodes: Vec<Range<usize>>,
    /// The owned elements (local indices) as runs of consecutive elements, in order.
    pub(crate) owned_elements: Vec<Range<usize>>,
    /// The nodes of the owned elements (local indices: per axis the node layers
    /// `[a, b]` of the owned element layers `[a, b)`, the owned nodes plus the layer `b`
    /// of the cut above) as runs, in order: the rank's piece of the mesh at outputs.
    piece_nodes: Vec<Range<usize>>,
}

impl<const D: usize> Place<D> {
    /// Elements `stored` of `global`, `owned` among them (per axis, global indices).
    pub(crate) fn new(
        global: &Grid<D>,
        stored: &[Range<usize>; D],
        owned: &[Range<usize>; D],
    ) -> Self {
        let local = |k: usize| owned[k].start - stored[k].start..owned[k].end - stored[k].start;
        let owned_elements: [Range<usize>; D] = std::array::from_fn(local);
        let owned_node_axes: [Range<usize>; D] = std::array::from_fn(|k| {
            let top = usize::from(owned[k].end == global.cells[k]);
            owned_elements[k].start..owned_elements[k].end + top
        });
        let stored_counts: [usize; D] = std::array::from_fn(|k| stored[k].len());
        let node_counts = stored_counts.map(|n| n + 1);
        let piece_node_axes: [Range<usize>; D] =
            std::array::from_fn(|k| owned_elements[k].start..owned_elements[k].end + 1);
        Self {
            global: global.clone(),
            offset: std::array::from_fn(|k| stored[k].start),
            stored: stored_counts,
            owned_nodes: runs(&owned_node_axes, &node_counts),
            owned_elements: runs(&owned_elements, &stored_counts),
            piece_nodes: runs(&piece_node_axes, &node_counts),
            owned_node_axes,
        }
    }

    /// Global index of the first stored element layer along the last axis.
    #[inline]
    pub(crate) fn first_layer(&self) -> usize {
        self.offset[D - 1]
    }

    /// Per-axis local indices of local entry `i` of a box of `counts` per axis.
    #[inline]
    fn split(mut i: usize, counts: impl Fn(usize) -> usize) -> [usize; D] {
        std::array::from_fn(|k| {
            let at = i % counts(k);
            i /= counts(k);
            at
        })
    }

    /// Global index of local node `i`.
    #[inline]
    pub(crate) fn global_node(&self, i: usize) -> usize {
        let at = Self::split(i, |k| self.stored[k] + 1);
        let (mut global, mut stride) = (0, 1);
        for k in 0..D {
            global += (self.offset[k] + at[k]) * stride;
            stride *= self.global.cells[k] + 1;
        }
        global
    }

    /// Global index of local element `c`.
    #[inline]
    pub(crate) fn global_element(&self, c: usize) -> usize {
        let at = Self::split(c, |k| self.stored[k]);
        let (mut global, mut stride) = (0, 1);
        for k in 0..D {
            global += (self.offset[k] + at[k]) * stride;
            stride *= self.global.cells[k];
        }
        global
    }

    /// Elements of the whole mesh around local node `i` (`2^D` inside, fewer on its faces).
    pub(crate) fn elements_around(&self, i: usize) -> usize {
        let at = Self::split(i, |k| self.stored[k] + 1);
        (0..D)
            .map(|k| {
                let g = self.offset[k] + at[k];
                usize::from(g > 0) + usize::from(g < self.global.cells[k])
            })
            .product()
    }

    /// Position of local node `i` in the undeformed mesh (from the whole mesh).
    #[inline]
    pub(crate) fn node_position(&self, i: usize) -> Vector<D> {
        self.global.vertex_position(self.global_node(i))
    }

    /// Centre of local element `c` (from the whole mesh).
    #[inline]
    pub(crate) fn element_centre(&self, c: usize) -> Vector<D> {
        self.global.cell_centre(self.global_element(c))
    }

    /// Whether local node `i` is owned (its loads' work and impulse count here).
    #[inline]
    pub(crate) fn owns_node(&self, i: usize) -> bool {
        let at = Self::split(i, |k| self.stored[k] + 1);
        (0..D).all(|k| self.owned_node_axes[k].contains(&at[k]))
    }

    /// The owned nodes in order (local indices).
    pub(crate) fn owned_node_iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.owned_nodes.iter().flat_map(Clone::clone)
    }

    /// The nodes of the owned elements in order (local indices; every node on one rank).
    pub(crate) fn piece_node_iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.piece_nodes.iter().flat_map(Clone::clone)
    }

    /// The owned elements in order (local indices).
    pub(crate) fn owned_element_iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.owned_elements.iter().flat_map(Clone::clone)
    }
}

/// The entries of the sub-box `ranges` of a box of `counts` per axis (lexicographic, axis 0
/// fastest) as runs of consecutive indices, a row along axis 0 each, merged where one row
/// ends where the next starts.
fn runs<const D: usize>(ranges: &[Range<usize>; D], counts: &[usize; D]) -> Vec<Range<usize>> {
    let mut rows = ranges.to_vec();
    let along = std::mem::replace(&mut rows[0], 0..1);
    let mut out: Vec<Range<usize>> = Vec::new();
    if along.is_empty() {
        return out;
    }
    for first in lexicographic(&rows, counts) {
        let row = first + along.start..first + along.end;
        match out.last_mut() {
            Some(last) if last.end == row.start => last.end = row.end,
            _ => out.push(row),
        }
    }
    out
}

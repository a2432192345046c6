//! Where a solver's stored mesh lies in the whole one: all of it on one rank, a slab of
//! element layers along the last axis on several (`slab.rs`). Positions are always formed
//! from the whole mesh and global indices (`global.vertex_position(offset + i)`), never
//! from the slab's shifted origin, whose sums round differently: so the loads' segments,
//! the initial fields and the sample places are the same bits as on one rank.
use impact_core::{Grid, Vector};
use std::ops::Range;

/// The stored element layers `stored` of the whole mesh `global`, of which `owned` belong
/// to this solver (global layer indices; both the whole range on one rank).
#[derive(Debug, Clone)]
pub(crate) struct Place<const D: usize> {
    /// The whole mesh.
    pub(crate) global: Grid<D>,
    /// Global index of the first stored element layer.
    pub(crate) first_layer: usize,
    /// The owned nodes (local indices): the node layers of the owned element layers' lower
    /// faces, and the top face too where the owned layers end the mesh.
    pub(crate) owned_nodes: Range<usize>,
    /// The owned elements (local indices).
    pub(crate) owned_elements: Range<usize>,
}

impl<const D: usize> Place<D> {
    /// Element layers `stored` of `global`, `owned` among them.
    pub(crate) fn new(global: &Grid<D>, stored: &Range<usize>, owned: &Range<usize>) -> Self {
        let (layer_nodes, layer_elements) = Self::layer_sizes(global);
        let layers = global.cells[D - 1];
        let owned_node_end = owned.end + usize::from(owned.end == layers);
        let local = |layer: usize| layer - stored.start;
        Self {
            global: global.clone(),
            first_layer: stored.start,
            owned_nodes: local(owned.start) * layer_nodes..local(owned_node_end) * layer_nodes,
            owned_elements: local(owned.start) * layer_elements..local(owned.end) * layer_elements,
        }
    }

    /// Nodes and elements per layer along the last axis.
    pub(crate) fn layer_sizes(grid: &Grid<D>) -> (usize, usize) {
        let nodes = grid.cells[..D - 1].iter().map(|n| n + 1).product();
        (nodes, grid.cells[..D - 1].iter().product())
    }

    /// Global index of local node `i`.
    #[inline]
    pub(crate) fn global_node(&self, i: usize) -> usize {
        i + self.first_layer * Self::layer_sizes(&self.global).0
    }

    /// Position of local node `i` in the undeformed mesh (from the whole mesh).
    #[inline]
    pub(crate) fn node_position(&self, i: usize) -> Vector<D> {
        self.global.vertex_position(self.global_node(i))
    }

    /// Centre of local element `c` (from the whole mesh).
    #[inline]
    pub(crate) fn element_centre(&self, c: usize) -> Vector<D> {
        let first = self.first_layer * Self::layer_sizes(&self.global).1;
        self.global.cell_centre(first + c)
    }

    /// Whether local node `i` is owned (its loads' work and impulse count here).
    #[inline]
    pub(crate) fn owns_node(&self, i: usize) -> bool {
        self.owned_nodes.contains(&i)
    }
}

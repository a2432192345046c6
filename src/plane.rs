//! The plane a colour map shows: in 2D the body; in 3D the cell layer that holds the
//! measuring line ([`impact_core::line`]), spanned by the line's axis and the next axis
//! (the x–y plane at the line's z for a line along x or y; the x–z plane at the line's y
//! for a line along z): for the block impact, the mid-plane through the impact.
use impact_core::line::MeasureLine;
use impact_core::{Grid, Vector};

/// A plane of cells of a `D`-dimensional grid (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPlane {
    /// The two in-plane axes, increasing (the map's horizontal and vertical axes).
    pub axes: [usize; 2],
    /// In 3D: the normal axis and the layer of cells along it.
    pub layer: Option<(usize, usize)>,
}

impl MapPlane {
    /// The plane of `grid` through `line` (module doc; `None` in 1D).
    pub fn of<const D: usize>(grid: &Grid<D>, line: &MeasureLine) -> Option<Self> {
        match D {
            1 => None,
            2 => Some(Self {
                axes: [0, 1],
                layer: None,
            }),
            _ => {
                let normal = if line.axis == 2 { 1 } else { 2 };
                let axes = if normal == 2 { [0, 1] } else { [0, 2] };
                let layer = grid.layer_of(normal, line.point::<D>(line.start)[normal]);
                Some(Self {
                    axes,
                    layer: Some((normal, layer)),
                })
            }
        }
    }

    /// The plane's own 2D grid.
    pub fn grid<const D: usize>(&self, g: &Grid<D>) -> Grid<2> {
        let [a, b] = self.axes;
        Grid::<2> {
            origin: Vector::<2>::new(g.origin[a], g.origin[b]),
            spacing: Vector::<2>::new(g.spacing[a], g.spacing[b]),
            cells: [g.cells[a], g.cells[b]],
        }
    }

    /// The index in the plane's grid of cell `cell` of `g`, if it lies in the plane.
    pub fn cell_in_plane<const D: usize>(&self, g: &Grid<D>, cell: usize) -> Option<usize> {
        let idx = g.cell_multi_index(cell);
        if let Some((normal, layer)) = self.layer {
            if idx[normal] != layer {
                return None;
            }
        }
        let [a, b] = self.axes;
        Some(idx[a] + g.cells[a] * idx[b])
    }

    /// The box of `g` a plane cell `[lo, hi]` stands for: its extent along the normal is
    /// the layer's.
    pub fn lift<const D: usize>(
        &self,
        g: &Grid<D>,
        lo: &Vector<2>,
        hi: &Vector<2>,
    ) -> (Vector<D>, Vector<D>) {
        let (mut low, mut high) = (g.origin, g.upper());
        for (slot, &axis) in self.axes.iter().enumerate() {
            low[axis] = lo[slot];
            high[axis] = hi[slot];
        }
        if let Some((normal, layer)) = self.layer {
            low[normal] = g.origin[normal] + layer as f64 * g.spacing[normal];
            high[normal] = low[normal] + g.spacing[normal];
        }
        (low, high)
    }

    /// A few words for figure titles: "" in 2D, "plane z = 1.44 m" in 3D (the layer's
    /// centre).
    pub fn describe<const D: usize>(&self, g: &Grid<D>) -> String {
        match self.layer {
            None => String::new(),
            Some((normal, layer)) => format!(
                "plane {} = {:.3} m",
                ["x", "y", "z"][normal],
                g.origin[normal] + (layer as f64 + 0.5) * g.spacing[normal]
            ),
        }
    }
}

//! The points' shape-function weights ([`crate::shape`]): evaluated at the current
//! positions every step (updated Lagrangian) or once at the reference positions (total
//! Lagrangian), stored one row per point, or one row shared by every point where they are
//! all equal, or (total Lagrangian otherwise) each distinct row once in a table with a
//! row index per point; and the points sorted by layer for the coloured scatters.
//!
//! The table ([`MpmSolver::tabulate_weights`]): a point's row (its `stencil.nodes` shape
//! values, then the gradients' components) is keyed on a hash of its bits, and a row
//! found under that hash is confirmed bit for bit before it is shared (so a collision
//! cannot merge two rows): every point reads exactly the row it would have stored itself.
//! A uniform seeding of `n` points per cell has a handful of distinct rows (`n` in the
//! body's interior, as in `impact-dgmpm`'s cell layouts); an irregular one up to one per
//! point, where the index is the identity and is dropped (a row per point, as before).
use crate::MpmSolver;
use impact_core::distinct::DistinctBlocks;
use impact_core::method::MpmFrame;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};
use std::convert::Infallible;

/// Points per chunk of the point loops.
const CHUNK: usize = 2048;

impl<const D: usize> MpmSolver<D> {
    /// Shape functions at the current (updated Lagrangian) or reference (total
    /// Lagrangian, computed once) positions ([`crate::shape`]).
    pub(crate) fn update_shapes(&mut self, points: &MaterialPoints<D>) {
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        if !moving && self.shapes_ready {
            return;
        }
        // new weights: phase 1 adds the masses again (`crate::NodeSums::point_mass`)
        self.nodes.point_mass_ready = false;
        let nodes = self.stencil.nodes;
        // on the whole grid, shifted to this one's nodes (`crate::Place`)
        let (grid, stencil, offset) = (&self.place.whole, &self.stencil, self.place.node_offset);
        let parts = (
            chunks(&mut self.point_base, CHUNK),
            chunks(&mut self.shape, CHUNK * nodes),
            chunks(&mut self.shape_gradient, CHUNK * nodes),
        );
        for_each_chunk(self.parallel, 1, parts, |r, (bases, shape, gradient)| {
            for (j, base) in bases.iter_mut().enumerate() {
                let p = r * CHUNK + j;
                let x = if moving {
                    &points.position[p]
                } else {
                    &points.reference[p]
                };
                let range = j * nodes..(j + 1) * nodes;
                let (values, gradients) = (&mut shape[range.clone()], &mut gradient[range]);
                // a point whose stencil leaves the padded grid keeps its last stencil and
                // weights; check_finite reports it
                let evaluated = match points.domain.get(p) {
                    Some(domain) => stencil.evaluate_domain(grid, x, domain, values, gradients),
                    None => stencil.evaluate(grid, x, values, gradients),
                };
                if let Some((b, _)) = evaluated {
                    *base = b - offset;
                }
            }
        });
        self.sort_by_layer();
    }

    /// The weights' storage, at construction: in the total Lagrangian frame, if every
    /// point's weights equal the first point's (to 1e-12 of their size: the same local
    /// position in every cell), one row shared by all (`weight_stride` 0) and the shapes
    /// are ready; otherwise a row per point, filled by [`Self::update_shapes`]. The shared
    /// row is evaluated at `share_from`, the reference position and CPDI domain of the
    /// body's first point (a slab's first point is another one: its row would differ from
    /// one rank's in the last bits).
    pub(crate) fn allocate_weights(
        &mut self,
        points: &MaterialPoints<D>,
        share_from: (Option<Vector<D>>, Option<Tensor<D>>),
    ) {
        let nodes = self.stencil.nodes;
        let count = points.len();
        if let (MpmFrame::TotalLagrangian, Some(first_x)) = (self.options.frame, share_from.0) {
            let mut first = (vec![0.0; nodes], vec![Vector::<D>::zeros(); nodes]);
            let mut other = first.clone();
            let (grid, stencil) = (&self.place.whole, &self.stencil);
            let offset = self.place.node_offset;
            let evaluate =
                |x: &Vector<D>,
                 domain: Option<&Tensor<D>>,
                 (values, gradients): &mut (Vec<f64>, Vec<Vector<D>>)| {
                    match domain {
                        Some(domain) => stencil.evaluate_domain(grid, x, domain, values, gradients),
                        None => stencil.evaluate(grid, x, values, gradients),
                    }
                };
            let base = evaluate(&first_x, share_from.1.as_ref(), &mut first);
            let scale = first.1.iter().map(|g| g.amax()).fold(0.0, f64::max);
            let mut shared = base.is_some();
            for p in 0..count {
                match evaluate(&points.reference[p], points.domain.get(p), &mut other) {
                    Some((b, _)) => self.point_base[p] = b - offset,
                    None => shared = false,
                }
                shared &= other
                    .0
                    .iter()
                    .zip(&first.0)
                    .all(|(a, b)| (a - b).abs() <= 1e-12);
                shared &=
                    (other.1.iter().zip(&first.1)).all(|(a, b)| (a - b).amax() <= 1e-12 * scale);
                if !shared {
                    break;
                }
            }
            if shared {
                (self.shape, self.shape_gradient) = first;
                self.weight_stride = 0;
                self.shapes_ready = true;
                self.sort_by_layer();
                return;
            }
        }
        self.weight_stride = nodes;
        if self.options.frame == MpmFrame::TotalLagrangian && self.tabulate_weights(points) {
            self.shapes_ready = true;
            self.sort_by_layer();
            return;
        }
        self.shape = vec![0.0; count * nodes];
        self.shape_gradient = vec![Vector::<D>::zeros(); count * nodes];
        self.point_row = Vec::new();
    }

    /// The total Lagrangian weights as a table of the distinct rows (module doc): each
    /// point's row evaluated at its reference position (and CPDI domain) as
    /// [`Self::update_shapes`] does, stored once per distinct bit pattern, with the point's
    /// index into the table in `point_row` (dropped where it is the identity: every row
    /// distinct). `false` (nothing stored) where a point's stencil leaves the padded grid
    /// (its row is then kept per point, as before) or the points outnumber `u32`.
    pub(crate) fn tabulate_weights(&mut self, points: &MaterialPoints<D>) -> bool {
        let nodes = self.stencil.nodes;
        let count = points.len();
        if u32::try_from(count).is_err() {
            return false;
        }
        let (grid, stencil, offset) = (&self.place.whole, &self.stencil, self.place.node_offset);
        let mut values = vec![0.0; nodes];
        let mut gradients = vec![Vector::<D>::zeros(); nodes];
        let mut table: Rows<D> = (Vec::new(), Vec::new());
        let mut point_row = Vec::with_capacity(count);
        let mut index = DistinctBlocks::new();
        for p in 0..count {
            let x = &points.reference[p];
            let evaluated = match points.domain.get(p) {
                Some(domain) => {
                    stencil.evaluate_domain(grid, x, domain, &mut values, &mut gradients)
                }
                None => stencil.evaluate(grid, x, &mut values, &mut gradients),
            };
            let Some((base, _)) = evaluated else {
                return false;
            };
            self.point_base[p] = base - offset;
            let holds = |(shape, gradient): &Rows<D>, r: u32| {
                let held = r as usize * nodes..(r as usize + 1) * nodes;
                let bits = row_bits(&shape[held.clone()], &gradient[held]);
                bits.eq(row_bits(&values, &gradients))
            };
            let push = |(shape, gradient): &mut Rows<D>| {
                // at most `count` rows: fits (checked above)
                let r = (shape.len() / nodes) as u32;
                shape.extend_from_slice(&values);
                gradient.extend_from_slice(&gradients);
                Ok::<u32, Infallible>(r)
            };
            let bits = row_bits(&values, &gradients);
            let Ok(row) = index.find_or_push(&mut table, bits, holds, push);
            point_row.push(row);
        }
        let (mut shape, mut shape_gradient) = table;
        shape.shrink_to_fit();
        shape_gradient.shrink_to_fit();
        (self.shape, self.shape_gradient) = (shape, shape_gradient);
        // every row distinct: row `p` is point `p`'s, no index needed
        self.point_row = if self.shape.len() == count * nodes {
            Vec::new()
        } else {
            point_row
        };
        true
    }

    /// How the weights are stored: `(rows, indexed)`, the rows held and whether the points
    /// read theirs through an index (the table of distinct rows, `tabulate_weights`).
    pub fn weight_rows(&self) -> (usize, bool) {
        let nodes = self.stencil.nodes.max(1);
        (self.shape.len() / nodes, !self.point_row.is_empty())
    }

    /// Where point `p`'s row of weights starts in `shape` and `shape_gradient`.
    #[inline]
    pub(crate) fn weight_row_start(&self, p: usize) -> usize {
        row_start(&self.point_row, self.weight_stride, p)
    }

    /// Whether every point reads one shared row of weights (see `allocate_weights`).
    pub fn shares_weights(&self) -> bool {
        self.weight_stride == 0
    }

    /// Store a row of weights per point again (the reference the shared row is tested
    /// against); they are evaluated in the next step.
    pub fn unshare_weights(&mut self, points: &MaterialPoints<D>) {
        let nodes = self.stencil.nodes;
        self.shape = vec![0.0; points.len() * nodes];
        self.shape_gradient = vec![Vector::<D>::zeros(); points.len() * nodes];
        self.weight_stride = nodes;
        self.point_row = Vec::new();
        self.shapes_ready = false;
    }

    /// Sort the points by the layer (along the last axis) of their stencil's base node into
    /// `layer_order` (a counting sort, stable: points already in cell order keep it). Where
    /// that order is the points' own, the scatters read no order (`in_layer_order`), and in
    /// the total Lagrangian frame, sorted once, `layer_order` is freed.
    pub(crate) fn sort_by_layer(&mut self) {
        // freed by an earlier sort in the total Lagrangian frame
        self.layer_order.resize(self.point_base.len(), 0);
        let layer_nodes: usize = self.grid.cells[..D - 1].iter().map(|n| n + 1).product();
        let starts = &mut self.layer_start;
        starts.iter_mut().for_each(|s| *s = 0);
        for &base in &self.point_base {
            starts[base / layer_nodes + 1] += 1;
        }
        for k in 1..starts.len() {
            starts[k] += starts[k - 1];
        }
        // `starts[k]` is the next free slot of layer k while filling; shifted back after
        // within a layer in the global point order (`Place::scatter_order`)
        let by_id = &self.place.scatter_order;
        for k in 0..self.point_base.len() {
            let p = if by_id.is_empty() { k } else { by_id[k] };
            let layer = self.point_base[p] / layer_nodes;
            self.layer_order[starts[layer]] = p;
            starts[layer] += 1;
        }
        for k in (1..starts.len()).rev() {
            starts[k] = starts[k - 1];
        }
        starts[0] = 0;
        self.in_layer_order = self.layer_order.iter().enumerate().all(|(k, &p)| k == p);
        if self.in_layer_order && self.options.frame == MpmFrame::TotalLagrangian {
            self.layer_order = Vec::new();
        }
    }
}

#[cfg(test)]
mod tests;

/// Where point `p`'s row of weights starts: `r · stride` with `r = point_row[p]`, or
/// `r = p` where `point_row` is empty (a row per point, or `stride` 0: one shared row).
#[inline]
pub(crate) fn row_start(point_row: &[u32], stride: usize, p: usize) -> usize {
    let r = if point_row.is_empty() {
        p
    } else {
        point_row[p] as usize
    };
    r * stride
}

/// The bits of a row of weights: its shape values, then its gradients' components.
fn row_bits<'a, const D: usize>(
    values: &'a [f64],
    gradients: &'a [Vector<D>],
) -> impl Iterator<Item = u64> + 'a {
    let gradients = gradients.iter().flat_map(|g| g.iter().map(|x| x.to_bits()));
    values.iter().map(|x| x.to_bits()).chain(gradients)
}

/// The table of distinct rows being formed: shape values and gradients.
type Rows<const D: usize> = (Vec<f64>, Vec<Vector<D>>);

//! Transfers between points and grid: phase 1 (particles→grid, internal and external
//! forces), phase 3 (grid→particles), phase 4 (the MUSL remap), phase 5 (stress update)
//! and the prescribed point velocities; phases 3-5 are in `transfer/gather.rs`.
//!
//! Scatters (points adding to the nodes of their cell) are coloured by blocks of cell
//! layers along the last axis: a point of cell layer `j` writes node layers `j` to
//! `j + w - 1` only (`w` nodes per axis), so a block of `B ≥ w - 1` layers writes within the
//! `2B` node layers up to the next block but one, and the even blocks, then the odd ones,
//! write disjoint bands of the nodal arrays, each band on its own rayon task (disjoint
//! writes through `split_at_mut`, no partial sums, no lock, no unsafe). Blocks of
//! `BLOCK_LAYERS` (8) layers, fixed by the grid: a block's nodes stay in cache while its
//! points add to them (colouring single layers sent every node layer through memory once
//! per colour), and sums do not depend on the thread count. The blocks follow the whole
//! grid's layers, so a rank's slab (`slab.rs`) adds each node's points in the order of one
//! rank's run (the colour passes change that order for nodes where two blocks meet). A
//! serial run takes one pass,
//! layer by layer, zeroing each node layer just before its first point. The points are
//! counting-sorted by layer when their cells change (once in the total Lagrangian frame,
//! where they are in layer order from the start and the scatters read them directly).
//! Point loops write disjoint points.
use crate::{Band, MpmSolver};
use impact_core::method::{Model, MpmFrame, MpmOptions, MpmTransfer};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{LinearElastic, Tensor, Vector};

/// Points (or nodes) per chunk of the point and node loops.
pub(crate) const CHUNK: usize = 2048;
/// Point layers per block of the coloured scatter (module doc): a block's node layers
/// (about 40 KB each at 1000 cells a row in 2D) stay in cache while its points add to them.
const BLOCK_LAYERS: usize = 8;

/// The point velocity update of the transfers without an affine part, with
/// `v_i = Σ_i N_ip p_i/m_i` the interpolated new nodal velocity and
/// `Δv = Σ_i N_ip Δv_i` the interpolated increment (`Δv_i = f_i (Δt (1/m_i))`, formed
/// per node by the grid update).
#[derive(Clone, Copy)]
pub(crate) enum PointVelocity {
    /// FLIP (Brackbill & Ruppel 1986): `v_p += Δv`.
    Flip,
    /// PIC (Harlow 1964): `v_p = v_i`.
    Pic,
    /// `v_p = α (v_p + Δv) + (1 − α) v_i` (FLIP share `α`): exactly FLIP at `α = 1` and
    /// PIC at `α = 0` (`1·x + 0·y = x` in floating point for finite `y`).
    Blend(f64),
}

impl PointVelocity {
    /// The update of `options.transfer`; `None` for APIC (`crate::affine`).
    pub(crate) fn of(options: &MpmOptions) -> Option<Self> {
        match options.transfer {
            MpmTransfer::Flip => Some(Self::Flip),
            MpmTransfer::Pic => Some(Self::Pic),
            MpmTransfer::Blend => Some(Self::Blend(options.flip_fraction.unwrap_or(1.0))),
            MpmTransfer::Apic => None,
        }
    }
}

/// Which nodal sums a scatter fills.
#[derive(Clone, Copy)]
struct Fill {
    mass: bool,
    momentum: bool,
    force: bool,
}

/// The points' stencils as a scatter reads them: point `p`'s weights are entries
/// `r·stride .. r·stride + nodes` of `shape` and `gradient`, `r = point_row[p]` (the table
/// of distinct rows) or `r = p` (`point_row` empty; `stride` 0: one row shared by every
/// point), on the nodes `bases[p] + offsets[a]`.
struct Weights<'a, const D: usize> {
    stride: usize,
    point_row: &'a [u32],
    offsets: &'a [usize],
    /// The first node of each row of `width` consecutive nodes ([`crate::shape::Stencil`]'s
    /// `row_offsets`).
    row_offsets: &'a [u32],
    bases: &'a [usize],
    shape: &'a [f64],
    gradient: &'a [Vector<D>],
    /// Node positions relative to the base node ([`crate::shape::Stencil`]'s `steps`).
    steps: &'a [Vector<D>],
}

impl<const D: usize> Weights<'_, D> {
    /// APIC's velocity of point `p` at its stencil's local node `a`, `v_p + C_p (x_i − x_p)`
    /// (`crate::affine`), with `centre` the point relative to its base node and `a` the
    /// local node.
    #[inline]
    fn affine_velocity(
        &self,
        velocity: &Vector<D>,
        affine: &Tensor<D>,
        centre: &Vector<D>,
        a: usize,
    ) -> Vector<D> {
        velocity + affine * (self.steps[a] - centre)
    }

    /// Point `p` relative to its base node, `Σ_a w_ap (x_a − x_base)` (linear completeness:
    /// the weights' own centre, consistent with them to round-off).
    #[inline]
    fn centre(&self, p: usize) -> Vector<D> {
        let first = crate::weights::row_start(self.point_row, self.stride, p);
        let row = &self.shape[first..first + self.steps.len()];
        row.iter().zip(self.steps).map(|(w, x)| x * *w).sum()
    }

    /// Point `p`'s stencil: its shape values and gradients (one row of `nodes` entries,
    /// sliced once: no bounds check per node) and its base node less `offset` (the
    /// band's first node), to which the stencil's `offsets` add.
    /// `N`: the stencil's node count where the caller fixed it (the loops over the row then
    /// have a constant trip count and unroll), 0 where it did not (the count read at run
    /// time; every caller now: the default scatter and the fused gather read the stencil by
    /// rows, `transfer/plain.rs` and `transfer/gather.rs`). The same operations in the same
    /// order either way.
    /// The stencil's `offsets` come sliced to the same `nodes` entries, so that a zip of the
    /// three has the constant trip count too.
    #[inline]
    fn row<const N: usize>(&self, p: usize, offset: usize) -> Row<'_, D> {
        let nodes = if N == 0 { self.offsets.len() } else { N };
        let first = crate::weights::row_start(self.point_row, self.stride, p);
        Row {
            offsets: &self.offsets[..nodes],
            shape: &self.shape[first..first + nodes],
            gradient: &self.gradient[first..first + nodes],
            base: self.bases[p] - offset,
        }
    }
}

/// The rows of weights (`nodes` shape values and gradients each) that `point_row` names
/// in the table `shape`, `gradient` (`crate::weights`), one per point in turn: one load of
/// the point's index, then its row read from the (small, cached) table.
#[inline]
fn table_rows<'a, const D: usize>(
    shape: &'a [f64],
    gradient: &'a [Vector<D>],
    nodes: usize,
    point_row: &'a [u32],
) -> impl Iterator<Item = (&'a [f64], &'a [Vector<D>])> + 'a {
    // sliced to one length: a row checked against the values is proved for the gradients
    let gradient = &gradient[..shape.len()];
    point_row.iter().map(move |&r| {
        let first = r as usize * nodes;
        (
            &shape[first..first + nodes],
            &gradient[first..first + nodes],
        )
    })
}

/// Nodes `first .. first + W` of a nodal array, one row of a stencil: checked once (the
/// row's nodes are then indexed without a check).
#[inline]
fn node_row<T, const W: usize>(nodal: &[T], first: usize) -> &[T; W] {
    nodal[first..first + W]
        .try_into()
        .expect("a row of W nodes")
}

/// [`node_row`], to add to.
#[inline]
fn node_row_mut<T, const W: usize>(nodal: &mut [T], first: usize) -> &mut [T; W] {
    (&mut nodal[first..first + W])
        .try_into()
        .expect("a row of W nodes")
}

/// One point's stencil ([`Weights::row`]): node `base + offsets[a]` has the shape value
/// `shape[a]` and gradient `gradient[a]`.
struct Row<'a, const D: usize> {
    offsets: &'a [usize],
    shape: &'a [f64],
    gradient: &'a [Vector<D>],
    base: usize,
}

impl<const D: usize> Row<'_, D> {
    /// The stencil's nodes `(i, N_ip, ∇N_ip)` in the order of the local nodes.
    #[inline]
    fn nodes(&self) -> impl Iterator<Item = (usize, f64, &Vector<D>)> + '_ {
        let stencil = self.offsets.iter().zip(self.shape).zip(self.gradient);
        stencil.map(|((o, &s), g)| (self.base + o, s, g))
    }
}

/// The points of one run of the layer order that a scatter adds (a layer or a block of
/// layers): entries `points` of `order`, or (`order` empty: the points' own order is the
/// layer order) the points `points` themselves.
struct Run<'a> {
    points: std::ops::Range<usize>,
    order: &'a [usize],
}

impl Run<'_> {
    /// The run's points in the layer order.
    #[inline]
    fn each(&self) -> impl Iterator<Item = usize> + '_ {
        let in_order = self.order.is_empty();
        // the point at place `k` of the layer order
        (self.points.clone()).map(move |k| if in_order { k } else { self.order[k] })
    }
}

/// Add point `p`'s mass `N_ip m_p` and momentum `N_ip m_p v_p` to its nodes' sums (APIC,
/// `affine` not empty: `N_ip m_p (v_p + C_p (x_i − x_p))`, `crate::affine`): phase 1 with
/// APIC or without the internal force, and the MUSL remap (phase 4).
fn add_mass_and_momentum<const D: usize>(
    weights: &Weights<'_, D>,
    p: usize,
    sums: &mut Band<'_, D>,
    points: &MaterialPoints<D>,
    affine: &[Tensor<D>],
) {
    let (mass, velocity) = (points.mass[p], points.velocity[p]);
    let centre = if affine.is_empty() {
        Vector::<D>::zeros()
    } else {
        weights.centre(p)
    };
    let row = weights.row::<0>(p, sums.offset);
    for (a, (i, s, _)) in row.nodes().enumerate() {
        let w = s * mass;
        sums.mass[i] += w;
        if affine.is_empty() {
            sums.momentum[i] += velocity * w;
        } else {
            let v = weights.affine_velocity(&velocity, &affine[p], &centre, a);
            sums.momentum[i] += v * w;
        }
    }
}

impl<const D: usize> MpmSolver<D> {
    /// Add `contribution(p, band)` of every point to the nodal sums named by `fill` (which
    /// are zeroed first). A point whose stencil starts at node layer `j` (along the last
    /// axis) writes node layers `j` to `j + w − 1` only (`w` nodes per axis), so blocks of
    /// `B ≥ w − 1` such layers, every other block, write disjoint bands of `2B` node
    /// layers: two colour passes over disjoint chunks of the nodal arrays (in parallel when
    /// worth it; module doc). A serial run adds in one pass, layer by layer (the same sums
    /// up to round-off), and zeroes each node layer just before its first point, while it
    /// is in cache, instead of in a pass of its own. The contribution reads each point's
    /// stencil through [`Weights`].
    fn scatter(
        &mut self,
        fill: Fill,
        contribution: impl Fn(&Weights<'_, D>, usize, &mut Band<'_, D>) + Sync,
    ) {
        self.scatter_runs(fill, |weights, run, sums| {
            for p in run.each() {
                contribution(weights, p, sums);
            }
        });
    }

    /// [`Self::scatter`] with a contribution per run of points (`contribution(weights,
    /// run, band)`; [`Run`]), which walks the run's points itself: the default scatter
    /// (`scatter_plain`) reads a run in the points' own order in step with its arrays.
    fn scatter_runs(
        &mut self,
        fill: Fill,
        contribution: impl Fn(&Weights<'_, D>, Run<'_>, &mut Band<'_, D>) + Sync,
    ) {
        let layer_nodes: usize = self.grid.cells[..D - 1].iter().map(|n| n + 1).product();
        let layers = self.grid.cells[D - 1] + 1;
        let width = self.stencil.width;
        let (order, starts) = (&self.layer_order, &self.layer_start);
        // the layer order, or none where it is the points' own
        let order: &[usize] = if self.in_layer_order { &[] } else { order };
        let weights = Weights {
            stride: self.weight_stride,
            point_row: &self.point_row,
            offsets: &self.stencil.offsets,
            row_offsets: &self.stencil.row_offsets,
            bases: &self.point_base,
            shape: &self.shape,
            gradient: &self.shape_gradient,
            steps: &self.stencil.steps,
        };
        // the one place the contribution is called, once per run of points (a layer or a
        // block): its point loop and work compile into one function, the captured arrays
        // loaded once per run
        let run = |points: std::ops::Range<usize>, sums: &mut Band<'_, D>| {
            // the three sums sliced to one length: a node's index checked against the
            // mass proves it for the momentum and force (one bounds check per node, not 3)
            let nodes = sums.mass.len();
            let mut sums = Band {
                mass: &mut *sums.mass,
                momentum: &mut sums.momentum[..nodes],
                force: &mut sums.force[..nodes],
                offset: sums.offset,
            };
            contribution(&weights, Run { points, order }, &mut sums);
        };
        let nodes = &mut self.nodes;
        // the sums `fill` names start from zero
        let zero = |mass: &mut [f64], momentum: &mut [Vector<D>], force: &mut [Vector<D>]| {
            if fill.mass {
                mass.iter_mut().for_each(|m| *m = 0.0);
            }
            if fill.momentum {
                momentum.iter_mut().for_each(|m| *m = Vector::<D>::zeros());
            }
            if fill.force {
                force.iter_mut().for_each(|f| *f = Vector::<D>::zeros());
            }
        };
        if !self.parallel {
            // one pass, layer by layer; each node layer is zeroed just before the first
            // point that writes it (no pass of its own)
            let mut sums = Band {
                mass: &mut nodes.mass,
                momentum: &mut nodes.momentum,
                force: &mut nodes.force,
                offset: 0,
            };
            let mut zeroed = 0;
            let mut zero_to = |sums: &mut Band<'_, D>, layer: usize| {
                let range = zeroed * layer_nodes..layer * layer_nodes;
                if !range.is_empty() {
                    let (m, p, f) = (&mut *sums.mass, &mut *sums.momentum, &mut *sums.force);
                    zero(&mut m[range.clone()], &mut p[range.clone()], &mut f[range]);
                    zeroed = layer;
                }
            };
            for layer in 0..layers {
                zero_to(&mut sums, (layer + width).min(layers));
                run(starts[layer]..starts[layer + 1], &mut sums);
            }
            zero_to(&mut sums, layers);
            return;
        }
        // blocks of `block` point layers write `block + w - 1` node layers, within the
        // `2 block` layers up to the next block of the same colour; the blocks follow the
        // whole grid's layers (a slab's local layer `k` is `k + lead` of a grid whose blocks
        // start at 0), so every node adds its points in one rank's order
        let block = BLOCK_LAYERS.max(width - 1);
        let period = 2 * block;
        let lead = self.place.first_layer % period;
        let run_block = |first: isize, sums: &mut Band<'_, D>| {
            let clamp = |k: isize| k.clamp(0, layers as isize) as usize;
            run(
                starts[clamp(first)]..starts[clamp(first + block as isize)],
                sums,
            );
        };
        for colour in 0..2 {
            // this colour's first band at or above local layer 0, and below it the tail of
            // the band before (whose block starts below this grid: a slab's)
            let from_layer = (colour * block + period - lead) % period;
            let from = (from_layer * layer_nodes).min(nodes.mass.len());
            let (head_mass, mass) = nodes.mass.split_at_mut(from);
            let (head_momentum, momentum) = nodes.momentum.split_at_mut(from);
            let (head_force, force) = nodes.force.split_at_mut(from);
            if colour == 0 {
                zero(head_mass, head_momentum, head_force);
            }
            let mut head = Band {
                mass: head_mass,
                momentum: head_momentum,
                force: head_force,
                offset: 0,
            };
            run_block(from_layer as isize - period as isize, &mut head);
            let bands = (
                chunks(mass, period * layer_nodes),
                chunks(momentum, period * layer_nodes),
                chunks(force, period * layer_nodes),
            );
            for_each_chunk(self.parallel, 1, bands, |r, (mass, momentum, force)| {
                // colour 0's bands (and head) cover every node once, each written first by
                // its own task: zeroed there, while in cache (no pass of its own)
                if colour == 0 {
                    zero(mass, momentum, force);
                }
                let first = from_layer + r * period;
                if first >= layers {
                    return;
                }
                let mut sums = Band {
                    mass,
                    momentum,
                    force,
                    offset: first * layer_nodes,
                };
                run_block(first as isize, &mut sums);
            });
        }
    }

    /// Phase 1: shape functions, then mass `m_i = Σ_p N_ip m_p`, momentum
    /// `p_i = Σ_p N_ip m_p v_p` (APIC, `affine` not empty:
    /// `p_i = Σ_p N_ip m_p (v_p + C_p (x_i − x_p))`, `crate::affine`) and (with
    /// `with_internal`) the internal force `f_i = -Σ_p (V_p σ_p) ∇N_ip` on the grid.
    pub fn particles_to_grid(
        &mut self,
        points: &MaterialPoints<D>,
        affine: &[Tensor<D>],
        with_internal: bool,
    ) {
        self.update_shapes(points);
        let fill = Fill {
            mass: true,
            momentum: true,
            force: true,
        };
        // the branches on APIC and on the internal force are taken once per scatter, not
        // per node; each node's sums take the same operations in the same order
        let plain = affine.is_empty();
        match (plain, with_internal) {
            (true, true) => {
                let plain = match (self.stencil.width, self.stencil.nodes) {
                    (2, 4) => Self::scatter_plain::<2, 4>,
                    (2, 8) => Self::scatter_plain::<2, 8>,
                    (3, 9) => Self::scatter_plain::<3, 9>,
                    (3, 27) => Self::scatter_plain::<3, 27>,
                    (2, _) => Self::scatter_plain::<2, 0>,
                    (3, _) => Self::scatter_plain::<3, 0>,
                    _ => Self::scatter_plain::<4, 0>,
                };
                plain(self, points)
            }
            _ => self.scatter(fill, |weights, p, sums| {
                add_mass_and_momentum(weights, p, sums, points, affine);
                if with_internal {
                    let stress = points.stress[p] * points.volume[p];
                    for (i, _, g) in weights.row::<0>(p, sums.offset).nodes() {
                        sums.force[i] -= stress * g;
                    }
                }
            }),
        }
    }

    /// Internal forces only (USF computes them after its stress update).
    pub(crate) fn internal_forces(&mut self, points: &MaterialPoints<D>) {
        let fill = Fill {
            mass: false,
            momentum: false,
            force: true,
        };
        self.scatter(fill, |weights, p, sums| {
            let stress = points.stress[p] * points.volume[p];
            for (i, _, g) in weights.row::<0>(p, sums.offset).nodes() {
                sums.force[i] -= stress * g;
            }
        });
    }
}

mod gather;
mod plain;

#[cfg(test)]
mod tests;

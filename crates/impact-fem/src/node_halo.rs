//! The halo exchange of the FEM on one rank's box (`slab.rs`): once per step the nodal
//! state (`u^n`, `v^{n-1/2}`, `a^n`) of the owned nodes next to each cut goes to the
//! neighbour across it, axis by axis, one message each way per neighbour (the same
//! axis-by-axis scheme as the cells', `impact_core::comm_box`, on nodes).
//!
//! **The node boxes.** Along axis `k` a box stores the node layers `[a − 1, b + 1]` of its
//! owned element layers `[a, b)` (clamped), owns `[a, b)` (and the top face `L` where
//! `b = L`), and receives the layer `a − 1` from the lower neighbour (its first owned one
//! is the lower's `b`) and the layer `b` from the upper one (whose `a − 1` it is, so the
//! lower sends its layer `b − 1`): one node layer each way, from a halo of one element
//! layer. The layer `b + 1` of a cut is never received (nothing owned reads it: `slab.rs`).
//! Each message spans, across the axes before `k`, every stored node (their halo layers,
//! received one exchange earlier, carry the edges and corners on), and across the axes
//! after `k` the owned nodes only (their halo arrives later).
use crate::FemState;
use impact_core::comm::{Comm, RankBox};
use impact_core::comm_box::lexicographic;
use impact_core::comm_method::HaloBuffers;
use std::cmp::Ordering;
use std::ops::Range;

/// The buffers of one rank's nodal halo exchange: one per split axis, in axis order.
#[derive(Debug, Default)]
pub(crate) struct NodeHalo {
    axes: Vec<AxisHalo>,
}

/// The exchange along one axis: the buffers and the local nodes sent to and received from
/// the low and the high neighbour (lexicographic order in the stored box, the same nodes
/// on both ends).
#[derive(Debug, Default)]
struct AxisHalo {
    buffers: HaloBuffers,
    sent: [Vec<usize>; 2],
    received: [Vec<usize>; 2],
}

/// Values per node in the messages: `u`, `v^{n-1/2}`, `a`.
const fn packed_len(dim: usize) -> usize {
    3 * dim
}

/// The owned nodes of `rank_box` along `axis` (local indices): the lower faces of the
/// owned elements, and the top face where they end the mesh.
pub(crate) fn owned_nodes(rank_box: &RankBox, axis: usize) -> Range<usize> {
    let own = rank_box.owned_local(axis);
    let top = usize::from(rank_box.owned[axis].end == rank_box.cells[axis]);
    own.start..own.end + top
}

impl NodeHalo {
    /// The buffers for `rank_box`'s nodal halo in `dim` dimensions (module doc).
    pub(crate) fn new(rank_box: &RankBox, dim: usize) -> Self {
        let counts: Vec<usize> = rank_box.stored.iter().map(|r| r.len() + 1).collect();
        let axes = (0..dim)
            .filter(|&axis| rank_box.parts[axis] > 1)
            .map(|axis| {
                let own = rank_box.owned_local(axis);
                let width = |side: usize| rank_box.halo_width(axis, side);
                let (low, high) = (width(0), width(1));
                let nodes = |along: Range<usize>, side: usize| {
                    if rank_box.neighbour(axis, side).is_none() {
                        return Vec::new();
                    }
                    let ranges: Vec<Range<usize>> = (0..dim)
                        .map(|j| match j.cmp(&axis) {
                            Ordering::Less => 0..counts[j],
                            Ordering::Equal => along.clone(),
                            Ordering::Greater => owned_nodes(rank_box, j),
                        })
                        .collect();
                    lexicographic(&ranges, &counts)
                };
                let sent = [
                    nodes(own.start..own.start + low, 0),
                    nodes(own.end - high..own.end, 1),
                ];
                let received = [nodes(0..low, 0), nodes(own.end..own.end + high, 1)];
                let size = |side: usize| sent[side].len() * packed_len(dim);
                AxisHalo {
                    buffers: HaloBuffers::new(rank_box.neighbours(axis), size(0), size(1)),
                    sent,
                    received,
                }
            })
            .collect();
        Self { axes }
    }

    /// Bytes this rank sends per exchange (every neighbour).
    pub(crate) fn bytes_per_step(&self) -> usize {
        self.axes.iter().map(|a| a.buffers.bytes_sent()).sum()
    }

    /// Send the owned nodes next to each cut to the neighbours and take theirs into the
    /// halo, axis by axis.
    pub(crate) fn exchange<const D: usize>(&mut self, comm: &dyn Comm, state: &mut FemState<D>) {
        for axis in &mut self.axes {
            let b = &mut axis.buffers;
            pack(state, &axis.sent[0], &mut b.send_low);
            pack(state, &axis.sent[1], &mut b.send_high);
            b.exchange(comm);
            unpack(state, &axis.received[0], &b.receive_low);
            unpack(state, &axis.received[1], &b.receive_high);
        }
    }
}

/// Copy the nodal state of `nodes` into `out` (per node `u`, `v`, `a`).
fn pack<const D: usize>(s: &FemState<D>, nodes: &[usize], out: &mut [f64]) {
    let fields = [&s.displacement, &s.velocity_half, &s.acceleration];
    for (k, &i) in nodes.iter().enumerate() {
        for (f, field) in fields.iter().enumerate() {
            let at = packed_len(D) * k + f * D;
            out[at..at + D].copy_from_slice(field[i].as_slice());
        }
    }
}

/// The inverse of [`pack`].
fn unpack<const D: usize>(s: &mut FemState<D>, nodes: &[usize], data: &[f64]) {
    let fields = [
        &mut s.displacement,
        &mut s.velocity_half,
        &mut s.acceleration,
    ];
    for (f, field) in fields.into_iter().enumerate() {
        for (k, &i) in nodes.iter().enumerate() {
            let at = packed_len(D) * k + f * D;
            field[i].copy_from_slice(&data[at..at + D]);
        }
    }
}

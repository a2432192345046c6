//! The halo exchange of a point method split in boxes ([`crate::comm_box`]): a rank's points
//! are stored cell by cell (`per_cell` points a cell, the cells of its stored box in
//! lexicographic order), and once per step it sends the point state of its own cells next to
//! each cut to the neighbour across it and takes theirs into its halo, axis by axis, one
//! message each way per neighbour. Shared by the point methods' wrappers (DGMPM, MPM).
//!
//! Per point: position, velocity and stress, and where the points have them the
//! deformation gradient (large strain), the plastic history (J2: `ε̄`, `ε^p_zz`, plastic
//! work) and one extra tensor per point the method keeps beside the points (MPM's APIC
//! affine velocity; none: an empty slice). The mass, volume, reference position and
//! half-size are not sent: a total Lagrangian slab never changes them.
use crate::comm::{Comm, RankBox};
use crate::comm_method::HaloBuffers;
use crate::points::MaterialPoints;
use crate::Tensor;

/// The buffers of one rank's halo exchange: one [`HaloBuffers`] per split axis, in axis
/// order, with the stored cells each message carries (`crate::comm_box`: later axes carry
/// the halos of earlier ones, which fills the edges and corners).
#[derive(Debug, Default)]
pub struct PointHalo {
    axes: Vec<AxisHalo>,
    /// Points per cell.
    per_cell: usize,
}

/// The exchange along one axis: buffers and the local cells sent to and received from the
/// low and the high neighbour (lexicographic order in the box, the same cells on both ends).
#[derive(Debug, Default)]
struct AxisHalo {
    buffers: HaloBuffers,
    sent: [Vec<usize>; 2],
    received: [Vec<usize>; 2],
}

impl PointHalo {
    /// The buffers for `rank_box`'s halo, `per_cell` points a cell (stored cell by cell),
    /// shaped like `points` (which state they carry) and `extra` (a tensor per point if not
    /// empty).
    pub fn new<const D: usize>(
        rank_box: &RankBox,
        per_cell: usize,
        points: &MaterialPoints<D>,
        extra: &[Tensor<D>],
    ) -> Self {
        let present = |n: usize, v: bool| if v { n } else { 0 };
        let per_point = 2 * D
            + D * D
            + present(D * D, !points.deformation.is_empty())
            + present(3, !points.equivalent_plastic_strain.is_empty())
            + present(D * D, !extra.is_empty());
        let axes = (0..D)
            .filter(|&axis| rank_box.parts[axis] > 1)
            .map(|axis| {
                let cells = |boxes: fn(&RankBox, usize, usize) -> Vec<std::ops::Range<usize>>| {
                    [0, 1].map(|side| {
                        if rank_box.neighbour(axis, side).is_some() {
                            rank_box.local_cells(&boxes(rank_box, axis, side))
                        } else {
                            Vec::new()
                        }
                    })
                };
                let (sent, received) = (cells(RankBox::sent), cells(RankBox::received));
                let size = |side: usize| sent[side].len() * per_cell * per_point;
                AxisHalo {
                    buffers: HaloBuffers::new(rank_box.neighbours(axis), size(0), size(1)),
                    sent,
                    received,
                }
            })
            .collect();
        Self { axes, per_cell }
    }

    /// Bytes this rank sends per exchange (every neighbour).
    pub fn bytes_per_step(&self) -> usize {
        self.axes.iter().map(|a| a.buffers.bytes_sent()).sum()
    }

    /// Send the own cells next to each cut to the neighbours and take theirs into the halo,
    /// axis by axis (`points` and `extra` hold the stored cells' points).
    pub fn exchange<const D: usize>(
        &mut self,
        comm: &dyn Comm,
        points: &mut MaterialPoints<D>,
        extra: &mut [Tensor<D>],
    ) {
        let n = self.per_cell;
        for axis in &mut self.axes {
            let b = &mut axis.buffers;
            pack(points, extra, &axis.sent[0], n, &mut b.send_low);
            pack(points, extra, &axis.sent[1], n, &mut b.send_high);
            b.exchange(comm);
            unpack(points, extra, &axis.received[0], n, &b.receive_low);
            unpack(points, extra, &axis.received[1], n, &b.receive_high);
        }
    }
}

/// The points of the local cells `cells` (`per_cell` each, stored cell by cell).
fn points_of(cells: &[usize], per_cell: usize) -> impl Iterator<Item = usize> + '_ {
    cells
        .iter()
        .flat_map(move |&c| c * per_cell..(c + 1) * per_cell)
}

/// Copy the state of the points of `cells` into `out` (module doc).
fn pack<const D: usize>(
    p: &MaterialPoints<D>,
    extra: &[Tensor<D>],
    cells: &[usize],
    per_cell: usize,
    out: &mut [f64],
) {
    let mut k = 0;
    let mut put = |x: &[f64]| {
        out[k..k + x.len()].copy_from_slice(x);
        k += x.len();
    };
    for i in points_of(cells, per_cell) {
        put(p.position[i].as_slice());
        put(p.velocity[i].as_slice());
        put(p.stress[i].as_slice());
        if !p.deformation.is_empty() {
            put(p.deformation[i].as_slice());
        }
        if !p.equivalent_plastic_strain.is_empty() {
            put(&[
                p.equivalent_plastic_strain[i],
                p.plastic_strain_zz[i],
                p.plastic_work[i],
            ]);
        }
        if !extra.is_empty() {
            put(extra[i].as_slice());
        }
    }
}

/// The inverse of [`pack`].
fn unpack<const D: usize>(
    p: &mut MaterialPoints<D>,
    extra: &mut [Tensor<D>],
    cells: &[usize],
    per_cell: usize,
    data: &[f64],
) {
    let mut k = 0;
    let mut take = |n: usize| {
        k += n;
        &data[k - n..k]
    };
    for i in points_of(cells, per_cell) {
        p.position[i].copy_from_slice(take(D));
        p.velocity[i].copy_from_slice(take(D));
        p.stress[i].copy_from_slice(take(D * D));
        if !p.deformation.is_empty() {
            p.deformation[i].copy_from_slice(take(D * D));
        }
        if !p.equivalent_plastic_strain.is_empty() {
            let h = take(3);
            p.equivalent_plastic_strain[i] = h[0];
            p.plastic_strain_zz[i] = h[1];
            p.plastic_work[i] = h[2];
        }
        if !extra.is_empty() {
            extra[i].copy_from_slice(take(D * D));
        }
    }
}

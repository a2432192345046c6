//! The halo exchange of a point method split in slabs ([`crate::comm`]): a rank's points are
//! stored layer by layer (`per_layer` points a layer of cells), and once per step it sends
//! the point state of its own edge layers to its neighbours and takes theirs into its halo
//! layers, one message each way per neighbour. Shared by the point methods' slab wrappers
//! (DGMPM, MPM).
//!
//! Per point: position, velocity and stress, and where the points have them the
//! deformation gradient (large strain), the plastic history (J2: `ε̄`, `ε^p_zz`, plastic
//! work) and one extra tensor per point the method keeps beside the points (MPM's APIC
//! affine velocity; none: an empty slice). The mass, volume, reference position and
//! half-size are not sent: a total Lagrangian slab never changes them.
use crate::comm::{Comm, Slab};
use crate::comm_method::HaloBuffers;
use crate::points::MaterialPoints;
use crate::Tensor;

/// The buffers of one rank's halo exchange.
#[derive(Debug, Default)]
pub struct PointHalo {
    buffers: HaloBuffers,
    /// Points per layer of cells.
    per_layer: usize,
}

impl PointHalo {
    /// The buffers for `slab`'s halo, `per_layer` points a layer, shaped like `points`
    /// (which state they carry) and `extra` (a tensor per point if not empty).
    pub fn new<const D: usize>(
        slab: &Slab,
        per_layer: usize,
        points: &MaterialPoints<D>,
        extra: &[Tensor<D>],
    ) -> Self {
        let present = |n: usize, v: bool| if v { n } else { 0 };
        let per_point = 2 * D
            + D * D
            + present(D * D, !points.deformation.is_empty())
            + present(3, !points.equivalent_plastic_strain.is_empty())
            + present(D * D, !extra.is_empty());
        let size = |layers: usize| layers * per_layer * per_point;
        Self {
            buffers: HaloBuffers::new(size(slab.halo_below()), size(slab.halo_above())),
            per_layer,
        }
    }

    /// Bytes this rank sends per exchange (both neighbours).
    pub fn bytes_per_step(&self) -> usize {
        self.buffers.bytes_sent()
    }

    /// Send the own edge layers of `slab` to the neighbours and take theirs into the halo
    /// (`points` and `extra` hold the stored layers).
    pub fn exchange<const D: usize>(
        &mut self,
        comm: &dyn Comm,
        slab: &Slab,
        points: &mut MaterialPoints<D>,
        extra: &mut [Tensor<D>],
    ) {
        let (below, above) = (slab.halo_below(), slab.halo_above());
        let stored = slab.stored.len();
        let own = slab.owned_local();
        let n = self.per_layer;
        let b = &mut self.buffers;
        pack(
            points,
            extra,
            own.start * n..(own.start + below) * n,
            &mut b.send_low,
        );
        pack(
            points,
            extra,
            (own.end - above) * n..own.end * n,
            &mut b.send_high,
        );
        b.exchange(comm);
        unpack(points, extra, 0..below * n, &b.receive_low);
        unpack(
            points,
            extra,
            (stored - above) * n..stored * n,
            &b.receive_high,
        );
    }
}

/// Copy the state of the points `range` into `out` (module doc).
fn pack<const D: usize>(
    p: &MaterialPoints<D>,
    extra: &[Tensor<D>],
    range: std::ops::Range<usize>,
    out: &mut [f64],
) {
    let mut k = 0;
    let mut put = |x: &[f64]| {
        out[k..k + x.len()].copy_from_slice(x);
        k += x.len();
    };
    for i in range {
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
    range: std::ops::Range<usize>,
    data: &[f64],
) {
    let mut k = 0;
    let mut take = |n: usize| {
        k += n;
        &data[k - n..k]
    };
    for i in range {
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

//! The global values of a [`Method`](crate::Method) split over ranks, formed through its
//! [`Comm`] from each rank's share (issue 27): the samples gathered in rank order (the
//! ranks own consecutive runs of the global sample order, so the concatenation is the
//! one-rank order), the first failure over the ranks at its global place, the hottest
//! place, and nodal vectors gathered in rank order; and the buffers of a slab's halo
//! exchange ([`HaloBuffers`]). Shared by the slab solvers of the method crates, which may
//! not depend on each other.
use crate::comm::{Comm, CommError};
use crate::method::{BadState, Samples};
use crate::{Tensor, Vector};

/// Every rank's samples `mine`, in rank order, into `out` (on every rank).
pub fn gather_samples<const D: usize>(
    comm: &(impl Comm + ?Sized),
    mine: &Samples<D>,
    out: &mut Samples<D>,
) {
    let (plastic, zz) = (!mine.plastic_strain.is_empty(), !mine.stress_zz.is_empty());
    let width = 4 * D + D * D + usize::from(plastic) + usize::from(zz);
    let mut packed = Vec::with_capacity(mine.len() * width);
    for i in 0..mine.len() {
        packed.extend_from_slice(mine.reference[i].as_slice());
        packed.extend_from_slice(mine.position[i].as_slice());
        packed.extend_from_slice(mine.half_size[i].as_slice());
        packed.extend_from_slice(mine.stress[i].as_slice());
        packed.extend_from_slice(mine.velocity[i].as_slice());
        if plastic {
            packed.push(mine.plastic_strain[i]);
        }
        if zz {
            packed.push(mine.stress_zz[i]);
        }
    }
    let all = comm.all_gather(&packed);
    out.clear();
    for s in all.chunks_exact(width) {
        let v = |k: usize| Vector::<D>::from_column_slice(&s[k * D..(k + 1) * D]);
        out.reference.push(v(0));
        out.position.push(v(1));
        out.half_size.push(v(2));
        out.stress
            .push(Tensor::<D>::from_column_slice(&s[3 * D..3 * D + D * D]));
        let velocity = 3 * D + D * D;
        out.velocity
            .push(Vector::<D>::from_column_slice(&s[velocity..velocity + D]));
        let mut k = velocity + D;
        if plastic {
            out.plastic_strain.push(s[k]);
            k += 1;
        }
        if zz {
            out.stress_zz.push(s[k]);
        }
    }
}

/// Every rank's vectors `mine`, in rank order (on every rank).
pub fn gather_vectors<const D: usize>(
    comm: &(impl Comm + ?Sized),
    mine: &[Vector<D>],
) -> Vec<Vector<D>> {
    let packed: Vec<f64> = mine.iter().flat_map(|v| v.iter().copied()).collect();
    (comm.all_gather(&packed).chunks_exact(D))
        .map(Vector::<D>::from_column_slice)
        .collect()
}

/// The first failure over the ranks (the lowest failing rank's), the same
/// [`BadState`] on every rank, at the place that rank reported.
pub fn first_bad<const D: usize>(
    comm: &(impl Comm + ?Sized),
    local: Result<(), BadState<D>>,
) -> Result<(), BadState<D>> {
    let reason = local.as_ref().err().map(|b| b.reason.clone());
    let Some(CommError::Rank { rank, message }) = comm.first_error(reason.as_deref()) else {
        return Ok(());
    };
    let place = local.err().map_or_else(Vector::<D>::zeros, |b| b.place);
    let all = comm.all_gather(place.as_slice());
    Err(BadState {
        place: Vector::<D>::from_fn(|k, _| all[rank * D + k]),
        reason: message,
    })
}

/// The place of the largest speed over the ranks, from each rank's `(speed, place)` of
/// its owned carriers (`None`: it owns none): the last rank of the largest speed, as one
/// rank's `max_by` keeps the last of equals.
pub fn hottest_of_ranks<const D: usize>(
    comm: &(impl Comm + ?Sized),
    mine: Option<(f64, Vector<D>)>,
) -> Vector<D> {
    let (speed, place) = mine.unwrap_or((f64::NEG_INFINITY, Vector::<D>::zeros()));
    let mut entry = vec![speed];
    entry.extend_from_slice(place.as_slice());
    let all = comm.all_gather(&entry);
    let best = (0..comm.size())
        .max_by(|&a, &b| all[a * (D + 1)].total_cmp(&all[b * (D + 1)]))
        .unwrap_or(0);
    Vector::<D>::from_column_slice(&all[best * (D + 1) + 1..(best + 1) * (D + 1)])
}

/// The messages of a slab's halo exchange with its two neighbours, allocated once: what
/// goes to and comes from the lower (`rank − 1`) and the upper (`rank + 1`) neighbour.
#[derive(Debug, Default)]
pub struct HaloBuffers {
    /// To the lower neighbour (this rank's lowest owned layers).
    pub send_low: Vec<f64>,
    /// To the upper neighbour (this rank's highest owned layers).
    pub send_high: Vec<f64>,
    /// From the lower neighbour (the halo below the owned layers).
    pub receive_low: Vec<f64>,
    /// From the upper neighbour (the halo above).
    pub receive_high: Vec<f64>,
}

impl HaloBuffers {
    /// `below` values each way with the lower neighbour, `above` with the upper one.
    pub fn new(below: usize, above: usize) -> Self {
        Self {
            send_low: vec![0.0; below],
            send_high: vec![0.0; above],
            receive_low: vec![0.0; below],
            receive_high: vec![0.0; above],
        }
    }

    /// Send the send buffers, fill the receive buffers ([`Comm::exchange`]).
    pub fn exchange(&mut self, comm: &(impl Comm + ?Sized)) {
        comm.exchange(
            &self.send_low,
            &self.send_high,
            &mut self.receive_low,
            &mut self.receive_high,
        );
    }

    /// Bytes this rank sends per exchange.
    pub fn bytes_sent(&self) -> usize {
        8 * (self.send_low.len() + self.send_high.len())
    }
}

/// The [`Method`](crate::Method) functions of a slab solver that are its local method's
/// values reduced over the ranks, written once for every method crate: the time step
/// (minimum), energy and work (sums in rank order), momentum and impulse (the same per
/// component), the first failure ([`first_bad`]), the initial energy and the cell counts
/// of the whole grid. Expands inside `impl Method<D> for …` of a struct with the fields
/// `local` (the rank's own method), `comm: Arc<dyn Comm>`, `initial_energy: f64` (reduced
/// when built) and `global_cells: usize`.
#[macro_export]
macro_rules! reduced_over_ranks {
    () => {
        fn stable_dt(&self) -> f64 {
            self.comm.all_reduce_min(self.local.stable_dt())
        }
        fn energy(&self) -> f64 {
            self.comm.all_reduce_sum(self.local.energy())
        }
        fn external_work(&self) -> f64 {
            self.comm.all_reduce_sum(self.local.external_work())
        }
        fn initial_energy(&self) -> f64 {
            self.initial_energy
        }
        fn momentum(&self) -> $crate::Vector<D> {
            $crate::comm::sum_vector(self.comm.as_ref(), self.local.momentum())
        }
        fn external_impulse(&self) -> $crate::Vector<D> {
            $crate::comm::sum_vector(self.comm.as_ref(), self.local.external_impulse())
        }
        fn check_finite(&self) -> Result<(), $crate::method::BadState<D>> {
            $crate::comm_method::first_bad(self.comm.as_ref(), self.local.check_finite())
        }
        fn cells(&self) -> usize {
            self.global_cells
        }
        fn updates_per_step(&self) -> usize {
            self.global_cells
        }
    };
}

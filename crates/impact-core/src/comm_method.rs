//! What the slab solvers of the method crates (which may not depend on each other) share
//! beyond [`crate::comm_gather`] (samples, first failure, hottest place) and
//! [`crate::comm_halo`] (the point methods' halo): the buffers of a nodal halo exchange ([`HaloBuffers`]) and the [`Method`](crate::Method)
//! values that are a local method's reduced over the ranks ([`crate::reduced_over_ranks!`]).
use crate::comm::Comm;

/// The messages of a halo exchange along one axis with its two neighbours, allocated once:
/// what goes to and comes from the lower and the upper neighbour.
#[derive(Debug, Default)]
pub struct HaloBuffers {
    /// The lower and upper neighbour ranks (`None` at a physical edge).
    pub neighbours: [Option<usize>; 2],
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
    pub fn new(neighbours: [Option<usize>; 2], below: usize, above: usize) -> Self {
        Self {
            neighbours,
            send_low: vec![0.0; below],
            send_high: vec![0.0; above],
            receive_low: vec![0.0; below],
            receive_high: vec![0.0; above],
        }
    }

    /// Send the send buffers, fill the receive buffers ([`Comm::exchange`]).
    pub fn exchange(&mut self, comm: &(impl Comm + ?Sized)) {
        comm.exchange(
            self.neighbours,
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
/// values reduced or gathered over the ranks, written once for every method crate: the
/// configuration, the samples (the local method's, which are its own carriers', gathered in
/// rank order: [`crate::comm_gather::gather_samples`], put in the global order by the
/// inherent `sample_order(&self) -> &[usize]`: the global index of each own sample, empty
/// where rank order is the global order), the first failure
/// ([`crate::comm_gather::first_bad`]) and the rest of [`crate::reduced_sums_over_ranks!`].
/// Expands inside `impl Method<D> for …` of a struct with the fields `local` (the rank's own
/// method), `comm: Arc<dyn Comm>` and `initial_energy: f64` (reduced when built) and the
/// inherent `bytes_per_step(&self) -> usize` and `sample_order`.
#[macro_export]
macro_rules! reduced_over_ranks {
    () => {
        fn sample_into(&self, out: &mut $crate::method::Samples<D>) {
            // (outputs only: the guard reduces the owned samples; the buffers are the caller's)
            let mut mine = $crate::method::Samples::<D>::default();
            self.local.sample_into(&mut mine);
            $crate::comm_gather::gather_samples(
                self.comm.as_ref(),
                &mine,
                self.sample_order(),
                out,
            );
        }
        fn owned_sample_order(&self) -> &[usize] {
            self.sample_order()
        }
        fn check_finite(&self) -> Result<(), $crate::method::BadState<D>> {
            $crate::comm_gather::first_bad(self.comm.as_ref(), self.local.check_finite())
        }
        $crate::reduced_sums_over_ranks!();
    };
}

/// What [`crate::reduced_over_ranks!`] writes but the samples and the first failure (a
/// solver whose carriers change ranks gathers its samples in another order, and has
/// failures of its own: MPM's migrating slab): the configuration, the time step (minimum),
/// energy and work (sums in rank order), momentum and impulse (the same per component), the
/// initial energy, this rank's owned samples (the local method's samples), the comm and the
/// bytes exchanged per step. The same fields as [`crate::reduced_over_ranks!`].
#[macro_export]
macro_rules! reduced_sums_over_ranks {
    () => {
        fn config(&self) -> &$crate::method::MethodConfig {
            self.local.config()
        }
        fn bytes_exchanged_per_step(&self) -> usize {
            self.bytes_per_step()
        }
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
        fn owned_samples_into(&self, out: &mut $crate::method::Samples<D>) {
            self.local.sample_into(out);
        }
        fn comm(&self) -> &dyn $crate::comm::Comm {
            self.comm.as_ref()
        }
    };
}

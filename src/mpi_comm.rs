//! [`MpiComm`]: [`Comm`] over MPI (rsmpi on the system's MPI library; the `mpi` feature).
//! Variable-length all-gathers (`MPI_Allgatherv`, after an `MPI_Allgather` of the
//! lengths), the gather to rank 0 alone (`MPI_Gatherv`, after an `MPI_Gather` of the
//! lengths), the neighbours' exchange along an axis by non-blocking sends and blocking receives,
//! `MPI_Barrier` and `MPI_Abort`. MPI is initialised with `MPI_THREAD_SERIALIZED`: the
//! controller calls from one of rayon's workers, never two at once (a mutex holds the
//! communicator).
use impact_core::comm::{Comm, CommError};
use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;
use std::sync::Mutex;

/// MPI's world communicator.
pub struct MpiComm {
    world: Mutex<SimpleCommunicator>,
    rank: usize,
    size: usize,
}

impl std::fmt::Debug for MpiComm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MpiComm {{ rank: {}, size: {} }}", self.rank, self.size)
    }
}

// SAFETY: the communicator handle is only used under the mutex, and MPI was initialised
// with MPI_THREAD_SERIALIZED (calls from any thread, one at a time).
unsafe impl Send for MpiComm {}
// SAFETY: as above.
unsafe impl Sync for MpiComm {}

impl MpiComm {
    /// Initialise MPI; the universe finalises MPI when dropped (keep it to the end of
    /// `main`).
    pub fn start() -> Result<(Self, Box<dyn std::any::Any>), CommError> {
        let (universe, _) =
            mpi::initialize_with_threading(mpi::Threading::Serialized).ok_or_else(|| {
                CommError::Rank {
                    rank: 0,
                    message: "MPI was already initialised".into(),
                }
            })?;
        let world = universe.world();
        let (rank, size) = (world.rank() as usize, world.size() as usize);
        Ok((
            Self {
                world: Mutex::new(world),
                rank,
                size,
            },
            Box::new(universe),
        ))
    }

    fn world(&self) -> std::sync::MutexGuard<'_, SimpleCommunicator> {
        self.world.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn gather_varcount<T: Equivalence + Default + Clone>(
        &self,
        local: &[T],
        out: &mut Vec<T>,
        counts: &mut Vec<usize>,
    ) {
        let world = self.world();
        let mut lengths = vec![0 as Count; self.size];
        world.all_gather_into(&(local.len() as Count), &mut lengths[..]);
        let displs = offsets(&lengths);
        let total: usize = lengths.iter().map(|&n| n as usize).sum();
        out.clear();
        out.resize(total, T::default());
        {
            let mut partition = PartitionMut::new(&mut out[..], &lengths[..], &displs[..]);
            world.all_gather_varcount_into(local, &mut partition);
        }
        counts.clear();
        counts.extend(lengths.iter().map(|&n| n as usize));
    }
}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.size
    }
    fn all_gather_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        self.gather_varcount(local, out, counts);
    }
    fn all_gather_bytes(&self, local: &[u8], out: &mut Vec<u8>, counts: &mut Vec<usize>) {
        self.gather_varcount(local, out, counts);
    }
    fn gather_to_root_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        let world = self.world();
        let root = world.process_at_rank(0);
        out.clear();
        counts.clear();
        let length = local.len() as Count;
        if self.rank != 0 {
            root.gather_into(&length);
            root.gather_varcount_into(local);
            return;
        }
        let mut lengths = vec![0 as Count; self.size];
        root.gather_into_root(&length, &mut lengths[..]);
        let displs = offsets(&lengths);
        out.resize(lengths.iter().map(|&n| n as usize).sum(), 0.0);
        {
            let mut partition = PartitionMut::new(&mut out[..], &lengths[..], &displs[..]);
            root.gather_varcount_into_root(local, &mut partition);
        }
        counts.extend(lengths.iter().map(|&n| n as usize));
    }
    fn exchange(
        &self,
        [lower, upper]: [Option<usize>; 2],
        to_lower: &[f64],
        to_upper: &[f64],
        from_lower: &mut [f64],
        from_upper: &mut [f64],
    ) {
        let world = self.world();
        mpi::request::scope(|scope| {
            let send = |to: Option<usize>, data| {
                to.map(|r| world.process_at_rank(r as i32).immediate_send(scope, data))
            };
            let (low, high) = (send(lower, to_lower), send(upper, to_upper));
            if let Some(r) = lower {
                world.process_at_rank(r as i32).receive_into(from_lower);
            }
            if let Some(r) = upper {
                world.process_at_rank(r as i32).receive_into(from_upper);
            }
            for request in [low, high].into_iter().flatten() {
                request.wait();
            }
        });
    }
    fn barrier(&self) {
        self.world().barrier();
    }
    fn abort(&self, code: i32) -> ! {
        self.world().abort(code)
    }
}

/// Where each rank's part starts in the concatenation of parts of `lengths`.
fn offsets(lengths: &[Count]) -> Vec<Count> {
    lengths
        .iter()
        .scan(0, |acc, &n| {
            let at = *acc;
            *acc += n;
            Some(at)
        })
        .collect()
}

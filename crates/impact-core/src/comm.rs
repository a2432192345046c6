//! The communication seam of a run split across ranks (issue 27; the design note's "More
//! than one machine"): a [`Comm`] gives a rank its number, the rank count, reductions,
//! the halo exchange between neighbours along an axis and gathers; a
//! [`RankBox`] is one rank's share of the grid.
//!
//! Three implementations: [`SerialComm`] (one rank: every reduction is the identity, an
//! exchange has no neighbour), [`ThreadComm`] (ranks as threads of one process, over
//! channels: the decomposed path tested in the default build, with no MPI library), and
//! the MPI one behind the root crate's `mpi` feature (rsmpi on the system's OpenMPI).
//!
//! **Reductions in a fixed order.** [`Comm::all_reduce_sum`] gathers every rank's value
//! and adds them in rank order on every rank, so every rank holds the same bits and the
//! result depends only on the decomposition, never on message timing. (It still differs
//! from the one-rank sum by round-off where the one-rank sum groups its terms otherwise:
//! `Σ_r (Σ_{i∈r} x_i)` against `Σ_i x_i`.) Min and max are exact.
//!
//! **Boxes.** The cells are split over a grid of ranks along every axis
//! ([`crate::comm_box`]); the automatic choice is slabs along the last axis.
use crate::Vector;
use thiserror::Error;

/// Why a decomposition or a rank's work failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CommError {
    /// More ranks than the grid can share out.
    #[error(
        "{ranks} ranks cannot share the {layers} layers of cells along axis {axis}: \
         each rank needs at least {needed} (its halo width); run on at most {most} ranks \
         along that axis"
    )]
    TooManyRanks {
        /// Ranks asked for along `axis`.
        ranks: usize,
        /// Layers of cells along `axis`.
        layers: usize,
        /// The axis split.
        axis: usize,
        /// Layers each rank must own.
        needed: usize,
        /// Most ranks that fit.
        most: usize,
    },
    /// A rank grid (`--ranks-grid`) that does not fit the grid or the rank count.
    #[error("--ranks-grid {grid}: {message}")]
    RankGrid {
        /// The rank grid as given.
        grid: String,
        /// Why it is refused.
        message: String,
    },
    /// A method or option that has no decomposed form yet.
    #[error("{what} does not run on {ranks} ranks yet: {allowed}")]
    Unsupported {
        /// What was asked for.
        what: String,
        /// Ranks.
        ranks: usize,
        /// What is allowed instead.
        allowed: String,
    },
    /// A rank failed; every rank reports this one message.
    #[error("rank {rank}: {message}")]
    Rank {
        /// The failing rank (the lowest one, when several failed).
        rank: usize,
        /// Its message.
        message: String,
    },
}

/// Communication between the ranks of one run. Every rank calls the collective
/// operations in the same order (they match by order, not by tag).
pub trait Comm: Send + Sync + std::fmt::Debug {
    /// This rank, `0 ≤ rank < size`.
    fn rank(&self) -> usize;
    /// Number of ranks.
    fn size(&self) -> usize;
    /// Every rank's `local` values concatenated in rank order into `out` (lengths may
    /// differ); `counts[r]` is rank `r`'s length.
    fn all_gather_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>);
    /// Every rank's `local` bytes concatenated in rank order into `out`, with the lengths.
    fn all_gather_bytes(&self, local: &[u8], out: &mut Vec<u8>, counts: &mut Vec<usize>);
    /// Every rank's `local` values concatenated in rank order into `out` **on rank 0 only**
    /// (`counts[r]` is rank `r`'s length there); on the other ranks `out` and `counts` are
    /// left empty. For what rank 0 alone writes or draws (the figures' map plane): the
    /// other ranks send their part and receive nothing, where an all-gather would give each
    /// of them the whole.
    fn gather_to_root_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>);
    /// Halo exchange along one axis with the `neighbours` (lower, upper; `None` where
    /// there is none): send `to_lower` to the lower and `to_upper` to the upper one,
    /// receive `from_lower` from the lower and `from_upper` from the upper one (lengths
    /// agree pairwise). Every rank exchanges along the axes in the same order.
    fn exchange(
        &self,
        neighbours: [Option<usize>; 2],
        to_lower: &[f64],
        to_upper: &[f64],
        from_lower: &mut [f64],
        from_upper: &mut [f64],
    );
    /// Wait for every rank.
    fn barrier(&self);
    /// End every rank's process with `code` (a failure seen by one rank only).
    fn abort(&self, code: i32) -> !;

    /// Whether this is rank 0 (the one that prints and writes).
    fn is_root(&self) -> bool {
        self.rank() == 0
    }
    /// Every rank's value, in rank order.
    fn all_gather(&self, x: &[f64]) -> Vec<f64> {
        let (mut out, mut counts) = (Vec::new(), Vec::new());
        self.all_gather_into(x, &mut out, &mut counts);
        out
    }
    /// Smallest `x` over the ranks.
    fn all_reduce_min(&self, x: f64) -> f64 {
        if self.size() == 1 {
            return x;
        }
        self.all_gather(&[x])
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    }
    /// Largest `x` over the ranks.
    fn all_reduce_max(&self, x: f64) -> f64 {
        if self.size() == 1 {
            return x;
        }
        self.all_gather(&[x])
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// `Σ_r x_r`, added in rank order on every rank (module doc).
    fn all_reduce_sum(&self, x: f64) -> f64 {
        if self.size() == 1 {
            return x;
        }
        self.all_gather(&[x]).into_iter().fold(0.0, |s, v| s + v)
    }
    /// Whether `flag` holds on any rank.
    fn any(&self, flag: bool) -> bool {
        if self.size() == 1 {
            return flag;
        }
        self.all_gather(&[f64::from(u8::from(flag))])
            .into_iter()
            .any(|v| v != 0.0)
    }
    /// The first failure over the ranks (the lowest failing rank's message), the same
    /// on every rank: one message for a failure seen by one rank or by all.
    fn first_error(&self, local: Option<&str>) -> Option<CommError> {
        if self.size() == 1 {
            return local.map(|m| CommError::Rank {
                rank: 0,
                message: m.to_string(),
            });
        }
        let flags = self.all_gather(&[f64::from(u8::from(local.is_some()))]);
        let rank = flags.iter().position(|&f| f != 0.0)?;
        let mine = if self.rank() == rank { local } else { None };
        let (mut bytes, mut counts) = (Vec::new(), Vec::new());
        self.all_gather_bytes(mine.unwrap_or("").as_bytes(), &mut bytes, &mut counts);
        let start: usize = counts[..rank].iter().sum();
        let message = String::from_utf8_lossy(&bytes[start..start + counts[rank]]).into_owned();
        Some(CommError::Rank { rank, message })
    }
}

/// `Σ_r x_r` of a vector, component by component in rank order (any [`Comm`]).
pub fn sum_vector<const D: usize>(comm: &(impl Comm + ?Sized), x: Vector<D>) -> Vector<D> {
    if comm.size() == 1 {
        return x;
    }
    let all = comm.all_gather(x.as_slice());
    Vector::<D>::from_fn(|k, _| (0..comm.size()).fold(0.0, |s, r| s + all[r * D + k]))
}

/// One rank: every reduction is the identity and there is no neighbour.
#[derive(Debug, Clone, Copy, Default)]
pub struct SerialComm;

impl Comm for SerialComm {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn all_gather_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        out.clear();
        out.extend_from_slice(local);
        counts.clear();
        counts.push(local.len());
    }
    fn all_gather_bytes(&self, local: &[u8], out: &mut Vec<u8>, counts: &mut Vec<usize>) {
        out.clear();
        out.extend_from_slice(local);
        counts.clear();
        counts.push(local.len());
    }
    fn gather_to_root_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        self.all_gather_into(local, out, counts);
    }
    fn exchange(&self, _: [Option<usize>; 2], _: &[f64], _: &[f64], _: &mut [f64], _: &mut [f64]) {}
    fn barrier(&self) {}
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

pub use crate::comm_box::{RankBox, RankGrid};
pub use crate::comm_thread::ThreadComm;

#[cfg(test)]
mod tests {
    use super::*;

    /// The serial comm is the identity; the first error is rank 0's.
    #[test]
    fn serial_reductions_are_identities() {
        let c = SerialComm;
        assert_eq!(c.all_reduce_sum(0.1), 0.1);
        assert_eq!(c.all_reduce_min(-3.0), -3.0);
        assert!(c.any(true) && !c.any(false));
        assert!(c.first_error(None).is_none());
        let e = c.first_error(Some("bad")).unwrap();
        assert_eq!(e.to_string(), "rank 0: bad");
        let (mut out, mut counts) = (vec![9.0], vec![7]);
        c.gather_to_root_into(&[1.5, -2.0], &mut out, &mut counts);
        assert_eq!((out, counts), (vec![1.5, -2.0], vec![2]));
    }
}

//! The communication seam of a run split across ranks (issue 27; the design note's "More
//! than one machine"): a [`Comm`] gives a rank its number, the rank count, reductions,
//! the halo exchange between slab neighbours and gathers; a [`Slab`] is one rank's share
//! of the grid.
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
//! **Slabs.** The layers of cells along the last axis are split into `ranks` contiguous
//! runs, the first `layers mod ranks` ranks one layer longer ([`Slab::new`]). A rank stores
//! its own layers plus `halo` layers of each neighbour (fewer at a physical edge); a face
//! of the slab is a physical edge only where the slab reaches the end of the grid.
use crate::{Grid, Vector};
use std::ops::Range;
use thiserror::Error;

/// Why a decomposition or a rank's work failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CommError {
    /// More ranks than the grid can share out.
    #[error(
        "{ranks} ranks cannot share the {layers} layers of cells along the last axis: \
         each rank needs at least {needed} (its halo width); run on at most {most} ranks"
    )]
    TooManyRanks {
        /// Ranks asked for.
        ranks: usize,
        /// Layers of cells along the last axis.
        layers: usize,
        /// Layers each rank must own.
        needed: usize,
        /// Most ranks that fit.
        most: usize,
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
    /// Slab neighbours' halo exchange: send `to_lower` to `rank - 1` and `to_upper` to
    /// `rank + 1`, receive `from_lower` from `rank - 1` and `from_upper` from `rank + 1`
    /// (empty slices where there is no neighbour; lengths agree pairwise).
    fn exchange(
        &self,
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
    fn exchange(&self, _: &[f64], _: &[f64], _: &mut [f64], _: &mut [f64]) {}
    fn barrier(&self) {}
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

pub use crate::comm_thread::ThreadComm;

/// One rank's share of a grid split in slabs along the last axis (module doc). Layer
/// indices are global unless named `local`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Slab {
    /// This rank.
    pub rank: usize,
    /// Number of ranks.
    pub ranks: usize,
    /// Layers of cells along the last axis (the whole grid).
    pub layers: usize,
    /// Halo width (layers stored from each neighbour).
    pub halo: usize,
    /// The layers this rank owns.
    pub owned: Range<usize>,
    /// The layers it stores: owned plus the halo, clamped to the grid.
    pub stored: Range<usize>,
}

impl Slab {
    /// Rank `rank`'s slab of `layers` layers split over `ranks` ranks with a halo of
    /// `halo` layers. Refused where a rank would own fewer layers than the halo (its
    /// neighbours' halos would then reach past it).
    pub fn new(layers: usize, ranks: usize, rank: usize, halo: usize) -> Result<Self, CommError> {
        let needed = halo.max(1);
        let most = (layers / needed).max(1);
        if ranks == 0 || (ranks > 1 && layers / ranks < needed) || rank >= ranks.max(1) {
            return Err(CommError::TooManyRanks {
                ranks,
                layers,
                needed,
                most,
            });
        }
        let (base, extra) = (layers / ranks, layers % ranks);
        let start = rank * base + rank.min(extra);
        let owned = start..start + base + usize::from(rank < extra);
        let stored = owned.start.saturating_sub(halo)..(owned.end + halo).min(layers);
        Ok(Self {
            rank,
            ranks,
            layers,
            halo,
            owned,
            stored,
        })
    }

    /// The owned layers in stored (local) indices.
    pub fn owned_local(&self) -> Range<usize> {
        self.owned.start - self.stored.start..self.owned.end - self.stored.start
    }

    /// Whether the stored grid's low (`side = 0`) or high (`1`) face is a physical edge
    /// (the body's boundary condition applies there; elsewhere it is a cut, whose
    /// halo cells the neighbour refreshes).
    pub fn physical_edge(&self, side: usize) -> bool {
        match side {
            0 => self.stored.start == 0,
            _ => self.stored.end == self.layers,
        }
    }

    /// Layers received from the lower neighbour (stored below the owned ones).
    pub fn halo_below(&self) -> usize {
        self.owned.start - self.stored.start
    }

    /// Layers received from the upper neighbour.
    pub fn halo_above(&self) -> usize {
        self.stored.end - self.owned.end
    }

    /// The grid of the stored layers: `global` cut along its last axis, its origin moved
    /// to the first stored layer.
    pub fn grid<const D: usize>(&self, global: &Grid<D>) -> Grid<D> {
        global.layers(self.stored.start, self.stored.len())
    }

    /// A one-line description for summaries: `slabs along axis 1: rank r owns [a, b)`.
    pub fn describe(&self, dim: usize) -> String {
        format!(
            "{} slabs along axis {} ({} layers, halo {})",
            self.ranks,
            dim - 1,
            self.layers,
            self.halo
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Slabs cover the layers once, in rank order, balanced to one layer; halos are
    /// clamped at the physical edges; too many ranks are refused with the most that fit.
    #[test]
    fn slabs_partition_the_layers() {
        for layers in [4usize, 7, 25] {
            for ranks in 1..=4 {
                let mut next = 0;
                for rank in 0..ranks {
                    let s = Slab::new(layers, ranks, rank, 1).unwrap();
                    assert_eq!(s.owned.start, next);
                    next = s.owned.end;
                    assert!(s.owned.len() >= layers / ranks && s.owned.len() <= layers / ranks + 1);
                    // the stored grid's faces: physical where the halo reaches the end
                    assert_eq!(s.physical_edge(0), s.owned.start <= s.halo);
                    assert_eq!(s.physical_edge(1), s.owned.end + s.halo >= layers);
                    assert!(rank > 0 || s.physical_edge(0));
                    assert!(rank + 1 < ranks || s.physical_edge(1));
                    assert_eq!(s.halo_below(), usize::from(rank > 0));
                    assert_eq!(s.halo_above(), usize::from(rank + 1 < ranks));
                }
                assert_eq!(next, layers);
            }
        }
        let err = Slab::new(5, 3, 0, 2).unwrap_err();
        assert!(err.to_string().contains("at most 2 ranks"), "{err}");
    }

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
    }
}

//! [`ThreadComm`]: the ranks of a run as threads of one process, talking over channels.
//! It runs the decomposed path of a method in the default build (no MPI library), so the
//! tests compare 1 to N "ranks" against the serial run everywhere.
use crate::comm::Comm;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Mutex;

/// A message: sender rank and payload.
type Message = (usize, Payload);

/// How a part of an all-gather travels: wrapped into a payload, read back from one.
type Codec<T> = (fn(Vec<T>) -> Payload, fn(Payload) -> Vec<T>);

#[derive(Debug)]
enum Payload {
    Floats(Vec<f64>),
    Bytes(Vec<u8>),
}

/// One rank of a group of threads (see [`ThreadComm::group`]).
#[derive(Debug)]
pub struct ThreadComm {
    rank: usize,
    size: usize,
    to: Vec<Sender<Message>>,
    inbox: Mutex<(Receiver<Message>, Vec<Message>)>,
}

impl ThreadComm {
    /// `size` connected ranks; hand one to each thread.
    pub fn group(size: usize) -> Vec<ThreadComm> {
        let (senders, receivers): (Vec<_>, Vec<_>) = (0..size).map(|_| channel()).unzip();
        receivers
            .into_iter()
            .enumerate()
            .map(|(rank, rx)| ThreadComm {
                rank,
                size,
                to: senders.clone(),
                inbox: Mutex::new((rx, Vec::new())),
            })
            .collect()
    }

    /// `body` run on `ranks` thread ranks (one `ThreadComm` each, on scoped threads), its
    /// results in rank order: the decomposed path of a method in tests.
    pub fn on_ranks<T: Send>(
        ranks: usize,
        body: impl Fn(std::sync::Arc<dyn Comm>) -> T + Sync,
    ) -> Vec<T> {
        std::thread::scope(|s| {
            let handles: Vec<_> = Self::group(ranks)
                .into_iter()
                .map(|c| {
                    let body = &body;
                    s.spawn(move || body(std::sync::Arc::new(c)))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        })
    }

    fn send(&self, to: usize, payload: Payload) {
        // a receiver gone means its thread ended (panicked): the test fails there
        let _ = self.to[to].send((self.rank, payload));
    }

    /// The next message from `from` (messages of one sender arrive in order; others are
    /// kept until asked for).
    fn receive(&self, from: usize) -> Payload {
        let mut guard = self.inbox.lock().unwrap_or_else(|e| e.into_inner());
        let (rx, pending) = &mut *guard;
        if let Some(i) = pending.iter().position(|m| m.0 == from) {
            return pending.remove(i).1;
        }
        loop {
            let message = rx
                .recv()
                .expect("ThreadComm: every other rank has ended (a rank panicked)");
            if message.0 == from {
                return message.1;
            }
            pending.push(message);
        }
    }

    fn floats(&self, from: usize) -> Vec<f64> {
        Payload::floats(self.receive(from))
    }

    /// Every rank's `local` concatenated in rank order into `out`, the lengths in `counts`
    /// (both all-gathers: `pack` wraps a part for sending, `unpack` reads one received).
    fn all_gather_parts<T: Copy>(
        &self,
        local: &[T],
        (pack, unpack): Codec<T>,
        out: &mut Vec<T>,
        counts: &mut Vec<usize>,
    ) {
        for r in (0..self.size).filter(|&r| r != self.rank) {
            self.send(r, pack(local.to_vec()));
        }
        out.clear();
        counts.clear();
        for r in 0..self.size {
            if r == self.rank {
                counts.push(local.len());
                out.extend_from_slice(local);
            } else {
                let part = unpack(self.receive(r));
                counts.push(part.len());
                out.extend_from_slice(&part);
            }
        }
    }
}

impl Payload {
    fn floats(self) -> Vec<f64> {
        match self {
            Payload::Floats(v) => v,
            Payload::Bytes(_) => panic!("ThreadComm: ranks called different collectives"),
        }
    }
    fn bytes(self) -> Vec<u8> {
        match self {
            Payload::Bytes(b) => b,
            Payload::Floats(_) => panic!("ThreadComm: ranks called different collectives"),
        }
    }
}

impl Comm for ThreadComm {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.size
    }
    fn all_gather_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        self.all_gather_parts(local, (Payload::Floats, Payload::floats), out, counts);
    }
    fn all_gather_bytes(&self, local: &[u8], out: &mut Vec<u8>, counts: &mut Vec<usize>) {
        self.all_gather_parts(local, (Payload::Bytes, Payload::bytes), out, counts);
    }
    fn gather_to_root_into(&self, local: &[f64], out: &mut Vec<f64>, counts: &mut Vec<usize>) {
        out.clear();
        counts.clear();
        if self.rank != 0 {
            self.send(0, Payload::Floats(local.to_vec()));
            return;
        }
        counts.push(local.len());
        out.extend_from_slice(local);
        for r in 1..self.size {
            let part = self.floats(r);
            counts.push(part.len());
            out.extend_from_slice(&part);
        }
    }
    fn exchange(
        &self,
        [lower, upper]: [Option<usize>; 2],
        to_lower: &[f64],
        to_upper: &[f64],
        from_lower: &mut [f64],
        from_upper: &mut [f64],
    ) {
        if let Some(r) = lower {
            self.send(r, Payload::Floats(to_lower.to_vec()));
        }
        if let Some(r) = upper {
            self.send(r, Payload::Floats(to_upper.to_vec()));
        }
        if let Some(r) = lower {
            from_lower.copy_from_slice(&self.floats(r));
        }
        if let Some(r) = upper {
            from_upper.copy_from_slice(&self.floats(r));
        }
    }
    fn barrier(&self) {
        self.all_gather(&[]);
    }
    fn abort(&self, code: i32) -> ! {
        std::process::exit(code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four threads: sums in rank order, min/max, the halo exchange and the first error
    /// agree on every rank; the gather to the root gives rank 0 the parts in rank order and
    /// the other ranks nothing.
    #[test]
    fn thread_ranks_reduce_and_exchange() {
        let results: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = ThreadComm::group(4)
                .into_iter()
                .map(|c| {
                    s.spawn(move || {
                        let r = c.rank() as f64;
                        let sum = c.all_reduce_sum(0.1 * (r + 1.0));
                        let (lo, hi) = (c.all_reduce_min(r), c.all_reduce_max(r));
                        let (mut below, mut above) = (vec![f64::NAN], vec![f64::NAN]);
                        if c.rank() == 0 {
                            below.clear();
                        }
                        if c.rank() + 1 == c.size() {
                            above.clear();
                        }
                        let neighbours = [
                            c.rank().checked_sub(1),
                            (c.rank() + 1 < c.size()).then_some(c.rank() + 1),
                        ];
                        c.exchange(neighbours, &[r], &[r], &mut below, &mut above);
                        let (below, above) = (
                            below.first().copied().unwrap_or(f64::NAN),
                            above.first().copied().unwrap_or(f64::NAN),
                        );
                        let err = c.first_error((c.rank() >= 2).then_some("boom"));
                        // rank r sends r copies of r: only rank 0 receives them
                        let (mut rooted, mut counts) = (vec![f64::NAN], vec![9]);
                        c.gather_to_root_into(&vec![r; c.rank()], &mut rooted, &mut counts);
                        (sum, lo, hi, below, above, err, (rooted, counts))
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (rank, (sum, lo, hi, below, above, err, rooted)) in results.into_iter().enumerate() {
            if rank == 0 {
                let whole = vec![1.0, 2.0, 2.0, 3.0, 3.0, 3.0];
                assert_eq!(rooted, (whole, vec![0, 1, 2, 3]));
            } else {
                assert_eq!(rooted, (vec![], vec![]));
            }
            assert_eq!(sum, ((0.1 + 0.2) + 0.30000000000000004) + 0.4);
            assert_eq!((lo, hi), (0.0, 3.0));
            if rank > 0 {
                assert_eq!(below, rank as f64 - 1.0);
            }
            if rank < 3 {
                assert_eq!(above, rank as f64 + 1.0);
            }
            assert_eq!(err.unwrap().to_string(), "rank 2: boom");
        }
    }
}

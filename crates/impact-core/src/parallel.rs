//! One serial/parallel dispatch for the chunked loops of every method.
//!
//! A loop writes disjoint chunks of one or more arrays (`Chunks` of each array, zipped as
//! a tuple); [`for_each_chunk`] calls the kernel on every chunk with its index, either in
//! order on the calling thread or, when `parallel`, on rayon's pool by recursive halving
//! with `rayon::join` (no heap allocation inside the pool; leaves of at least `grain`
//! chunks run in order). [`sum_chunks`] does the same and adds up what the kernel returns
//! (in a fixed tree order for a given chunk count, so results do not depend on the thread
//! count). Only safe splitting (`split_at_mut`) is used: no unsafe aliasing.
//!
//! Loops that scatter into shared nodes (MPM, FEM) colour their cells so that the cells of
//! one colour write disjoint nodes, and run each colour through these helpers.

/// Whether a loop over `items` runs in parallel: from this many items on, and only when
/// rayon's pool has more than one thread (one thread would only add the join overhead).
pub const PARALLEL_ITEMS: usize = 4096;

/// Whether a loop over `items` should run on rayon's pool.
pub fn worth_parallel(items: usize) -> bool {
    items >= PARALLEL_ITEMS && rayon::current_num_threads() > 1
}

/// Threads of rayon's current pool.
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// Something that splits into a run of equal chunks (the last may be shorter).
pub trait Chunked: Sized + Send {
    /// One chunk.
    type Chunk: Send;
    /// Number of chunks.
    fn chunk_count(&self) -> usize;
    /// The first `chunks` chunks and the rest.
    fn split_chunks(self, chunks: usize) -> (Self, Self);
    /// The whole (a single chunk) as its chunk.
    fn into_chunk(self) -> Self::Chunk;
}

/// `data` cut into chunks of `size` items.
#[derive(Debug)]
pub struct Chunks<'a, T> {
    data: &'a mut [T],
    size: usize,
}

/// Cut `data` into chunks of `size` items (`size ≥ 1`).
pub fn chunks<T>(data: &mut [T], size: usize) -> Chunks<'_, T> {
    Chunks {
        data,
        size: size.max(1),
    }
}

impl<'a, T: Send> Chunked for Chunks<'a, T> {
    type Chunk = &'a mut [T];
    #[inline]
    fn chunk_count(&self) -> usize {
        self.data.len().div_ceil(self.size)
    }
    #[inline]
    fn split_chunks(self, chunks: usize) -> (Self, Self) {
        let at = (chunks * self.size).min(self.data.len());
        let (a, b) = self.data.split_at_mut(at);
        (
            Chunks {
                data: a,
                size: self.size,
            },
            Chunks {
                data: b,
                size: self.size,
            },
        )
    }
    #[inline]
    fn into_chunk(self) -> Self::Chunk {
        self.data
    }
}

impl<A: Chunked, B: Chunked> Chunked for (A, B) {
    type Chunk = (A::Chunk, B::Chunk);
    #[inline]
    fn chunk_count(&self) -> usize {
        self.0.chunk_count().min(self.1.chunk_count())
    }
    #[inline]
    fn split_chunks(self, chunks: usize) -> (Self, Self) {
        let (a0, a1) = self.0.split_chunks(chunks);
        let (b0, b1) = self.1.split_chunks(chunks);
        ((a0, b0), (a1, b1))
    }
    #[inline]
    fn into_chunk(self) -> Self::Chunk {
        (self.0.into_chunk(), self.1.into_chunk())
    }
}

impl<A: Chunked, B: Chunked, C: Chunked> Chunked for (A, B, C) {
    type Chunk = (A::Chunk, B::Chunk, C::Chunk);
    #[inline]
    fn chunk_count(&self) -> usize {
        self.0
            .chunk_count()
            .min(self.1.chunk_count())
            .min(self.2.chunk_count())
    }
    #[inline]
    fn split_chunks(self, chunks: usize) -> (Self, Self) {
        let (a0, a1) = self.0.split_chunks(chunks);
        let (b0, b1) = self.1.split_chunks(chunks);
        let (c0, c1) = self.2.split_chunks(chunks);
        ((a0, b0, c0), (a1, b1, c1))
    }
    #[inline]
    fn into_chunk(self) -> Self::Chunk {
        (
            self.0.into_chunk(),
            self.1.into_chunk(),
            self.2.into_chunk(),
        )
    }
}

/// Call `kernel(index, chunk)` on every chunk of `parts`: in order when `parallel` is
/// false, else on rayon's pool (leaves of at least `grain` chunks run in order).
#[inline]
pub fn for_each_chunk<P: Chunked>(
    parallel: bool,
    grain: usize,
    parts: P,
    kernel: impl Fn(usize, P::Chunk) + Sync,
) {
    sum_chunks(parallel, grain, parts, |i, c| {
        kernel(i, c);
        0.0
    });
}

/// [`for_each_chunk`] that adds up the kernel's results, by halves in both cases (serial:
/// the halves one after the other; parallel: on rayon's pool), so the sum's rounding
/// depends only on the chunk count and `grain`, never on the thread count.
#[inline]
pub fn sum_chunks<P: Chunked>(
    parallel: bool,
    grain: usize,
    parts: P,
    kernel: impl Fn(usize, P::Chunk) -> f64 + Sync,
) -> f64 {
    halves(0, grain.max(1), parts, &kernel, parallel)
}

fn in_order<P: Chunked>(start: usize, parts: P, kernel: &impl Fn(usize, P::Chunk) -> f64) -> f64 {
    let mut rest = parts;
    let mut sum = 0.0;
    for i in 0..rest.chunk_count() {
        let (head, tail) = rest.split_chunks(1);
        sum += kernel(start + i, head.into_chunk());
        rest = tail;
    }
    sum
}

fn halves<P: Chunked>(
    start: usize,
    grain: usize,
    parts: P,
    kernel: &(impl Fn(usize, P::Chunk) -> f64 + Sync),
    parallel: bool,
) -> f64 {
    let n = parts.chunk_count();
    if n <= grain {
        return in_order(start, parts, kernel);
    }
    let mid = n / 2;
    let (a, b) = parts.split_chunks(mid);
    let (x, y) = if parallel {
        rayon::join(
            || halves(start, grain, a, kernel, parallel),
            || halves(start + mid, grain, b, kernel, parallel),
        )
    } else {
        (
            halves(start, grain, a, kernel, parallel),
            halves(start + mid, grain, b, kernel, parallel),
        )
    };
    x + y
}

/// The indices `0..n` in runs of `size`: the chunks of a loop that only reads.
#[derive(Debug, Clone)]
pub struct Ranges {
    items: std::ops::Range<usize>,
    size: usize,
}

/// `0..n` cut into runs of `size` indices (`size ≥ 1`).
pub fn ranges(n: usize, size: usize) -> Ranges {
    Ranges {
        items: 0..n,
        size: size.max(1),
    }
}

impl Chunked for Ranges {
    type Chunk = std::ops::Range<usize>;
    #[inline]
    fn chunk_count(&self) -> usize {
        self.items.len().div_ceil(self.size)
    }
    #[inline]
    fn split_chunks(self, chunks: usize) -> (Self, Self) {
        let at = (self.items.start + chunks * self.size).min(self.items.end);
        (
            Ranges {
                items: self.items.start..at,
                size: self.size,
            },
            Ranges {
                items: at..self.items.end,
                size: self.size,
            },
        )
    }
    #[inline]
    fn into_chunk(self) -> Self::Chunk {
        self.items
    }
}

/// Indices per chunk of [`sum_over`] and [`first_failing`].
const READ_CHUNK: usize = 4096;

/// `Σ_{i<n} term(i)`, on rayon's pool from [`PARALLEL_ITEMS`] items on, in an order fixed
/// by `n` (chunks of 4,096 summed by halves).
pub fn sum_over(n: usize, term: impl Fn(usize) -> f64 + Sync) -> f64 {
    sum_over_runs(n, |run| run_sum(run, &term))
}

/// [`sum_over`] with the terms added a run at a time: `run_sum(run)` adds the terms of
/// one run (at most 4,096 indices) in order from `-0.0`, so that it can read the run's
/// slices (one bounds check a run, not one a term); the runs' sums add up by halves as
/// [`sum_over`]'s do, so the two give the same bits for the same terms.
pub fn sum_over_runs(n: usize, run_sum: impl Fn(std::ops::Range<usize>) -> f64 + Sync) -> f64 {
    sum_chunks(worth_parallel(n), 1, ranges(n, READ_CHUNK), |_, r| {
        run_sum(r)
    })
}

/// [`first_failing`] with the test made a run at a time: `all_ok(run)` tells whether every
/// index of a run passes (a loop over the run's slices), `ok(i)` tests one index, to find
/// the first failing one in order once a run has failed.
pub fn first_failing_by_runs(
    n: usize,
    all_ok: impl Fn(std::ops::Range<usize>) -> bool + Sync,
    ok: impl Fn(usize) -> bool,
) -> Option<usize> {
    let failing = sum_chunks(worth_parallel(n), 1, ranges(n, READ_CHUNK), |_, r| {
        f64::from(u8::from(!all_ok(r)))
    });
    if failing > 0.0 {
        (0..n).find(|&i| !ok(i))
    } else {
        None
    }
}

/// `Σ_{i ∈ run} term(i)` in order from `-0.0` (`Iterator::sum`'s start), as a plain loop
/// forced inline: through `Iterator::map` the term was called per item, not inlined
/// (callgrind: about 70 instructions a point for an energy term of 30).
#[inline(always)]
fn run_sum(run: std::ops::Range<usize>, term: &impl Fn(usize) -> f64) -> f64 {
    let mut sum = -0.0;
    for i in run {
        sum += term(i);
    }
    sum
}

/// Whether `ok(i)` holds for every `i ∈ run`, as [`run_sum`] a plain loop forced inline.
#[inline(always)]
fn run_all(run: std::ops::Range<usize>, ok: &impl Fn(usize) -> bool) -> bool {
    for i in run {
        if !ok(i) {
            return false;
        }
    }
    true
}

/// The first `i < n` for which `ok(i)` is false, if any: the check runs on rayon's pool
/// from [`PARALLEL_ITEMS`] items on; the first failing index is then found in order.
pub fn first_failing(n: usize, ok: impl Fn(usize) -> bool + Sync) -> Option<usize> {
    first_failing_by_runs(n, |run| run_all(run, &ok), &ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every chunk is visited once with its index, serially and in parallel, and the sums
    /// agree.
    #[test]
    fn chunks_are_visited_once_with_their_index() {
        for parallel in [false, true] {
            let mut a = vec![0usize; 10_003];
            let mut b = vec![0.0f64; 10_003];
            let sum = sum_chunks(
                parallel,
                3,
                (chunks(&mut a, 7), chunks(&mut b, 7)),
                |i, (a, b)| {
                    for (k, (x, y)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
                        *x += i * 7 + k;
                        *y = 1.0;
                    }
                    a.len() as f64
                },
            );
            assert_eq!(sum, 10_003.0);
            assert!(a.iter().enumerate().all(|(k, &x)| x == k));
            assert!(b.iter().all(|&y| y == 1.0));
        }
    }

    /// The read-only helpers: the sum is the same serially and in parallel (bit for bit,
    /// the order fixed by the item count) and equals the plain sum to round-off; the first
    /// failing index is the smallest.
    #[test]
    fn sums_and_searches_over_ranges() {
        let n = 100_003;
        let term = |i: usize| 1.0 / (1.0 + i as f64);
        let plain: f64 = (0..n).map(term).sum();
        let pool = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
        };
        let one = pool(1).install(|| sum_over(n, term));
        let two = pool(2).install(|| sum_over(n, term));
        assert_eq!(one.to_bits(), two.to_bits());
        assert!((one - plain).abs() <= 1e-13 * plain);
        for threads in [1, 2] {
            pool(threads).install(|| {
                assert_eq!(first_failing(n, |i| i % 50_000 != 49_999), Some(49_999));
                assert_eq!(first_failing(n, |_| true), None);
            });
        }
    }
}

//! What the in-process benches share (`threads.rs`, `fem_fused.rs`, `guard.rs`,
//! `rk2_euler.rs`): their arguments, the median, and rayon pools of a given size.

/// The numbers among the arguments: `NX NY` (default 1000×750, the plate of issue 14),
/// then the rest.
pub fn plate_arguments() -> (Vec<usize>, Vec<usize>) {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    match args.as_slice() {
        [nx, ny, rest @ ..] => (vec![*nx, *ny], rest.to_vec()),
        _ => (vec![1000, 750], vec![]),
    }
}

/// The median of `v` (the upper one of an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// A rayon pool of `threads` threads.
pub fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}

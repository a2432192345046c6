//! The time loop. It owns the schedule (land exactly on output times, never exceed the
//! stable step) and the stability guard, which stops a run whose state is non-finite,
//! whose energy grows far past the work done by the loads, or whose largest stress grows
//! like an unstable mode ([`Guard::stress_scale`]).
//!
//! The energy test alone misses a slowly growing mode on a body whose energy grows
//! physically: a free bar under a constant pressure gains kinetic energy like `t²`, so
//! `10 × (work + initial energy)` keeps ahead of a mode growing by `1.0005` per step for
//! thousands of steps (DGMPM at 2 points per cell and Courant 0.70, above its von Neumann
//! limit 0.686, reached ±7 GPa under a 1 GPa load unstopped). The stress is bounded
//! physically by a few times the loads' stress scale `s` (`p`, or `Z v_d` for an impactor;
//! a fixed end doubles it), and grows at most linearly in time (a resonant load), so at
//! every [`Guard::norm_every`]-th check (every 100 steps by default) and at every output,
//! after the first [`WARMUP_CHECKS`] such tests, the run stops when the largest stress
//! `S(t)` of the samples satisfies both
//!
//! `S(t) > STRESS_EXCESS · max(s, S(0), Z V(0))` and `S(t) > STRESS_GROWTH · max_{τ ≤ t/2} S(τ)`:
//!
//! far past the physical scale, and growing faster than any linear growth (`S(t)/S(t/2)
//! ≤ 2`; the running maximum, since a forced standing mode passes through `S ≈ 0`). An unstable mode grows exponentially from round-off, so it passes both soon
//! after it shows.
//!
//! Between two outputs the loop takes full stable steps `Δt_stable` and shortens only the
//! last one to land on `t_out` (as Clawpack does), so an output time that is a whole number
//! of stable steps is reached with exactly the stable step (needed for the Courant-1
//! exactness of DGMPM and FEM). The alternative, `n = ceil(span/Δt_stable)` equal steps,
//! lowers the Courant number of *every* step by up to `1/n`, and first-order upwind
//! diffusion grows with `1 - C`: on the SVK tension shock (150 cells, Courant 1, 123 steps)
//! equal steps ran at an effective 0.976 and smeared the shock to 2.44/3.24/3.85 cells;
//! full steps give 1.51/2.01/2.26 cells and a 3× smaller L1 error.
//!
//! No sliver steps ([`Span`]): when `t_out` falls a hair past a whole number `m` of stable
//! steps, the shortened last step would be a near-zero sliver, and a sliver is not a
//! harmless step: each DGMPM step applies the point-node projection, which at 2 points per
//! cell changed σ by 0.5-1.2 % of the amplitude, so results jumped with the output time
//! (issue 23). When the remainder `r = span - m Δt_stable` is at most
//! [`MERGE_FRACTION`]` · Δt_stable`, the span is covered by `m` equal steps
//! `span/m = Δt_stable (1 + r/(m Δt_stable))` instead: none exceeds the stable step by more
//! than the fraction `r/(m Δt)` ≤ [`MERGE_FRACTION`]`/m`, and the amplification this can
//! cause over the whole span is bounded (for upwind transport at `C = 1 + δ`,
//! `|G| ≤ 1 + 2δ`, so `(1 + 2r/(mΔt))^m ≤ e^{2·MERGE_FRACTION}` ≈ 1.002). The result is then
//! continuous in `t_out` on both sides of a whole number of steps (a hair before: the last
//! step tends to `Δt_stable`; a hair after: the `m` steps tend to `Δt_stable`), and an
//! output time that is a whole number of stable steps is still reached with exactly the
//! stable step (the paper's numbers are unchanged). A remainder above the fraction is a
//! real last step, taken as before.
use crate::comm::Comm;
use crate::method::{Blowup, Method, Samples};
use crate::Vector;

/// Stability guard settings.
#[derive(Debug, Clone, Copy)]
pub struct Guard {
    /// Check the state every this many steps (and at every output).
    pub check_every: usize,
    /// Stop when `energy > growth · (work + initial energy) + floor`.
    pub growth: f64,
    /// Stop (with [`RunError::Interrupted`]) once this flag is set: read after every step
    /// (the CLI sets it on SIGINT and SIGTERM).
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
    /// The loads' stress scale `s` (Pa) of the max-norm test (module doc); 0 disables it
    /// (the stability sweeps, which judge the max norm themselves).
    pub stress_scale: f64,
    /// Impedance `Z = ρ c_p` turning the initial speed into a stress scale.
    pub impedance: f64,
    /// The max-norm test runs at every `norm_every`-th check (and at every output): it
    /// samples the state, which costs FEM about 5 of its steps on the plate, and a slow
    /// mode takes thousands of steps to show.
    pub norm_every: usize,
}

/// The largest stress over the stress scale at which the max-norm test may fire.
pub const STRESS_EXCESS: f64 = 3.0;
/// The growth of the largest stress since half the time at which it fires.
pub const STRESS_GROWTH: f64 = 2.5;
/// Checks before the max-norm test starts (the stress builds up from the load first).
pub const WARMUP_CHECKS: usize = 4;

impl Default for Guard {
    fn default() -> Self {
        Self {
            check_every: 10,
            growth: 10.0,
            stop: None,
            stress_scale: 0.0,
            impedance: 0.0,
            norm_every: 10,
        }
    }
}

/// The largest stress component `max_i max_rc |σ_rc|` of `samples` and the index of its
/// sample (a NaN wins).
fn peak_stress<const D: usize>(samples: &Samples<D>) -> (f64, usize) {
    let mut peak = (0.0f64, 0usize);
    for (i, s) in samples.stress.iter().enumerate() {
        let m = s.amax();
        if m > peak.0 || m.is_nan() {
            peak = (m, i);
        }
    }
    peak
}

/// [`peak_stress`] over every rank's owned samples (`samples`, this rank's
/// [`Method::owned_samples_into`]) and the reference place of its sample: each rank's own
/// peak, gathered (one value and a place per rank, not the samples), then the same scan
/// over the ranks' peaks in rank order. The owned samples are in global order, so the
/// scan keeps what the one-rank scan keeps (the last NaN, else the first of equal maxima):
/// the same peak and place on any rank count.
fn peak_over_ranks<const D: usize>(comm: &dyn Comm, samples: &Samples<D>) -> (f64, Vector<D>) {
    let (peak, at) = peak_stress(samples);
    let place = samples
        .reference
        .get(at)
        .copied()
        .unwrap_or_else(Vector::<D>::zeros);
    if comm.size() == 1 {
        return (peak, place);
    }
    let mut entry = [0.0; 4];
    entry[0] = peak;
    entry[1..=D].copy_from_slice(place.as_slice());
    let all = comm.all_gather(&entry[..=D]);
    let mut best = 0;
    for r in 1..comm.size() {
        let m = all[r * (D + 1)];
        if m > all[best * (D + 1)] || m.is_nan() {
            best = r;
        }
    }
    let at = best * (D + 1);
    (
        all[at],
        Vector::<D>::from_column_slice(&all[at + 1..=at + D]),
    )
}

/// What a run did.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the stepping alone (s), outputs excluded.
    pub wall_s: f64,
}

/// Why a run stopped early.
#[derive(Debug)]
pub enum RunError<E> {
    /// The guard stopped the run.
    Blowup(Blowup),
    /// The output callback failed.
    Output(E),
    /// The stop flag was set.
    Interrupted {
        /// Steps taken.
        step: usize,
        /// Time reached (s).
        time: f64,
    },
}

impl<E: std::fmt::Display> std::fmt::Display for RunError<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Blowup(b) => write!(f, "{b}"),
            RunError::Output(e) => write!(f, "output failed: {e}"),
            RunError::Interrupted { step, time } => {
                write!(f, "interrupted at step {step}, t = {time:.6e} s")
            }
        }
    }
}

impl<E: std::fmt::Debug + std::fmt::Display> std::error::Error for RunError<E> {}

/// Largest remainder, as a fraction of the stable step, that is merged into the whole
/// steps before it instead of taken as a last step of its own (module doc).
pub const MERGE_FRACTION: f64 = 1e-3;

/// The steps from one output time to the next (module doc): `steps` steps, step `k`
/// ending at [`Span::step`]`(k).1`, the last one exactly at `t_out`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Start `t`.
    pub start: f64,
    /// End `t_out`.
    pub end: f64,
    /// Number of steps.
    pub steps: usize,
    /// Size of every step but the last: `Δt_stable`, or `span/steps` when a small
    /// remainder was merged.
    pub size: f64,
}

impl Span {
    /// The schedule from `start` to `end` with stable step `dt_stable`: full stable steps
    /// and a shortened last one, or, when the remainder past `m` whole steps is at most
    /// [`MERGE_FRACTION`] of a step, `m` equal steps.
    pub fn new(start: f64, end: f64, dt_stable: f64) -> Self {
        let span = end - start;
        // a span within 1e-12 of a whole number of steps is that number (round-off)
        let n = ((span / dt_stable) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
        let last = span - (n - 1) as f64 * dt_stable;
        if n > 1 && last <= MERGE_FRACTION * dt_stable {
            let steps = n - 1;
            return Self {
                start,
                end,
                steps,
                size: span / steps as f64,
            };
        }
        Self {
            start,
            end,
            steps: n,
            size: dt_stable,
        }
    }

    /// Start and end of step `k` (`k < steps`); the last ends exactly at `end`.
    #[inline]
    pub fn step(&self, k: usize) -> (f64, f64) {
        let t0 = self.start + k as f64 * self.size;
        let t1 = if k + 1 == self.steps {
            self.end
        } else {
            t0 + self.size
        };
        (t0, t1)
    }
}

/// Run `method` from `t = 0` through every output time. `on_output(method, index, t,
/// step)` is called at each output time; `on_progress(t)` after each step.
///
/// The loop runs on a worker of rayon's global pool, so the parallel loops of a step are
/// forked from inside the pool (onto the worker's own deque). Forked from outside, each
/// parallel loop would be injected through rayon's global queue, which allocates a block
/// every 63 jobs: a heap allocation in the step loop.
pub fn run<const D: usize, M, E>(
    method: &mut M,
    output_times: &[f64],
    guard: Guard,
    on_output: impl FnMut(&M, usize, f64, usize) -> Result<(), E> + Send,
    on_progress: impl FnMut(f64) + Send,
) -> Result<RunStats, RunError<E>>
where
    M: Method<D> + ?Sized,
    E: Send,
{
    rayon::scope(|_| run_here(method, output_times, guard, on_output, on_progress))
}

/// [`run`] on the calling thread.
fn run_here<const D: usize, M, E>(
    method: &mut M,
    output_times: &[f64],
    guard: Guard,
    mut on_output: impl FnMut(&M, usize, f64, usize) -> Result<(), E>,
    mut on_progress: impl FnMut(f64),
) -> Result<RunStats, RunError<E>>
where
    M: Method<D> + ?Sized,
{
    let dt_stable = method.stable_dt();
    let name = method.config().kind().name();
    let initial_energy = method.energy();
    let mut t = 0.0;
    let mut steps = 0usize;
    let mut wall = 0.0;
    // the max-norm test's buffers, allocated here: the step loop only refills them
    let mut samples = Samples::<D>::default();
    let mut history: Vec<(f64, f64)> = Vec::new();
    let mut stress_scale = guard.stress_scale;
    if guard.stress_scale > 0.0 {
        // this rank's own samples, the maxima reduced over the ranks (no gather of samples)
        method.owned_samples_into(&mut samples);
        let comm = method.comm();
        let speed = samples.velocity.iter().fold(0.0f64, |m, v| m.max(v.amax()));
        let speed = comm.all_reduce_max(speed);
        let peak = peak_over_ranks(comm, &samples).0;
        stress_scale = stress_scale.max(peak).max(guard.impedance * speed);
        let t_end = output_times.last().copied().unwrap_or(0.0);
        let checks = (t_end / dt_stable * 1.01).ceil() as usize
            / (guard.check_every.max(1) * guard.norm_every.max(1));
        history.reserve_exact(checks + output_times.len() + 2);
        history.push((0.0, peak));
    }
    let norm_every = guard.check_every.max(1) * guard.norm_every.max(1);
    let mut check = |m: &M, step: usize, t: f64, norm: bool| -> Result<(), Blowup> {
        let blowup = |place: Vec<f64>, reason: String| Blowup {
            method: name.to_string(),
            step,
            time: t,
            place,
            reason,
        };
        if let Err(bad) = m.check_finite() {
            return Err(blowup(bad.place.iter().copied().collect(), bad.reason));
        }
        let energy = m.energy();
        let work = m.external_work().abs();
        let bound = guard.growth * (work + initial_energy) + f64::MIN_POSITIVE;
        // a NaN energy is not within the bound either
        let within = energy <= bound;
        if !within {
            return Err(blowup(
                m.hottest_place().iter().copied().collect(),
                format!(
                    "energy {energy:.3e} J exceeds {:.0}× (work done {work:.3e} J + initial {initial_energy:.3e} J)",
                    guard.growth
                ),
            ));
        }
        if guard.stress_scale > 0.0 && norm {
            m.owned_samples_into(&mut samples);
            let (peak, place) = peak_over_ranks(m.comm(), &samples);
            // the largest stress up to half the time (a running maximum: a forced standing
            // mode passes through σ ≈ 0, so a single value at t/2 could be near zero)
            let half = history
                .partition_point(|&(s, _)| s <= 0.5 * t)
                .saturating_sub(1);
            let at_half = history[half].1;
            if history.len() > WARMUP_CHECKS
                && peak > STRESS_EXCESS * stress_scale
                && peak > STRESS_GROWTH * at_half
            {
                return Err(blowup(
                    place.iter().copied().collect(),
                    format!(
                        "the largest stress {peak:.3e} Pa is {:.1}× the loads' stress scale \
                         {stress_scale:.3e} Pa and {:.1}× its largest value up to t = {:.4e} s: \
                         a growing mode (the scheme is unstable here)",
                        peak / stress_scale,
                        peak / at_half,
                        history[half].0
                    ),
                ));
            }
            let running = history.last().map_or(peak, |h| h.1.max(peak));
            if history.len() < history.capacity() {
                history.push((t, running));
            } else if let Some(last) = history.last_mut() {
                // past the reserved checks (never, by the count above): keep the latest
                *last = (t, running);
            }
        }
        Ok(())
    };
    for (index, &t_out) in output_times.iter().enumerate() {
        let span = Span::new(t, t_out, dt_stable);
        if t_out - t > 0.0 {
            let n = span.steps;
            let start = std::time::Instant::now();
            for k in 0..n {
                let (t0, t1) = span.step(k);
                method.step(t0, t1 - t0);
                steps += 1;
                if steps.is_multiple_of(guard.check_every.max(1)) {
                    // the max-norm test every `norm_every` steps, but not on the last step
                    // of a span: the output's check right after runs it
                    let norm = steps.is_multiple_of(norm_every) && k + 1 < n;
                    check(method, steps, t1, norm).map_err(RunError::Blowup)?;
                }
                on_progress(t1);
                if guard
                    .stop
                    .is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed))
                {
                    return Err(RunError::Interrupted {
                        step: steps,
                        time: t1,
                    });
                }
            }
            wall += start.elapsed().as_secs_f64();
            t = t_out;
        }
        check(method, steps, t, true).map_err(RunError::Blowup)?;
        on_output(method, index, t, steps).map_err(RunError::Output)?;
    }
    Ok(RunStats {
        steps,
        wall_s: wall,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whole steps land with the stable step; a hair past them is merged (no sliver, no
    /// step above the stable one by more than the merged fraction); a real remainder is a
    /// last step of its own.
    #[test]
    fn spans_take_no_sliver_steps() {
        let dt = 0.1;
        let whole = Span::new(0.0, 10.0 * dt, dt);
        assert_eq!((whole.steps, whole.size), (10, dt));
        assert_eq!(whole.step(9).1, 10.0 * dt);
        let hair = Span::new(0.0, 10.0 * dt * (1.0 + 1e-10), dt);
        assert_eq!(hair.steps, 10);
        assert!(hair.size > dt && hair.size < dt * (1.0 + 2e-10));
        let (t0, t1) = hair.step(9);
        assert_eq!(t1, 10.0 * dt * (1.0 + 1e-10));
        assert!((t1 - t0 - hair.size).abs() < 1e-15);
        // a remainder of 1e-4 steps after 3 steps: 3 steps of (1 + 1e-4/3) Δt
        let small = Span::new(1.0, 1.0 + 3.0001 * dt, dt);
        assert_eq!(small.steps, 3);
        assert!(small.size <= dt * (1.0 + MERGE_FRACTION / 3.0));
        // a real remainder: 3 full steps and 0.3 of one
        let real = Span::new(0.0, 3.3 * dt, dt);
        assert_eq!((real.steps, real.size), (4, dt));
        let (t0, t1) = real.step(3);
        assert!((t1 - t0 - 0.3 * dt).abs() < 1e-15);
        // a span shorter than a step is one step
        let short = Span::new(0.0, 1e-6 * dt, dt);
        assert_eq!(short.steps, 1);
        assert_eq!(short.step(0), (0.0, 1e-6 * dt));
        // a hair before a whole number: the last step is within a hair of Δt
        let before = Span::new(0.0, 10.0 * dt * (1.0 - 1e-10), dt);
        assert_eq!((before.steps, before.size), (10, dt));
    }

    /// The peak stress over ranks (each rank's owned samples, consecutive runs of the
    /// global order) is the one-rank peak and place: ties keep the first, a NaN the last.
    #[test]
    fn peak_over_ranks_is_the_one_rank_peak() {
        use crate::comm::{SerialComm, ThreadComm};
        use crate::Tensor;
        let peaks = |values: &[f64]| {
            let mut all = Samples::<1>::default();
            for (i, &v) in values.iter().enumerate() {
                all.stress.push(Tensor::<1>::new(v));
                all.reference.push(Vector::<1>::new(i as f64));
            }
            all
        };
        let cases: [&[f64]; 4] = [
            &[1.0, -3.0, 2.0, 3.0, 0.5, -3.0, 1.0],
            &[0.0; 7],
            &[1.0, f64::NAN, 9.0, 2.0, f64::NAN, 1.0, 4.0],
            &[5.0, 1.0, 1.0, 1.0, 1.0, 1.0, 5.0],
        ];
        for values in cases {
            let all = peaks(values);
            let (peak, place) = peak_over_ranks(&SerialComm, &all);
            for ranks in 2..=4 {
                let got = ThreadComm::on_ranks(ranks, |comm| {
                    // rank r owns the r-th of `ranks` consecutive runs
                    let (r, n) = (comm.rank(), values.len());
                    let own = r * n / ranks..(r + 1) * n / ranks;
                    let mut mine = Samples::<1>::default();
                    mine.stress.extend_from_slice(&all.stress[own.clone()]);
                    mine.reference.extend_from_slice(&all.reference[own]);
                    peak_over_ranks(comm.as_ref(), &mine)
                });
                for (p, x) in got {
                    assert_eq!(p.to_bits(), peak.to_bits(), "{values:?} on {ranks} ranks");
                    assert_eq!(x, place, "{values:?} on {ranks} ranks");
                }
            }
        }
        // the one-rank answers themselves (largest |σ|): the first of equal maxima, zeros'
        // first sample, the last NaN, the first of two equal ends
        assert_eq!(peak_over_ranks(&SerialComm, &peaks(cases[0])).1[0], 1.0);
        assert_eq!(peak_over_ranks(&SerialComm, &peaks(cases[1])).1[0], 0.0);
        assert_eq!(peak_over_ranks(&SerialComm, &peaks(cases[2])).1[0], 4.0);
        assert!(peak_over_ranks(&SerialComm, &peaks(cases[2])).0.is_nan());
        assert_eq!(peak_over_ranks(&SerialComm, &peaks(cases[3])).1[0], 0.0);
    }
}

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
//! each check `k` (after the first [`WARMUP_CHECKS`]) the run stops when the largest
//! stress `S(t)` of the samples satisfies both
//!
//! `S(t) > STRESS_EXCESS · max(s, S(0), Z V(0))` and `S(t) > STRESS_GROWTH · S(t/2)`:
//!
//! far past the physical scale, and growing faster than any linear growth (`S(t)/S(t/2)
//! ≤ 2`). An unstable mode grows exponentially from round-off, so it passes both soon
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
use crate::method::{Blowup, Method, Samples};

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
        method.sample_into(&mut samples);
        let speed = samples.velocity.iter().fold(0.0f64, |m, v| m.max(v.amax()));
        stress_scale = stress_scale
            .max(peak_stress(&samples).0)
            .max(guard.impedance * speed);
        let t_end = output_times.last().copied().unwrap_or(0.0);
        let checks = (t_end / dt_stable * 1.01).ceil() as usize / guard.check_every.max(1);
        history.reserve_exact(checks + output_times.len() + 2);
        history.push((0.0, peak_stress(&samples).0));
    }
    let mut check = |m: &M, step: usize, t: f64| -> Result<(), Blowup> {
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
        if guard.stress_scale > 0.0 {
            m.sample_into(&mut samples);
            let (peak, at) = peak_stress(&samples);
            let half = history.partition_point(|&(s, _)| s < 0.5 * t);
            let at_half = history.get(half).map_or(peak, |h| h.1);
            if history.len() > WARMUP_CHECKS
                && peak > STRESS_EXCESS * stress_scale
                && peak > STRESS_GROWTH * at_half
            {
                let place = samples.reference[at].iter().copied().collect();
                return Err(blowup(
                    place,
                    format!(
                        "the largest stress {peak:.3e} Pa is {:.1}× the loads' stress scale \
                         {stress_scale:.3e} Pa and grew {:.1}× since t = {:.4e} s: a growing \
                         mode (the scheme is unstable here)",
                        peak / stress_scale,
                        peak / at_half,
                        history[half.min(history.len() - 1)].0
                    ),
                ));
            }
            if history.len() < history.capacity() {
                history.push((t, peak));
            }
        }
        Ok(())
    };
    for (index, &t_out) in output_times.iter().enumerate() {
        let span = t_out - t;
        if span > 0.0 {
            let n = ((span / dt_stable) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
            let start = std::time::Instant::now();
            for k in 0..n {
                let t0 = t + k as f64 * dt_stable;
                let t1 = if k + 1 == n { t_out } else { t0 + dt_stable };
                method.step(t0, t1 - t0);
                steps += 1;
                if steps.is_multiple_of(guard.check_every.max(1)) {
                    check(method, steps, t1).map_err(RunError::Blowup)?;
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
        check(method, steps, t).map_err(RunError::Blowup)?;
        on_output(method, index, t, steps).map_err(RunError::Output)?;
    }
    Ok(RunStats {
        steps,
        wall_s: wall,
    })
}

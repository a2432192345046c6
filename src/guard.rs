//! The stability guard around a run: before it, DGMPM's Courant number against its von
//! Neumann limit; after a blow-up, advice that applies to the configuration.
//!
//! - **Before the run** ([`check_stable`]): the project computes DGMPM's von Neumann
//!   amplification for any layout ([`crate::stability::max_amplification`]: the one-step
//!   matrices of the scheme on the scene's material, points per cell, integrator, flux and
//!   update, Fourier-transformed; 256 wave numbers in 1D, 24² in 2D, 16³ in 3D, of which
//!   the octant 9³ where the layout is mirror symmetric, [`crate::von_neumann`]). A
//!   configuration whose
//!   largest spectral radius exceeds `1 + 1e-9` at its Courant number grows some mode every
//!   step on any boundary conditions; it is refused, with its limit (bisection to 1e-5) and
//!   what would make it stable, unless `--allow-unstable` is given (then it runs, and the
//!   outputs record the flag). Nonlinear models (SVK, J2) are checked on their
//!   linearisation at rest (linear elasticity with the same `E`, `ν`, `ρ`).
//! - **MPM and FEM** have no von Neumann limit computed here. Before their run the guard
//!   measures instead ([`grows`]): the scene's body cut to 40 cells (1D) or 16×12 (2D)
//!   with the cell size and edges kept and the loads removed (a pressure edge free, a whole
//!   impactor edge fixed, an impactor segment free), at rest plus a deterministic random
//!   velocity of ±1 m/s, run 2000 (1D) or 500 (2D) steps under the in-run max-norm test
//!   ([`impact_core::controller`]) with the scale `Z · 1 m/s`: a mode growing faster than
//!   linearly (not the linear growth of a double eigenvalue at the exact limit, e.g. FEM in
//!   1D at Courant 1) refuses the run as unstable, with the limit the same measurement
//!   bisects (12 halvings). An unstable free corner of a plate (MPM at Courant 0.75, FEM
//!   at 1.0) grows only after 50 to 90 steps of the loaded run, past the paper plate's 24
//!   to 48 steps, so it finished with exit 0 before this check.
//! - **After a blow-up** ([`diagnose_blowup`]): for DGMPM the von Neumann limit, and RK2
//!   as advice only where the run used Euler; for MPM and FEM the limit the stability
//!   sweep measures for the same configuration (a short perturbed run: a measurement,
//!   stated as such).
use impact_core::method::{Integrator, MethodConfig};
use impact_core::problem::Model;
use impact_core::Problem;

/// A configuration refused before its run: its Courant number is above its von Neumann
/// limit (exit code 2, as any bad input).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Unstable(pub String);

/// Wave numbers per axis of the von Neumann check.
fn samples(d: usize) -> usize {
    match d {
        1 => 256,
        2 => 24,
        // 16³ = 4096 wave numbers (θ = π on every axis among them): the 9 × 9 matrices of
        // one point per cell then cost 3e6, within `MAX_COST`
        _ => 16,
    }
}

/// Largest cost of the check, in `wave numbers × n³` for `n × n` amplification matrices
/// (`n` = points per cell × unknowns per point): 1D up to 17 points per cell, 2D up to 4
/// (0.1 s to a few seconds with the bisection of a refusal). Beyond it the check would
/// take minutes (2D, 64 points per cell: 320 × 320 matrices at 576 wave numbers), so it
/// is skipped with a note, and the in-run max-norm test guards the run.
const MAX_COST: f64 = 1e7;

/// The same in 3D, where the mirror-symmetric layouts sample the octant
/// ([`crate::von_neumann`]: 9³ wave numbers) on rayon's pool: up to 8 points per cell
/// (72 × 72 matrices, 2.7e8; measured in `README.md`'s stability section), not 27 (1e10).
const MAX_COST_3D: f64 = 3e8;

/// The cost of the check for `config` in dimension `d` (see [`MAX_COST`]); in 3D with
/// a centred layout the octant's wave numbers ([`crate::von_neumann`]).
fn cost<const D: usize>(problem: &Problem<D>, config: &MethodConfig) -> f64 {
    let d = D;
    let n = (config.points_per_cell * (d * (d + 1) / 2 + d)) as f64;
    let centred = problem.layout == impact_core::points::PointLayout::Centred;
    let per_axis = if d == 3 && centred {
        samples(d) / 2 + 1
    } else {
        samples(d)
    };
    (per_axis as f64).powi(d as i32) * n.powi(3)
}

/// Whether the check runs for `config` (its cost within [`MAX_COST`], 3D
/// [`MAX_COST_3D`]).
fn affordable<const D: usize>(problem: &Problem<D>, config: &MethodConfig) -> bool {
    cost(problem, config) <= if D == 3 { MAX_COST_3D } else { MAX_COST }
}

/// What the check before a run found.
#[derive(Debug, Clone, PartialEq)]
pub enum Stability {
    /// Within the von Neumann limit, or a method without one (MPM, FEM).
    Stable,
    /// Not checked (too costly): the sentence saying so.
    Unchecked(String),
    /// Above the limit and run under `--allow-unstable`: the sentence to print and record.
    AllowedUnstable(String),
}

/// The linear-elastic body at rest of `problem` and `config` on it (the linearisation
/// the von Neumann analysis applies to): the model's face solver becomes the linear one,
/// which the J2 solvers are at rest (the elastic solver is the linear one; the
/// elastoplastic one is too while both sides are inside the yield surface, its module
/// doc). Before this, a J2 configuration's `riemann` (refused on a linear-elastic body)
/// made the linearisation unbuildable and the check passed every Courant number: DCU at
/// Courant 1 on `ep-plate-wave` ran, and blew up at step 70 with the elastoplastic solver.
fn linearised<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> (Problem<D>, MethodConfig) {
    let mut body = problem.clone();
    body.model = Model::LinearElastic;
    body.initial = impact_core::initial::InitialState::Rest;
    let mut config = config;
    if let Some(o) = config.dgmpm_mut() {
        o.riemann = impact_core::method::DgmpmOptions::default().riemann;
    }
    (body, config)
}

/// DGMPM's largest von Neumann amplification at `config`'s Courant number, and its limit
/// when above 1; `None` for MPM and FEM, or a configuration the linearisation cannot
/// build ([`check_stable`] says so).
pub fn von_neumann<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Option<(f64, Option<f64>)> {
    config.dgmpm()?;
    if !affordable(problem, &config) {
        return None;
    }
    let (body, config) = linearised(problem, config);
    impact_dgmpm::Dgmpm::new(&body, config).ok()?;
    let rho = crate::stability::max_amplification(&body, config, samples(D))?;
    let limit = (rho > 1.0 + 1e-9)
        .then(|| crate::stability::von_neumann_limit(&body, config, samples(D)))
        .filter(|l| l.is_finite());
    Some((rho, limit))
}

/// The configuration's words: method, points per cell, integrator and (DGMPM) update.
fn describe(config: &MethodConfig) -> String {
    let update = config
        .dgmpm()
        .map(|o| {
            let order = match o.wave_limiter() {
                Some(l) => format!(", order 2 with limiter {l} (analysed unlimited)"),
                None => String::new(),
            };
            format!(", {} update{order}", o.update.name())
        })
        .unwrap_or_default();
    format!(
        "{}, {} points per cell, {}{update}",
        config.kind(),
        config.points_per_cell,
        config.integrator_label()
    )
}

/// What would make DGMPM `config` stable: a lower Courant number, and RK2 where the run
/// uses Euler (with RK2's limit).
fn advice<const D: usize>(problem: &Problem<D>, config: MethodConfig, limit: f64) -> String {
    let lower = if limit > 0.0 {
        // the bisection's stable end, rounded down to the digits shown
        format!(
            "lower --courant to at most {:.4}",
            (limit * 1e4).floor() / 1e4
        )
    } else {
        "no Courant number is stable for it".to_string()
    };
    let euler = config
        .dgmpm()
        .is_some_and(|o| o.integrator == Integrator::Euler);
    let mut other = config;
    if let Some(o) = other.dgmpm_mut() {
        o.integrator = Integrator::Rk2;
    }
    let rk2 = match euler.then(|| von_neumann(problem, other)).flatten() {
        Some((_, None)) => Some(format!(
            "--integrator rk2 (stable at Courant {})",
            config.courant
        )),
        Some((_, Some(l))) => Some(format!("--integrator rk2 (von Neumann limit {l:.4})")),
        None => None,
    };
    match rk2 {
        Some(r) => format!("{lower}, or use {r}"),
        None => lower,
    }
}

/// Whether a perturbed unloaded cut of `problem`'s body grows under `config` faster than
/// linearly (module doc: MPM and FEM).
pub fn grows<const D: usize>(problem: &Problem<D>, config: MethodConfig) -> bool {
    use impact_core::{Boundary, Load};
    let mut body = problem.clone();
    let most = if D == 1 { [40, 1] } else { [16, 12] };
    for l in 0..D {
        body.grid.cells[l] = body.grid.cells[l].min(most[l.min(1)]);
    }
    for edge in body.boundaries.iter_mut().flatten() {
        *edge = match *edge {
            Boundary::Velocity { load, bonded } if load.patch.is_none() => Boundary::Velocity {
                load: Load::step(0.0),
                bonded,
            },
            Boundary::Symmetry => Boundary::Symmetry,
            _ => Boundary::Free,
        };
    }
    body.initial = impact_core::initial::InitialState::Rest;
    let Ok(mut method) = crate::build(&body, config) else {
        return false;
    };
    let mut seed = 12345u64;
    method.perturb_velocity(&mut |_, _| {
        impact_core::Vector::<D>::from_fn(|_, _| crate::stability::noise(&mut seed))
    });
    let steps = if D == 1 { 2000 } else { 500 };
    let t_end = steps as f64 * method.stable_dt();
    let impedance = body.material.density * body.material.p_wave_speed::<D>();
    let guard = impact_core::controller::Guard {
        growth: f64::INFINITY,
        stress_scale: impedance,
        impedance,
        // every check: these runs are 500 to 2000 steps
        norm_every: 1,
        ..crate::interrupt::guard()
    };
    matches!(
        impact_core::controller::run::<D, dyn impact_core::Method<D>, std::convert::Infallible>(
            method.as_mut(),
            &[t_end],
            guard,
            |_, _, _, _| Ok(()),
            |_| {},
        ),
        Err(impact_core::controller::RunError::Blowup(_))
    )
}

/// A Courant number within this fraction above the measured limit is accepted (the
/// bisection's resolution is 3.5e-4, and a mode at the exact limit grows linearly).
const MEASURED_TOLERANCE: f64 = 2e-3;

/// The largest Courant number at which [`grows`] sees no growth (12 halvings in [0.05,
/// 1.5]; 0 when it grows even at 0.05).
fn measured_limit<const D: usize>(problem: &Problem<D>, config: MethodConfig) -> f64 {
    let stable = |c: f64| {
        let mut cfg = config;
        cfg.courant = c;
        !grows(problem, cfg)
    };
    if !stable(0.05) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.05, 1.5);
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// MPM and FEM: refuse `config` when [`grows`] sees a growing mode (module doc).
fn check_measured<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    allow: bool,
) -> Result<Stability, Unstable> {
    if !grows(problem, config) {
        return Ok(Stability::Stable);
    }
    let limit = measured_limit(problem, config);
    // within the measurement's resolution of its limit: marginal, not refused (FEM in 1D
    // at Courant 1, exact on the bar, measures 0.999)
    if config.courant <= limit * (1.0 + MEASURED_TOLERANCE) {
        return Ok(Stability::Stable);
    }
    let what = format!(
        "{}: Courant {} is unstable for this configuration ({}) on this body: a perturbed \
         unloaded cut of it (its edges, cell size and material) grows faster than linearly \
         within {} steps; measured stable up to Courant {:.3}",
        config.kind(),
        config.courant,
        describe(&config),
        if D == 1 { 2000 } else { 500 },
        (limit * 1e3).floor() / 1e3
    );
    if allow {
        return Ok(Stability::AllowedUnstable(format!(
            "{what}: run anyway (--allow-unstable)"
        )));
    }
    Err(Unstable(format!(
        "{what}: lower --courant to at most {:.3}, or pass --allow-unstable to run it anyway",
        (limit * 1e3).floor() / 1e3
    )))
}

/// Refuse `config` on `problem` when its Courant number is above its von Neumann limit
/// (DGMPM) or a growing mode is measured (MPM, FEM; module doc), unless `allow`.
pub fn check_stable<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    allow: bool,
) -> Result<Stability, Unstable> {
    if config.dgmpm().is_none() {
        return check_measured(problem, config, allow);
    }
    if !affordable(problem, &config) {
        return Ok(Stability::Unchecked(format!(
            "{}: the von Neumann check is skipped at {} points per cell in {D}D (its matrices \
             would take minutes); the in-run max-norm test guards the run",
            config.kind(),
            config.points_per_cell
        )));
    }
    let (rho, limit) = match von_neumann(problem, config) {
        Some((rho, Some(limit))) => (rho, limit),
        Some((_, None)) => return Ok(Stability::Stable),
        // never a silent pass: say that the check did not run
        None => {
            return Ok(Stability::Unchecked(format!(
                "{}: the von Neumann check could not build the linearised scheme of this                  configuration ({}); the in-run max-norm test guards the run",
                config.kind(),
                describe(&config)
            )))
        }
    };
    let what = format!(
        "{}: Courant {} is above the von Neumann limit {limit:.4} of this configuration ({}; \
         amplification {rho:.6} per step at this Courant number, so a mode grows on any \
         boundary conditions)",
        config.kind(),
        config.courant,
        describe(&config)
    );
    if allow {
        return Ok(Stability::AllowedUnstable(format!(
            "{what}: run anyway (--allow-unstable)"
        )));
    }
    Err(Unstable(format!(
        "{what}: {}, or pass --allow-unstable to run it anyway",
        advice(problem, config, limit)
    )))
}

/// Why a run of `config` on `problem` may have blown up (module doc); `None` when its
/// Courant number is within the limit (the cause lies elsewhere: the load, the model).
pub fn diagnose_blowup<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Option<String> {
    if config.dgmpm().is_some() {
        let (_, limit) = von_neumann(problem, config)?;
        let limit = limit?;
        return Some(format!(
            "the Courant number {} is above {limit:.4}, the von Neumann limit of this \
             configuration ({}): {}",
            config.courant,
            describe(&config),
            advice(problem, config, limit)
        ));
    }
    crate::stability::diagnose_blowup(problem, config)
}

//! The stability guard around a run: before it, DGMPM's Courant number against its von
//! Neumann limit; after a blow-up, advice that applies to the configuration.
//!
//! - **Before the run** ([`check_stable`]): the project computes DGMPM's von Neumann
//!   amplification for any layout ([`crate::stability::max_amplification`]: the one-step
//!   matrices of the scheme on the scene's material, points per cell, integrator, flux and
//!   update, Fourier-transformed; 256 wave numbers in 1D, 24² in 2D). A configuration whose
//!   largest spectral radius exceeds `1 + 1e-9` at its Courant number grows some mode every
//!   step on any boundary conditions; it is refused, with its limit (bisection to 1e-5) and
//!   what would make it stable, unless `--allow-unstable` is given (then it runs, and the
//!   outputs record the flag). Nonlinear models (SVK, J2) are checked on their
//!   linearisation at rest (linear elasticity with the same `E`, `ν`, `ρ`). MPM and FEM
//!   have no von Neumann limit computed here: the in-run max-norm test
//!   ([`impact_core::controller`]) guards them.
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
    if d == 1 {
        256
    } else {
        24
    }
}

/// Largest cost of the check, in `wave numbers × n³` for `n × n` amplification matrices
/// (`n` = points per cell × unknowns per point): 1D up to 17 points per cell, 2D up to 4
/// (0.1 s to a few seconds with the bisection of a refusal). Beyond it the check would
/// take minutes (2D, 64 points per cell: 320 × 320 matrices at 576 wave numbers), so it
/// is skipped with a note, and the in-run max-norm test guards the run.
const MAX_COST: f64 = 1e7;

/// The cost of the check for `config` in dimension `d` (see [`MAX_COST`]).
fn cost(config: &MethodConfig, d: usize) -> f64 {
    let n = (config.points_per_cell * (d * (d + 1) / 2 + d)) as f64;
    (samples(d) as f64).powi(d as i32) * n.powi(3)
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

/// The linear-elastic body at rest of `problem` (the linearisation the von Neumann
/// analysis applies to).
fn linearised<const D: usize>(problem: &Problem<D>) -> Problem<D> {
    let mut body = problem.clone();
    body.model = Model::LinearElastic;
    body.initial = impact_core::initial::InitialState::Rest;
    body
}

/// DGMPM's largest von Neumann amplification at `config`'s Courant number, and its limit
/// when above 1; `None` for MPM and FEM, or a configuration the linearisation cannot
/// build.
pub fn von_neumann<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Option<(f64, Option<f64>)> {
    config.dgmpm()?;
    if cost(&config, D) > MAX_COST {
        return None;
    }
    let body = linearised(problem);
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
        .map(|o| format!(", {} update", o.update.name()))
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

/// Refuse DGMPM `config` on `problem` when its Courant number is above its von Neumann
/// limit (module doc), unless `allow`.
pub fn check_stable<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    allow: bool,
) -> Result<Stability, Unstable> {
    if config.dgmpm().is_some() && cost(&config, D) > MAX_COST {
        return Ok(Stability::Unchecked(format!(
            "{}: the von Neumann check is skipped at {} points per cell in {D}D (its matrices \
             would take minutes); the in-run max-norm test guards the run",
            config.kind(),
            config.points_per_cell
        )));
    }
    let Some((rho, Some(limit))) = von_neumann(problem, config) else {
        return Ok(Stability::Stable);
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

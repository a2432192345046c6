//! What the studies (`bench work-precision`, `bench convergence`, `stability`) share to run
//! on any scene: the flags a ladder sets itself, the check of the options it keeps, the
//! configurations the scene's model takes (and those it refuses, with the reason), the
//! default levels, the provenance record of a ladder's folder, and DGMPM's order-2 rows.
use crate::work_precision::{configurations, Config};
use crate::Study;
use anyhow::Result;
use impact_core::method::{
    Integrator, MethodKind, MpmShape, SchemeOrder, TransverseFlux, WaveLimiter,
};
use impact_core::Scene;
use std::path::Path;

/// The flags a ladder sets itself (grid, Courant number and the options it varies): refused
/// by `bench work-precision` and `bench convergence`.
pub const LADDER_FLAGS: &[&str] = &[
    "--cells",
    "--courant",
    "--points-per-cell",
    "--integrator",
    "--flux",
    "--shape",
    "--order",
    "--limiter",
];

/// A configuration left out of a ladder: its label and why.
pub type Skipped = (String, String);

/// The ladder's configurations for `study` (built on its resolved scene, so the method
/// flags given apply to each), split into those the problem runs and those it refuses
/// (label and reason: e.g. CTU on a Saint-Venant-Kirchhoff plate). The options a study
/// does not vary are checked first ([`check_fixed_options`]): one the problem refuses is an
/// error.
pub fn usable_configurations(study: &Study) -> Result<(Vec<Config>, Vec<Skipped>)> {
    let kinds = MethodKind::ALL;
    check_fixed_options(study)?;
    let scene = crate::provenance::resolved_scene(study, &kinds);
    let (mut usable, mut skipped) = (Vec::new(), Vec::new());
    for c in configurations(&scene) {
        match study
            .check_configs(&[c.config])
            .map_err(anyhow::Error::from)
            .and_then(|()| within_von_neumann(study, c.config))
        {
            Ok(()) => usable.push(c),
            Err(e) => skipped.push((c.label, e.to_string())),
        }
    }
    Ok((usable, skipped))
}

/// A ladder configuration above its von Neumann limit on this scene (another Poisson
/// ratio or point layout moves it) is skipped with the guard's reason, not run.
fn within_von_neumann(study: &Study, config: impact_core::method::MethodConfig) -> Result<()> {
    match study.dim() {
        1 => crate::guard::check_stable(&study.problem::<1>()?, config, false)?,
        2 => crate::guard::check_stable(&study.problem::<2>()?, config, false)?,
        _ => crate::guard::check_stable(&study.problem::<3>()?, config, false)?,
    };
    Ok(())
}

/// Refuse the DGMPM and MPM options of `study` that a ladder or sweep keeps as given (the
/// update, Riemann solver and edges; the stress update and frame) when the problem refuses
/// them, before anything runs. The options the studies vary (Courant number, points per
/// cell, integrator, flux, shape) are set to values every model takes for this check.
pub fn check_fixed_options(study: &Study) -> Result<()> {
    let mut dgmpm = study.config(MethodKind::Dgmpm);
    (dgmpm.courant, dgmpm.points_per_cell) = (1.0, 1);
    if let Some(o) = dgmpm.dgmpm_mut() {
        (o.integrator, o.flux) = (Integrator::Euler, TransverseFlux::DonorCell);
    }
    let mut mpm = study.config(MethodKind::Mpm);
    (mpm.courant, mpm.points_per_cell) = (0.5, 1);
    if let Some(o) = mpm.mpm_mut() {
        o.shape = MpmShape::Linear;
    }
    study.check_configs(&[dgmpm, mpm])?;
    Ok(())
}

/// What a ladder was run on, for its output folder: `provenance.json` (with the
/// configurations, the reference and what was skipped, one note each) and the resolved `scene.toml`.
pub fn provenance(
    command: &str,
    study: &Study,
    source: &str,
    reference: &str,
    configs: &[Config],
    skipped: &[Skipped],
    dir: &Path,
) -> Result<crate::provenance::Provenance> {
    let mut record =
        crate::provenance::Provenance::new(command, &crate::provenance::Clock::start())
            .with_study(study, source, &MethodKind::ALL, dir)?;
    record.reference = reference.to_string();
    record.configurations = configs
        .iter()
        .map(|c| crate::provenance::MethodOptionsRecord::of(&c.config, study.dim()))
        .collect();
    record.notes = skipped
        .iter()
        .map(|(label, why)| format!("skipped `{label}`: {why}"))
        .collect();
    Ok(record)
}

/// Default refinement levels of the ladder on `study`: the shipped scenes' (plate-wave 7,
/// plate 5: its 512x388 level's 8x finer reference would pass the 1e7-cell limit), 9 in 1D
/// and 5 in 2D otherwise.
pub fn default_levels(study: &Study) -> usize {
    match (study.name(), study.dim()) {
        ("plate-wave", 2) => 7,
        ("plate", 2) => 5,
        (_, 1) => 9,
        _ => 5,
    }
}

/// The flags `impact stability` sets or varies itself.
pub const SWEEP_FLAGS: &[&str] = &[
    "--cells",
    "--courant",
    "--points-per-cell",
    "--integrator",
    "--flux",
    "--update",
    "--load",
    "--load-magnitude",
    "--t-end",
    "--output-times",
    "--work-budget",
];

/// The scenes `impact stability` sweeps, resolved with `overrides` (the flags of
/// [`SWEEP_FLAGS`] refused): the scene `source` (a shipped name or a file) cut to a small
/// grid of its own cells ([`crate::stability::cut_scene`]), or the default sweep scenes of
/// `dims` (default 1 and 2).
pub fn sweep_scenes(
    source: Option<&str>,
    dims: Option<&[usize]>,
    overrides: &crate::Overrides,
) -> Result<Vec<impact_core::Scene>> {
    overrides.refuse(
        "impact stability",
        SWEEP_FLAGS,
        "sweeps the Courant number, points per cell, integrator, flux and update on an \
         unloaded cut of the scene",
    )?;
    let resolved = |study: &Study| -> Result<impact_core::Scene> {
        check_fixed_options(study)?;
        Ok(crate::provenance::resolved_scene(study, &MethodKind::ALL))
    };
    let Some(source) = source else {
        let dims = dims.unwrap_or(&[1, 2]);
        if let Some(d) = dims.iter().find(|&&d| !(d == 1 || d == 2)) {
            anyhow::bail!("--dim {d} is not supported (allowed: 1 and/or 2)");
        }
        return dims
            .iter()
            .map(|&d| {
                resolved(&Study::new(
                    crate::stability::sweep_scene(d),
                    overrides.clone(),
                )?)
            })
            .collect();
    };
    let study = Study::load(source, overrides.clone())?;
    Ok(vec![crate::stability::cut_scene(&resolved(&study)?)])
}

/// The order-2 rows of the ladder at `ppc` points per cell (linear elasticity and J2 with
/// the elastic solver, 1D-3D; the ladder skips them where `Problem::check_config`
/// refuses them): no limiter (Lax-Wendroff) and MC. One point per cell: forward Euler, at
/// Courant 0.5 in 1D (at Courant 1 the corrections vanish, `1 − Δt c/Δx = 0`, and the
/// scheme is the exact first-order shift), with CTU at 0.9 in 2D and 3D (the scene's edges;
/// CTU set, since donor-cell with Euler is unstable at order 2);
/// several: RK2 (1D at 0.9; 2D with CTU at 0.7, inside RK2's order-2 CTU limit 0.7342 at
/// one point per cell), since with forward Euler the corrections leave no stable
/// Courant number there (von Neumann, README).
pub(crate) fn order2_configurations(scene: &Scene, ppc: usize) -> Vec<Config> {
    let (integrator, courant) = match (ppc, scene.dim) {
        (1, 1) => (Integrator::Euler, 0.5),
        (1, _) => (Integrator::Euler, 0.9),
        (_, 1) => (Integrator::Rk2, 0.9),
        _ => (Integrator::Rk2, 0.7),
    };
    let flux = match scene.dim {
        1 => String::new(),
        _ => " ctu".to_string(),
    };
    [WaveLimiter::None, WaveLimiter::Mc]
        .into_iter()
        .map(|limiter| {
            let mut config = scene.method_config(MethodKind::Dgmpm);
            (config.points_per_cell, config.courant) = (ppc, courant);
            if let Some(o) = config.dgmpm_mut() {
                o.integrator = integrator;
                if scene.dim > 1 {
                    o.flux = TransverseFlux::Ctu;
                }
                o.order = SchemeOrder::Second;
                o.limiter = Some(limiter);
            }
            Config {
                label: format!(
                    "dgmpm {}{flux} o2 {} {ppc}ppc C{courant:?}",
                    integrator.name(),
                    limiter.name()
                ),
                config,
                dim: scene.dim,
            }
        })
        .collect()
}

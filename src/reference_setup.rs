//! Which converged reference judges a scene without an exact solution, and the second one
//! whose distance from it is reported as the errors' uncertainty (issue 26).
//!
//! - **Method** (`--reference`, `[metrics] reference`): DGMPM, FEM or MPM on a grid
//!   `--reference-refinement` (`[metrics] reference_refinement`, default
//!   [`REFERENCE_REFINEMENT`] in 1D and 2D, [`REFERENCE_REFINEMENT_3D`] in 3D) times finer along each axis, one point per cell. Unless stated,
//!   the first of DGMPM, FEM that the command does not compare: `impact check` (DGMPM
//!   against MPM) is judged by FEM, `impact run --method mpm` by DGMPM, `impact run --method
//!   dgmpm` by FEM. Where both are compared (`impact run` with all three methods, the
//!   ladders) no independent judge is left: DGMPM judges (the numbers of earlier versions),
//!   and the spread below says how much that choice can move each error.
//! - **Spread** (`--reference-spread`, `[metrics] reference_spread`): a second reference of
//!   another method on the same fine grid (default: the other of DGMPM and FEM; MPM where
//!   one of them cannot run the scene, e.g. FEM with an initial stress by formula). A
//!   default method is always one that can run the scene. Beside
//!   every L1 error the outputs give the relative L1 distance between the two references
//!   over the same samples ([`impact_core::converged::Spread`]): by the triangle inequality
//!   the error against the second reference lies within it of the error reported.
//! - **Configurations**: DGMPM as [`converged_config`] (`--reference-flux` changes its
//!   transverse flux); FEM (bilinear elements, lumped mass, central differences) at Courant
//!   0.9; MPM (USL, total Lagrangian, `--reference-shape`, default quadratic B-splines) at
//!   Courant 0.5.
use impact_core::method::{
    DgmpmOptions, Integrator, MethodConfig, MethodKind, MethodOptions, MpmShape, TransverseFlux,
};
use impact_core::scene::ReferenceOptions;
use impact_core::{Problem, SceneError};
use serde::Serialize;

/// Default refinement factor of the converged reference along each axis in 1D and 2D: on
/// the 33x25 plate at 0.49 ms the DGMPM and FEM references lie 2.2e-2 apart (relative L1 of
/// σ_xx along the bottom row) at 4x, half of DGMPM's error (4.1e-2) and more than the gap
/// between DGMPM's and FEM's errors; at 8x 7.8e-3, under a sixth of the smallest error
/// judged (4.9e-2) and under the DGMPM-FEM gap (1.4e-2); at 16x 7.0e-3 for 8 times the
/// work (README, "Which reference judges").
pub const REFERENCE_REFINEMENT: usize = 8;

/// Default refinement in 3D: 8x would be 512 times the cells (the 33x25x25 block's fine
/// grid would pass [`crate::reference::MAX_REFERENCE_CELLS`]).
pub const REFERENCE_REFINEMENT_3D: usize = 4;

/// The default refinement in dimension `dim`.
pub fn default_refinement(dim: usize) -> usize {
    match dim {
        3 => REFERENCE_REFINEMENT_3D,
        _ => REFERENCE_REFINEMENT,
    }
}

/// The methods a reference is taken from unless stated, in order of preference.
const PREFERENCE: [MethodKind; 2] = [MethodKind::Dgmpm, MethodKind::Fem];

/// One converged reference's method and configuration.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceMethod {
    /// The method.
    pub method: MethodKind,
    /// Every option of its run.
    pub options: crate::provenance::MethodOptionsRecord,
    /// The configuration.
    #[serde(skip)]
    pub config: MethodConfig,
}

/// The resolved converged reference of a problem (`summary.json`'s `reference_setup`).
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceSetup {
    /// The reference the errors are measured against.
    #[serde(flatten)]
    pub judge: ReferenceMethod,
    /// Refinement along each axis.
    pub refinement: usize,
    /// Cells per axis of the fine grid.
    pub cells: Vec<usize>,
    /// Why this method (stated, or the default rule).
    pub chosen: String,
    /// The second reference whose distance is each error's uncertainty.
    pub spread: ReferenceMethod,
}

/// The configuration of a converged reference of `kind` for `model` with the stated
/// method-specific options (module doc).
pub fn reference_config(
    kind: MethodKind,
    model: &impact_core::method::Model,
    stated: &ReferenceOptions,
) -> MethodConfig {
    let mut config = match kind {
        MethodKind::Dgmpm => converged_config(model),
        MethodKind::Fem => MethodConfig::new(MethodKind::Fem, 0.9, 1),
        MethodKind::Mpm => MethodConfig::new(MethodKind::Mpm, 0.5, 1),
    };
    if let (Some(o), Some(flux)) = (config.dgmpm_mut(), stated.flux) {
        o.flux = flux;
    }
    if let Some(o) = config.mpm_mut() {
        o.shape = stated.shape.unwrap_or(MpmShape::Bspline2);
    }
    config
}

/// The DGMPM reference's configuration: 1 point per cell; CTU at Courant 1 with forward
/// Euler for linear elasticity and J2 (the elastic solver, then the return map);
/// donor-cell with RK2 at Courant 0.9 for SVK (CTU is implemented for linear elasticity
/// only; RK2 with donor-cell is stable to 1.0, and 0.9 ran bounded on the 132x100 SVK plate
/// for 1 ms; at 0.5 it smears twice as much).
pub fn converged_config(model: &impact_core::method::Model) -> MethodConfig {
    use impact_core::method::{Model, RiemannSolver};
    let linear = !matches!(model, Model::Svk(_));
    let riemann = match model {
        Model::J2(_) => RiemannSolver::Elastic,
        _ => DgmpmOptions::default().riemann,
    };
    let options = DgmpmOptions {
        riemann,
        integrator: if linear {
            Integrator::Euler
        } else {
            Integrator::Rk2
        },
        flux: if linear {
            TransverseFlux::Ctu
        } else {
            TransverseFlux::DonorCell
        },
        ..DgmpmOptions::default()
    };
    MethodConfig {
        courant: if linear { 1.0 } else { 0.9 },
        points_per_cell: 1,
        options: MethodOptions::Dgmpm(options),
    }
}

/// The reference of `problem` when a command compares the methods `compared` (module
/// doc); errors name the `[metrics]` field (or its flag) a stated option contradicts.
pub fn resolve<const D: usize>(
    problem: &Problem<D>,
    compared: &[MethodKind],
) -> Result<ReferenceSetup, SceneError> {
    let stated = problem.reference;
    let refinement = stated.refinement.unwrap_or(default_refinement(D));
    // a default is a method that can run the scene (FEM refuses an initial stress by formula)
    let runs = |k: &MethodKind| {
        problem
            .check_config(&reference_config(*k, &problem.model, &stated))
            .is_ok()
    };
    let (method, chosen) = match stated.method {
        Some(m) => (
            m,
            "stated (`--reference` or `[metrics] reference`)".to_string(),
        ),
        None => {
            let free = PREFERENCE
                .into_iter()
                .filter(runs)
                .find(|k| !compared.contains(k) && Some(*k) != stated.spread);
            let names: Vec<&str> = compared.iter().map(|k| k.name()).collect();
            match free {
                Some(m) => (
                    m,
                    format!(
                        "default: the first of dgmpm, fem not compared ({})",
                        names.join(", ")
                    ),
                ),
                None => (
                    MethodKind::ALL
                        .into_iter()
                        .filter(runs)
                        .find(|k| Some(*k) != stated.spread)
                        .unwrap_or(MethodKind::Dgmpm),
                    format!(
                        "default: dgmpm and fem are both compared ({}), so no independent \
                         judge is left; the spread says how much the choice moves each error",
                        names.join(", ")
                    ),
                ),
            }
        }
    };
    // DGMPM and FEM first, MPM where one of them cannot run the scene
    let spread = stated.spread.unwrap_or_else(|| {
        [MethodKind::Dgmpm, MethodKind::Fem, MethodKind::Mpm]
            .into_iter()
            .filter(runs)
            .find(|k| *k != method)
            .unwrap_or(MethodKind::Fem)
    });
    if spread == method {
        return Err(SceneError::new(
            "metrics.reference_spread (--reference-spread)",
            format!("\"{spread}\""),
            format!(
                "a method other than the reference's (\"{method}\"): {}",
                MethodKind::allowed()
            ),
        ));
    }
    let uses = |kind: MethodKind| method == kind || spread == kind;
    if let (Some(shape), false) = (stated.shape, uses(MethodKind::Mpm)) {
        return Err(SceneError::new(
            "metrics.reference_shape (--reference-shape)",
            format!("\"{shape}\""),
            "an MPM reference's shape functions: only with `reference = \"mpm\"` or \
             `reference_spread = \"mpm\"`",
        ));
    }
    if let (Some(flux), false) = (stated.flux, uses(MethodKind::Dgmpm)) {
        return Err(SceneError::new(
            "metrics.reference_flux (--reference-flux)",
            format!("\"{flux}\""),
            "a DGMPM reference's transverse flux: only with `reference = \"dgmpm\"` or \
             `reference_spread = \"dgmpm\"`",
        ));
    }
    let of = |kind: MethodKind| {
        let config = reference_config(kind, &problem.model, &stated);
        ReferenceMethod {
            method: kind,
            options: crate::provenance::MethodOptionsRecord::of(&config, D),
            config,
        }
    };
    Ok(ReferenceSetup {
        judge: of(method),
        refinement,
        cells: problem.grid.cells.iter().map(|n| n * refinement).collect(),
        chosen,
        spread: of(spread),
    })
}

/// A reference configuration in words, e.g. `FEM (bilinear elements, lumped mass, central
/// differences, Courant 0.9)`.
pub fn describe_config(config: &MethodConfig, dim: usize) -> String {
    match &config.options {
        MethodOptions::Dgmpm(o) => {
            let flux = match dim {
                1 => String::new(),
                _ => format!("{}, ", o.flux.name().to_uppercase()),
            };
            format!(
                "DGMPM (1 ppc, {flux}{}, Courant {})",
                o.integrator.name(),
                config.courant
            )
        }
        MethodOptions::Fem(_) => format!(
            "FEM (bilinear elements, lumped mass, central differences, Courant {})",
            config.courant
        ),
        MethodOptions::Mpm(o) => format!(
            "MPM (1 ppc, {}, {}, {}, Courant {})",
            o.shape.name(),
            o.stress_update.name(),
            o.frame.name(),
            config.courant
        ),
    }
}

impl ReferenceSetup {
    /// The grid in words: `528 cells` (1D) or `a 132x100 grid`.
    pub fn grid(&self) -> String {
        match self.cells.len() {
            1 => format!("{} cells", self.cells[0]),
            _ => {
                let counts: Vec<String> = self.cells.iter().map(|n| n.to_string()).collect();
                format!("a {} grid", counts.join("x"))
            }
        }
    }

    /// The setup in one line (the spread included).
    pub fn describe(&self) -> String {
        let dim = self.cells.len();
        format!(
            "converged reference: {} on {} ({}x finer); spread: {} on the same grid",
            describe_config(&self.judge.config, dim),
            self.grid(),
            self.refinement,
            describe_config(&self.spread.config, dim),
        )
    }
}

/// Write the converged reference a study comparing `compared` uses (method, spread,
/// refinement) into the resolved `scene`'s `[metrics]`, so that every run of it (a ladder's
/// `impact run --method X` processes, `impact run --from`) is judged by the same reference;
/// nothing for a scene with an exact solution.
pub fn state_in(study: &crate::Study, compared: &[MethodKind], scene: &mut impact_core::Scene) {
    if let Ok(Some(setup)) = study.reference_setup(compared) {
        let m = scene.metrics.get_or_insert_with(Default::default);
        m.reference = Some(setup.judge.method);
        m.reference_spread = Some(setup.spread.method);
        m.reference_refinement = Some(setup.refinement);
    }
}

impl crate::Overrides {
    /// Put the reference flags into the scene's `[metrics]` (checked there by the scene's
    /// validation; the refinement here, naming its flag).
    pub(crate) fn apply_reference(&self, scene: &mut impact_core::Scene) -> Result<(), SceneError> {
        if let Some(r) = self.reference_refinement {
            impact_core::scene::check_reference_refinement("--reference-refinement", r)?;
        }
        if let (Some(flux), 1) = (self.reference_flux, scene.dim) {
            return Err(SceneError::new(
                "--reference-flux",
                flux,
                "a transverse flux only in 2D and 3D scenes",
            ));
        }
        let given = self.reference.is_some()
            || self.reference_refinement.is_some()
            || self.reference_spread.is_some()
            || self.reference_shape.is_some()
            || self.reference_flux.is_some();
        if !given {
            return Ok(());
        }
        let m = scene.metrics.get_or_insert_with(Default::default);
        m.reference = self.reference.or(m.reference);
        m.reference_refinement = self.reference_refinement.or(m.reference_refinement);
        m.reference_spread = self.reference_spread.or(m.reference_spread);
        m.reference_shape = self.reference_shape.or(m.reference_shape);
        m.reference_flux = self.reference_flux.or(m.reference_flux);
        // a stated spread equal to the new reference: the flag wins, the spread defaults
        if self.reference.is_some()
            && self.reference_spread.is_none()
            && m.reference_spread == m.reference
        {
            m.reference_spread = None;
        }
        Ok(())
    }
}

impl crate::Study {
    /// The resolved converged reference of the study's scene when `compared` are compared;
    /// `None` where the scene has an exact solution.
    pub fn reference_setup(
        &self,
        compared: &[MethodKind],
    ) -> Result<Option<ReferenceSetup>, impact_core::CoreError> {
        fn of<const D: usize>(
            study: &crate::Study,
            compared: &[MethodKind],
        ) -> Result<Option<ReferenceSetup>, impact_core::CoreError> {
            let problem = study.problem::<D>()?;
            if impact_core::reference::Reference::for_problem(&problem).is_some() {
                return Ok(None);
            }
            Ok(Some(resolve(&problem, compared)?))
        }
        match self.dim() {
            1 => of::<1>(self, compared),
            2 => of::<2>(self, compared),
            _ => of::<3>(self, compared),
        }
    }

    /// The work of the two converged reference runs a scene without an exact solution needs
    /// when `compared` are compared (each on a grid `r` times finer: `r^D` the cells, `r`
    /// the steps at its Courant number); none where it has an exact solution.
    pub(crate) fn reference_work(
        &self,
        compared: &[MethodKind],
    ) -> Result<Vec<impact_core::scene::WorkEstimate>, impact_core::CoreError> {
        let Some(setup) = self.reference_setup(compared)? else {
            return Ok(Vec::new());
        };
        let r = setup.refinement as f64;
        Ok([&setup.judge, &setup.spread]
            .into_iter()
            .map(|m| {
                let coarse = self.scene.work_estimate(&m.config);
                impact_core::scene::WorkEstimate {
                    what: "a converged reference",
                    points: coarse.points * r.powi(self.dim() as i32),
                    steps: coarse.steps * r,
                }
            })
            .collect())
    }

    /// The reference a study comparing `compared` measures its errors against, in words:
    /// the scene's exact solution, or the converged reference of each grid.
    pub fn reference_for_errors(
        &self,
        compared: &[MethodKind],
    ) -> Result<String, impact_core::CoreError> {
        fn exact<const D: usize>(
            study: &crate::Study,
        ) -> Result<Option<String>, impact_core::CoreError> {
            let problem = study.problem::<D>()?;
            Ok(impact_core::reference::Reference::for_problem(&problem).map(|r| r.describe()))
        }
        let exact = match self.dim() {
            1 => exact::<1>(self)?,
            2 => exact::<2>(self)?,
            _ => exact::<3>(self)?,
        };
        if let Some(description) = exact {
            return Ok(format!("exact: {description}"));
        }
        let setup = self
            .reference_setup(compared)?
            .expect("internal: a scene without an exact solution");
        Ok(format!(
            "converged: {} on a grid {}x finer than each run's, computed per grid (and \
             cached), since the scene has no exact solution ({}); spread (each error's \
             uncertainty): {} on the same grid",
            describe_config(&setup.judge.config, self.dim()),
            setup.refinement,
            setup.chosen,
            describe_config(&setup.spread.config, self.dim()),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate() -> Problem<2> {
        let scene = impact_core::Scene::builtin("plate").unwrap();
        Problem::<2>::from_scene(&scene).unwrap()
    }

    #[test]
    fn no_compared_method_judges_where_one_is_free() {
        let p = plate();
        let check = resolve(&p, &[MethodKind::Dgmpm, MethodKind::Mpm]).unwrap();
        assert_eq!(check.judge.method, MethodKind::Fem);
        assert_eq!(check.spread.method, MethodKind::Dgmpm);
        let mpm = resolve(&p, &[MethodKind::Mpm]).unwrap();
        assert_eq!(mpm.judge.method, MethodKind::Dgmpm);
        assert_eq!(
            resolve(&p, &[MethodKind::Fem]).unwrap().judge.method,
            MethodKind::Dgmpm
        );
        assert_eq!(
            resolve(&p, &[MethodKind::Dgmpm]).unwrap().judge.method,
            MethodKind::Fem
        );
        let all = resolve(&p, &MethodKind::ALL).unwrap();
        assert_eq!(
            (all.judge.method, all.spread.method),
            (MethodKind::Dgmpm, MethodKind::Fem)
        );
        assert_eq!(all.cells, vec![264, 200]);
    }

    #[test]
    fn contradicting_reference_options_name_their_field() {
        let mut p = plate();
        p.reference.method = Some(MethodKind::Fem);
        p.reference.spread = Some(MethodKind::Fem);
        let e = resolve(&p, &MethodKind::ALL).unwrap_err().to_string();
        assert!(e.contains("reference_spread") && e.contains("fem"), "{e}");
        p.reference.spread = None;
        p.reference.shape = Some(MpmShape::Gimp);
        let e = resolve(&p, &MethodKind::ALL).unwrap_err().to_string();
        assert!(e.contains("reference_shape") && e.contains("gimp"), "{e}");
        p.reference.spread = Some(MethodKind::Mpm);
        let ok = resolve(&p, &MethodKind::ALL).unwrap();
        assert_eq!(ok.spread.config.mpm().unwrap().shape, MpmShape::Gimp);
        p.reference.flux = Some(TransverseFlux::DonorCell);
        let e = resolve(&p, &MethodKind::ALL).unwrap_err().to_string();
        assert!(e.contains("reference_flux"), "{e}");
    }
}

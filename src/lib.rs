//! `impact`: DGMPM, USL MPM and explicit FEM on the same stress-wave problems.
//!
//! This library holds what the CLI and the cross-method tests share: building a method
//! from a scene ([`build`]), applying command-line overrides ([`Overrides`]) and running a
//! scene through the controller with metrics and outputs ([`run::run_method`]).
pub mod output;
pub mod run;
pub mod stability;
pub mod work_precision;

use impact_core::method::{
    Integrator, MethodConfig, MethodKind, MpmFrame, PointUpdate, RiemannSolver, StressUpdate,
    TransverseFlux,
};
use impact_core::scene::{check_courant, check_points_per_cell, MethodSpec, Scene};
use impact_core::{CoreError, Method, Problem, SceneError};

/// Build a method for `problem` from its configuration.
pub fn build<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Result<Box<dyn Method<D>>, CoreError> {
    Ok(match config.kind {
        MethodKind::Dgmpm => Box::new(impact_dgmpm::Dgmpm::new(problem, config)?),
        MethodKind::Mpm => Box::new(impact_mpm::Mpm::new(problem, config)?),
        MethodKind::Fem => Box::new(impact_fem::Fem::new(problem, config)?),
    })
}

/// The configuration of `kind` written in `scene`.
pub fn scene_config(scene: &Scene, kind: MethodKind) -> MethodConfig {
    let spec: &MethodSpec = match kind {
        MethodKind::Dgmpm => &scene.dgmpm,
        MethodKind::Mpm => &scene.mpm,
        MethodKind::Fem => &scene.fem,
    };
    MethodConfig {
        kind,
        courant: spec.courant,
        points_per_cell: scene.domain.points_per_cell,
        integrator: match spec.integrator.as_deref() {
            Some("rk2") => Integrator::Rk2,
            _ => Integrator::Euler,
        },
        update: match spec.update.as_deref() {
            Some("increment") => PointUpdate::Increment,
            _ => PointUpdate::Nodal,
        },
        stress_update: match spec.stress_update.as_deref() {
            Some("usf") => StressUpdate::Usf,
            Some("musl") => StressUpdate::Musl,
            _ => StressUpdate::Usl,
        },
        riemann: match spec.riemann.as_deref() {
            Some("exact") => RiemannSolver::Exact,
            _ => RiemannSolver::Approximate,
        },
        flux: match spec.flux.as_deref() {
            Some("dcu") => TransverseFlux::DonorCell,
            _ => TransverseFlux::Ctu,
        },
        frame: match spec.frame.as_deref() {
            Some("updated-lagrangian") => MpmFrame::UpdatedLagrangian,
            _ => MpmFrame::TotalLagrangian,
        },
    }
}

/// Command-line overrides of a scene (each `None` keeps the scene's value).
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    /// Cells along x (other axes scaled to keep the cell shape).
    pub cells: Option<usize>,
    /// Courant number.
    pub courant: Option<f64>,
    /// Points per cell.
    pub points_per_cell: Option<usize>,
    /// DGMPM integrator.
    pub integrator: Option<Integrator>,
    /// DGMPM point update.
    pub update: Option<PointUpdate>,
    /// MPM stress update.
    pub stress_update: Option<StressUpdate>,
    /// MPM frame.
    pub frame: Option<MpmFrame>,
    /// DGMPM transverse flux (2D).
    pub flux: Option<TransverseFlux>,
    /// DGMPM Riemann solver (SVK).
    pub riemann: Option<RiemannSolver>,
    /// Direction of the pressure load: `true` for compression, `false` for tension.
    pub compression: Option<bool>,
    /// Magnitude of the pressure load (Pa).
    pub load_magnitude: Option<f64>,
    /// End time (s).
    pub t_end: Option<f64>,
    /// Output times (s).
    pub output_times: Option<Vec<f64>>,
}

impl Overrides {
    /// Apply the scene-level overrides (cells) to `scene`, checking each value (points per
    /// cell is checked against the scene's dimension but applied per method).
    pub fn apply_to_scene(&self, scene: &mut Scene) -> Result<(), SceneError> {
        if self.compression.is_some() || self.load_magnitude.is_some() {
            let edge = [&mut scene.boundary.left, &mut scene.boundary.right]
                .into_iter()
                .flatten()
                .find(|e| e.kind == "pressure")
                .ok_or_else(|| {
                    SceneError::new("--load", "given", "a scene with a pressure-loaded end")
                })?;
            let current = edge.value.unwrap_or(0.0);
            let magnitude = self.load_magnitude.unwrap_or(current.abs());
            if !(magnitude.is_finite() && magnitude > 0.0) {
                return Err(SceneError::new(
                    "--load-magnitude",
                    magnitude,
                    "a positive finite pressure in Pa",
                ));
            }
            let compression = self.compression.unwrap_or(current >= 0.0);
            edge.value = Some(if compression { magnitude } else { -magnitude });
        }
        if self.flux.is_some() && scene.dim != 2 {
            return Err(SceneError::new(
                "--flux",
                self.flux.map_or("", |f| f.name()),
                "a transverse flux only in 2D scenes",
            ));
        }
        if let Some(cells) = self.cells {
            if cells == 0 || cells > 100_000_000 {
                return Err(SceneError::new(
                    "--cells",
                    cells,
                    "at least 1 cell (at most 1e8)",
                ));
            }
            let ratio = cells as f64 / scene.domain.cells[0] as f64;
            for (l, n) in scene.domain.cells.iter_mut().enumerate() {
                *n = if l == 0 {
                    cells
                } else {
                    ((*n as f64) * ratio).round().max(1.0) as usize
                };
            }
        }
        let total: f64 = scene
            .domain
            .cells
            .iter()
            .map(|&n| n as f64)
            .product::<f64>()
            * self
                .points_per_cell
                .unwrap_or(1)
                .max(scene.domain.points_per_cell) as f64;
        if total > impact_core::scene::MAX_POINTS {
            return Err(SceneError::new(
                "--cells/--points-per-cell",
                format!("{:?} cells", scene.domain.cells),
                format!(
                    "at most {:.0e} cells × points per cell in total",
                    impact_core::scene::MAX_POINTS
                ),
            ));
        }
        if let Some(ppc) = self.points_per_cell {
            // checked here against the scene's dimension; applied per method
            check_points_per_cell(scene.dim, ppc).map_err(|mut e| {
                e.field = "--points-per-cell".into();
                e
            })?;
        }
        Ok(())
    }

    /// Apply the method-level overrides to `config`.
    pub fn apply_to_config(&self, config: &mut MethodConfig) -> Result<(), SceneError> {
        if let Some(c) = self.courant {
            check_courant("--courant", c)?;
            config.courant = c;
        }
        if let Some(ppc) = self.points_per_cell {
            config.points_per_cell = ppc;
        }
        if let Some(i) = self.integrator {
            config.integrator = i;
        }
        if let Some(u) = self.update {
            config.update = u;
        }
        if let Some(s) = self.stress_update {
            config.stress_update = s;
        }
        if let Some(f) = self.frame {
            config.frame = f;
        }
        if let Some(f) = self.flux {
            config.flux = f;
        }
        if let Some(r) = self.riemann {
            config.riemann = r;
        }
        Ok(())
    }

    /// Apply the schedule overrides to `problem`.
    pub fn apply_to_problem<const D: usize>(
        &self,
        problem: &mut Problem<D>,
    ) -> Result<(), SceneError> {
        problem.set_schedule(self.output_times.clone(), self.t_end)
    }
}

/// Refinement factor of the converged reference of scenes without an exact solution.
pub const REFERENCE_REFINEMENT: usize = 4;

/// The reference of `problem`: its exact solution when it has one; otherwise, in 2D, a
/// converged solution: DGMPM (1 point per cell, CTU, forward Euler, Courant 1) on a grid
/// [`REFERENCE_REFINEMENT`] times finer, at the same output times. `say` prints what is
/// being computed.
pub fn reference_for<const D: usize>(
    problem: &Problem<D>,
    say: bool,
) -> anyhow::Result<Option<impact_core::reference::Reference>> {
    use impact_core::reference::{Converged, Reference};
    if let Some(r) = Reference::for_problem(problem) {
        return Ok(Some(r));
    }
    if D != 2 {
        return Ok(None);
    }
    let r = REFERENCE_REFINEMENT;
    let fine_cells = problem.grid.cell_count() as f64 * (r as f64).powi(D as i32);
    if fine_cells > impact_core::scene::MAX_POINTS {
        if say {
            use std::io::Write as _;
            let _ = writeln!(
                std::io::stdout(),
                "no converged reference: a grid {r}x finer ({fine_cells:.2e} cells) exceeds the \
                 {:.0e}-cell limit; errors are not computed",
                impact_core::scene::MAX_POINTS
            );
        }
        return Ok(None);
    }
    let mut fine = problem.clone();
    for l in 0..D {
        fine.grid.cells[l] *= r;
        fine.grid.spacing[l] /= r as f64;
    }
    // CTU at Courant 1 for linear elasticity; donor-cell with RK2 at Courant 0.9 for SVK
    // (CTU is implemented for linear elasticity only; RK2 with donor-cell is stable to 1.0,
    // and 0.9 ran bounded on the 132x100 SVK plate for 1 ms; at 0.5 it smears twice as much)
    let linear = fine.model == impact_core::method::Model::LinearElastic;
    let config = MethodConfig {
        kind: MethodKind::Dgmpm,
        courant: if linear { 1.0 } else { 0.9 },
        points_per_cell: 1,
        integrator: if linear {
            Integrator::Euler
        } else {
            Integrator::Rk2
        },
        update: PointUpdate::Nodal,
        stress_update: StressUpdate::Usl,
        frame: MpmFrame::TotalLagrangian,
        flux: if linear {
            TransverseFlux::Ctu
        } else {
            TransverseFlux::DonorCell
        },
        riemann: RiemannSolver::Approximate,
    };
    let description = format!(
        "converged reference: DGMPM (1 ppc, {}, {}, Courant {}) on a {}x{} grid ({}x finer)",
        config.flux.name().to_uppercase(),
        config.integrator.name(),
        config.courant,
        fine.grid.cells[0],
        fine.grid.cells[1],
        r
    );
    if say {
        use std::io::Write as _;
        // a closed pipe only loses this line
        let _ = writeln!(std::io::stdout(), "computing the {description}");
    }
    let mut method = build(&fine, config)?;
    let mut samples = impact_core::method::Samples::<D>::default();
    let (mut stress_xx, mut velocity_x, mut work) = (Vec::new(), Vec::new(), Vec::new());
    let cells = fine.grid.cells;
    impact_core::controller::run::<D, dyn Method<D>, std::convert::Infallible>(
        method.as_mut(),
        &problem.output_times,
        impact_core::controller::Guard::default(),
        |m, _, _, _| {
            m.sample_into(&mut samples);
            // one point per cell, stored cell by cell: sample i is cell i
            stress_xx.push(samples.stress.iter().map(|s| s[(0, 0)]).collect());
            velocity_x.push(samples.velocity.iter().map(|v| v[0]).collect());
            work.push(m.external_work());
            Ok(())
        },
        |_| {},
    )
    .map_err(|e| anyhow::anyhow!("the reference run failed: {e}"))?;
    Ok(Some(Reference::Converged(Box::new(Converged {
        description,
        cells: [cells[0], cells[1 % D]],
        spacing: [fine.grid.spacing[0], fine.grid.spacing[1 % D]],
        times: problem.output_times.clone(),
        stress_xx,
        velocity_x,
        speed: problem.material.p_wave_speed::<D>(),
        length: problem.grid.upper()[0] - problem.grid.origin[0],
        coarse_dx: problem.grid.spacing[0],
        work,
    }))))
}

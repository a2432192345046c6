//! A [`Study`]: one scene and the command-line [`Overrides`], validated once, from which
//! every command takes its problem and method configurations.
use impact_core::method::{
    EdgeKind, EdgeTreatment, Integrator, LoadDirection, MethodConfig, MethodKind, MpmFrame,
    MpmShape, MpmTransfer, PointUpdate, RiemannSolver, SchemeOrder, StressUpdate, TransverseFlux,
    WaveLimiter,
};
use impact_core::scene::{
    check_courant, check_output_times, check_points_per_cell, check_work, Scene,
    DEFAULT_WORK_BUDGET, MAX_POINTS,
};
use impact_core::{CoreError, Problem, SceneError};

/// Command-line overrides of a scene (each `None` keeps the scene's value). The option
/// flags take the core enums directly (their names are spelled once, in
/// [`impact_core::options`]).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct Overrides {
    /// Cells along x (other axes scaled to keep the cell shape). Output times stay in
    /// seconds: a scene's `output_transits` count on its own grid.
    #[arg(long)]
    pub cells: Option<usize>,
    /// Courant number c·Δt/Δx, in (0, 2].
    #[arg(long, allow_negative_numbers = true)]
    pub courant: Option<f64>,
    /// Material points per cell (1D: 1..64; 2D: 1, 4, 9, ...).
    #[arg(long)]
    pub points_per_cell: Option<usize>,
    /// DGMPM time integrator.
    #[arg(long, value_enum)]
    pub integrator: Option<Integrator>,
    /// DGMPM point update after the nodal solve.
    #[arg(long, value_enum)]
    pub update: Option<PointUpdate>,
    /// MPM stress update.
    #[arg(long, value_enum)]
    pub stress_update: Option<StressUpdate>,
    /// MPM frame: shape functions at reference (total) or current (updated) positions.
    #[arg(long, value_enum)]
    pub frame: Option<MpmFrame>,
    /// MPM shape functions: linear hats, uniform GIMP, quadratic or cubic B-splines.
    #[arg(long, value_enum)]
    pub shape: Option<MpmShape>,
    /// MPM velocity transfer: FLIP (default), PIC, a PIC/FLIP blend (--flip-fraction) or
    /// APIC.
    #[arg(long, value_enum)]
    pub transfer: Option<MpmTransfer>,
    /// The FLIP share α in [0, 1] of --transfer blend (1 is FLIP, 0 is PIC).
    #[arg(long, allow_negative_numbers = true)]
    pub flip_fraction: Option<f64>,
    /// DGMPM transverse flux in 2D: donor-cell upwind or corner transport upwind.
    #[arg(long, value_enum)]
    pub flux: Option<TransverseFlux>,
    /// DGMPM Riemann solver for Saint-Venant-Kirchhoff.
    #[arg(long, value_enum)]
    pub riemann: Option<RiemannSolver>,
    /// DGMPM CTU edge treatment in 2D: restricted corrections (default) or ghost cells only
    /// (Clawpack's).
    #[arg(long, value_enum)]
    pub edges: Option<EdgeTreatment>,
    /// DGMPM spatial order: 1 (the paper's first-order flux) or 2 (limited second-order
    /// wave corrections, 1D-3D).
    #[arg(long, value_enum)]
    pub order: Option<SchemeOrder>,
    /// DGMPM wave limiter of --order 2 (default mc; none is Lax-Wendroff).
    #[arg(long, value_enum)]
    pub limiter: Option<WaveLimiter>,
    /// Direction of the pressure load on the loaded end.
    #[arg(long = "load", value_enum)]
    pub load: Option<LoadDirection>,
    /// Magnitude of the pressure load in Pa (keeps the direction unless --load is given).
    #[arg(long, allow_negative_numbers = true)]
    pub load_magnitude: Option<f64>,
    /// End time in seconds. With the scene's output times, those after it are dropped and
    /// it becomes the last output; with --output-times, none may lie after it.
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Output times in seconds, comma-separated and increasing.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub output_times: Option<Vec<f64>>,
    /// Largest work one method run may take, in point-updates (cells × points per cell ×
    /// steps; default 1e11, about an hour on one core). Runs estimated above it are refused
    /// before they start.
    #[arg(long, allow_negative_numbers = true)]
    pub work_budget: Option<f64>,
    /// J2 yield stress σ_y in Pa (scenes with model = "j2").
    #[arg(long, allow_negative_numbers = true)]
    pub yield_stress: Option<f64>,
    /// J2 hardening modulus H in Pa (scenes with model = "j2").
    #[arg(long, allow_negative_numbers = true)]
    pub hardening: Option<f64>,
    /// Run a DGMPM configuration whose Courant number is above its von Neumann limit
    /// (refused otherwise); the outputs record it.
    #[arg(long)]
    pub allow_unstable: bool,
    /// The converged reference's method, for a scene without an exact solution (default:
    /// the first of dgmpm, fem the command does not compare; `[metrics] reference`).
    #[arg(long, value_enum)]
    pub reference: Option<MethodKind>,
    /// The converged reference's grid: this many times finer along each axis (2 to 16,
    /// default 8 in 1D and 2D, 4 in 3D; `[metrics] reference_refinement`).
    #[arg(long)]
    pub reference_refinement: Option<usize>,
    /// The second reference, whose distance from the first is each error's uncertainty
    /// (default: the other of dgmpm, fem; `[metrics] reference_spread`).
    #[arg(long, value_enum)]
    pub reference_spread: Option<MethodKind>,
    /// Shape functions of an MPM reference (default bspline2; `[metrics] reference_shape`).
    #[arg(long, value_enum)]
    pub reference_shape: Option<MpmShape>,
    /// Transverse flux of a DGMPM reference (`[metrics] reference_flux`).
    #[arg(long, value_enum)]
    pub reference_flux: Option<TransverseFlux>,
}

impl Overrides {
    /// The flags given, as typed (`--cells`, `--shape`, ...), in declaration order.
    pub fn given(&self) -> Vec<String> {
        let set = [
            ("--cells", self.cells.is_some()),
            ("--courant", self.courant.is_some()),
            ("--points-per-cell", self.points_per_cell.is_some()),
            ("--integrator", self.integrator.is_some()),
            ("--update", self.update.is_some()),
            ("--stress-update", self.stress_update.is_some()),
            ("--frame", self.frame.is_some()),
            ("--shape", self.shape.is_some()),
            ("--transfer", self.transfer.is_some()),
            ("--flip-fraction", self.flip_fraction.is_some()),
            ("--flux", self.flux.is_some()),
            ("--riemann", self.riemann.is_some()),
            ("--edges", self.edges.is_some()),
            ("--order", self.order.is_some()),
            ("--limiter", self.limiter.is_some()),
            ("--load", self.load.is_some()),
            ("--load-magnitude", self.load_magnitude.is_some()),
            ("--t-end", self.t_end.is_some()),
            ("--output-times", self.output_times.is_some()),
            ("--work-budget", self.work_budget.is_some()),
            ("--yield-stress", self.yield_stress.is_some()),
            ("--hardening", self.hardening.is_some()),
            ("--reference", self.reference.is_some()),
            (
                "--reference-refinement",
                self.reference_refinement.is_some(),
            ),
            ("--reference-spread", self.reference_spread.is_some()),
            ("--reference-shape", self.reference_shape.is_some()),
            ("--reference-flux", self.reference_flux.is_some()),
        ];
        set.iter()
            .filter(|(_, given)| *given)
            .map(|(flag, _)| flag.to_string())
            .collect()
    }

    /// Refuse the flags of `not_allowed` that were given: `command` sets or sweeps them
    /// itself (`why`).
    pub fn refuse(&self, command: &str, not_allowed: &[&str], why: &str) -> Result<(), SceneError> {
        match self
            .given()
            .into_iter()
            .find(|f| not_allowed.contains(&f.as_str()))
        {
            Some(flag) => Err(SceneError::new(
                flag.as_str(),
                "given",
                format!("not with `{command}`, which {why}; the other `impact run` flags are"),
            )),
            None => Ok(()),
        }
    }

    /// Apply the scene-level overrides (cells, load) to `scene`, checking each value
    /// (points per cell is checked against the scene's dimension but applied per method).
    fn apply_to_scene(&self, scene: &mut Scene) -> Result<(), SceneError> {
        for (flag, value, slot) in [
            (
                "--yield-stress",
                self.yield_stress,
                &mut scene.material.yield_stress,
            ),
            ("--hardening", self.hardening, &mut scene.material.hardening),
        ] {
            if let Some(v) = value {
                if scene.material.model != impact_core::method::MaterialModel::J2 {
                    return Err(SceneError::new(
                        flag,
                        v,
                        "a plasticity parameter only for scenes with model = \"j2\"",
                    ));
                }
                *slot = Some(v);
            }
        }
        if self.load.is_some() || self.load_magnitude.is_some() {
            let edge = [&mut scene.boundary.left, &mut scene.boundary.right]
                .into_iter()
                .flatten()
                .find(|e| e.kind == EdgeKind::Pressure)
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
            let compression = match self.load {
                Some(direction) => direction == LoadDirection::Compression,
                None => current >= 0.0,
            };
            edge.value = Some(if compression { magnitude } else { -magnitude });
        }
        self.apply_reference(scene)?; // crate::reference_setup
        if let (Some(flux), 1) = (self.flux, scene.dim) {
            return Err(SceneError::new(
                "--flux",
                flux,
                "a transverse flux only in 2D scenes",
            ));
        }
        if let (Some(edges), 1) = (self.edges, scene.dim) {
            return Err(SceneError::new(
                "--edges",
                edges,
                "an edge treatment only in 2D scenes (CTU)",
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
            // output times stay physical: transits count on the scene file's own grid
            if scene.time.output_transits.is_some() {
                let (times, _) = scene.schedule_seconds();
                scene.time.output_times = Some(times);
                scene.time.output_transits = None;
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
        let per_cell = self
            .points_per_cell
            .unwrap_or(1)
            .max(scene.domain.points_per_cell) as f64;
        let total: f64 = scene
            .domain
            .cells
            .iter()
            .map(|&n| n as f64)
            .product::<f64>()
            * per_cell;
        if total > MAX_POINTS {
            return Err(SceneError::new(
                "--cells/--points-per-cell",
                format!("{:?} cells", scene.domain.cells),
                format!("at most {MAX_POINTS:.1e} cells × points per cell in total"),
            ));
        }
        if let Some(ppc) = self.points_per_cell {
            // checked here against the scene's dimension; applied per method
            check_points_per_cell(scene.dim, ppc).map_err(|mut e| {
                e.field = "--points-per-cell".into();
                e
            })?;
        }
        if let Some(c) = self.courant {
            check_courant("--courant", c)?;
        }
        self.apply_schedule(scene)
    }

    /// Apply `--output-times` and `--t-end` to the (validated) scene's time section.
    fn apply_schedule(&self, scene: &mut Scene) -> Result<(), SceneError> {
        if let Some(times) = &self.output_times {
            check_output_times("--output-times", times)?;
            scene.time.output_times = Some(times.clone());
            scene.time.output_transits = None;
            scene.time.t_end = None;
        }
        if let Some(t_end) = self.t_end {
            if !(t_end.is_finite() && t_end > 0.0) {
                return Err(SceneError::new(
                    "--t-end",
                    t_end,
                    "a positive finite time in s",
                ));
            }
            if self.output_times.is_none() {
                let (mut times, _) = scene.schedule_seconds();
                times.retain(|&t| t < t_end * (1.0 - 1e-12));
                times.push(t_end);
                scene.time.output_times = Some(times);
                scene.time.output_transits = None;
            }
            scene.time.t_end = Some(t_end);
        }
        if let Some(budget) = self.work_budget {
            if !(budget.is_finite() && budget >= 1.0) {
                return Err(SceneError::new(
                    "--work-budget",
                    budget,
                    "a finite number of point-updates, at least 1",
                ));
            }
        }
        Ok(())
    }

    /// Apply the method-level overrides to `config` (each to the method it belongs to).
    pub fn apply_to_config(&self, config: &mut MethodConfig) {
        if let Some(c) = self.courant {
            config.courant = c;
        }
        if let Some(ppc) = self.points_per_cell {
            config.points_per_cell = ppc;
        }
        if let Some(o) = config.dgmpm_mut() {
            o.integrator = self.integrator.unwrap_or(o.integrator);
            o.update = self.update.unwrap_or(o.update);
            o.flux = self.flux.unwrap_or(o.flux);
            o.riemann = self.riemann.unwrap_or(o.riemann);
            o.edges = self.edges.unwrap_or(o.edges);
            o.order = self.order.unwrap_or(o.order);
            o.limiter = self.limiter.or(o.limiter);
        }
        if let Some(o) = config.mpm_mut() {
            o.stress_update = self.stress_update.unwrap_or(o.stress_update);
            o.frame = self.frame.unwrap_or(o.frame);
            o.shape = self.shape.unwrap_or(o.shape);
            o.transfer = self.transfer.unwrap_or(o.transfer);
            o.flip_fraction = self.flip_fraction.or(o.flip_fraction);
        }
    }
}

/// The work budget of a study's runs.
pub(crate) fn budget_of(study: &Study) -> f64 {
    study.overrides.work_budget.unwrap_or(DEFAULT_WORK_BUDGET)
}

/// A scene with its overrides applied, validated once: the problem and the method
/// configurations of every command come from here.
#[derive(Debug, Clone)]
pub struct Study {
    /// The scene, overrides applied (cells, load).
    pub scene: Scene,
    /// The overrides (method options and schedule are applied on demand).
    pub overrides: Overrides,
}

/// The scene of `source`: a shipped scene name (`impact scenes`) or the path of a scene
/// file (a name ending in `.toml` or holding a `/`), parsed but not yet validated
/// ([`Study::new`] validates it).
pub fn parse_scene(source: &str) -> Result<Scene, CoreError> {
    if source.ends_with(".toml") || source.contains('/') {
        return Scene::parse_file(std::path::Path::new(source));
    }
    Scene::builtin(source).ok_or_else(|| {
        SceneError::new(
            "scene",
            format!("unknown scene {source:?}"),
            format!(
                "a shipped scene ({}) or a path to a .toml file",
                impact_core::scene::BUILTIN.join(", ")
            ),
        )
        .into()
    })
}

impl Study {
    /// The study of `source` ([`parse_scene`]) with `overrides`.
    pub fn load(source: &str, overrides: Overrides) -> Result<Self, CoreError> {
        Ok(Self::new(parse_scene(source)?, overrides)?)
    }

    /// Validate `scene` (parsed, not yet validated: errors name its fields), apply
    /// `overrides` (errors name the flags) and validate the result again (errors name the
    /// field and say the overrides are in effect).
    pub fn new(mut scene: Scene, overrides: Overrides) -> Result<Self, SceneError> {
        scene.validate()?;
        overrides.apply_to_scene(&mut scene)?;
        scene.validate().map_err(|mut e| {
            e.field = format!("{} (with the command-line overrides)", e.field);
            e
        })?;
        Ok(Self { scene, overrides })
    }

    /// Refuse, before anything is allocated, a run of `kinds` whose configuration the
    /// problem cannot run ([`Self::check_configs`]) or whose estimated work exceeds the
    /// budget (`--work-budget`, default [`DEFAULT_WORK_BUDGET`]), the converged
    /// reference's included.
    pub fn check_work(&self, kinds: &[MethodKind]) -> Result<(), CoreError> {
        self.check_methods_work(kinds)?;
        for reference in self.reference_work(kinds)? {
            check_work(&reference, budget_of(self))?;
        }
        Ok(())
    }

    /// [`Self::check_work`] without the reference (`--no-reference`).
    pub fn check_methods_work(&self, kinds: &[MethodKind]) -> Result<(), CoreError> {
        let configs: Vec<MethodConfig> = kinds.iter().map(|&k| self.config(k)).collect();
        self.check_configs(&configs)?;
        for config in &configs {
            check_work(&self.scene.work_estimate(config), budget_of(self))?;
        }
        if let Some(machine) = crate::memory::machine_bytes() {
            let cells = &self.scene.domain.cells;
            let cell_count: f64 = cells.iter().map(|&n| n as f64).product();
            for config in &configs {
                let field = match self.overrides.cells.is_some() {
                    true => "--cells",
                    false => "domain.cells",
                };
                crate::memory::check_fits(
                    field,
                    format!("{cells:?} × {} points per cell", config.points_per_cell),
                    config.kind(),
                    self.dim(),
                    cell_count * config.points_per_cell as f64,
                    machine,
                )?;
            }
        }
        Ok(())
    }

    /// Refuse every configuration of `configs` the study's problem cannot run (an option
    /// the material model or the dimension does not take, points per cell the layout does
    /// not seed: [`Problem::check_config`]), before any reference is computed or any run
    /// starts. Builds the problem only (no points, no buffers).
    pub fn check_configs(&self, configs: &[MethodConfig]) -> Result<(), CoreError> {
        fn each<const D: usize>(study: &Study, configs: &[MethodConfig]) -> Result<(), CoreError> {
            let problem = study.problem::<D>()?;
            configs.iter().try_for_each(|c| problem.check_config(c))
        }
        match self.dim() {
            1 => each::<1>(self, configs),
            2 => each::<2>(self, configs),
            3 => each::<3>(self, configs),
            d => Err(SceneError::new("dim", d, "1, 2 or 3").into()),
        }
    }

    /// Scene name.
    pub fn name(&self) -> &str {
        &self.scene.name
    }

    /// Spatial dimension.
    pub fn dim(&self) -> usize {
        self.scene.dim
    }

    /// The configuration of `kind`: the scene's, with the method overrides.
    pub fn config(&self, kind: MethodKind) -> MethodConfig {
        let mut config = self.scene.method_config(kind);
        self.overrides.apply_to_config(&mut config);
        config
    }

    /// The configuration of `kind` as the scene states it (no method override).
    pub fn scene_config(&self, kind: MethodKind) -> MethodConfig {
        self.scene.method_config(kind)
    }

    /// The problem in dimension `D` (the schedule overrides are in the scene).
    pub fn problem<const D: usize>(&self) -> Result<Problem<D>, CoreError> {
        Problem::<D>::from_valid_scene(&self.scene)
    }
}

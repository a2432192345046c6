//! A validated scene turned into typed data for dimension `D`: grid, material, boundary
//! conditions (one per side of each axis) and the output schedule.
use crate::error::{CoreError, SceneError};
use crate::initial::InitialState;
use crate::load::LoadHistory;
use crate::options::{EdgeKind, MaterialModel, SegmentCover};
use crate::patch::{Patch, PatchShape};
use crate::scene::{points_per_axis, EdgeSpec, Scene};
use crate::{Grid, LinearElastic, Tensor, Vector};

/// Condition on one side of the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Boundary {
    /// Traction-free.
    Free,
    /// Normal pressure `p g(t)` (Pa, positive in compression): traction `t = -p g(t) n`.
    Pressure(Load),
    /// An impactor moving at `v_d g(t)` into the body (m/s): bonded (the whole velocity
    /// vector `v_d n_in` is imposed: no slip) or frictionless (the normal velocity only, zero
    /// tangential traction).
    Velocity {
        /// Magnitude (positive into the body), segment and history.
        load: Load,
        /// Bonded (`velocity`) or frictionless (`normal-velocity`).
        bonded: bool,
    },
    /// Zero normal velocity and zero shear traction (a mirror plane).
    Symmetry,
}

/// A load on an edge or face: magnitude, where on it, and its time history.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Load {
    /// Magnitude: pressure (Pa) or velocity (m/s).
    pub value: f64,
    /// Loaded patch of the face (a segment in 2D, a box or disc in 3D; [`crate::patch`]);
    /// outside it the face is free. `None`: the whole face.
    pub patch: Option<Patch>,
    /// Time history `g(t)` ([`crate::load`]).
    pub history: LoadHistory,
}

impl Load {
    /// A step load on the whole edge.
    pub fn step(value: f64) -> Self {
        Self {
            value,
            patch: None,
            history: LoadHistory::Step,
        }
    }

    /// The magnitude at time `t`, `value · g(t)`.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        self.value * self.history.factor(t)
    }

    /// The magnitude over the step `[t0, t1]`, `value · ḡ` ([`LoadHistory::mean`]: the
    /// step's impulse to round-off).
    #[inline]
    pub fn mean(&self, (t0, t1): (f64, f64)) -> f64 {
        self.value * self.history.mean(t0, t1)
    }

    /// Share of the face (cell side, tributary area) normal to axis `l` centred at
    /// `centre` with half widths `half` (the entries along `l` are unused) that the load
    /// acts on: 1 without a patch, else [`Patch::coverage`] (by centre, or by covered
    /// fraction).
    #[inline]
    pub fn coverage<const D: usize>(&self, l: usize, centre: &Vector<D>, half: &Vector<D>) -> f64 {
        let Some(patch) = self.patch else {
            return 1.0;
        };
        patch.coverage(
            Patch::tangential(l, centre),
            Patch::tangential(l, half),
            D - 1,
        )
    }

    /// Whether the point `x` of a face normal to `l` lies in the loaded patch.
    #[inline]
    pub fn acts_on<const D: usize>(&self, l: usize, x: &Vector<D>) -> bool {
        self.patch
            .is_none_or(|patch| patch.contains(Patch::tangential(l, x)))
    }
}

/// A prescribed velocity component of a node or point: `value · g(t)`.
#[derive(Debug, Clone, Copy)]
pub struct Constraint {
    /// Node or point index.
    pub carrier: usize,
    /// Component.
    pub axis: usize,
    /// Magnitude.
    pub value: f64,
    /// Time history (a step for symmetry edges).
    pub history: LoadHistory,
}

impl Constraint {
    /// The prescribed value at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        self.value * self.history.factor(t)
    }

    /// The prescribed value over the step `[t0, t1]`, `value · ḡ` ([`LoadHistory::mean`]:
    /// the step's displacement to round-off).
    #[inline]
    pub fn mean(&self, (t0, t1): (f64, f64)) -> f64 {
        self.value * self.history.mean(t0, t1)
    }
}

impl Boundary {
    /// The load of a pressure or velocity edge.
    pub fn load(&self) -> Option<&Load> {
        match self {
            Boundary::Pressure(load) | Boundary::Velocity { load, .. } => Some(load),
            Boundary::Free | Boundary::Symmetry => None,
        }
    }
}

/// Constitutive model of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Model {
    /// Small-strain linear elasticity (stress `σ`, points fixed in the reference grid).
    LinearElastic,
    /// Saint-Venant–Kirchhoff, total Lagrangian (deformation gradient `F`, stress `Π`).
    Svk(crate::material::Svk),
    /// Small-strain J2 plasticity (`crate::plasticity`): Cauchy stress, return map at the
    /// points (or Gauss points) after each elastic update.
    J2(crate::plasticity::J2),
}

impl Model {
    /// Which stress the model's points carry and the outputs write.
    pub fn stress_measure(&self) -> StressMeasure {
        match self {
            Model::LinearElastic | Model::J2(_) => StressMeasure::Cauchy,
            Model::Svk(_) => StressMeasure::FirstPiola,
        }
    }
}

/// The stress measure in a run's outputs: the Cauchy stress `σ` in small strain (where it
/// equals every other measure to first order), the first Piola–Kirchhoff stress
/// `P = Π = F·S` in large strain (total Lagrangian: force per reference area, the paper's
/// eq. (2)). Array and column names carry it, so a file never says `stress` alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StressMeasure {
    /// Cauchy stress `σ` (linear elasticity).
    Cauchy,
    /// First Piola–Kirchhoff stress `P` (Saint-Venant–Kirchhoff).
    FirstPiola,
}

impl StressMeasure {
    /// The array name in VTU, HDF5 and XDMF: `cauchy_stress` or `piola_stress`.
    pub fn array_name(self) -> &'static str {
        match self {
            StressMeasure::Cauchy => "cauchy_stress",
            StressMeasure::FirstPiola => "piola_stress",
        }
    }

    /// The CSV column of the xx component: `cauchy_stress_xx` or `piola_stress_xx`.
    pub fn xx_column(self) -> &'static str {
        match self {
            StressMeasure::Cauchy => "cauchy_stress_xx",
            StressMeasure::FirstPiola => "piola_stress_xx",
        }
    }

    /// A plot label for the xx component.
    pub fn xx_label(self) -> &'static str {
        match self {
            StressMeasure::Cauchy => "Cauchy stress σₓₓ",
            StressMeasure::FirstPiola => "first Piola–Kirchhoff stress Πₓₓ",
        }
    }

    /// The xx component's symbol on plot axes (`σₓₓ`, `Πₓₓ`: the paper's names).
    pub fn xx_symbol(self) -> &'static str {
        match self {
            StressMeasure::Cauchy => "σₓₓ",
            StressMeasure::FirstPiola => "Πₓₓ",
        }
    }
}

/// A scene in typed form for dimension `D`.
#[derive(Debug, Clone)]
pub struct Problem<const D: usize> {
    /// Scene name.
    pub name: String,
    /// The body `[0, length]` and its grid.
    pub grid: Grid<D>,
    /// Material parameters (`E`, `ν`, `ρ₀`).
    pub material: LinearElastic,
    /// Constitutive model.
    pub model: Model,
    /// `boundaries[l][0]` at the low side of axis `l`, `[l][1]` at the high side.
    pub boundaries: [[Boundary; 2]; D],
    /// Points per cell from the scene.
    pub points_per_cell: usize,
    /// State at `t = 0`.
    pub initial: InitialState,
    /// Where the points sit in a cell.
    pub layout: crate::points::PointLayout,
    /// Output times (s).
    pub output_times: Vec<f64>,
    /// End time (s).
    pub t_end: f64,
    /// The measuring line stated by the scene; `None`: inferred from the loads
    /// ([`crate::line::MeasureLine::of`]).
    pub line: Option<crate::line::MeasureLine>,
    /// Where errors are measured ([`Scene::interior_rule`], [`crate::interior`]).
    pub interior: crate::interior::InteriorRule,
    /// The converged reference as `[metrics]` states it (the command resolves the rest).
    pub reference: crate::scene::ReferenceOptions,
}

impl<const D: usize> Problem<D> {
    /// Validate `scene` and build the problem ([`Self::from_valid_scene`]).
    pub fn from_scene(scene: &Scene) -> Result<Self, CoreError> {
        scene.validate()?;
        Self::from_valid_scene(scene)
    }

    /// Build from a scene that [`Scene::validate`] accepted. `scene.dim` must equal `D`.
    pub fn from_valid_scene(scene: &Scene) -> Result<Self, CoreError> {
        if scene.dim != D || scene.domain.length.len() != D || scene.domain.cells.len() != D {
            return Err(
                SceneError::new("dim", scene.dim, format!("{D} for this build path")).into(),
            );
        }
        let d = &scene.domain;
        let spacing = Vector::<D>::from_fn(|l, _| d.length[l] / d.cells[l] as f64);
        let mut cells = [0usize; D];
        cells.copy_from_slice(&d.cells);
        let grid = Grid {
            origin: Vector::<D>::zeros(),
            spacing,
            cells,
        };
        let m = &scene.material;
        let material = LinearElastic::new(m.young, m.poisson, m.density);
        let model = match m.model {
            MaterialModel::Svk => Model::Svk(crate::material::Svk::new(material)),
            MaterialModel::LinearElastic => Model::LinearElastic,
            MaterialModel::J2 => Model::J2(crate::plasticity::J2 {
                elastic: material,
                yield_stress: m.yield_stress.unwrap_or(f64::INFINITY),
                hardening: m.hardening.unwrap_or(0.0),
            }),
        };
        let mut boundaries = [[Boundary::Free; 2]; D];
        for (l, pair) in boundaries.iter_mut().enumerate() {
            for (side, bc) in pair.iter_mut().enumerate() {
                if let Some((_, spec)) = scene.boundary.side(l, side) {
                    *bc = to_boundary(spec, l, &scene.domain.length);
                }
            }
        }
        let (output_times, t_end) = scene.schedule_seconds();
        let mut problem = Self {
            name: scene.name.clone(),
            grid,
            material,
            model,
            boundaries,
            points_per_cell: d.points_per_cell,
            initial: scene.initial_state(),
            layout: scene.point_layout(),
            output_times,
            t_end,
            line: scene.measure_line(),
            interior: scene.interior_rule(),
            reference: scene.reference_options(),
        };
        problem.set_schedule(None, scene.time.t_end)?;
        Ok(problem)
    }

    /// The loads' stress scale and whether every load is a step: the largest `|p|`, or
    /// `Z |v_d|` for an impactor (`Z = ρ c_p`), over the loads of non-zero magnitude (0
    /// with none; a fixed wall is no load).
    pub fn load_scale(&self) -> (f64, bool) {
        let impedance = self.material.density * self.material.p_wave_speed::<D>();
        let (mut scale, mut step) = (0.0f64, true);
        for boundary in self.boundaries.iter().flatten() {
            let (load, factor) = match boundary {
                Boundary::Pressure(load) => (load, 1.0),
                Boundary::Velocity { load, .. } => (load, impedance),
                Boundary::Free | Boundary::Symmetry => continue,
            };
            if load.value != 0.0 {
                scale = scale.max(load.value.abs() * factor);
                step &= load.history.is_step();
            }
        }
        (scale, step)
    }

    /// Replace the output times and/or the end time. With only `t_end`, outputs after it
    /// are dropped and `t_end` becomes the last output.
    pub fn set_schedule(
        &mut self,
        output_times: Option<Vec<f64>>,
        t_end: Option<f64>,
    ) -> Result<(), SceneError> {
        if let Some(times) = output_times {
            crate::scene::check_output_times("--output-times", &times)?;
            self.output_times = times;
            self.t_end = *self
                .output_times
                .last()
                .expect("internal: checked non-empty");
        }
        if let Some(t_end) = t_end {
            if !(t_end.is_finite() && t_end > 0.0) {
                return Err(SceneError::new(
                    "t_end",
                    t_end,
                    "a positive finite time in s",
                ));
            }
            self.output_times.retain(|&t| t < t_end * (1.0 - 1e-12));
            self.output_times.push(t_end);
            self.t_end = t_end;
        }
        Ok(())
    }

    /// Largest wave speed the loads can produce: `c_p` for linear elasticity; for SVK the
    /// largest of `c(1)` and the speeds at the uniaxial stretch each pressure or velocity
    /// load implies (1D: `Π(F) = -p`; 2D: strain `±p/M` or `±v/c_p`, with 10 % margin for the
    /// transverse stiffening the estimate misses). The guard stops a run whose state
    /// outruns this speed by more than 5 % (e.g. a 1D bar long after the reflection of a
    /// strong compression as tension).
    pub fn max_wave_speed(&self) -> f64 {
        let c_p = self.material.p_wave_speed::<D>();
        let Model::Svk(svk) = self.model else {
            return c_p;
        };
        let mut c: f64 = c_p;
        for pair in &self.boundaries {
            for bc in pair {
                let stretch = match *bc {
                    Boundary::Pressure(Load { value, .. }) => {
                        if D == 1 {
                            svk.stretch_for_1d(-value).unwrap_or(1.0)
                        } else {
                            1.0 - value / self.material.p_modulus::<D>()
                        }
                    }
                    Boundary::Velocity {
                        load: Load { value, .. },
                        ..
                    } => 1.0 - value.abs() / c_p,
                    _ => 1.0,
                };
                // 1D: the stretch the load produces; 2D: also its mirror (reflections, shear)
                let mirror = if D == 1 { stretch } else { 2.0 - stretch };
                for f in [stretch, mirror] {
                    let mut t = Tensor::<D>::identity();
                    t[(0, 0)] = f;
                    let s = svk.max_wave_speed(&t);
                    if s.is_finite() {
                        c = c.max(s);
                    }
                }
            }
        }
        if D > 1 {
            c *= 1.1;
        }
        c
    }

    /// Time for a P wave to cross the smallest cell, `Δx/c_p`.
    pub fn cell_transit_time(&self) -> f64 {
        self.grid.min_spacing() / self.material.p_wave_speed::<D>()
    }

    /// Points per axis of the configured points per cell.
    pub fn points_per_axis(&self, ppc: usize) -> Result<usize, SceneError> {
        crate::scene::check_points_per_cell(D, ppc)?;
        Ok(points_per_axis(D, ppc).expect("internal: checked power"))
    }

    /// The material points of a point method (`config`: DGMPM or MPM) on `grid`: placed by
    /// the scene's layout, in the initial state, with the arrays the model needs (`F` under
    /// Saint-Venant–Kirchhoff, the plastic history under J2).
    pub fn material_points(
        &self,
        grid: &Grid<D>,
        config: &crate::options::MethodConfig,
    ) -> Result<crate::points::MaterialPoints<D>, CoreError> {
        let whole: [std::ops::Range<usize>; D] = std::array::from_fn(|k| 0..grid.cells[k]);
        self.material_points_of_box(grid, config, &whole)
    }

    /// [`Self::material_points`] of the box of cells `cells` (a range per axis of `grid`)
    /// only (a rank's stored box, [`crate::points::MaterialPoints::seeded_box`]): the same
    /// points, with the same bits, as the whole body's points of those cells, in the
    /// box's lexicographic cell order.
    pub fn material_points_of_box(
        &self,
        grid: &Grid<D>,
        config: &crate::options::MethodConfig,
        cells: &[std::ops::Range<usize>; D],
    ) -> Result<crate::points::MaterialPoints<D>, CoreError> {
        let per_axis = self.points_per_axis(config.points_per_cell)?;
        if !self.layout.fits(config.points_per_cell) {
            return Err(CoreError::Unsupported {
                method: config.kind().name().into(),
                message: format!(
                    "the scene's point layout ({}) does not seed {} points per cell",
                    self.layout.label(),
                    config.points_per_cell
                ),
            });
        }
        let mut points = crate::points::MaterialPoints::seeded_box(
            grid,
            per_axis,
            self.material.density,
            &self.layout,
            cells,
        );
        points.apply_initial(&self.initial);
        Ok(match self.model {
            Model::Svk(_) => points.with_deformation(),
            Model::J2(_) => points.with_plasticity(),
            Model::LinearElastic => points,
        })
    }
}

fn to_boundary(e: &EdgeSpec, axis: usize, length: &[f64]) -> Boundary {
    let cover = e.cover.unwrap_or(SegmentCover::Centre);
    let tangents: Vec<usize> = (0..length.len()).filter(|&k| k != axis).collect();
    let patch = match (&e.from, &e.to, &e.centre, e.radius) {
        (None, None, None, None) => None,
        (_, _, Some(centre), Some(radius)) => Some(Patch {
            shape: PatchShape::Disc {
                centre: [centre[0], centre.get(1).copied().unwrap_or(0.0)],
                radius,
            },
            cover,
        }),
        (from, to, _, _) => {
            let (mut lo, mut hi) = ([f64::NEG_INFINITY; 2], [f64::INFINITY; 2]);
            let from = from.as_ref().map(|c| c.to_vec());
            let to = to.as_ref().map(|c| c.to_vec());
            for slot in 0..tangents.len() {
                lo[slot] = from.as_ref().map_or(f64::NEG_INFINITY, |v| v[slot]);
                hi[slot] = to.as_ref().map_or(f64::INFINITY, |v| v[slot]);
            }
            Some(Patch {
                shape: PatchShape::Box { lo, hi },
                cover,
            })
        }
    };
    let load = Load {
        value: e.value.unwrap_or_default(),
        patch,
        history: LoadHistory::new(
            e.history.unwrap_or(crate::options::LoadShape::Step),
            e.duration.unwrap_or(0.0),
        ),
    };
    match e.kind {
        EdgeKind::Pressure => Boundary::Pressure(load),
        EdgeKind::Velocity | EdgeKind::NormalVelocity => Boundary::Velocity {
            load,
            bonded: e.kind == EdgeKind::Velocity,
        },
        EdgeKind::Symmetry => Boundary::Symmetry,
        EdgeKind::Free => Boundary::Free,
    }
}

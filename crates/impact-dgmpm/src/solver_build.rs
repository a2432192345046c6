//! Building a [`DgmpmSolver`]: the physics, the step path and every buffer it reads
//! (allocated once here, so the step loop allocates nothing).
use super::*;

impl<const D: usize> DgmpmSolver<D> {
    /// Allocate every buffer the fastest applicable [`StepPath`] reads and cache the shape
    /// functions at the (fixed) points.
    pub(crate) fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        options: DgmpmOptions,
        points: &MaterialPoints<D>,
    ) -> Result<Self, CoreError> {
        let grid = problem.grid.clone();
        let inside = all_inside(&grid, points)?;
        let (p, s) = problem.material.impedances::<D>();
        let lame = problem.material.lame;
        let elastic = Elastic {
            lambda: lame.lambda,
            mu: if D == 1 {
                0.5 * problem.material.elastic.young
            } else {
                lame.mu
            },
            density: problem.material.density,
            z: Impedances { p, s },
        };
        // (the fused sweeps have no wave corrections: order 2 takes the general paths)
        let linear = matches!(problem.model, Model::LinearElastic | Model::J2(_));
        let fusable = Fusable::of(
            D,
            linear
                && options.riemann != RiemannSolver::Elastoplastic
                && options.wave_limiter().is_none(),
        );
        let path = StepPath::fastest(config.points_per_cell, options.integrator, inside, fusable);
        let mut solver = Self {
            config,
            options,
            path,
            parallel: worth_parallel(grid.cell_count()),
            material: problem.material,
            boundaries: problem.boundaries,
            load_now: [[0.0; 2]; D],
            edge_conditions: faces::EdgeConditions::new(&grid),
            points_per_cell: config.points_per_cell,
            layouts: layouts::CellLayouts::default(),
            shape: Vec::new(),
            shape_gradient: Vec::new(),
            heun_weights: Vec::new(),
            heun_scaled: Vec::new(),
            heun_scaled_dt: f64::NAN,
            heun_layout: Vec::new(),
            inverse_mass: Vec::new(),
            inside,
            nodes: NodalFields::default(),
            face_flux: std::array::from_fn(|_| Vec::new()),
            correction_scratch: Vec::new(),
            transverse_sources: std::array::from_fn(|_| Vec::new()),
            face_waves: Vec::new(),
            wave_flux: std::array::from_fn(|_| Vec::new()),
            fused: fused::FusedBuffers::default(),
            fusable,
            elastic,
            plastic: match problem.model {
                Model::J2(j2) => Some(j2),
                _ => None,
            },
            rod_solver: match problem.model {
                Model::J2(j2) if options.riemann == RiemannSolver::Elastoplastic => {
                    // the rod: E and E_t; plane strain: λ + 2μ and M_p (uniaxial strain)
                    let rho = problem.material.density;
                    let (elastic, plastic) = if D == 1 {
                        (problem.material.elastic.young, j2.uniaxial_stress_tangent())
                    } else {
                        (
                            problem.material.p_modulus::<D>(),
                            j2.uniaxial_strain_tangent(),
                        )
                    };
                    Some((
                        j2,
                        riemann::elastoplastic::RodImpedances {
                            elastic: (rho * elastic).sqrt(),
                            plastic: (rho * plastic).sqrt(),
                        },
                    ))
                }
                _ => None,
            },
            physics: match problem.model {
                Model::LinearElastic | Model::J2(_) => Physics::Linear,
                Model::Svk(svk) => Physics::Svk {
                    svk,
                    riemann: options.riemann,
                },
            },
            wave_speed: problem.max_wave_speed(),
            place: GridPlace::whole(&grid),
            grid,
        };
        solver.form_weights(points)?;
        // (the loads at zero until the first step's `set_load_window` fills it again)
        solver.fill_edge_conditions();
        Ok(solver)
    }

    /// Whether the volume term takes the cells' weights `K_ab` ([`Self::layouts`]): the
    /// nodal paths with linear elasticity (`σ_h` linear in the nodal stresses; not under
    /// Saint-Venant–Kirchhoff, whose `Π(F_h)` is not) and at least `2^D` points per cell,
    /// where `(2^D - 1) × 2^D` weights per cell cost fewer operations and less memory than
    /// the points' `2^D` gradients each (2D, 4 points: 192 flops and 12 weights against 448
    /// flops and 16 gradients per cell).
    pub(crate) fn takes_volume_weights(&self) -> bool {
        self.path.nodal()
            && matches!(self.physics, Physics::Linear)
            && self.points_per_cell >= Grid::<D>::NODES_PER_CELL
    }

    /// The blocks the path reads from the cell layouts ([`Self::layouts`]; `None`: the
    /// cell paths and the Heun cell sweeps, which read none): the shape values, the
    /// gradients unless the volume weights replace them, and with several points per cell
    /// phase 1's weights and the lumped masses (the points never move in the grid of this
    /// total Lagrangian scheme and their masses are fixed, so phase 1 never forms them).
    fn wanted_blocks(&self) -> Option<layouts::Blocks> {
        (self.path.nodal() && !self.heun_on_cells()).then(|| layouts::Blocks {
            gradient: !self.takes_volume_weights(),
            volume: self.takes_volume_weights(),
            mapping: self.points_per_cell > 1,
        })
    }

    /// Form what the path reads at the (fixed) points and allocate its buffers: the cell
    /// layouts (formed anew where the path reads other blocks), the buffers
    /// ([`Self::allocate_buffers`]) and the Heun sweeps' weights (from the points' shape
    /// functions, which `form_heun_weights` then drops).
    pub(crate) fn form_weights(&mut self, points: &MaterialPoints<D>) -> Result<(), CoreError> {
        let wanted = self.wanted_blocks();
        if self.layouts.blocks() != wanted {
            self.layouts = match wanted {
                Some(blocks) => {
                    layouts::CellLayouts::new(&self.grid, points, self.points_per_cell, blocks)?
                }
                None => layouts::CellLayouts::default(),
            };
        }
        if self.heun_on_cells() && self.heun_weights.is_empty() {
            (self.shape, self.shape_gradient) = shapes(&self.grid, points)?;
        }
        self.allocate_buffers();
        // the cell sweeps' inverse masses (at the points' fixed masses)
        let cell_sweeps = self.path == StepPath::Fused || self.heun_on_cells();
        self.inverse_mass = match cell_sweeps {
            true => points.mass.iter().map(|m| 1.0 / m).collect(),
            false => Vec::new(),
        };
        self.form_heun_weights(points)
    }

    /// Allocate the buffers the path reads where they are missing (never in the step
    /// loop): the nodal fields (nodal paths), the face arrays (every path but the fused
    /// one; the CTU scratch with CTU), the fused path's rows and next state.
    pub(crate) fn allocate_buffers(&mut self) {
        let grid = &self.grid;
        let nodes = grid.cell_count() * Grid::<D>::NODES_PER_CELL;
        let fused_nodal = self.path == StepPath::FusedNodal;
        let rk2 = self.options.integrator == Integrator::Rk2;
        // RK2 at one point per cell on the fused nodal sweep: nodal fields only; none on
        // the Heun cell sweeps (their `2D` side states per cell are the fused buffers',
        // `fused/heun.rs`)
        let single = fused_nodal && self.fused_nodal_single();
        let heun = self.heun_on_cells();
        let nodes = match heun {
            true => 0,
            false => nodes,
        };
        // the start-of-step fields: RK2, and the increment update of the phase paths (the
        // fused sweep's single Euler stage reads its own input instead)
        let increment = self.options.update == PointUpdate::Increment;
        // (RK2 at 2^D points per cell keeps its stage fields in the points' arrays,
        // `fused/nodal.rs`: neither start nor next fields)
        let in_points = self.fused_nodal_in_points();
        let keep_start = !single && !in_points && (rk2 || (increment && !fused_nodal));
        let wanted = NodalLayout {
            nodes,
            mass: !single && !self.layouts.has_mapping(),
            start: keep_start,
            rates: !fused_nodal,
        };
        if self.path.nodal() && self.nodes.layout() != wanted {
            self.nodes = NodalFields::new(wanted);
        }
        let ctu = D > 1 && self.options.flux == TransverseFlux::Ctu;
        if self.path.fused() {
            // the next state: one per point on the cell path; per node between RK2's two
            // nodal stages unless the first writes in place (the last writes the points)
            // (the Heun cell sweeps: one per cell, `q_p + ½ Δq(F¹)`)
            let layout = match (fused_nodal, rk2 && !single && !in_points) {
                (false, _) => fused::Layout::cell(ctu),
                (true, true) => fused::Layout::nodal(Grid::<D>::NODES_PER_CELL, ctu),
                (true, false) if heun => fused::Layout::heun(ctu),
                (true, false) => fused::Layout::nodal(0, ctu),
            };
            if self.fused.layout() != Some(layout) {
                self.fused = fused::FusedBuffers::new(grid.cells, layout);
            }
        } else if self.face_flux[0].is_empty() {
            self.fused = fused::FusedBuffers::default(); // (another path was the default)
            self.face_flux = std::array::from_fn(|l| vec![Conserved::zeros(); grid.face_count(l)]);
            if self.options.wave_limiter().is_some() {
                // one row of waves: the longest axis's faces and a ghost face at each end
                let longest = grid.cells.iter().copied().max().unwrap_or(0);
                self.face_waves = vec![Default::default(); longest + 3];
                if ctu {
                    self.wave_flux =
                        std::array::from_fn(|l| vec![Conserved::zeros(); grid.face_count(l)]);
                }
            }
            // 2D: one face array of scratch; 3D: the per-axis sources (`ctu3`)
            let scratch = if ctu && D == 2 {
                grid.face_count(D - 1)
            } else {
                0
            };
            self.correction_scratch = vec![Conserved::zeros(); scratch];
            if ctu && D == 3 {
                // the fluctuations W_l (a ghost layer on the other axes; order 2: twice, with
                // G_l) and one source array V_k (a ghost layer along k), the largest of three
                let halves = 1 + usize::from(!self.wave_flux[0].is_empty());
                let cells = grid.cells;
                let padded = |l: usize, across: bool| -> usize {
                    (0..D)
                        .map(|j| cells[j] + 2 * usize::from((j != l) == across))
                        .product::<usize>()
                        * if across { halves } else { 1 }
                };
                self.transverse_sources =
                    std::array::from_fn(|l| vec![Conserved::zeros(); padded(l, true)]);
                let largest = (0..D).map(|k| padded(k, false)).max().unwrap_or(0);
                self.correction_scratch = vec![Conserved::zeros(); largest];
            }
        }
    }

    /// Run another step path on `points` (for comparison; the default is
    /// [`StepPath::fastest`]): the shape functions and nodal buffers it reads are allocated
    /// here (the cell layouts formed anew where it reads other blocks). Refused where it
    /// does not apply.
    pub fn set_step_path(
        &mut self,
        path: StepPath,
        points: &MaterialPoints<D>,
    ) -> Result<(), CoreError> {
        if !path.applies(
            self.points_per_cell,
            self.options.integrator,
            self.inside,
            self.fusable,
        ) {
            return Err(unsupported(&format!(
                "step path {path:?} does not apply to {} points per cell with {}",
                self.points_per_cell, self.options.integrator
            )));
        }
        self.path = path;
        self.form_weights(points)
    }

    /// The path the step takes.
    pub fn step_path(&self) -> StepPath {
        self.path
    }

    /// Whether RK2 runs as the Heun cell sweeps (`fused/heun.rs`: the fused nodal path at
    /// one point per cell, every point strictly inside its cell).
    pub fn heun_cells(&self) -> bool {
        self.heun_on_cells()
    }

    /// The tensor field of the points the scheme evolves: `σ` (linear elasticity) or `F`
    /// (Saint-Venant–Kirchhoff).
    pub(crate) fn point_tensor<'a>(&self, points: &'a MaterialPoints<D>) -> &'a [Tensor<D>] {
        match self.physics {
            Physics::Linear => &points.stress,
            Physics::Svk { .. } => &points.deformation,
        }
    }

    /// The points' tensor field (as [`Self::point_tensor`]) and velocities, to update.
    pub(crate) fn point_fields_mut<'a>(
        &self,
        points: &'a mut MaterialPoints<D>,
    ) -> (&'a mut [Tensor<D>], &'a mut [Vector<D>]) {
        let tensor = match self.physics {
            Physics::Linear => &mut points.stress,
            Physics::Svk { .. } => &mut points.deformation,
        };
        (tensor, &mut points.velocity)
    }
}

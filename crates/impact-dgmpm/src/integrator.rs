//! Phases 3-4 and the step: nodal rates of the semi-discrete system (paper eq. 16), the
//! nodal update, and one `DgmpmSolver::stage` that forward Euler calls once and RK2
//! (Heun) twice.
use crate::riemann::Conserved;
use crate::{DgmpmSolver, DgmpmState, Physics, StepPath, CHUNK, MAX_NODES};
use impact_core::method::{Integrator, PointUpdate, TransverseFlux};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

/// Cells per rayon leaf of the per-cell loops.
const CELL_GRAIN: usize = 512;

/// Phase 4 at one node: `q + Δt q̇`, or with the start-of-step value `q⁰` (Heun's second
/// stage, `start_weight = a = ½`) `a q⁰ + (1 - a)(q + Δt q̇)`.
#[inline(always)]
pub(crate) fn stage_update<T>(q: T, rate: T, dt: f64, start: Option<T>, start_weight: f64) -> T
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
{
    let next = q + rate * dt;
    match start {
        None => next,
        Some(q0) => q0 * start_weight + next * (1.0 - start_weight),
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 3: nodal rates `dq_i/dt`, `dv_i/dt` of every cell (`cell_rates_into`).
    pub fn nodal_rates(&mut self, points: &MaterialPoints<D>) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let mut rate_tensor = std::mem::take(&mut self.nodes.rate_tensor);
        let mut rate_velocity = std::mem::take(&mut self.nodes.rate_velocity);
        let this = &*self;
        let parts = (
            chunks(&mut rate_tensor, nodes_per_cell),
            chunks(&mut rate_velocity, nodes_per_cell),
        );
        for_each_chunk(this.parallel, CELL_GRAIN, parts, |c, (rq, rv)| {
            this.cell_rates_into(c, points, rq, rv)
        });
        self.nodes.rate_tensor = rate_tensor;
        self.nodes.rate_velocity = rate_velocity;
    }

    /// The nodal rates of cell `c` from the face arrays ([`Self::rates_of_cell`]).
    fn cell_rates_into(
        &self,
        c: usize,
        points: &MaterialPoints<D>,
        rq: &mut [Tensor<D>],
        rv: &mut [Vector<D>],
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let (grid, nodes) = (&self.grid, &self.nodes);
        let idx = grid.cell_multi_index(c);
        // the high face is one l-stride of the l-face array further
        let faces: [[&Conserved<D>; 2]; D] = std::array::from_fn(|l| {
            let low = Self::face_index(grid, l, idx);
            let stride: usize = grid.cells[..l].iter().product();
            [&self.face_flux[l][low], &self.face_flux[l][low + stride]]
        });
        let cell_nodes = c * nodes_per_cell..(c + 1) * nodes_per_cell;
        let nodal = (
            &nodes.tensor[cell_nodes.clone()],
            &nodes.velocity[cell_nodes.clone()],
            self.cell_masses(c, &nodes.mass),
        );
        self.rates_of_cell(c, &points.volume, nodal, faces, (rq, rv));
    }

    /// The lumped masses `M_i` of cell `c`'s nodes: from the cell layouts where they hold
    /// them (several points per cell), else from the nodal masses `masses` phase 1 formed.
    #[inline(always)]
    pub(crate) fn cell_masses<'a>(&'a self, c: usize, masses: &'a [f64]) -> &'a [f64] {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        match self.layouts.has_mapping() {
            true => self.layouts.mass_of(self.layouts.layout_of(c)),
            false => &masses[c * nodes_per_cell..(c + 1) * nodes_per_cell],
        }
    }

    /// The nodal rates `(dq_i/dt, dv_i/dt)` of cell `c` into `(rq, rv)` (module doc of
    /// the crate), given the points' volumes `V_α`, its nodes' fields and masses `(q_i, v_i, M_i)` and its faces'
    /// final fluxes `[low, high]` per axis: the volume term on the points, with the nodal
    /// field interpolated there (paper eq. 14-15), and the face fluxes,
    /// `M_i dv_i/dt = -Σ_α V_α σ_h(X_α) ∇S_iα + Σ_f ∫_f S_i t*_out dΓ`,
    /// `(M_i/ρ) dσ_i/dt = C : [-Σ_α V_α sym(v_h(X_α) ⊗ ∇S_iα) + Σ_f ∫_f S_i sym(v* ⊗ n) dΓ]`;
    /// under Saint-Venant–Kirchhoff `Π(F_h)` replaces `σ_h` and `v_h ⊗ ∇S` (no `C :`) the
    /// strain rate (paper eq. 5-6). `C :` and `sym` are linear, so they are applied once per
    /// node to the sum `-Σ_α V_α v_h ⊗ ∇S_iα`. With linear elasticity and `2^D` points per
    /// cell or more the volume sums are `-Σ_b σ_b K_ib`, `-Σ_b v_b ⊗ K_ib` from the cell's
    /// weights `K_ib = Σ_α V_α S_bα ∇S_iα` (`layouts::cell_volume_weights`, formed once), which
    /// costs `2^D × 2^D` terms per cell instead of `2 × 2^D` per point; the last node's are
    /// minus the sum of the others' (`Σ_i K_ib = 0` since `Σ_i ∇S_i = 0`, the partition of
    /// unity), so `(2^D - 1) × 2^D` terms (to round-off: tested against the per-point
    /// form). Rates are zero at a node without mass.
    /// Shared by the phase path and the fused nodal sweep.
    #[inline(always)]
    pub(crate) fn rates_of_cell(
        &self,
        c: usize,
        volume: &[f64],
        (nq, nv, nm): (&[Tensor<D>], &[Vector<D>], &[f64]),
        faces: [[&Conserved<D>; 2]; D],
        (rq, rv): (&mut [Tensor<D>], &mut [Vector<D>]),
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let (nq, nv, nm) = (
            &nq[..nodes_per_cell],
            &nv[..nodes_per_cell],
            &nm[..nodes_per_cell],
        );
        let (rq, rv) = (&mut rq[..nodes_per_cell], &mut rv[..nodes_per_cell]);
        let grid = &self.grid;
        let svk = match self.physics {
            Physics::Linear => None,
            Physics::Svk { svk, .. } => Some(svk),
        };
        // -Σ_α V_α v_h ⊗ ∇S_iα and -Σ_α V_α σ_h ∇S_iα (+ the face tractions below)
        let mut velocity_gradient = [Tensor::<D>::zeros(); MAX_NODES];
        let mut force = [Vector::<D>::zeros(); MAX_NODES];
        let layouts = &self.layouts;
        if layouts.has_volume() {
            // linear elasticity, 2^D points or more: -Σ_b v_b ⊗ K_ab and -Σ_b σ_b K_ab
            // (`layouts::cell_volume_weights`) for every node but the last, whose terms
            // are minus the others' sum (Σ_a K_ab = 0: Σ_a ∇S_a = 0)
            let last = nodes_per_cell - 1;
            let k = layouts.volume_weights_of(layouts.layout_of(c));
            for (a, row) in k.chunks_exact(nodes_per_cell).enumerate() {
                for b in 0..nodes_per_cell {
                    velocity_gradient[a] -= nv[b] * row[b].transpose();
                    force[a] -= nq[b] * row[b];
                }
            }
            for a in 0..last {
                velocity_gradient[last] -= velocity_gradient[a];
                force[last] -= force[a];
            }
        }
        let per_point = match layouts.has_volume() {
            true => 0..0,
            false => 0..self.points_per_cell,
        };
        let (shapes, gradients) = match layouts.has_volume() {
            true => (&[][..], &[][..]),
            false => {
                let l = layouts.layout_of(c);
                (layouts.shape_of(l), layouts.gradient_of(l))
            }
        };
        for k in per_point {
            let p = c * self.points_per_cell + k;
            let s = &shapes[k * nodes_per_cell..(k + 1) * nodes_per_cell];
            let g = &gradients[k * nodes_per_cell..(k + 1) * nodes_per_cell];
            let mut qh = Tensor::<D>::zeros();
            let mut vh = Vector::<D>::zeros();
            for b in 0..nodes_per_cell {
                qh += nq[b] * s[b];
                vh += nv[b] * s[b];
            }
            let vol = volume[p];
            // the stress that acts: σ_h, or Π(F_h)
            let stress = match &svk {
                None => qh,
                Some(svk) => svk.piola(&qh),
            } * vol;
            let vh = vh * vol;
            for a in 0..nodes_per_cell {
                velocity_gradient[a] -= vh * g[a].transpose();
                force[a] -= stress * g[a];
            }
        }
        let mut tensor_flux = [Tensor::<D>::zeros(); MAX_NODES];
        for l in 0..D {
            let weight = grid.cell_volume() / grid.spacing[l] * 2.0 / nodes_per_cell as f64;
            // the face's nodes: bit l of the local node index set to `side`
            let low_bits = (1usize << l) - 1;
            for side in 0..2 {
                // outward flux F_n = sign · F_{e_l}; it leaves the cell
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let q = faces[l][side];
                let (tensor, momentum) = (q.tensor * (sign * weight), q.momentum * (sign * weight));
                for k in 0..nodes_per_cell / 2 {
                    let a = (k & low_bits) | (side << l) | ((k & !low_bits) << 1);
                    tensor_flux[a] -= tensor;
                    force[a] -= momentum;
                }
            }
        }
        let density = self.material.density;
        for a in 0..nodes_per_cell {
            let m = nm[a];
            if m > 0.0 {
                let gradient = velocity_gradient[a];
                let volume_part = match svk {
                    None => self
                        .material
                        .stress(&((gradient + gradient.transpose()) * 0.5)),
                    Some(_) => gradient,
                };
                let inv_mass = 1.0 / m;
                rq[a] = (volume_part + tensor_flux[a]) * (density * inv_mass);
                rv[a] = force[a] * inv_mass;
            } else {
                rq[a] = Tensor::<D>::zeros();
                rv[a] = Vector::<D>::zeros();
            }
        }
    }

    /// Phase 4: `q_i ← a q_i^n + (1 - a) (q_i + Δt q̇_i)` with `a = start_weight`: Euler and
    /// Heun's first stage are `a = 0`, Heun's second stage `a = ½`.
    pub fn nodal_update(&mut self, dt: f64, start_weight: f64) {
        let nodes = &mut self.nodes;
        let (rq, rv) = (&nodes.rate_tensor, &nodes.rate_velocity);
        let (q0, v0) = (&nodes.start_tensor, &nodes.start_velocity);
        let parts = (
            chunks(&mut nodes.tensor, CHUNK),
            chunks(&mut nodes.velocity, CHUNK),
        );
        for_each_chunk(self.parallel, 1, parts, |r, (tensor, velocity)| {
            for (j, (q, v)) in tensor.iter_mut().zip(velocity.iter_mut()).enumerate() {
                let i = r * CHUNK + j;
                let starts = (start_weight != 0.0).then(|| (q0[i], v0[i]));
                *q = stage_update(*q, rq[i], dt, starts.map(|s| s.0), start_weight);
                *v = stage_update(*v, rv[i], dt, starts.map(|s| s.1), start_weight);
            }
        });
    }

    /// One stage of the nodal paths: phase 2 (fluxes; 2b, CTU corrections), the boundary
    /// force, phase 3 (rates) and phase 4 (update with `start_weight`); on
    /// [`StepPath::FusedNodal`] in one sweep ([`crate::fused`]), the step's `last` stage
    /// with phase 5 in it. Returns the power and force of the boundary conditions at the
    /// stage's state.
    fn stage(
        &mut self,
        points: &mut MaterialPoints<D>,
        dt: f64,
        start_weight: f64,
        last: bool,
    ) -> (f64, Vector<D>) {
        if self.path == StepPath::FusedNodal {
            return self.fused_nodal_stage(points, dt, start_weight, last);
        }
        let mut power = self.interface_fluxes(points);
        power += self.wave_corrections(points, dt);
        if self.ctu() {
            self.transverse_corrections(points, dt);
        }
        let force = self.boundary_force();
        self.nodal_rates(points);
        self.nodal_update(dt, start_weight);
        (power, force)
    }

    /// Phase 6 (J2 only): the return map at every point, the points' new stress being the
    /// elastic trial (`impact_core::plasticity::J2::correct_points`): the paper's elastic
    /// Riemann solver followed by a return mapping.
    fn plastic_correction(&self, points: &mut MaterialPoints<D>) {
        if let Some(j2) = &self.plastic {
            j2.correct_points(points, self.parallel);
        }
    }

    fn ctu(&self) -> bool {
        D > 1 && self.options.flux == TransverseFlux::Ctu
    }

    /// One step. Nodal paths: phase 1, then one `stage` (forward Euler) or two
    /// (Heun: `q¹ = q⁰ + Δt L(q⁰)`, `q = ½ q⁰ + ½ (q¹ + Δt L(q¹))`), then phase 5. Cell
    /// path: `interface_fluxes`, `transverse_corrections` (CTU), `boundary_force` and
    /// [`Self::cell_update`]. Adds the work and impulse of the loads to the state.
    ///
    /// Loads act at their step average `p ḡ`, `ḡ = (I(t + Δt) - I(t))/Δt`
    /// (`impact_core::load`), in the one stage of Euler and in both of Heun's: the boundary
    /// force times `Δt` is then the load's impulse over the step to round-off (Heun's
    /// `½Δt (F¹ + F²)` too), and at Courant 1 in 1D the boundary cell takes exactly the
    /// load's average over the step, as the exact solution's cell average does.
    pub fn step(&mut self, state: &mut DgmpmState<D>, t: f64, dt: f64) {
        self.set_load_window((t, t + dt));
        if self.path == StepPath::Fused {
            let (power, force) = self.fused_step(&mut state.points, dt);
            state.work += dt * power;
            state.impulse += force * dt;
            self.plastic_correction(&mut state.points);
            return;
        }
        if self.path == StepPath::Cell {
            let mut power = self.interface_fluxes(&state.points);
            power += self.wave_corrections(&state.points, dt);
            if self.ctu() {
                self.transverse_corrections(&state.points, dt);
            }
            let force = self.boundary_force();
            self.cell_update(&mut state.points, dt);
            state.work += dt * power;
            state.impulse += force * dt;
            self.plastic_correction(&mut state.points);
            self.move_points(&mut state.points, dt);
            return;
        }
        let fused = self.path == StepPath::FusedNodal;
        if !(fused && self.fused_nodal_single()) {
            // (RK2 at one point per cell on the fused sweep forms its nodes from the points)
            self.particles_to_nodes(&state.points);
        }
        let integrator = self.options.integrator;
        // (the fused nodal stages keep the start-of-step fields by swapping buffers)
        let keep_start =
            integrator == Integrator::Rk2 || self.options.update == PointUpdate::Increment;
        if keep_start && !fused {
            let nodes = &mut self.nodes;
            nodes.start_tensor.copy_from_slice(&nodes.tensor);
            nodes.start_velocity.copy_from_slice(&nodes.velocity);
        }
        if fused && self.heun_on_cells() {
            // Heun's two stages as cell sweeps (`fused/heun.rs`; they move the points)
            let [(power, force), (power2, force2)] = self.heun_step(&mut state.points, dt);
            state.work += 0.5 * dt * (power + power2);
            state.impulse += (force + force2) * (0.5 * dt);
            self.plastic_correction(&mut state.points);
            return;
        }
        let euler = integrator == Integrator::Euler;
        let (power, force) = self.stage(&mut state.points, dt, 0.0, euler);
        match integrator {
            Integrator::Euler => {
                state.work += dt * power;
                state.impulse += force * dt;
            }
            Integrator::Rk2 => {
                let (power2, force2) = self.stage(&mut state.points, dt, 0.5, true);
                state.work += 0.5 * dt * (power + power2);
                state.impulse += (force + force2) * (0.5 * dt);
            }
        }
        if !fused {
            // (the fused nodal sweep ran phase 5 and the move in its last stage)
            self.nodes_to_particles(&mut state.points);
        }
        self.plastic_correction(&mut state.points);
        if !fused {
            // (the fused nodal sweep and the Heun cell sweeps move them in their last stage)
            self.move_points(&mut state.points, dt);
        }
    }
}

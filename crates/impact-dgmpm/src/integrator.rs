//! Phases 3-4 and the step: nodal rates of the semi-discrete system (paper eq. 16), the
//! nodal update, and one [`DgmpmSolver::stage`] that forward Euler calls once and RK2
//! (Heun) twice.
use crate::{sym, DgmpmSolver, DgmpmState, Physics, StepPath, CHUNK, MAX_NODES};
use impact_core::method::{Integrator, PointUpdate, TransverseFlux};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

/// Cells per rayon leaf of the per-cell loops.
const CELL_GRAIN: usize = 512;

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 3: nodal rates `dq_i/dt`, `dv_i/dt` of every cell ([`Self::cell_rates_into`]).
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

    /// The nodal rates of cell `c` (module doc of the crate): the volume term on the points,
    /// with the nodal field interpolated there (paper eq. 14-15), and the face fluxes,
    /// `M_i dv_i/dt = -Σ_α V_α σ_h(X_α) ∇S_iα + Σ_f ∫_f S_i t*_out dΓ`,
    /// `(M_i/ρ) dσ_i/dt = C : [-Σ_α V_α sym(v_h(X_α) ⊗ ∇S_iα) + Σ_f ∫_f S_i sym(v* ⊗ n) dΓ]`;
    /// under Saint-Venant–Kirchhoff `Π(F_h)` replaces `σ_h` and `v_h ⊗ ∇S` (no `C :`) the
    /// strain rate (paper eq. 5-6).
    fn cell_rates_into(
        &self,
        c: usize,
        points: &MaterialPoints<D>,
        rq: &mut [Tensor<D>],
        rv: &mut [Vector<D>],
    ) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let (grid, nodes) = (&self.grid, &self.nodes);
        let mut volume_tensor = [Tensor::<D>::zeros(); MAX_NODES];
        let mut force = [Vector::<D>::zeros(); MAX_NODES];
        let cell_nodes = c * nodes_per_cell..(c + 1) * nodes_per_cell;
        let (nq, nv) = (
            &nodes.tensor[cell_nodes.clone()],
            &nodes.velocity[cell_nodes],
        );
        for p in c * self.points_per_cell..(c + 1) * self.points_per_cell {
            let s = &self.shape[p * nodes_per_cell..(p + 1) * nodes_per_cell];
            let g = &self.shape_gradient[p * nodes_per_cell..(p + 1) * nodes_per_cell];
            let mut qh = Tensor::<D>::zeros();
            let mut vh = Vector::<D>::zeros();
            for b in 0..nodes_per_cell {
                qh += nq[b] * s[b];
                vh += nv[b] * s[b];
            }
            let vol = points.volume[p];
            // the stress that acts: σ_h, or Π(F_h)
            let stress = match self.physics {
                Physics::Linear => qh,
                Physics::Svk { svk, .. } => svk.piola(&qh),
            };
            for a in 0..nodes_per_cell {
                volume_tensor[a] -= match self.physics {
                    Physics::Linear => sym(&vh, &g[a]),
                    Physics::Svk { .. } => vh * g[a].transpose(),
                } * vol;
                force[a] -= (stress * g[a]) * vol;
            }
        }
        let idx = grid.cell_multi_index(c);
        let mut tensor_flux = [Tensor::<D>::zeros(); MAX_NODES];
        for l in 0..D {
            let weight = grid.cell_volume() / grid.spacing[l] * 2.0 / nodes_per_cell as f64;
            // the high face is one l-stride of the l-face array further
            let low = Self::face_index(grid, l, idx);
            let stride: usize = grid.cells[..l].iter().product();
            for side in 0..2 {
                // outward flux F_n = sign · F_{e_l}; it leaves the cell
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let q = self.face_flux[l][low + side * stride];
                for a in (0..nodes_per_cell).filter(|a| (a >> l) & 1 == side) {
                    tensor_flux[a] -= q.tensor * (sign * weight);
                    force[a] -= q.momentum * (sign * weight);
                }
            }
        }
        let density = self.material.density;
        for a in 0..nodes_per_cell {
            let m = nodes.mass[c * nodes_per_cell + a];
            if m > 0.0 {
                let volume_part = match self.physics {
                    Physics::Linear => self.material.stress(&volume_tensor[a]),
                    Physics::Svk { .. } => volume_tensor[a],
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
        let b = 1.0 - start_weight;
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
                let q_next = *q + rq[i] * dt;
                let v_next = *v + rv[i] * dt;
                if start_weight == 0.0 {
                    *q = q_next;
                    *v = v_next;
                } else {
                    *q = q0[i] * start_weight + q_next * b;
                    *v = v0[i] * start_weight + v_next * b;
                }
            }
        });
    }

    /// One stage of the nodal paths: phase 2 (fluxes; 2b, CTU corrections), the boundary
    /// force, phase 3 (rates) and phase 4 (update with `start_weight`). Returns the power
    /// and force of the boundary conditions at the stage's state.
    fn stage(
        &mut self,
        points: &MaterialPoints<D>,
        dt: f64,
        start_weight: f64,
    ) -> (f64, Vector<D>) {
        let power = self.interface_fluxes(points);
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

    /// One step. Nodal paths: phase 1, then one [`Self::stage`] (forward Euler) or two
    /// (Heun: `q¹ = q⁰ + Δt L(q⁰)`, `q = ½ q⁰ + ½ (q¹ + Δt L(q¹))`), then phase 5. Cell
    /// path: `interface_fluxes`, `transverse_corrections` (CTU), `boundary_force` and
    /// [`Self::cell_update`]. Adds the work and impulse of the loads to the state.
    ///
    /// Loads act at their magnitude at the flux time: `t + Δt/2` for one stage (at Courant
    /// 1 in 1D the boundary cell then takes the load's average over the step to second
    /// order, as the exact solution's cell average does), `t` and `t + Δt` for Heun's two.
    pub fn step(&mut self, state: &mut DgmpmState<D>, t: f64, dt: f64) {
        if self.path == StepPath::Fused {
            self.set_load_time(t + 0.5 * dt);
            let (power, force) = self.fused_step(&mut state.points, dt);
            state.work += dt * power;
            state.impulse += force * dt;
            self.plastic_correction(&mut state.points);
            return;
        }
        if self.path == StepPath::Cell {
            self.set_load_time(t + 0.5 * dt);
            let power = self.interface_fluxes(&state.points);
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
        self.particles_to_nodes(&state.points);
        let integrator = self.options.integrator;
        if integrator == Integrator::Rk2 || self.options.update == PointUpdate::Increment {
            let nodes = &mut self.nodes;
            nodes.start_tensor.copy_from_slice(&nodes.tensor);
            nodes.start_velocity.copy_from_slice(&nodes.velocity);
        }
        let first_time = match integrator {
            Integrator::Euler => t + 0.5 * dt,
            Integrator::Rk2 => t,
        };
        self.set_load_time(first_time);
        let (power, force) = self.stage(&state.points, dt, 0.0);
        match integrator {
            Integrator::Euler => {
                state.work += dt * power;
                state.impulse += force * dt;
            }
            Integrator::Rk2 => {
                self.set_load_time(t + dt);
                let (power2, force2) = self.stage(&state.points, dt, 0.5);
                state.work += 0.5 * dt * (power + power2);
                state.impulse += (force + force2) * (0.5 * dt);
            }
        }
        self.nodes_to_particles(&mut state.points);
        self.plastic_correction(&mut state.points);
        self.move_points(&mut state.points, dt);
    }
}

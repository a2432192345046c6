//! The central-difference phases of the step (module doc of the crate): the loads at a
//! time, the nodal update with its prescribed velocities, the work of the loads, and the
//! step itself (two phases, or fused into one pass on the stencil path).
use crate::{FemSolver, FemState, CHUNK};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::Vector;

/// The central-difference update of one node: `v += Δt_avg a`, then `u += Δt v`. The one
/// place these operations are written, so the two-phase step, the fused pass and its halo
/// (`stencil.rs`) give the same bits.
#[inline]
pub(crate) fn advance_node<const D: usize>(
    u: &mut Vector<D>,
    v: &mut Vector<D>,
    a: &Vector<D>,
    (dt, dt_avg): (f64, f64),
) {
    *v += a * dt_avg;
    *u += *v * dt;
}

impl<const D: usize> FemSolver<D> {
    /// `f_ext` averaged over `window = (t0, t1)`: `Σ ḡ f` over the loaded nodes (the
    /// others stay zero), `ḡ` the step mean of `g` (`impact_core::load`; `g(t0)` for an
    /// empty window).
    pub fn set_load_window(&mut self, (t0, t1): (f64, f64)) {
        for &(node, _, _) in &self.loaded {
            self.external[node] = Vector::<D>::zeros();
        }
        for &(node, force, history) in &self.loaded {
            self.external[node] += force * history.mean(t0, t1);
        }
    }

    /// The central-difference update of the nodes, in one pass:
    /// `v^{n+1/2} = v^{n-1/2} + Δt_avg a^n` (`Δt_avg` the mean of the last and this step),
    /// `u^{n+1} = u^n + Δt v^{n+1/2}`. The prescribed velocity components take their mean
    /// over `[t, t + Δt]` first (their acceleration is zeroed, so the pass keeps them).
    /// Returns the work of the constraints' reactions and of the external forces,
    /// `Δt r · v_d + Δt f_ext · v^{n+1/2}`; adds the impulse of both to the state.
    pub fn nodal_update(&self, state: &mut FemState<D>, dt: f64, t: f64) -> f64 {
        let dt_avg = 0.5 * (state.last_dt + dt);
        let work = self.hold_velocities(state, dt, t);
        let acceleration = &state.acceleration;
        let parts = (
            chunks(&mut state.velocity_half, CHUNK),
            chunks(&mut state.displacement, CHUNK),
        );
        for_each_chunk(self.parallel, 1, parts, |r, (velocity, displacement)| {
            for (j, (v, u)) in velocity.iter_mut().zip(displacement.iter_mut()).enumerate() {
                advance_node(u, v, &acceleration[r * CHUNK + j], (dt, dt_avg));
            }
        });
        work + self.external_work(state, dt)
    }

    /// The loads' part of `a^n` becomes their mean over the velocity update's window
    /// `[t - Δt_{n-1}/2, t + Δt/2]` (it held the trailing half step's, crate doc; for a
    /// step load the two are both 1 and nothing changes). The prescribed velocity
    /// components of `v^{n+1/2}` take their mean over `[t, t + Δt]`, and their
    /// acceleration is zeroed (so the update keeps them); returns the work of the
    /// reactions, `Δt r · v_d`, and adds their impulse and the loads' to the state. On a
    /// slab every stored node is held, but only the owned ones count in the work and the
    /// impulse (each node once over the ranks).
    fn hold_velocities(&self, state: &mut FemState<D>, dt: f64, t: f64) -> f64 {
        let dt_avg = 0.5 * (state.last_dt + dt);
        let owns = |n: usize| self.place.owns_node(n);
        for &n in self.loaded_nodes.iter().filter(|&&n| owns(n)) {
            state.impulse += self.external[n] * dt_avg;
        }
        let trailing = (t - 0.5 * state.last_dt, t);
        let window = (trailing.0, t + 0.5 * dt);
        for &(node, force, history) in &self.loaded {
            let change = history.mean(window.0, window.1) - history.mean(trailing.0, trailing.1);
            if change != 0.0 {
                state.acceleration[node] += force * (change * self.inv_mass[node]);
                if owns(node) {
                    state.impulse += force * (change * dt_avg);
                }
            }
        }
        let mut work = 0.0;
        for c in &self.constraints {
            let (node, axis, value) = (c.carrier, c.axis, c.mean((t, t + dt)));
            // the velocity the update would give it, then the reaction that holds it
            let free = state.velocity_half[node][axis] + state.acceleration[node][axis] * dt_avg;
            let reaction = self.mass[node] * (value - free) / dt_avg;
            state.velocity_half[node][axis] = value;
            state.acceleration[node][axis] = 0.0;
            if owns(node) {
                work += dt * reaction * value;
                state.impulse[axis] += reaction * dt_avg;
            }
        }
        work
    }

    /// Work of the external forces over the step, `Δt f_ext · v^{n+1/2}` (`f_ext` is zero
    /// but at the loaded nodes), over the owned nodes.
    fn external_work(&self, state: &FemState<D>, dt: f64) -> f64 {
        let velocity = &state.velocity_half;
        (self.loaded_nodes.iter())
            .filter(|&&n| self.place.owns_node(n))
            .map(|&n| dt * self.external[n].dot(&velocity[n]))
            .sum()
    }

    /// One step (module doc) from `t^n = t` to `t^{n+1} = t + Δt`: the velocity update
    /// takes the loads' mean over `[t - Δt_{n-1}/2, t + Δt/2]`; the new acceleration takes
    /// their mean over the trailing half step `[t + Δt/2, t + Δt]`, and prescribed
    /// velocities their mean over `[t, t + Δt]` (crate doc). With the
    /// stencil, the nodal update and the internal force run in one pass
    /// (`Stencil::step_into` in `stencil.rs`) unless [`Self::set_fused_step`] turned it off.
    pub fn step(&mut self, state: &mut FemState<D>, t: f64, dt: f64) {
        match &self.stencil {
            Some(stencil) if self.fuse_step => {
                let dt_avg = 0.5 * (state.last_dt + dt);
                let work = self.hold_velocities(state, dt, t);
                let fields = (
                    &mut state.displacement[..],
                    &mut state.velocity_half[..],
                    &mut state.acceleration[..],
                );
                let bands = (&mut self.halo[..], self.band_layers);
                let times = (dt, dt_avg);
                stencil.step_into(fields, &self.inv_mass, times, bands, self.parallel);
                state.work += work + self.external_work(state, dt);
                self.set_load_window((t + 0.5 * dt, t + dt));
                self.add_loads_into(&mut state.acceleration);
            }
            _ => {
                state.work += self.nodal_update(state, dt, t);
                self.set_load_window((t + 0.5 * dt, t + dt));
                self.internal_forces_into(&state.displacement, &mut state.acceleration);
            }
        }
        state.last_dt = dt;
    }

    /// Bands of layers the fused step runs in parallel (1 where it runs serially; 0
    /// without the stencil).
    pub fn fused_bands(&self) -> usize {
        match &self.stencil {
            Some(stencil) => stencil.layers().div_ceil(self.band_layers),
            None => 0,
        }
    }

    /// Run the stencil path's step as its two phases (`false`: the reference the fused
    /// pass is tested against) or fused (`true`, the default).
    pub fn set_fused_step(&mut self, fused: bool) {
        self.fuse_step = fused;
    }
}

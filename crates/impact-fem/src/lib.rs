//! Explicit finite elements: multilinear elements on the body's regular mesh (2-node bars
//! in 1D, 4-node quadrilaterals with 2×2 Gauss points in 2D, 8-node hexahedra with 2×2×2
//! in 3D: `N_a(ξ) = Π_k (1 − ξ_k)^{1−a_k} ξ_k^{a_k}`, Gauss points `ξ_k = ½ ± 1/(2√3)`,
//! weights `V_e / 2^D`; Hughes 1987, §3.5), row-sum lumped mass and central differences.
//!
//! Central differences with the standard half-step start (Belytschko et al., *Nonlinear
//! Finite Elements*, Box 6.1):
//! With Saint-Venant–Kirchhoff the internal force is the total Lagrangian one,
//! `f_int,a = Σ_g w_g V_e Π(F_g) ∇N_a`, `F_g = 1 + Σ_b u_b ⊗ ∇N_b(ξ_g)`.
//!
//! `a^n = M⁻¹ (f_ext - f_int(u^n))`, `v^{n+1/2} = v^{n-1/2} + Δt_avg a^n` (first step:
//! `v^{1/2} = v^0 + Δt/2 a^0`), `u^{n+1} = u^n + Δt v^{n+1/2}`, with
//! `f_int,a = Σ_g w_g V_e σ_g ∇N_a(ξ_g)`, `σ_g = C : sym(∇u_g)`, `∇u_g = Σ_b u_b ⊗ ∇N_b(ξ_g)`.
//!
//! One step, one phase per function: [`FemSolver::nodal_update`] (the velocity and the
//! displacement in one pass over the nodes, the prescribed velocities set before it),
//! [`FemSolver::internal_forces_into`] (which already
//! prepares `a^{n+1}` for the next step, so the full-step velocity
//! `v^{n+1} = v^{n+1/2} + Δt/2 a^{n+1}` is available for output and energy). On the
//! stencil path (linear elasticity) the two phases run fused in one pass over the node
//! layers, the update one layer ahead of the force (`stencil.rs`, bit for bit the two
//! phases, which [`FemSolver::set_fused_step`] restores).
//!
//! Loads: a pressure is the consistent nodal force of the loaded edge (in 1D `p A` on the
//! end node); a prescribed velocity is imposed on the nodes of its edge segment (the
//! paper's plate: nodes with `y ≤ 1 m`); a symmetry edge zeroes the normal velocity.
//! Both act at their step averages (`impact_core::load`): the velocity update
//! `v^{n+1/2} = v^{n-1/2} + Δt_avg a^n` covers `[t^n - Δt_{n-1}/2, t^n + Δt_n/2]`, so
//! `a^n` takes the load's mean over that window (the impulse `p I(t^{n+1/2})` reaches
//! `v^{n+1/2}` to round-off), while `a^{n+1}` as the step leaves it holds the mean over
//! the trailing half step `[t^{n+1} - Δt_n/2, t^{n+1}]`, so the full-step velocity
//! `v^{n+1/2} + Δt_n/2 a^{n+1}` of the outputs has received `p I(t^{n+1})`; a prescribed
//! velocity takes its mean over `[t^n, t^{n+1}]`, the step `u^{n+1} - u^n = Δt v^{n+1/2}`
//! it sets.
//!
//! Layout: this file holds the solver and its coloured internal force; `build.rs` its
//! construction (lumped mass, shape gradients, initial state); `loads.rs` the boundary
//! loads and prescribed velocities; `central.rs` the central-difference phases and the
//! step; `method.rs` the `Method` impl; `stencil.rs` the internal force of linear
//! elasticity as a node stencil (the default there; the Gauss-point path stays the
//! reference it is tested against); `place.rs` where the stored mesh lies in the whole
//! one, and `slab.rs` the FEM on one rank's box of elements (issue 27).

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]
use impact_core::method::{MethodConfig, Model};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::{Constraint, Grid, LinearElastic, LoadHistory, Tensor, Vector};

mod build;
mod central;
mod loads;
mod method;
mod node_halo;
mod place;
mod plastic;
pub mod slab;
mod stencil;
pub use plastic::GaussPlasticity;

const MAX_NODES: usize = 8;
/// Nodes per chunk of the node loops.
const CHUNK: usize = 4096;

/// Nodal state of the FEM.
#[derive(Debug, Clone)]
pub struct FemState<const D: usize> {
    /// Displacement `u^n`.
    pub displacement: Vec<Vector<D>>,
    /// Mid-step velocity `v^{n-1/2}`.
    pub velocity_half: Vec<Vector<D>>,
    /// Acceleration `a^n` (of the current displacement).
    pub acceleration: Vec<Vector<D>>,
    /// Last step size (0 before the first step: half-step start).
    pub last_dt: f64,
    /// Work done by the loads.
    pub work: f64,
    /// Impulse of the loads and reactions, consistent with `Σ m v^{n+1/2}`.
    pub impulse: Vector<D>,
    /// Energy of the state at `t = 0` (J).
    pub initial_energy: f64,
}

/// Configuration and buffers of the explicit FEM.
#[derive(Debug, Clone)]
pub struct FemSolver<const D: usize> {
    config: MethodConfig,
    grid: Grid<D>,
    /// Where `grid` lies in the whole mesh and what of it this solver owns (`place.rs`).
    place: place::Place<D>,
    material: LinearElastic,
    model: Model,
    wave_speed: f64,
    mass: Vec<f64>,
    /// `1/m` per node (the stencil's acceleration multiplies by it).
    inv_mass: Vec<f64>,
    /// `f_ext` of the last [`FemSolver::set_load_window`].
    external: Vec<Vector<D>>,
    /// The loaded nodes' forces at full magnitude and their histories: `f_ext(t)` is
    /// `Σ g(t) f` over them.
    loaded: Vec<(usize, Vector<D>, LoadHistory)>,
    /// The loaded nodes, each once (the only ones where `f_ext` can be nonzero).
    loaded_nodes: Vec<usize>,
    /// Prescribed velocity components.
    constraints: Vec<Constraint>,
    /// Per node: 1 for a free component, 0 for a prescribed one.
    free_mask: Vec<Vector<D>>,
    force: Vec<Vector<D>>,
    parallel: bool,
    /// `∇N_a` at the Gauss points of an element (the mesh is regular): `gauss × 2^D`.
    gauss_gradient: Vec<Vector<D>>,
    gauss_weight: f64,
    /// `∇N_a` at the element centre.
    centre_gradient: [Vector<D>; MAX_NODES],
    /// J2 plasticity: stresses and history at the Gauss points (`plastic.rs`).
    plastic: Option<GaussPlasticity<D>>,
    /// Linear elasticity: the internal force as a node stencil (`stencil.rs`); `None`: the
    /// Gauss-point path.
    stencil: Option<stencil::Stencil<D>>,
    /// Whether the stencil path fuses the nodal update into the internal force
    /// ([`stencil::Stencil::step_into`]).
    fuse_step: bool,
    /// Layers per band of the fused step, and its halo buffer (two layers per band).
    band_layers: usize,
    halo: Vec<Vector<D>>,
}

/// Explicit FEM as a [`Method`](impact_core::Method).
#[derive(Debug, Clone)]
pub struct Fem<const D: usize> {
    /// Configuration and buffers.
    pub solver: FemSolver<D>,
    /// Nodal state.
    pub state: FemState<D>,
}

impl<const D: usize> FemSolver<D> {
    /// `f_int(u)` into the force buffer (module doc): each element adds
    /// `Σ_g w_g V_e σ_g ∇N_a(ξ_g)` to its nodes.
    ///
    /// The elements of layer `j` along the last axis write node layers `j` and `j + 1`
    /// only, so the even layers write disjoint bands of two node layers, and so do the odd
    /// ones: two colour passes, each over disjoint chunks of the force array (in parallel
    /// when worth it), with no partial sums, locks or unsafe code. Serial and parallel runs
    /// add in the same order, so their forces agree bit for bit.
    /// Then the acceleration `a = M⁻¹ (f_ext - f_int)` into `acceleration` (on the stencil
    /// path in the same pass, `-f_int/m`, then `+ f_ext/m` at the loaded nodes; the force
    /// itself is not stored there: [`Self::internal_force_at`]).
    pub fn internal_forces_into(
        &mut self,
        displacement: &[Vector<D>],
        acceleration: &mut [Vector<D>],
    ) {
        if let Some(stencil) = &self.stencil {
            let buffers = (&self.inv_mass[..], &mut acceleration[..]);
            stencil.accelerations_into(displacement, buffers, CHUNK, self.parallel);
            self.add_loads_into(acceleration);
            return;
        }
        self.gauss_forces_into(displacement);
        self.acceleration_into(acceleration);
    }

    /// `a += f_ext/m` at the loaded nodes (the stencil path writes `-f_int/m` only).
    fn add_loads_into(&self, acceleration: &mut [Vector<D>]) {
        for &n in &self.loaded_nodes {
            acceleration[n] += self.external[n] * self.inv_mass[n];
        }
    }

    /// The Gauss-point path of [`Self::internal_forces_into`] (force only).
    fn gauss_forces_into(&mut self, displacement: &[Vector<D>]) {
        self.update_gauss_stresses(displacement);
        let layer_nodes: usize = self.grid.cells[..D - 1].iter().map(|n| n + 1).product();
        let layer_elements: usize = self.grid.cells[..D - 1].iter().product();
        let layers = self.grid.cells[D - 1];
        let mut force = std::mem::take(&mut self.force);
        let grain = (CHUNK / (2 * layer_nodes)).max(1);
        for_each_chunk(self.parallel, 1, chunks(&mut force, CHUNK), |_, f| {
            f.iter_mut().for_each(|x| *x = Vector::<D>::zeros());
        });
        // the layers of even global index first, as on one rank (a box may start on an
        // odd one): each node adds its elements' forces in the same order (within a layer
        // the box keeps the global relative order, so no other axis needs a parity)
        for pass in 0..2 {
            let colour = (pass + self.place.first_layer()) % 2;
            let band = &mut force[colour * layer_nodes..];
            for_each_chunk(
                self.parallel,
                grain,
                chunks(band, 2 * layer_nodes),
                |r, f| {
                    let layer = colour + 2 * r;
                    if layer >= layers {
                        return;
                    }
                    let offset = layer * layer_nodes;
                    for c in layer * layer_elements..(layer + 1) * layer_elements {
                        self.element_forces_into(displacement, c, f, offset);
                    }
                },
            );
        }
        self.force = force;
    }

    /// The element stiffness `K_e[a * 2^D + b]`: the force of the Gauss-point path on
    /// local node `a` per unit displacement of local node `b` (column `j`: `u_b = e_j`),
    /// for a linear material.
    fn element_stiffness(&self) -> Vec<Tensor<D>> {
        let npc = Grid::<D>::NODES_PER_CELL;
        let volume = self.grid.cell_volume() * self.gauss_weight;
        let mut k = vec![Tensor::<D>::zeros(); npc * npc];
        for b in 0..npc {
            for j in 0..D {
                let unit = Vector::<D>::from_fn(|i, _| f64::from(u8::from(i == j)));
                for q in 0..npc {
                    let g = &self.gauss_gradient[q * npc..(q + 1) * npc];
                    let stress = self.stress_of(&(unit * g[b].transpose()));
                    for a in 0..npc {
                        let column = (stress * g[a]) * volume;
                        for i in 0..D {
                            k[a * npc + b][(i, j)] += column[i];
                        }
                    }
                }
            }
        }
        k
    }

    /// Take the Gauss-point path for the internal force (the reference the stencil is
    /// tested against; benchmarks).
    pub fn use_gauss_path(&mut self) {
        self.stencil = None;
        self.halo = Vec::new();
        self.force = vec![Vector::<D>::zeros(); self.mass.len()];
    }

    /// The internal force `f_int` at node `i` of the last [`Self::internal_forces_into`],
    /// which gave `acceleration`: the Gauss path's stored force, or on the stencil path
    /// `f_ext - m a` (equal to round-off).
    pub fn internal_force_at(&self, acceleration: &[Vector<D>], i: usize) -> Vector<D> {
        match self.stencil {
            Some(_) => self.external[i] - acceleration[i] * self.mass[i],
            None => self.force[i],
        }
    }

    /// Whether the internal force runs as a node stencil.
    pub fn uses_stencil(&self) -> bool {
        self.stencil.is_some()
    }

    /// Add the internal force of element `c` to `force`, which holds the nodes from
    /// `offset` on.
    #[inline]
    fn element_forces_into(
        &self,
        displacement: &[Vector<D>],
        c: usize,
        force: &mut [Vector<D>],
        offset: usize,
    ) {
        let npc = Grid::<D>::NODES_PER_CELL;
        let volume = self.grid.cell_volume() * self.gauss_weight;
        let nodes = self.element_nodes(c);
        for q in 0..npc {
            let g = &self.gauss_gradient[q * npc..(q + 1) * npc];
            let stress = match &self.plastic {
                Some(p) => p.points.stress[c * npc + q],
                None => self.stress_of(&Self::displacement_gradient(displacement, &nodes, g)),
            };
            for a in 0..npc {
                force[nodes[a] - offset] += (stress * g[a]) * volume;
            }
        }
    }

    /// The nodes of element `c` (local node `a` first `2^D` entries).
    #[inline]
    fn element_nodes(&self, c: usize) -> [usize; MAX_NODES] {
        let mut nodes = [0usize; MAX_NODES];
        for (a, n) in nodes.iter_mut().enumerate().take(Grid::<D>::NODES_PER_CELL) {
            *n = self.grid.vertex_of(c, a);
        }
        nodes
    }

    /// Displacement gradient `∇u = Σ_a u_a ⊗ ∇N_a` of the element with nodes `nodes`, with
    /// `gradients` the `∇N_a` at one point of the element (a Gauss point or the centre).
    #[inline]
    fn displacement_gradient(
        displacement: &[Vector<D>],
        nodes: &[usize; MAX_NODES],
        gradients: &[Vector<D>],
    ) -> Tensor<D> {
        let mut grad = Tensor::<D>::zeros();
        for (g, &n) in gradients.iter().zip(nodes) {
            grad += displacement[n] * g.transpose();
        }
        grad
    }

    /// Stress from the displacement gradient `∇u`: `C : sym(∇u)` or `Π(1 + ∇u)`.
    #[inline]
    fn stress_of(&self, grad: &Tensor<D>) -> Tensor<D> {
        match self.model {
            Model::LinearElastic | Model::J2(_) => {
                self.material.stress(&((grad + grad.transpose()) * 0.5))
            }
            Model::Svk(svk) => svk.piola(&(Tensor::<D>::identity() + grad)),
        }
    }

    /// Strain energy density from the displacement gradient.
    #[inline]
    fn energy_of(&self, grad: &Tensor<D>) -> f64 {
        match self.model {
            // J2: the energy reads the Gauss-point state instead (`Method::energy`)
            Model::LinearElastic | Model::J2(_) => self
                .material
                .energy_density(&self.material.stress(&((grad + grad.transpose()) * 0.5))),
            Model::Svk(svk) => svk.energy_density(&(Tensor::<D>::identity() + grad)),
        }
    }

    /// `a = M⁻¹ (f_ext - f_int)` from the force buffer: `-f_int/m` everywhere (bit for bit
    /// `(0 - f)/m` where no load acts), then the loaded nodes.
    fn acceleration_into(&self, acceleration: &mut [Vector<D>]) {
        for_each_chunk(self.parallel, 1, chunks(acceleration, CHUNK), |r, acc| {
            for (j, a) in acc.iter_mut().enumerate() {
                let i = r * CHUNK + j;
                *a = -self.force[i] / self.mass[i];
            }
        });
        self.loaded_accelerations(acceleration);
    }

    /// `a = (f_ext - f_int)/m` at the loaded nodes.
    fn loaded_accelerations(&self, acceleration: &mut [Vector<D>]) {
        for &n in &self.loaded_nodes {
            acceleration[n] = (self.external[n] - self.force[n]) / self.mass[n];
        }
    }

    /// Full-step velocity `v^{n} = v^{n-1/2} + Δt/2 a^n` of node `i`.
    #[inline]
    fn full_velocity(&self, state: &FemState<D>, i: usize) -> Vector<D> {
        // prescribed components of v^{n-1/2} already hold their value; the mask zeroes
        // their acceleration
        state.velocity_half[i]
            + state.acceleration[i].component_mul(&self.free_mask[i]) * (0.5 * state.last_dt)
    }

    /// Stress at the centre of element `c`.
    fn centre_stress(&self, state: &FemState<D>, c: usize) -> Tensor<D> {
        let npc = Grid::<D>::NODES_PER_CELL;
        if let Some(p) = &self.plastic {
            // the mean of the element's Gauss stresses
            return p.points.stress[c * npc..(c + 1) * npc]
                .iter()
                .fold(Tensor::<D>::zeros(), |sum, s| sum + s)
                / npc as f64;
        }
        let grad = Self::displacement_gradient(
            &state.displacement,
            &self.element_nodes(c),
            &self.centre_gradient[..npc],
        );
        self.stress_of(&grad)
    }

    /// The mesh.
    pub fn grid(&self) -> &Grid<D> {
        &self.grid
    }
}

impl<const D: usize> Fem<D> {
    /// Full-step nodal velocities (for output).
    pub fn nodal_velocities(&self) -> Vec<Vector<D>> {
        (0..self.state.displacement.len())
            .map(|i| self.solver.full_velocity(&self.state, i))
            .collect()
    }
}

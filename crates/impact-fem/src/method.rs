//! The [`Method`] impl of FEM: stepping, sampling at element centres, energy, momentum,
//! the stability guard's checks. Every sum, sample and check covers the owned nodes and
//! elements only (all of them on one rank; a box's own, `slab.rs`), at their places in the
//! whole mesh. The owned nodes and elements are runs of consecutive local indices (one run
//! on one rank and on slabs); a sum over them is the sum of each run's, in order.
use crate::{Fem, FemSolver};
use impact_core::method::{BadState, Method, MethodConfig, Model, Samples};
use impact_core::parallel::{first_failing, sum_over};
use impact_core::{Grid, Tensor, Vector};

impl<const D: usize> Method<D> for Fem<D> {
    fn config(&self) -> &MethodConfig {
        &self.solver.config
    }
    fn stable_dt(&self) -> f64 {
        self.solver.config.courant * self.solver.grid.min_spacing() / self.solver.wave_speed
    }
    fn step(&mut self, t: f64, dt: f64) {
        self.solver.step(&mut self.state, t, dt);
    }
    fn sample_into(&self, out: &mut Samples<D>) {
        out.clear();
        let grid = &self.solver.grid;
        let npc = Grid::<D>::NODES_PER_CELL;
        for c in self.solver.place.owned_element_iter() {
            let centre = self.solver.place.element_centre(c);
            let mut u = Vector::<D>::zeros();
            let mut v = Vector::<D>::zeros();
            for a in 0..npc {
                let i = grid.vertex_of(c, a);
                u += self.state.displacement[i] / npc as f64;
                v += self.solver.full_velocity(&self.state, i) / npc as f64;
            }
            out.reference.push(centre);
            out.position.push(centre + u);
            out.half_size.push(grid.spacing * 0.5);
            out.stress.push(self.solver.centre_stress(&self.state, c));
            out.velocity.push(v);
            if let Some(p) = &self.solver.plastic {
                // element means of the Gauss points' ε̄ and σ_zz
                let g = c * npc..(c + 1) * npc;
                let mean = |f: &dyn Fn(usize) -> f64| g.clone().map(f).sum::<f64>() / npc as f64;
                out.plastic_strain
                    .push(mean(&|i| p.points.equivalent_plastic_strain[i]));
                if D == 2 {
                    out.stress_zz.push(mean(&|i| {
                        p.j2.out_of_plane(p.points.stress[i].trace(), p.points.plastic_strain_zz[i])
                    }));
                }
            }
        }
    }
    fn energy(&self) -> f64 {
        let s = &self.solver;
        let npc = Grid::<D>::NODES_PER_CELL;
        let over_owned = |term: &(dyn Fn(usize) -> f64 + Sync)| {
            (s.place.owned_nodes.iter()).fold(0.0, |sum, run| {
                sum + sum_over(run.len(), |k| term(run.start + k))
            })
        };
        let kinetic =
            over_owned(&|i| 0.5 * s.mass[i] * s.full_velocity(&self.state, i).norm_squared());
        let volume = s.grid.cell_volume() * s.gauss_weight;
        if let Some(p) = &s.plastic {
            // elastic energy of the stored Gauss stresses plus the plastic work
            let g = &p.points;
            let stored: f64 = (s.place.owned_element_iter())
                .flat_map(|c| c * npc..(c + 1) * npc)
                .map(|i| {
                    p.j2.elastic_energy_density(&g.stress[i], g.plastic_strain_zz[i])
                        + g.plastic_work[i]
                })
                .sum();
            return kinetic + volume * stored;
        }
        if s.uses_stencil() {
            // linear elasticity: Σ_e Σ_g w_g V_e ½ σ_g : ε_g = ½ uᵀ K u = ½ Σ_n u_n · f_int,n,
            // the same quadrature, with f_int of the current displacement (every step ends
            // computing it)
            let (u, a) = (&self.state.displacement, &self.state.acceleration);
            let strain_energy = over_owned(&|i| 0.5 * u[i].dot(&s.internal_force_at(a, i)));
            return kinetic + strain_energy;
        }
        let mut strain_energy = 0.0;
        for c in s.place.owned_element_iter() {
            let nodes = s.element_nodes(c);
            for q in 0..npc {
                let g = &s.gauss_gradient[q * npc..(q + 1) * npc];
                let grad = FemSolver::displacement_gradient(&self.state.displacement, &nodes, g);
                strain_energy += volume * s.energy_of(&grad);
            }
        }
        kinetic + strain_energy
    }
    fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    /// `Σ m_i v_i^{n-1/2}`: central differences conserve the mid-step momentum exactly.
    fn momentum(&self) -> Vector<D> {
        let s = &self.solver;
        s.place
            .owned_node_iter()
            .fold(Vector::<D>::zeros(), |m, i| {
                m + self.state.velocity_half[i] * s.mass[i]
            })
    }
    fn external_impulse(&self) -> Vector<D> {
        self.state.impulse
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let state = &self.state;
        let finite = |i: usize| {
            state.displacement[i].iter().all(|x| x.is_finite())
                && state.velocity_half[i].iter().all(|x| x.is_finite())
        };
        let place = &self.solver.place;
        for run in &place.owned_nodes {
            if let Some(k) = first_failing(run.len(), |k| finite(run.start + k)) {
                return Err(BadState {
                    place: place.node_position(run.start + k),
                    reason: "non-finite displacement or velocity at a node".into(),
                });
            }
        }
        if let Model::Svk(svk) = self.solver.model {
            let npc = Grid::<D>::NODES_PER_CELL;
            for c in place.owned_element_iter() {
                let grad = FemSolver::displacement_gradient(
                    &self.state.displacement,
                    &self.solver.element_nodes(c),
                    &self.solver.centre_gradient[..npc],
                );
                let f = Tensor::<D>::identity() + grad;
                if !svk.admissible(&f, self.solver.wave_speed) {
                    return Err(BadState {
                        place: place.element_centre(c),
                        reason: impact_core::material::Svk::inadmissible_reason(&f),
                    });
                }
            }
        }
        Ok(())
    }
    fn hottest_place(&self) -> Vector<D> {
        self.hottest_owned()
            .map_or_else(|| self.solver.place.node_position(0), |(_, x)| x)
    }
    /// Every stored node, by its global index and place.
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let place = &self.solver.place;
        for i in 0..self.state.velocity_half.len() {
            let x = place.node_position(i);
            self.state.velocity_half[i] += kick(place.global_node(i), &x);
        }
    }
    fn cells(&self) -> usize {
        self.solver.grid.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.solver.grid.cell_count()
    }
    /// The owned elements' nodes (every node on one rank), in order: the owned nodes and
    /// the halo layer above a cut, whose state is its owner's (received after each step,
    /// `slab.rs`), so the same bits as the owner's and one rank's.
    fn piece_nodal_fields(&self) -> Option<(Vec<Vector<D>>, Vec<Vector<D>>)> {
        let nodes = || self.solver.place.piece_node_iter();
        let velocity = nodes()
            .map(|i| self.solver.full_velocity(&self.state, i))
            .collect();
        let displacement = nodes().map(|i| self.state.displacement[i]).collect();
        Some((velocity, displacement))
    }
}

impl<const D: usize> Fem<D> {
    /// The owned node of the largest `|v^{n-1/2}|` (the last of equals), its speed and
    /// its place; `None` without owned nodes.
    pub fn hottest_owned(&self) -> Option<(f64, Vector<D>)> {
        let v = &self.state.velocity_half;
        let place = &self.solver.place;
        (place.owned_node_iter())
            .max_by(|&a, &b| v[a].norm().total_cmp(&v[b].norm()))
            .map(|i| (v[i].norm(), place.node_position(i)))
    }
}

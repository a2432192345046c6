//! DGMPM as a [`Method`].
use crate::{Dgmpm, Physics};
use impact_core::material::Svk;
use impact_core::method::{BadState, Method, MethodConfig, Samples};
use impact_core::parallel::first_failing;
use impact_core::Vector;

impl<const D: usize> Method<D> for Dgmpm<D> {
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
        self.state
            .points
            .sample_runs_into(self.owned_point_runs(), out);
        if let Some(j2) = &self.solver.plastic {
            let zz = &self.state.points.plastic_strain_zz;
            let runs = &self.solver.place.owned_cell_runs;
            if let [run] = runs.as_slice() {
                // one run (one rank, a slab): no copy
                let n = self.solver.points_per_cell;
                j2.samples_zz(out, &zz[run.start * n..run.end * n]);
            } else {
                let own_zz: Vec<f64> = (self.owned_point_runs())
                    .flat_map(|r| zz[r].iter().copied())
                    .collect();
                j2.samples_zz(out, &own_zz);
            }
        }
    }
    fn energy(&self) -> f64 {
        let p = &self.state.points;
        let m = &self.solver.material;
        // a run per row of own cells, added in order (one run on one rank)
        let mut runs = self.owned_point_runs();
        let first = runs.next().unwrap_or(0..0);
        let energy_in = |run: std::ops::Range<usize>| {
            if let Some(j2) = &self.solver.plastic {
                // elastic energy and the plastic work (dissipated and stored in hardening)
                return p.energy_in(run, |i| {
                    j2.elastic_energy_density(&p.stress[i], p.plastic_strain_zz[i])
                        + p.plastic_work[i]
                });
            }
            // (the physics chosen once per run of points, not per point)
            match self.solver.physics {
                Physics::Linear => p.energy_in(run, |i| m.energy_density(&p.stress[i])),
                Physics::Svk { svk, .. } => {
                    p.energy_in(run, |i| svk.energy_density(&p.deformation[i]))
                }
            }
        };
        runs.fold(energy_in(first), |sum, run| sum + energy_in(run))
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }
    fn momentum(&self) -> Vector<D> {
        let p = &self.state.points;
        let mut runs = self.owned_point_runs();
        let first = p.momentum_in(runs.next().unwrap_or(0..0));
        runs.fold(first, |sum, run| sum + p.momentum_in(run))
    }
    fn external_impulse(&self) -> Vector<D> {
        self.state.impulse
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let p = &self.state.points;
        // every component finite (`MaterialPoints::first_non_finite`: without a branch per
        // component) and, Saint-Venant–Kirchhoff, an admissible deformation
        let finite = |i: usize| p.values_finite(i, false);
        let first_in = |own: std::ops::Range<usize>| match self.solver.physics {
            Physics::Linear => p.first_non_finite(own, false),
            Physics::Svk { svk, .. } => first_failing(own.len(), |j| {
                let i = own.start + j;
                finite(i) && svk.admissible(&p.deformation[i], self.solver.wave_speed)
            }),
        };
        let Some(i) = self
            .owned_point_runs()
            .find_map(|own| first_in(own.clone()).map(|j| own.start + j))
        else {
            return Ok(());
        };
        let reason = match self.solver.physics {
            _ if finite(i) => Svk::inadmissible_reason(&p.deformation[i]),
            Physics::Linear => "non-finite stress or velocity at a material point".into(),
            Physics::Svk { .. } => "non-finite state at a material point: no admissible Riemann \
                                    state (Saint-Venant-Kirchhoff hyperbolicity lost at F = 1/√3)"
                .into(),
        };
        Err(BadState {
            place: p.reference[i],
            reason,
        })
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.state.points;
        (p.hottest_in(self.owned_point_runs().flatten()))
            .map_or_else(Vector::<D>::zeros, |i| p.reference[i])
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        self.state.points.perturb_velocity(kick);
    }
    fn cells(&self) -> usize {
        self.solver.grid.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.solver.grid.cell_count()
    }
}

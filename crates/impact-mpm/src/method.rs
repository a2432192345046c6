//! MPM as a [`Method`].
use crate::Mpm;
use impact_core::method::{BadState, Method, MethodConfig, Model, MpmFrame, Samples};
use impact_core::parallel::first_failing;
use impact_core::Vector;

impl<const D: usize> Method<D> for Mpm<D> {
    fn config(&self) -> &MethodConfig {
        &self.solver.config
    }
    fn stable_dt(&self) -> f64 {
        self.solver.config.courant * self.solver.body.min_spacing() / self.solver.wave_speed
    }
    fn step(&mut self, t: f64, dt: f64) {
        self.solver.step(&mut self.state, t, dt);
    }
    fn sample_into(&self, out: &mut Samples<D>) {
        let runs = self.owned_point_runs();
        let points = &self.state.points;
        points.sample_runs_into(runs.iter().cloned(), out);
        if let Model::J2(j2) = &self.solver.model {
            let zz = &points.plastic_strain_zz;
            if let [run] = runs {
                // one run (one rank, a slab): no copy
                j2.samples_zz(out, &zz[run.clone()]);
            } else {
                let own_zz: Vec<f64> = runs.iter().flat_map(|r| zz[r.clone()].to_vec()).collect();
                j2.samples_zz(out, &own_zz);
            }
        }
    }
    fn energy(&self) -> f64 {
        let p = &self.state.points;
        let m = &self.solver.material;
        // (the model chosen once per run of points, not per point)
        let energy_in = |run: std::ops::Range<usize>| match self.solver.model {
            Model::LinearElastic => p.energy_in(run, |i| m.energy_density(&p.stress[i])),
            Model::Svk(svk) => p.energy_in(run, |i| svk.energy_density(&p.deformation[i])),
            Model::J2(j2) => p.energy_in(run, |i| {
                j2.elastic_energy_density(&p.stress[i], p.plastic_strain_zz[i]) + p.plastic_work[i]
            }),
        };
        // a run per row of own cells, added in order (one run on one rank)
        let mut runs = self.owned_point_runs().iter().cloned();
        let first = energy_in(runs.next().unwrap_or(0..0));
        runs.fold(first, |sum, run| sum + energy_in(run))
    }
    fn initial_energy(&self) -> f64 {
        self.state.initial_energy
    }
    fn external_work(&self) -> f64 {
        self.state.work
    }
    fn momentum(&self) -> Vector<D> {
        let p = &self.state.points;
        let mut runs = self.owned_point_runs().iter().cloned();
        let first = p.momentum_in(runs.next().unwrap_or(0..0));
        runs.fold(first, |sum, run| sum + p.momentum_in(run))
    }
    fn external_impulse(&self) -> Vector<D> {
        self.state.impulse
    }
    fn check_finite(&self) -> Result<(), BadState<D>> {
        // Total Lagrangian and not Saint-Venant–Kirchhoff: a point fails only by a
        // non-finite value (`MaterialPoints::first_non_finite` alone); otherwise every check of
        // `point_failure`. Its reason is formed for the first failing point only.
        let only_values = self.solver.options.frame == MpmFrame::TotalLagrangian
            && !matches!(self.solver.model, Model::Svk(_));
        let first_in = |own: &std::ops::Range<usize>| {
            let failing = if only_values {
                self.state.points.first_non_finite(own.clone(), true)
            } else {
                first_failing(own.len(), |j| self.point_failure(own.start + j).is_none())
            };
            failing.map(|j| own.start + j)
        };
        let first = self.owned_point_runs().iter().find_map(first_in);
        first
            .and_then(|i| self.point_failure(i))
            .map_or(Ok(()), Err)
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.state.points;
        p.hottest_in(self.owned_point_runs().iter().cloned().flatten())
            .map_or_else(Vector::<D>::zeros, |i| p.reference[i])
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        self.state.points.perturb_velocity(kick);
    }
    fn cells(&self) -> usize {
        self.solver.body.cell_count()
    }
    fn updates_per_step(&self) -> usize {
        self.owned_point_runs().iter().map(|r| r.len()).sum()
    }
}

impl<const D: usize> Mpm<D> {
    /// What is wrong with point `i`, if anything: a non-finite stress, velocity or
    /// position, an inadmissible deformation (Saint-Venant–Kirchhoff), or (updated frame)
    /// a stencil that left the background grid.
    pub(crate) fn point_failure(&self, i: usize) -> Option<BadState<D>> {
        let p = &self.state.points;
        let finite = p.values_finite(i, true);
        let admissible = || match self.solver.model {
            Model::Svk(svk) => svk.admissible(&p.deformation[i], self.solver.wave_speed),
            _ => true,
        };
        let moving = self.solver.options.frame == MpmFrame::UpdatedLagrangian;
        // the stencil, not just the point: a smooth stencil needs nodes around it
        let fits = || {
            !moving
                || match p.domain.get(i) {
                    Some(domain) => {
                        self.solver
                            .stencil
                            .fits_domain(&self.solver.grid, &p.position[i], domain)
                    }
                    None => self.solver.stencil.fits(&self.solver.grid, &p.position[i]),
                }
        };
        let reason = if !finite {
            "non-finite stress, velocity or position at a material point".into()
        } else if !admissible() {
            impact_core::material::Svk::inadmissible_reason(&p.deformation[i])
        } else if !fits() {
            format!(
                "material point's stencil left the background grid (x = {:?})",
                p.position[i].as_slice()
            )
        } else {
            return None;
        };
        Some(BadState {
            place: p.reference[i],
            reason,
        })
    }

    /// The points this solver owns, a run per row of own cells in order: all of them on
    /// one rank, a slab's own layers' points (one run), a box's own rows (`crate::slab`);
    /// the diagnostics and samples cover these.
    pub fn owned_point_runs(&self) -> &[std::ops::Range<usize>] {
        &self.solver.place.owned_runs
    }

    /// The points this solver owns where they are one run (one rank, a slab, the migrating
    /// slab of `crate::migrate`): from the first own point to the last.
    pub fn owned_points(&self) -> std::ops::Range<usize> {
        let runs = self.owned_point_runs();
        let start = runs.first().map_or(0, |r| r.start);
        start..runs.last().map_or(start, |r| r.end)
    }
}

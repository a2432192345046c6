//! The travelling oblique plane wave (issue 24; scenes `oblique-wave`, 3D, and
//! `oblique-plate-wave`, 2D; exact solution `impact_core::exact::PlaneWave`, whose unit
//! tests check it against the equations of motion by finite differences): the boundaries
//! never reach the clean interior the errors are measured in, and DGMPM CTU converges at
//! first order on it (`impact bench convergence --scene oblique-wave`).
use crate::common::{measured, order, Error};
use impact_core::controller;
use impact_core::method::{MethodConfig, Samples};
use impact_core::{Method, Problem, Scene};

/// 3D, 8³ to 64³ cells: DGMPM CTU (Euler, Courant 1) at first order in σ_xx and v_x.
#[test]
fn ctu_converges_at_first_order_on_the_oblique_wave_in_3d() {
    let ctu = "dgmpm euler ctu 1ppc C1.0";
    let runs = measured::<3>("oblique-wave", &[ctu], 4);
    let pairs: [(Error, &str); 2] = [(|e| e.l2_stress, "L2 σ"), (|e| e.l2_velocity, "L2 v")];
    for (error, name) in pairs {
        let o = order(&runs, ctu, error);
        assert!((0.9..1.4).contains(&o), "DGMPM CTU {name}: order {o}");
    }
}

/// 2D, 32² to 256² cells: DGMPM CTU and donor-cell at first order, FEM at second.
#[test]
fn orders_on_the_oblique_wave_in_2d() {
    let (ctu, dcu, fem) = (
        "dgmpm euler ctu 1ppc C1.0",
        "dgmpm euler dcu 1ppc C0.6",
        "fem C0.9",
    );
    let runs = measured::<2>("oblique-plate-wave", &[ctu, dcu, fem], 4);
    let pairs: [(Error, &str); 2] = [(|e| e.l2_stress, "L2 σ"), (|e| e.l2_velocity, "L2 v")];
    for (error, name) in pairs {
        for label in [ctu, dcu] {
            let o = order(&runs, label, error);
            assert!((0.9..1.4).contains(&o), "{label} {name}: order {o}");
        }
        let o = order(&runs, fem, error);
        assert!((1.9..2.2).contains(&o), "FEM {name}: order {o}");
    }
}

/// The samples of `config` on `scene` at its last output time, and the steps taken.
fn final_state<const D: usize>(scene: &Scene, config: MethodConfig) -> (Samples<D>, usize) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut method = impact::build(&problem, config).unwrap();
    let mut samples = Samples::<D>::default();
    let mut taken = 0;
    let last = problem.output_times.len() - 1;
    controller::run::<D, dyn Method<D>, String>(
        method.as_mut(),
        &problem.output_times,
        impact::run::guard_for(&problem),
        |m, index, _, steps| {
            if index == last {
                m.sample_into(&mut samples);
                taken = steps;
            }
            Ok(())
        },
        |_| {},
    )
    .unwrap();
    (samples, taken)
}

/// The margin rule of `impact_core::interior` holds: with free faces and with symmetry
/// faces every sample of the clean interior is the same to round-off, in every method
/// (DGMPM donor-cell and CTU with Euler, CTU with RK2, MPM with hats, FEM), while samples
/// next to the faces differ (the boundaries do act).
fn boundaries_stay_out_of_the_interior<const D: usize>(name: &str, cells: usize) {
    let text = impact_core::scene::builtin(name).unwrap();
    let mut free = Scene::from_toml(text, name).unwrap();
    free.domain.cells = vec![cells; D];
    let held = text.replace("kind = \"free\"", "kind = \"symmetry\"");
    assert_ne!(held, text);
    let mut symmetry = Scene::from_toml(&held, name).unwrap();
    symmetry.domain.cells = vec![cells; D];
    let problem = Problem::<D>::from_scene(&free).unwrap();
    let mut configs = vec![free.method_config(impact_core::MethodKind::Fem)];
    configs.push(free.method_config(impact_core::MethodKind::Mpm));
    use impact_core::method::{Integrator, TransverseFlux};
    for (integrator, flux, courant) in [
        (Integrator::Euler, TransverseFlux::Ctu, 1.0),
        (Integrator::Euler, TransverseFlux::DonorCell, 0.45),
        (Integrator::Rk2, TransverseFlux::Ctu, 0.6),
    ] {
        let mut c = free.method_config(impact_core::MethodKind::Dgmpm);
        c.courant = courant;
        let o = c.dgmpm_mut().unwrap();
        (o.integrator, o.flux) = (integrator, flux);
        configs.push(c);
    }
    for config in configs {
        let (a, steps) = final_state::<D>(&free, config);
        let (b, _) = final_state::<D>(&symmetry, config);
        let inside = impact_core::interior::Interior::after(&problem.grid, &config, steps)
            .expect("the scene keeps a clean interior");
        let scale = a.stress.iter().fold(0.0f64, |m, s| m.max(s.amax()));
        let (mut clean, mut differ) = (0, 0);
        for i in 0..a.len() {
            let gap = (a.stress[i] - b.stress[i]).amax();
            let gap_v = (a.velocity[i] - b.velocity[i]).amax();
            if inside.holds(&a.reference[i], &a.half_size[i]) {
                clean += 1;
                assert!(
                    gap <= 1e-12 * scale && gap_v <= 1e-12,
                    "{config:?}: sample at {:?} in the clean interior moved by {gap:e} Pa",
                    a.reference[i]
                );
            } else if gap > 1e-6 * scale {
                differ += 1;
            }
        }
        assert!(
            clean > 0 && differ > 0,
            "{config:?}: {clean} clean, {differ} differ"
        );
    }
}

#[test]
fn boundaries_stay_out_of_the_clean_interior_2d() {
    boundaries_stay_out_of_the_interior::<2>("oblique-plate-wave", 64);
}

#[test]
fn boundaries_stay_out_of_the_clean_interior_3d() {
    boundaries_stay_out_of_the_interior::<3>("oblique-wave", 24);
}

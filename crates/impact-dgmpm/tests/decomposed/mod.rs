//! What the decomposed DGMPM tests share (`slab.rs`, `boxes.rs`): a run on thread ranks
//! split as a rank grid says, compared with the one-rank run. (Each test file uses part.)
#![allow(dead_code)]
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::method::{MethodConfig, MethodKind};
use impact_core::slab_method::RunEnd;
use impact_core::{Problem, Scene};
use impact_dgmpm::slab::SlabDgmpm;
use impact_dgmpm::Dgmpm;

pub fn scene(name: &str) -> Scene {
    Scene::builtin(name).unwrap()
}

/// The one-rank run and each of `ranks` thread ranks' run split as `grid` says, `n` steps.
pub fn runs<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    grid: &RankGrid,
    ranks: usize,
    n: usize,
) -> (RunEnd<D>, Vec<RunEnd<D>>) {
    let serial = RunEnd::after_steps(&mut Dgmpm::<D>::new(problem, config).unwrap(), n);
    let ends = ThreadComm::on_ranks(ranks, |comm| {
        let mut m = SlabDgmpm::<D>::on_grid(problem, config, comm, grid).unwrap();
        RunEnd::after_steps(&mut m, n)
    });
    (serial, ends)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// `scene` (its DGMPM configuration changed by `edit`) on each of `grids` (rank grid, rank
/// count) against the serial run after 40 steps: the gathered fields exactly (`exact`) or
/// to 1e-13 of their peaks, in the global point order; sums to 1e-12.
pub fn check_on<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    exact: bool,
    grids: &[(RankGrid, usize)],
) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    edit(&mut config);
    for (grid, ranks) in grids {
        let label = format!("{label}, rank grid {:?} on {ranks} ranks", grid.0);
        let (serial, ends) = runs::<D>(&problem, config, grid, *ranks, 40);
        compare(&label, &serial, &ends, exact);
    }
}

fn compare<const D: usize>(label: &str, serial: &RunEnd<D>, ends: &[RunEnd<D>], exact: bool) {
    let s = &serial.samples;
    let peak_s = s.stress.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let peak_v = s.velocity.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    assert!(
        peak_s > 1e5 && peak_v > 1e-3,
        "{label}: the wave must be there"
    );
    let owned: usize = ends.iter().map(|e| e.owned.len()).sum();
    assert_eq!(owned, s.len(), "{label}: every point owned once");
    for (rank, end) in ends.iter().enumerate() {
        let e = &end.samples;
        assert_eq!(e.len(), s.len(), "{label}, rank {rank}");
        assert_eq!(e.reference, s.reference, "{label}: reference positions");
        if exact {
            assert_eq!(e.stress, s.stress, "{label}: stress bit for bit");
            assert_eq!(e.velocity, s.velocity, "{label}: velocity");
            assert_eq!(e.position, s.position, "{label}: position");
            assert_eq!(
                e.plastic_strain, s.plastic_strain,
                "{label}: plastic strain"
            );
            assert_eq!(e.stress_zz, s.stress_zz, "{label}: out-of-plane stress");
        } else {
            for i in 0..s.len() {
                assert!(
                    (e.stress[i] - s.stress[i]).amax() <= 1e-13 * peak_s,
                    "{label}"
                );
                assert!(
                    (e.velocity[i] - s.velocity[i]).amax() <= 1e-13 * peak_v,
                    "{label}"
                );
            }
        }
        let tol = 1e-12;
        assert!(relative(end.energy, serial.energy) < tol, "{label}: energy");
        assert!(
            relative(end.work, serial.work) < tol,
            "{label}: work {} {}",
            end.work,
            serial.work
        );
        let p = serial.momentum.norm().max(serial.impulse.norm());
        assert!(
            (end.momentum - serial.momentum).norm() <= tol * p,
            "{label}: momentum"
        );
        assert!(
            (end.impulse - serial.impulse).norm() <= tol * p,
            "{label}: impulse"
        );
    }
}

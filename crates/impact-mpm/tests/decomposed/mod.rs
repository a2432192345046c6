//! What the decomposed MPM tests share (`slab.rs`, `boxes.rs`): a run on thread ranks split
//! as a rank grid says, compared with the one-rank run. (Each test file uses part.)
#![allow(dead_code)]
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::method::{MethodConfig, MethodKind, MpmOptions};
use impact_core::slab_method::{assert_matches_serial, owned_in_rank_order, slab_grids, RunEnd};
use impact_core::{Problem, Scene};
use impact_mpm::slab::SlabMpm;
use impact_mpm::Mpm;

pub fn scene(name: &str) -> Scene {
    Scene::builtin(name).unwrap()
}

pub fn options(c: &mut MethodConfig) -> &mut MpmOptions {
    c.mpm_mut().unwrap()
}

/// `problem` under `config` on each of `grids` (rank grid, rank count) against the serial
/// run after `n` steps: the gathered fields bit for bit in the global point order, every
/// point owned once (on slabs: the own samples in rank order are the whole body's); the
/// global sums to 1e-12 (rank-order sums; `assert_matches_serial`).
pub fn check<const D: usize>(
    label: &str,
    problem: &Problem<D>,
    config: MethodConfig,
    grids: &[(RankGrid, usize)],
    n: usize,
) {
    let serial = RunEnd::after_steps(&mut Mpm::<D>::new(problem, config).unwrap(), n);
    for (grid, ranks) in grids {
        let label = format!("{label}, rank grid {:?} on {ranks} ranks", grid.0);
        let ends = ThreadComm::on_ranks(*ranks, |comm| {
            let mut m = SlabMpm::<D>::on_grid(problem, config, comm, grid).unwrap();
            RunEnd::after_steps(&mut m, n)
        });
        assert_matches_serial(&label, &serial, &ends, true);
        if grid.is_slabs(D) {
            let owned: Vec<_> = ends.iter().map(|e| &e.owned).collect();
            assert!(
                owned_in_rank_order(&owned, &serial.samples),
                "{label}: the own samples in rank order are not the whole body's"
            );
        }
    }
}

/// `scene`'s MPM configuration edited by `edit`, on `grids`, over 40 steps.
pub fn check_scene<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    grids: &[(RankGrid, usize)],
) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    edit(&mut config);
    check::<D>(label, &problem, config, grids, 40);
}

/// Slabs (the automatic rank grid) on 1 to 4 ranks.
pub fn slabs() -> Vec<(RankGrid, usize)> {
    slab_grids(4)
}

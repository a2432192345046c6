//! What the decomposed DGMPM tests share (`slab.rs`, `boxes.rs`): a run on thread ranks
//! split as a rank grid says, compared with the one-rank run. (Each test file uses part.)
#![allow(dead_code)]
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::method::{MethodConfig, MethodKind};
use impact_core::slab_method::{assert_matches_serial, RunEnd};
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
        assert_matches_serial(&label, &serial, &ends, exact);
    }
}

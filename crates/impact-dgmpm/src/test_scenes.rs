//! Solvers for the unit tests of the edge pieces: the partial-patch scenes of
//! `benchmarks/compare/scenes/` (every kind of edge condition, traction corners) in both
//! edge treatments.
use crate::Dgmpm;
use impact_core::method::{EdgeTreatment, MethodKind};
use impact_core::{Problem, Scene};

/// `check(edges, dgmpm)` on each partial-patch scene's DGMPM in each edge treatment, its
/// loads averaged over a window of the sine and ramp histories (7-9 µs).
pub(crate) fn for_partial_edge_scenes(mut check: impl FnMut(EdgeTreatment, &Dgmpm<2>)) {
    let scenes = [
        include_str!("../../../benchmarks/compare/scenes/edges-partial-a.toml"),
        include_str!("../../../benchmarks/compare/scenes/edges-partial-b.toml"),
    ];
    for text in scenes {
        let scene = Scene::from_toml(text, "test").unwrap();
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        for edges in [EdgeTreatment::Restricted, EdgeTreatment::Ghost] {
            let mut config = scene.method_config(MethodKind::Dgmpm);
            config.dgmpm_mut().unwrap().edges = edges;
            let mut dgmpm = Dgmpm::new(&problem, config).unwrap();
            dgmpm.solver.set_load_window((7e-6, 9e-6));
            check(edges, &dgmpm);
        }
    }
}

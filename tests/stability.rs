//! Stability limits: empirical (perturbed runs, bisection) against von Neumann (the
//! program's amplification matrices), and the paper's qualitative claims (§5.1: more points
//! per cell lower the Courant limit with Euler; RK2 raises it back).
use impact::stability::{empirical_limit, free_edge_limit, von_neumann_limit};
use impact_core::method::{Integrator, MethodConfig, MethodKind, TransverseFlux};
use impact_core::{Problem, Scene};

fn bar() -> (Scene, Problem<1>) {
    let scene = Scene::builtin("bar").unwrap();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    (scene, problem)
}

fn plate() -> (Scene, Problem<2>) {
    let mut scene = Scene::builtin("plate-wave").unwrap();
    scene.domain.cells = vec![16, 12];
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    (scene, problem)
}

fn dgmpm(scene: &Scene, ppc: usize, integrator: Integrator, flux: TransverseFlux) -> MethodConfig {
    let mut c = scene.method_config(MethodKind::Dgmpm);
    c.points_per_cell = ppc;
    let o = c.dgmpm_mut().unwrap();
    (o.integrator, o.flux) = (integrator, flux);
    c
}

#[test]
fn one_point_per_cell_euler_is_stable_up_to_courant_one_in_1d() {
    let (scene, problem) = bar();
    let c = dgmpm(&scene, 1, Integrator::Euler, TransverseFlux::DonorCell);
    let (e, v) = (
        empirical_limit(&problem, c, 20000),
        von_neumann_limit(&problem, c, 256),
    );
    println!("1D 1 ppc Euler: empirical {e:.4}, von Neumann {v:.4}");
    assert!((e - 1.0).abs() <= 0.01 && (v - 1.0).abs() <= 0.01);
}

#[test]
fn ctu_one_point_per_cell_is_stable_up_to_courant_one_in_2d() {
    let (scene, problem) = plate();
    let c = dgmpm(&scene, 1, Integrator::Euler, TransverseFlux::Ctu);
    let (e, v) = (
        empirical_limit(&problem, c, 3000),
        von_neumann_limit(&problem, c, 24),
    );
    println!("2D 1 ppc CTU: empirical {e:.4}, von Neumann {v:.4}");
    assert!((e - 1.0).abs() <= 0.01 && (v - 1.0).abs() <= 0.01);
    // donor-cell's limit is far lower (von Neumann)
    let d = von_neumann_limit(
        &problem,
        dgmpm(&scene, 1, Integrator::Euler, TransverseFlux::DonorCell),
        24,
    );
    println!("2D 1 ppc DCU: von Neumann {d:.4}");
    assert!(d < 0.75);
    // free edges (and the corners where two meet) keep the limit at 1
    let f = free_edge_limit(&problem, c, 3000);
    println!("2D 1 ppc CTU, free edges: empirical {f:.4}");
    assert!((f - 1.0).abs() <= 0.01, "free edges: {f}");
}

/// Every 1D layout and integrator: the empirical and von Neumann limits agree within 3 %,
/// and the paper's claims hold: with Euler the limit falls as points are added; RK2 brings
/// it back to about 1.
#[test]
fn empirical_and_von_neumann_limits_agree_in_1d_and_follow_the_paper() {
    let (scene, problem) = bar();
    let mut euler = Vec::new();
    for ppc in 1..=4 {
        for integrator in [Integrator::Euler, Integrator::Rk2] {
            let c = dgmpm(&scene, ppc, integrator, TransverseFlux::DonorCell);
            let (e, v) = (
                empirical_limit(&problem, c, 20000),
                von_neumann_limit(&problem, c, 256),
            );
            println!(
                "1D {ppc} ppc {}: empirical {e:.4}, von Neumann {v:.4}",
                integrator.name()
            );
            assert!(
                (e - v).abs() <= 0.03 * v,
                "{ppc} ppc {integrator:?}: {e} vs {v}"
            );
            match integrator {
                Integrator::Euler => euler.push(v),
                Integrator::Rk2 => assert!(v > 0.98, "RK2 {ppc} ppc: {v}"),
            }
        }
    }
    for w in euler.windows(2) {
        assert!(
            w[1] < w[0],
            "Euler limits must fall with points per cell: {euler:?}"
        );
    }
    assert!(euler[1] < 0.75, "{euler:?}");
}

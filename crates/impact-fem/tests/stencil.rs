//! The node stencil of linear elasticity (`stencil.rs`) against the Gauss-point path it
//! replaces: the same internal force at every node (on the stencil path `-m a`, from the
//! acceleration it writes), edges and corners included, to 1e-13 of the largest force, in
//! 1D (one slab and several), in 2D, on a strip one element wide, and in 3D (27 points).
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene, Vector};
use impact_fem::Fem;

/// A reproducible displacement field in (-1, 1) mm (a linear congruential sequence).
fn displacement<const D: usize>(nodes: usize) -> Vec<Vector<D>> {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 1e-3
    };
    (0..nodes)
        .map(|_| Vector::<D>::from_fn(|_, _| next()))
        .collect()
}

fn compare<const D: usize>(name: &str, cells: Vec<usize>) {
    let mut scene = Scene::builtin(name).unwrap();
    scene.domain.cells = cells.clone();
    compare_scene::<D>(&scene);
}

fn compare_scene<const D: usize>(scene: &Scene) {
    let (name, cells) = (&scene.name, &scene.domain.cells);
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let config = scene.method_config(MethodKind::Fem);
    assert_eq!(problem.grid.cells.to_vec(), *cells);
    let mut stencil = Fem::<D>::new(&problem, config).unwrap();
    assert!(stencil.solver.uses_stencil());
    let mut gauss = stencil.clone();
    gauss.solver.use_gauss_path();
    let u = displacement::<D>(problem.grid.vertex_count());
    let (mut acc_stencil, mut acc_gauss) = (u.clone(), u.clone());
    stencil.solver.internal_forces_into(&u, &mut acc_stencil);
    gauss.solver.internal_forces_into(&u, &mut acc_gauss);
    let force = |fem: &Fem<D>, acc: &[Vector<D>]| -> Vec<Vector<D>> {
        (0..acc.len())
            .map(|i| fem.solver.internal_force_at(acc, i))
            .collect()
    };
    let (a, b) = (force(&stencil, &acc_stencil), force(&gauss, &acc_gauss));
    // the acceleration fused into the stencil's pass is the Gauss path's
    let acc_scale = acc_gauss.iter().map(|f| f.amax()).fold(0.0, f64::max);
    let acc_worst = acc_stencil
        .iter()
        .zip(&acc_gauss)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    assert!(
        acc_worst <= 1e-13 * acc_scale,
        "{name}: acceleration {acc_worst} vs {acc_scale}"
    );
    let scale = b.iter().map(|f| f.amax()).fold(0.0, f64::max);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    println!(
        "{name} {cells:?}: largest difference {:.2e} of the largest force",
        worst / scale
    );
    assert!(
        scale > 0.0 && worst <= 1e-13 * scale,
        "{name} {cells:?}: {worst} vs {scale}"
    );
}

#[test]
fn the_stencil_gives_the_gauss_point_force_at_every_node() {
    compare::<1>("bar", vec![9]);
    // 1,201 nodes: slabs of 512 nodes (the 1D interior loop), the last one shorter
    compare::<1>("bar", vec![1200]);
    compare::<2>("plate-wave", vec![7, 5]);
    compare::<2>("plate-wave", vec![6, 1]);
    compare::<2>("plate-wave", vec![1, 4]);
    // 101 × 61 nodes: the chunks of 4096 nodes end inside a row (node 4096 is column 56)
    compare::<2>("plate-wave", vec![100, 60]);
}

/// A 3D block (hex8, 2×2×2 Gauss points; the 27-point stencil): a partial impact on one
/// face, symmetry and free faces, unequal spacings; blocks one element thick along each
/// axis in turn; and 21 × 13 × 11 nodes, whose chunks of 4096 nodes end inside a layer.
#[test]
fn the_3d_stencil_gives_the_gauss_point_force_at_every_node() {
    for cells in [
        [5, 4, 3],
        [1, 3, 2],
        [3, 1, 2],
        [3, 2, 1],
        [1, 1, 1],
        [20, 12, 10],
    ] {
        let text = format!(
            "name = \"block\"\ndim = 3\n[domain]\nlength = [2.0, 1.5, 1.0]\ncells = {cells:?}\n\
             [material]\nmodel = \"linear-elastic\"\nyoung = 2.0e11\npoisson = 0.3\n\
             density = 7800.0\n[boundary]\n\
             x.low = {{ kind = \"normal-velocity\", value = 5.0, from = [0.0, 0.0], to = [1.0, 0.6] }}\n\
             y.low = {{ kind = \"symmetry\" }}\nz.high = {{ kind = \"symmetry\" }}\n\
             [time]\noutput_transits = [4]\n"
        );
        compare_scene::<3>(&Scene::from_toml(&text, "3D stencil test").unwrap());
    }
}

/// Saint-Venant–Kirchhoff and J2 keep the Gauss-point path.
#[test]
fn nonlinear_models_keep_the_gauss_path() {
    for name in ["svk-bar", "ep-bar"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        let fem = Fem::<1>::new(&problem, scene.method_config(MethodKind::Fem)).unwrap();
        assert!(!fem.solver.uses_stencil(), "{name}");
    }
}

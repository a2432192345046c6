//! The coloured scatter's sums against the points' order (`transfer.rs`).
use crate::Mpm;
use impact_core::method::MethodKind;
use impact_core::{Method, Problem, Scene};

/// MPM (the defaults) on the built-in plate with `cells`, after `steps` steps.
fn stepped_plate(cells: Vec<usize>, steps: usize) -> Mpm<2> {
    let mut scene = Scene::builtin("plate").unwrap();
    scene.domain.cells = cells;
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let mut mpm = Mpm::<2>::new(&problem, scene.method_config(MethodKind::Mpm)).unwrap();
    let dt = mpm.stable_dt();
    for n in 0..steps {
        mpm.step(n as f64 * dt, dt);
    }
    mpm
}

/// The coloured scatter reads the points of each layer through `layer_order` unless
/// they are in it already: an order reversed within every layer gives the sums of the
/// points' own order to round-off (2 threads, the parallel passes).
#[test]
fn scatter_sums_do_not_depend_on_the_order_within_a_layer() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        let mut own = stepped_plate(vec![80, 60], 5);
        assert!(own.solver.parallel && own.solver.in_layer_order);
        let mut reversed = own.clone();
        let solver = &mut reversed.solver;
        solver.in_layer_order = false;
        solver.layer_order = (0..own.state.points.len()).collect();
        for layer in solver.layer_start.windows(2) {
            solver.layer_order[layer[0]..layer[1]].reverse();
        }
        assert!(solver.layer_order[0] != 0);
        own.solver
            .particles_to_grid(&own.state.points, &own.state.affine, true);
        reversed
            .solver
            .particles_to_grid(&reversed.state.points, &reversed.state.affine, true);
        let (a, b) = (&own.solver.nodes, &reversed.solver.nodes);
        let peak = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let force: Vec<f64> = a.force.iter().map(|f| f.amax()).collect();
        let momentum: Vec<f64> = a.momentum.iter().map(|p| p.amax()).collect();
        let (mass_scale, force_scale) = (peak(&a.mass), peak(&force));
        let momentum_scale = peak(&momentum);
        assert!(
            force_scale > 0.0 && momentum_scale > 0.0,
            "the wave must be there"
        );
        for i in 0..a.mass.len() {
            assert!((a.mass[i] - b.mass[i]).abs() <= 1e-14 * mass_scale);
            assert!((a.force[i] - b.force[i]).amax() <= 1e-13 * force_scale);
            assert!((a.momentum[i] - b.momentum[i]).amax() <= 1e-13 * momentum_scale);
        }
    });
}

/// The nodal velocity the grid update stores is the product the gathers formed per
/// node-point pair before, `p_i (1/m_i)`, bit for bit on every node, the constrained ones
/// included (the plate's velocity edge sets momentum components after the node pass).
#[test]
fn nodal_velocity_is_the_momentum_times_the_inverse_mass() {
    let mpm = stepped_plate(vec![40, 30], 3);
    let solver = &mpm.solver;
    assert!(
        !solver.node_constraints.is_empty(),
        "the plate's edges hold nodes"
    );
    let nodes = &solver.nodes;
    assert!(
        (solver.node_constraints.iter())
            .any(|c| nodes.momentum[c.carrier][c.axis] == c.value * nodes.mass[c.carrier]),
        "a node with mass whose momentum component the constraints set"
    );
    for i in 0..nodes.mass.len() {
        let product = nodes.momentum[i] * nodes.inv_mass[i];
        assert_eq!(
            nodes.velocity[i].map(f64::to_bits),
            product.map(f64::to_bits),
            "node {i}"
        );
    }
}

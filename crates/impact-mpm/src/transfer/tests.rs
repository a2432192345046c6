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
        // the masses added again in the new order, not the kept sums of the old one
        solver.nodes.point_mass_ready = false;
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
/// node-point pair before, `p_i (1/m_i)`, and the increment is `f_i (Δt (1/m_i))`, bit
/// for bit on every node, the constrained ones included (the plate's velocity edge sets
/// momentum components after the node pass, and their reactions to the force).
#[test]
fn nodal_velocity_and_increment_are_the_grid_update_products() {
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
    let dt = mpm.stable_dt();
    assert_eq!(nodes.increment_dt, dt);
    for i in 0..nodes.mass.len() {
        let m = nodes.mass[i];
        let inv = if solver.empty.holds(i, m) {
            1.0 / m
        } else {
            0.0
        };
        let product = nodes.momentum[i] * inv;
        assert_eq!(
            nodes.velocity[i].map(f64::to_bits),
            product.map(f64::to_bits),
            "node {i}"
        );
        let increment = nodes.force[i] * (dt * inv);
        assert_eq!(
            nodes.increment[i].map(f64::to_bits),
            increment.map(f64::to_bits),
            "node {i}"
        );
    }
}

/// The plate at 40 × 30 cells, quadratic B-splines at 4 points per cell (the table of
/// distinct rows of weights), after 5 steps.
fn stepped_bspline_plate() -> Mpm<2> {
    let mut scene = Scene::builtin("plate").unwrap();
    scene.domain.cells = vec![40, 30];
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    config.points_per_cell = 4;
    config.mpm_mut().unwrap().shape = impact_core::method::MpmShape::Bspline2;
    let mut mpm = Mpm::<2>::new(&problem, config).unwrap();
    let dt = mpm.stable_dt();
    for n in 0..5 {
        mpm.step(n as f64 * dt, dt);
    }
    mpm
}

/// The FLIP gather interpolates the nodal increments, `v_p += Σ_i N_ip Δv_i` with
/// `Δv_i = f_i (Δt (1/m_i))` formed per node, where it formed `f_i (N_ip Δt (1/m_i))` per
/// node-point pair before: the same sum in another rounding, to 1e-13 of the largest
/// term's size. B-splines at 4 points per cell (the table of rows), after the grid update
/// of a stepped plate, against that per-pair sum formed here from `f_i` and `m_i`.
#[test]
fn flip_gather_of_the_increments_is_the_per_pair_sum() {
    let mut mpm = stepped_bspline_plate();
    let dt = mpm.stable_dt();
    let (solver, state) = (&mut mpm.solver, &mut mpm.state);
    assert!(solver.weight_rows().1, "the table of distinct rows");
    solver.particles_to_grid(&state.points, &state.affine, true);
    solver.grid_update(dt, (5.0 * dt, 6.0 * dt));
    let before = state.points.clone();
    solver.grid_to_particles(&mut state.points, &mut state.affine, dt);
    let nodes = &solver.nodes;
    let mut peak = 0.0_f64;
    for p in 0..before.len() {
        let start = solver.weight_row_start(p);
        let mut dv = impact_core::Vector::<2>::zeros();
        let mut largest = 0.0_f64;
        for a in 0..solver.stencil.nodes {
            let i = solver.point_base[p] + solver.stencil.offsets[a];
            let m = nodes.mass[i];
            let inv = if solver.empty.holds(i, m) {
                1.0 / m
            } else {
                0.0
            };
            let term = nodes.force[i] * (solver.shape[start + a] * dt * inv);
            largest = largest.max(term.amax());
            dv += term;
        }
        let (expected, got) = (before.velocity[p] + dv, state.points.velocity[p]);
        assert!(
            (expected - got).amax() <= 1e-13 * (largest + before.velocity[p].amax()),
            "point {p}: {expected:?} against {got:?}"
        );
        peak = peak.max(largest);
    }
    assert!(peak > 0.0, "the wave must be there");
}

/// Phase 1 after the first step copies the kept mass sums (`NodeSums::point_mass`) where
/// it added `N_ip m_p` again before: the nodal masses, momenta and forces are those of a
/// scatter that adds the masses, bit for bit, on a stepped plate (B-splines at 4 points
/// per cell through the table, one pass; hats on 2 threads, the colour passes).
#[test]
fn kept_mass_sums_are_the_scattered_ones() {
    let same_sums = |mpm: &Mpm<2>| {
        let mut own = mpm.clone();
        assert!(own.solver.nodes.point_mass_ready, "kept after a step");
        let mut summed = mpm.clone();
        summed.solver.nodes.point_mass_ready = false;
        for m in [&mut own, &mut summed] {
            (m.solver).particles_to_grid(&m.state.points, &m.state.affine, true);
        }
        let (a, b) = (&own.solver.nodes, &summed.solver.nodes);
        let bits = |v: &[impact_core::Vector<2>]| -> Vec<u64> {
            v.iter()
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .collect()
        };
        let mass_bits = |v: &[f64]| -> Vec<u64> { v.iter().map(|x| x.to_bits()).collect() };
        assert_eq!(mass_bits(&a.mass), mass_bits(&b.mass));
        assert_eq!(bits(&a.momentum), bits(&b.momentum));
        assert_eq!(bits(&a.force), bits(&b.force));
        assert!(a.mass.iter().any(|&m| m > 0.0) && a.force.iter().any(|f| f.amax() > 0.0));
    };
    let pool = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    };
    pool(1).install(|| {
        let mpm = stepped_bspline_plate();
        assert!(mpm.solver.weight_rows().1 && !mpm.solver.parallel);
        same_sums(&mpm);
    });
    pool(2).install(|| {
        let hats = stepped_plate(vec![80, 60], 5);
        assert!(hats.solver.parallel);
        same_sums(&hats);
    });
}

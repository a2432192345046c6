//! Phase 1 (`particles_to_nodes`) equals the per-node formula
//! `M_i = Σ_α S_iα m_α`, `q_i = Σ_α S_iα m_α q_α / M_i` (paper eq. 17), each sum taken
//! node by node in point order: point by point (`cell_sums`) bit for bit, and with the
//! mapping weights `W_αi = S_iα m_α / M_i` (`layouts::cell_mapping_weights`) the masses
//! bit for bit and the fields to round-off (the division by `M_i` comes before the sum, so each term is
//! rounded once more: 1e-13 of the peak is checked, a few 1e-16 measured): 1D with 3 points
//! per cell, 2D with 4 and 9, 3D with 8, on states a few steps into a loaded run (so every
//! point differs).
use crate::layouts::{Blocks, CellLayouts};
use crate::{Dgmpm, StepPath};
use impact_core::method::MethodKind;
use impact_core::{Grid, Method, Problem, Scene, Tensor, Vector};

/// The per-node formula: for each node, its sums over the cell's points in point order.
fn reference<const D: usize>(dgmpm: &Dgmpm<D>) -> (Vec<f64>, Vec<Tensor<D>>, Vec<Vector<D>>) {
    let (solver, points) = (&dgmpm.solver, &dgmpm.state.points);
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let per_cell = solver.points_per_cell;
    let cells = points.len() / per_cell;
    let (mut mass, mut tensor, mut velocity) = (Vec::new(), Vec::new(), Vec::new());
    for c in 0..cells {
        for a in 0..nodes_per_cell {
            let mut m = 0.0;
            let mut q = Tensor::<D>::zeros();
            let mut v = Vector::<D>::zeros();
            let shape = solver.layouts.shape(c);
            for p in c * per_cell..(c + 1) * per_cell {
                let k = p - c * per_cell;
                let w = shape[k * nodes_per_cell + a] * points.mass[p];
                m += w;
                q += points.stress[p] * w;
                v += points.velocity[p] * w;
            }
            mass.push(m);
            tensor.push(if m > 0.0 { q / m } else { Tensor::<D>::zeros() });
            velocity.push(if m > 0.0 { v / m } else { Vector::<D>::zeros() });
        }
    }
    (mass, tensor, velocity)
}

/// The builtin scene `name` on `cells` at `points_per_cell`, Courant 0.5, six steps into
/// its loaded run (so every point differs), the wave checked to be there.
pub(super) fn loaded<const D: usize>(
    name: &str,
    cells: &[usize],
    points_per_cell: usize,
) -> Dgmpm<D> {
    let mut scene = Scene::builtin(name).unwrap();
    scene.domain.cells = cells.to_vec();
    let problem = Problem::<D>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    config.points_per_cell = points_per_cell;
    config.courant = 0.5;
    let mut dgmpm = Dgmpm::<D>::new(&problem, config).unwrap();
    let dt = dgmpm.stable_dt();
    for n in 0..6 {
        dgmpm.step(n as f64 * dt, dt);
    }
    let (peak_s, peak_v) = dgmpm.state.points.peaks();
    assert!(
        peak_s > 0.0 && peak_v > 0.0,
        "{name}: the wave must be there"
    );
    dgmpm
}

/// The largest difference of `a` and `b` over the largest entry of `b`.
fn relative<T: Copy>(a: &[T], b: &[T], amax: impl Fn(T) -> f64, diff: impl Fn(T, T) -> T) -> f64 {
    let peak = b.iter().map(|&x| amax(x)).fold(0.0, f64::max);
    assert!(peak > 0.0);
    let worst = a.iter().zip(b).map(|(&x, &y)| amax(diff(x, y)));
    worst.fold(0.0, f64::max) / peak
}

fn check<const D: usize>(name: &str, cells: &[usize], points_per_cell: usize) {
    let mut dgmpm = loaded::<D>(name, cells, points_per_cell);
    assert_ne!(dgmpm.solver.step_path(), StepPath::SinglePoint);
    assert!(dgmpm.solver.layouts.has_mapping(), "{name}: weights");
    let (mass, tensor, velocity) = reference(&dgmpm);
    // with the mapping weights (the step's phase 1)
    dgmpm.solver.nodes.tensor.fill(Tensor::<D>::zeros());
    dgmpm.solver.nodes.velocity.fill(Vector::<D>::zeros());
    dgmpm.solver.particles_to_nodes(&dgmpm.state.points);
    let nodes = &dgmpm.solver.nodes;
    let cells = mass.len() / Grid::<D>::NODES_PER_CELL;
    let masses: Vec<f64> = (0..cells)
        .flat_map(|c| {
            dgmpm
                .solver
                .layouts
                .mass_of(dgmpm.solver.layouts.layout_of(c))
                .to_vec()
        })
        .collect();
    assert_eq!(masses, mass, "{name}: nodal masses");
    let tensor_error = relative(&nodes.tensor, &tensor, |t| t.amax(), |x, y| x - y);
    let velocity_error = relative(&nodes.velocity, &velocity, |v| v.amax(), |x, y| x - y);
    println!("{name} {points_per_cell} ppc: weights against the sums {tensor_error:.1e} (stress), {velocity_error:.1e} (velocity) of the peak");
    assert!(
        tensor_error <= 1e-13,
        "{name}: nodal stresses {tensor_error:e}"
    );
    assert!(
        velocity_error <= 1e-13,
        "{name}: nodal velocities {velocity_error:e}"
    );
    // point by point (without the weights): bit for bit
    let blocks = dgmpm.solver.layouts.blocks().unwrap();
    let (grid, points) = (&dgmpm.solver.grid, &dgmpm.state.points);
    let without = Blocks {
        mapping: false,
        ..blocks
    };
    dgmpm.solver.layouts = CellLayouts::new(grid, points, points_per_cell, without).unwrap();
    dgmpm.solver.nodes.mass = vec![0.0; mass.len()];
    dgmpm.solver.particles_to_nodes(&dgmpm.state.points);
    let nodes = &dgmpm.solver.nodes;
    assert_eq!(nodes.mass, mass, "{name}: nodal masses");
    assert_eq!(nodes.tensor, tensor, "{name}: nodal stresses");
    assert_eq!(nodes.velocity, velocity, "{name}: nodal velocities");
}

#[test]
fn phase_1_point_by_point_equals_the_per_node_sums() {
    check::<1>("bar", &[40], 3);
    check::<2>("plate", &[12, 9], 4);
    check::<2>("plate", &[9, 7], 9);
    check::<3>("block", &[6, 4, 4], 8);
}

/// Phase 5's sums start from `-0` (module doc of `mapping.rs`): bit for bit the sums from
/// `+0` whenever a term is not `-0`, and `-0` (equal under `==`) where every term is.
#[test]
fn phase_5_sums_from_minus_zero_equal_the_sums_from_zero() {
    use super::point_from_nodes;
    let shapes = [0.125, 0.375, 0.375, 0.125];
    let tensors: Vec<Tensor<2>> = (0..4)
        .map(|a| Tensor::<2>::from_fn(|i, j| (a as f64 - 1.5) * 1e6 + (i * 2 + j) as f64 * 0.1))
        .collect();
    let velocities: Vec<Vector<2>> = (0..4)
        .map(|a| Vector::<2>::new(a as f64 - 2.0, 0.0))
        .collect();
    let (q, v) = point_from_nodes(&shapes, (&tensors, &velocities), None);
    let (mut q0, mut v0) = (Tensor::<2>::zeros(), Vector::<2>::zeros());
    for a in 0..4 {
        q0 += tensors[a] * shapes[a];
        v0 += velocities[a] * shapes[a];
    }
    let bits = |x: &[f64]| x.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(q.as_slice()), bits(q0.as_slice()), "stress");
    assert_eq!(
        bits(v.as_slice()),
        bits(v0.as_slice()),
        "velocity (y: +0 terms)"
    );
    // every term -0: the sum is -0, the sum from +0 is +0
    let negative = vec![Vector::<2>::from_element(-0.0); 4];
    let (_, v) = point_from_nodes(&shapes, (&tensors, &negative), None);
    assert!(
        v[0] == 0.0 && v[0].is_sign_negative(),
        "all -0 terms: {}",
        v[0]
    );
}

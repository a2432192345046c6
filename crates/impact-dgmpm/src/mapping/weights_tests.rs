//! The volume term from the cells' weights `K_ab = Σ_α V_α S_bα ∇S_aα`
//! ([`crate::layouts::cell_volume_weights`]) equals the per-point form
//! `-Σ_α V_α σ_h(X_α) ∇S_aα`, `-Σ_α V_α v_h(X_α) ⊗ ∇S_aα` to round-off (1e-13 of the
//! largest rate: the sums are associated differently), on the nodal rates of every cell a
//! few steps into a loaded run: 1D with 2 and 3 points per cell, 2D with 4 and 9, 3D
//! with 8. Only the volume term differs between the two, so the face fluxes are zero.
use crate::layouts::{Blocks, CellLayouts};
use crate::riemann::Conserved;
use crate::Dgmpm;
use impact_core::{Grid, Tensor, Vector};

/// Every cell's nodal rates (zero face fluxes) of `dgmpm`'s solver as it is.
fn rates<const D: usize>(dgmpm: &Dgmpm<D>) -> (Vec<Tensor<D>>, Vec<Vector<D>>) {
    let (solver, points) = (&dgmpm.solver, &dgmpm.state.points);
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let nodes = &solver.nodes;
    let zero = Conserved::<D>::zeros();
    let faces = [[&zero; 2]; D];
    let cells = points.len() / solver.points_per_cell;
    let mut rq = vec![Tensor::<D>::zeros(); cells * nodes_per_cell];
    let mut rv = vec![Vector::<D>::zeros(); cells * nodes_per_cell];
    for c in 0..cells {
        let range = c * nodes_per_cell..(c + 1) * nodes_per_cell;
        let nodal = (
            &nodes.tensor[range.clone()],
            &nodes.velocity[range.clone()],
            solver.cell_masses(c, &nodes.mass),
        );
        let out = (&mut rq[range.clone()], &mut rv[range]);
        solver.rates_of_cell(c, &points.volume, nodal, faces, out);
    }
    (rq, rv)
}

fn check<const D: usize>(name: &str, cells: &[usize], points_per_cell: usize) {
    let mut dgmpm = super::tests::loaded::<D>(name, cells, points_per_cell);
    let label = format!("{name}, {points_per_cell} points per cell");
    let takes = points_per_cell >= Grid::<D>::NODES_PER_CELL;
    let blocks = dgmpm.solver.layouts.blocks().unwrap();
    assert_eq!(blocks.volume, takes, "{label}");
    assert_eq!(blocks.gradient, !takes, "{label}");
    dgmpm.solver.particles_to_nodes(&dgmpm.state.points);
    let (wq, wv) = rates(&dgmpm);
    // the same solver with the points' gradients and without the weights
    let mut per_point = dgmpm.clone();
    let per_point_blocks = Blocks {
        gradient: true,
        volume: false,
        ..blocks
    };
    let (grid, points) = (&per_point.solver.grid, &per_point.state.points);
    per_point.solver.layouts =
        CellLayouts::new(grid, points, points_per_cell, per_point_blocks).unwrap();
    let (pq, pv) = rates(&per_point);
    let peak_q = pq.iter().map(|q| q.amax()).fold(0.0, f64::max);
    let peak_v = pv.iter().map(|v| v.amax()).fold(0.0, f64::max);
    assert!(peak_q > 0.0 && peak_v > 0.0, "{label}: rates must be there");
    let worst_q = wq
        .iter()
        .zip(&pq)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    let worst_v = wv
        .iter()
        .zip(&pv)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    let worst = (worst_q / peak_q).max(worst_v / peak_v);
    println!("{label}: rates differ by {worst:.1e} of their peak");
    assert!(worst <= 1e-13, "{label}: {worst:e}");
}

#[test]
fn volume_weights_match_the_points() {
    check::<1>("bar", &[40], 2);
    check::<1>("bar", &[40], 3);
    check::<2>("plate", &[12, 9], 4);
    check::<2>("plate", &[9, 7], 9);
    check::<3>("block", &[6, 4, 4], 8);
}

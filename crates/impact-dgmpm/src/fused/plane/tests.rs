//! The fused 2D sweeps' edge pieces against the general functions they stand in for.
use crate::faces::Fields;
use crate::riemann::Conserved;
use crate::test_scenes::for_partial_edge_scenes;
use impact_core::{Tensor, Vector};

/// On every boundary face of scenes whose partial patches give every kind of condition,
/// in both edge treatments, from fluctuations that differ from face to face:
/// `edge_correction` (the axis transverse solver) equals `face_correction` (the general
/// one, `n = e_K`) value for value (`==`: a zero's sign aside, the claim of its doc).
#[test]
fn edge_corrections_equal_the_general_ones() {
    let wobble = |f: usize, k: usize| ((f * 5 + k * 3) as f64 * 0.61).sin();
    let fluctuation = |f: usize| {
        let shear = 1e7 * wobble(f, 2);
        Conserved {
            tensor: Tensor::<2>::new(1e7 * wobble(f, 0), shear, shear, 1e7 * wobble(f, 1)),
            momentum: Vector::<2>::new(1e3 * wobble(f, 3), 1e3 * wobble(f, 4)),
        }
    };
    let (mut checked, mut nonzero) = (0, 0);
    for_partial_edge_scenes(|edges, dgmpm| {
        let solver = &dgmpm.solver;
        let sweep = solver.sweep_2d_constants(1e-7);
        let [nx, ny] = solver.grid.cells;
        let fields = Fields::per_cell(&[], &[]);
        let faces = (0..ny).flat_map(|j| [(0, [0, j]), (0, [nx, j])]);
        let faces = faces.chain((0..nx).flat_map(|i| [(1, [i, 0]), (1, [i, ny])]));
        for (f, (k, idx)) in faces.enumerate() {
            let w = [fluctuation(2 * f), fluctuation(2 * f + 1)];
            let axis = match k {
                0 => solver.edge_correction::<0>(idx, w, &sweep),
                _ => solver.edge_correction::<1>(idx, w, &sweep),
            };
            let general = solver.face_correction(k, idx, w.map(Some), fields, sweep.scale[k]);
            assert_eq!(axis, general, "{edges:?}, face {idx:?} normal to {k}");
            nonzero += usize::from(general.tensor.norm() + general.momentum.norm() > 0.0);
            checked += 1;
        }
    });
    assert!(
        checked > 200 && nonzero > checked / 2,
        "{checked}, {nonzero}"
    );
}

//! The Heun sweeps' side weights (`super`): the volume matrix against its formula.
use super::volume_matrix;
use impact_core::Vector;

/// `M v` equals `(C : sym(v ⊗ W)) e_l = λ (v · W) e_l + μ (v W_l + W v_l)` on every
/// axis in 1D to 3D, with unequal components (a transposed `M` differs).
fn matches<const D: usize>() {
    let (lambda, mu) = (1.21e11, 0.81e11);
    let w: Vec<f64> = (0..D).map(|k| 0.3 - 0.7 * k as f64).collect();
    let v = Vector::<D>::from_fn(|k, _| 2.0 + 1.5 * k as f64);
    let w_vector = Vector::<D>::from_column_slice(&w);
    for l in 0..D {
        let mut expected = (v * w[l] + w_vector * v[l]) * mu;
        expected[l] += lambda * v.dot(&w_vector);
        let got = volume_matrix::<D>(&w, l, lambda, mu) * v;
        assert!(
            (got - expected).amax() <= 1e-15 * expected.amax(),
            "D {D}, l {l}"
        );
    }
}

#[test]
fn the_volume_matrix_is_the_sides_volume_term() {
    matches::<1>();
    matches::<2>();
    matches::<3>();
}

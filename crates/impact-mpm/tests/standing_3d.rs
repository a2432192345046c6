//! The 3D standing P mode (1, 1, 1) of a unit cube with symmetry on all six faces
//! (`impact_core::exact::StandingWave`: eight oblique plane waves, exact for symmetry
//! faces): the RMS error of the stress and of the velocity at the samples, against the exact
//! fields at the samples' places, at three resolutions `n³`, `(2n)³`, `(4n)³`, and the
//! observed order `log2(e_h / e_{h/2})` of the finer pair, asserted.
use impact_core::exact::StandingWave;
use impact_core::initial::InitialState;
use impact_core::method::{MethodConfig, MethodKind, Samples};
use impact_core::{Method, Problem, Scene};

/// The cube at `n³` cells.
pub fn cube(n: usize) -> Scene {
    let text = format!(
        "name = \"smooth-block\"\ndim = 3\n[domain]\nlength = [1.0, 1.0, 1.0]\n\
         cells = [{n}, {n}, {n}]\n[material]\nmodel = \"linear-elastic\"\nyoung = 2.0e11\n\
         poisson = 0.3\ndensity = 7800.0\n[initial]\n\
         standing_wave = {{ amplitude = 5.0, modes = [1, 1, 1] }}\n[boundary]\n{}\
         [time]\noutput_transits = [4]\n[mpm]\ncourant = 0.5\n[fem]\ncourant = 0.9\n",
        ["x.low", "x.high", "y.low", "y.high", "z.low", "z.high"]
            .map(|s| format!("{s} = {{ kind = \"symmetry\" }}\n"))
            .concat()
    );
    Scene::from_toml(&text, "standing mode test").unwrap()
}

/// RMS errors `(stress, velocity)` of `method` at `t` relative to the peak stress and the
/// peak speed of the mode: `sqrt(Σ |σ − σ*|²/N) / max|σ_xx*|`, `σ` all six components.
pub fn errors(method: &dyn Method<3>, wave: &StandingWave, t: f64) -> (f64, f64) {
    let mut s = Samples::<3>::default();
    method.sample_into(&mut s);
    let (mut es, mut ev) = (0.0, 0.0);
    for i in 0..s.len() {
        let x = s.reference[i];
        let x = [x[0], x[1], x[2]];
        let [xx, yy, zz, yz, xz, xy] = wave.stress(x, t);
        let exact = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        es += (s.stress[i] - exact).norm_squared();
        let v = wave.velocity(x, t);
        ev += (s.velocity[i] - nalgebra::Vector3::new(v[0], v[1], v[2])).norm_squared();
    }
    let n = s.len() as f64;
    (
        (es / n).sqrt() / wave.peak_stress_xx(),
        (ev / n).sqrt() / wave.amplitude,
    )
}

/// Errors `(stress, velocity)` at three levels and the two observed orders of each.
pub type Study = ([(f64, f64); 3], [(f64, f64); 2]);

/// Errors at `n³`, `(2n)³`, `(4n)³` cells (at 3/8 of the period, where stress and velocity
/// are both at 71 % of their peaks) of the method `build` makes, and the two observed
/// orders of each.
pub fn study(
    n: usize,
    kind: MethodKind,
    edit: &dyn Fn(&mut MethodConfig),
    build: &dyn Fn(&Problem<3>, MethodConfig) -> Box<dyn Method<3>>,
) -> Study {
    let mut e = [(0.0, 0.0); 3];
    for (level, n) in [n, 2 * n, 4 * n].into_iter().enumerate() {
        let scene = cube(n);
        let problem = Problem::<3>::from_scene(&scene).unwrap();
        let InitialState::StandingWave(wave) = problem.initial.clone() else {
            panic!("the standing mode")
        };
        let mut config = scene.method_config(kind);
        edit(&mut config);
        let mut method = build(&problem, config);
        let t_end = 0.375 * 2.0 * std::f64::consts::PI / wave.frequency;
        let steps = (t_end / method.stable_dt()).ceil() as usize;
        let dt = t_end / steps as f64;
        for k in 0..steps {
            method.step(k as f64 * dt, dt);
        }
        e[level] = errors(method.as_ref(), &wave, t_end);
    }
    let order = |a: f64, b: f64| (a / b).log2();
    let orders = [0, 1].map(|k| (order(e[k].0, e[k + 1].0), order(e[k].1, e[k + 1].1)));
    (e, orders)
}

/// Every shape (USL, total Lagrangian) at one point per cell, and the B-splines at
/// 8 per cell, 8³ to 32³: the errors and orders, printed and asserted.
#[test]
fn the_3d_standing_mode_converges_for_every_shape() {
    use impact_core::method::MpmShape;
    for (shape, per_cell) in MpmShape::ALL
        .map(|s| (s, 1))
        .into_iter()
        .chain([(MpmShape::Bspline2, 8), (MpmShape::Bspline3, 8)])
    {
        let edit = move |c: &mut MethodConfig| {
            c.mpm_mut().unwrap().shape = shape;
            c.points_per_cell = per_cell;
        };
        let build = |p: &Problem<3>, c: MethodConfig| -> Box<dyn Method<3>> {
            Box::new(impact_mpm::Mpm::<3>::new(p, c).unwrap())
        };
        let n = 8;
        let (e, orders) = study(n, MethodKind::Mpm, &edit, &build);
        println!(
            "MPM {shape:?} {per_cell} ppc, {n}³..: errors (σ, v) {e:.3?}, orders {orders:.2?}"
        );
        for (level, (s, v)) in e.iter().enumerate() {
            assert!(
                s.is_finite() && v.is_finite() && *s < 0.5,
                "{shape:?} level {level}"
            );
        }
        // stress: second order with the B-splines at 2 points per axis, near it at one
        // point per cell (every shape there is the hat at the cell centres); velocity: first
        // order at least (USL's lag, README "Convergence")
        let stress_floor = if per_cell == 8 { 1.8 } else { 1.6 };
        assert!(
            orders[1].0 > stress_floor && orders[1].1 > 0.9,
            "{shape:?} {per_cell} ppc: orders {orders:?}"
        );
    }
}

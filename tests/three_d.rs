//! 3D (issue 24): the scene schema for any dimension (sides by axis and their 1D/2D
//! aliases, loaded patches whose resultant survives refinement), and the physics every
//! method must keep in 3D: the plane wave equals its 2D run, a centred impact stays
//! symmetric under the mirrors and the y ↔ z swap of a square patch, momentum equals the
//! impulse of a partly covered disc.
use impact_core::method::{MethodConfig, MethodKind, Samples, TransverseFlux};
use impact_core::{Boundary, Method, Problem, Scene};

/// Run `steps` steps of the method's stable step and sample.
fn advance<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    steps: usize,
) -> (Box<dyn Method<D>>, Samples<D>) {
    let mut m = impact::build(problem, config).unwrap();
    let dt = m.stable_dt();
    for k in 0..steps {
        m.step(k as f64 * dt, dt);
    }
    m.check_finite().unwrap();
    let mut s = Samples::default();
    m.sample_into(&mut s);
    (m, s)
}

/// A 3D block `4 × 3 × 3` m (`cells`), free, with `x.low` given by `load`.
fn block(cells: [usize; 3], load: &str) -> Scene {
    let text = format!(
        "name = \"block\"\ndim = 3\n[domain]\nlength = [4.0, 3.0, 3.0]\ncells = {cells:?}\n\
         [material]\nmodel = \"linear-elastic\"\nyoung = 2.0e11\npoisson = 0.3\ndensity = 7800.0\n\
         [boundary]\nx.low = {load}\n[time]\noutput_transits = [8]\n\
         [dgmpm]\nflux = \"dcu\"\ncourant = 0.3\n[mpm]\ncourant = 0.3\n[fem]\ncourant = 0.5\n"
    );
    Scene::from_toml(&text, "test").unwrap()
}

/// `x.low`, `y.high`, ... name the same sides as `left`, `top`, ...: the problems built
/// from the two spellings of the plate are equal.
#[test]
fn sides_by_axis_equal_their_aliases() {
    let text = impact_core::scene::builtin("plate").unwrap();
    let named = text
        .replace("left =", "x.low =")
        .replace("right =", "x.high =")
        .replace("bottom =", "y.low =")
        .replace("top =", "y.high =");
    assert_ne!(named, text);
    let a = Problem::<2>::from_scene(&Scene::from_toml(text, "a").unwrap()).unwrap();
    let b = Problem::<2>::from_scene(&Scene::from_toml(&named, "b").unwrap()).unwrap();
    assert_eq!(a.boundaries, b.boundaries);
    assert!(matches!(a.boundaries[0][0], Boundary::Velocity { .. }));
}

/// The total covered area of a loaded patch over the faces of a side, `Σ share · face
/// area`, equals the patch's area on every grid under `cover = "fraction"` (a box cut by
/// faces; a disc, exact areas of a disc cut by a rectangle), so the load's resultant never
/// changes under refinement; by centre it converges to it.
#[test]
fn a_patch_keeps_its_resultant_under_refinement() {
    let patches = [
        ("from = [0.37, 0.81], to = [1.93, 2.2]", 1.56 * 1.39),
        (
            "centre = [1.3, 1.6], radius = 0.77",
            std::f64::consts::PI * 0.77 * 0.77,
        ),
    ];
    for (patch, area) in patches {
        let mut centre_errors = Vec::new();
        for n in [6, 12, 24, 48] {
            for cover in ["fraction", "centre"] {
                let load =
                    format!("{{ kind = \"pressure\", value = 1e8, {patch}, cover = \"{cover}\" }}");
                let problem = Problem::<3>::from_scene(&block([4, n, n], &load)).unwrap();
                let load = problem.boundaries[0][0].load().copied().unwrap();
                let g = &problem.grid;
                let half = g.spacing * 0.5;
                let mut covered = 0.0;
                for j in 0..g.cells[1] {
                    for k in 0..g.cells[2] {
                        let centre = impact_core::Vector::<3>::new(
                            0.0,
                            (j as f64 + 0.5) * g.spacing[1],
                            (k as f64 + 0.5) * g.spacing[2],
                        );
                        covered += load.coverage(0, &centre, &half) * g.spacing[1] * g.spacing[2];
                    }
                }
                if cover == "fraction" {
                    assert!(
                        (covered - area).abs() <= 1e-12 * area,
                        "{patch} on {n}²: {covered} vs {area}"
                    );
                } else {
                    centre_errors.push((covered - area).abs() / area);
                }
            }
        }
        // by centre: within a few cells' worth of the perimeter, shrinking
        assert!(centre_errors[3] < 0.05, "{patch}: {centre_errors:?}");
        assert!(
            centre_errors[3] < centre_errors[0],
            "{patch}: {centre_errors:?}"
        );
    }
}

/// The 3D plane wave (`block-wave`: roller y and z faces) gives the same profile and
/// errors and energy balance as the 2D `plate-wave` in every method, and DGMPM at
/// Courant 1 is exact.
#[test]
fn the_plane_wave_in_3d_is_the_plane_wave_in_2d() {
    let three = Scene::builtin("block-wave").unwrap();
    let two = Scene::builtin("plate-wave").unwrap();
    let p3 = Problem::<3>::from_scene(&three).unwrap();
    let p2 = Problem::<2>::from_scene(&two).unwrap();
    let (r3, r2) = (
        impact_core::reference::Reference::for_problem(&p3).unwrap(),
        impact_core::reference::Reference::for_problem(&p2).unwrap(),
    );
    for kind in MethodKind::ALL {
        let mut c3 = three.method_config(kind);
        let mut c2 = two.method_config(kind);
        if let (Some(a), Some(b)) = (c3.dgmpm_mut(), c2.dgmpm_mut()) {
            a.flux = TransverseFlux::DonorCell;
            b.flux = TransverseFlux::DonorCell;
        }
        let silent = &mut impact::run::Silent;
        let (a, _) = impact::run::run_method(&p3, c3, Some(&r3), silent).unwrap();
        let (b, _) = impact::run::run_method(&p2, c2, Some(&r2), silent).unwrap();
        for (x, y) in a.times.iter().zip(&b.times) {
            let (e3, e2) = (x.l1, y.l1);
            assert!(
                (e3 - e2).abs() <= 1e-9 * e2.abs().max(1e-12),
                "{kind:?} at t = {}: L1 {e3} (3D) vs {e2} (2D)",
                x.t
            );
            if kind == MethodKind::Dgmpm {
                assert!(e3 < 1e-12, "DGMPM at Courant 1: L1 {e3}");
            }
            // the energy balance too (3D compliance, the cross-section's work)
            let (w3, w2) = (x.energy_error, y.energy_error);
            assert!(
                (w3 - w2).abs() <= 1e-9 * w2.abs() + 1e-12,
                "{kind:?} at t = {}: energy error {w3} (3D) vs {w2} (2D)",
                x.t
            );
        }
    }
}

/// A square patch centred on the x.low face: every method's fields stay symmetric under
/// the mirrors y → 3 − y and z → 3 − z and under the swap y ↔ z.
#[test]
fn a_centred_square_impact_stays_symmetric() {
    let scene = block(
        [10, 8, 8],
        "{ kind = \"normal-velocity\", value = 5.0, from = [1.125, 1.125], to = [1.875, 1.875] }",
    );
    let problem = Problem::<3>::from_scene(&scene).unwrap();
    let scale = problem.material.density * problem.material.p_wave_speed::<3>() * 5.0;
    let mut ctu = scene.method_config(MethodKind::Dgmpm);
    ctu.courant = 1.0;
    if let Some(o) = ctu.dgmpm_mut() {
        o.flux = TransverseFlux::Ctu;
    }
    let configs = MethodKind::ALL
        .iter()
        .map(|&k| scene.method_config(k))
        .chain([ctu]);
    for config in configs {
        let kind = config.kind();
        let (_, s) = advance(&problem, config, 30);
        let find = |x: impact_core::Vector<3>| {
            (0..s.len())
                .find(|&j| (s.reference[j] - x).abs().max() < 1e-9)
                .expect("image sample")
        };
        let peak = s.stress.iter().map(|t| t.abs().max()).fold(0.0, f64::max);
        assert!(peak > 0.1 * scale, "{kind:?}: the impact moved nothing");
        for i in 0..s.len() {
            let x = s.reference[i];
            // (map of the position, sign flips of the velocity, of the stress (i, j))
            let images: [(impact_core::Vector<3>, [f64; 3]); 3] = [
                (
                    impact_core::Vector::<3>::new(x[0], 3.0 - x[1], x[2]),
                    [1.0, -1.0, 1.0],
                ),
                (
                    impact_core::Vector::<3>::new(x[0], x[1], 3.0 - x[2]),
                    [1.0, 1.0, -1.0],
                ),
                (
                    impact_core::Vector::<3>::new(x[0], x[2], x[1]),
                    [1.0, 1.0, 1.0],
                ),
            ];
            for (n, (image, signs)) in images.iter().enumerate() {
                let j = find(*image);
                let swap = n == 2;
                let axis = |a: usize| if swap && a > 0 { 3 - a } else { a };
                for a in 0..3 {
                    let v = signs[a] * s.velocity[j][axis(a)];
                    assert!(
                        (s.velocity[i][a] - v).abs() <= 1e-10 * 5.0,
                        "{kind:?}: v_{a} at {x:?} under image {n}"
                    );
                    for b in 0..3 {
                        let t = signs[a] * signs[b] * s.stress[j][(axis(a), axis(b))];
                        assert!(
                            (s.stress[i][(a, b)] - t).abs() <= 1e-10 * scale,
                            "{kind:?}: σ_{a}{b} at {x:?} under image {n}: {} vs {t}",
                            s.stress[i][(a, b)]
                        );
                    }
                }
            }
        }
    }
}

/// Momentum equals the impulse of a pressure on a disc that cuts faces (`cover =
/// "fraction"`), in every method: the free faces carry no force and the partly covered
/// faces deliver their share; the impulse is `p · π r² · t` (FEM: at its velocities' time
/// `t − Δt/2`) and it has no y or z part.
#[test]
fn momentum_equals_the_impulse_of_a_partly_covered_disc() {
    let (p, r) = (1e8, 0.8);
    let scene = block(
        [10, 9, 9],
        &format!(
            "{{ kind = \"pressure\", value = {p}, centre = [1.4, 1.55], radius = {r}, \
             cover = \"fraction\" }}"
        ),
    );
    let problem = Problem::<3>::from_scene(&scene).unwrap();
    for kind in MethodKind::ALL {
        let (m, _) = advance(&problem, scene.method_config(kind), 20);
        // FEM's central differences hold the velocity half a step behind
        // (`v_{n-1/2}`), and its momentum the impulse up to that time
        let lag = if kind == MethodKind::Fem { 0.5 } else { 0.0 };
        let t = (20.0 - lag) * m.stable_dt();
        let (momentum, impulse) = (m.momentum(), m.external_impulse());
        let expected = p * std::f64::consts::PI * r * r * t;
        assert!(
            (momentum - impulse).norm() <= 1e-10 * impulse.norm(),
            "{kind:?}: momentum {momentum:?} impulse {impulse:?}"
        );
        assert!(
            (impulse[0] - expected).abs() <= 1e-10 * expected,
            "{kind:?}: impulse {} vs p π r² t = {expected}",
            impulse[0]
        );
        assert!(momentum[1].abs() + momentum[2].abs() <= 1e-10 * momentum[0].abs());
    }
}

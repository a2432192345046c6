//! Reductions of 3D FEM (hex8, 2×2×2 Gauss points) to 2D and 1D (issue 24): a 3D scene
//! invariant along z (symmetry on both z faces, 1 to 3 elements through the thickness) is
//! the 2D plane-strain run of the same scene, and one invariant along y and z with Poisson's
//! ratio 0 is the 1D run (uniaxial strain with `λ = 0`, `λ + 2μ = E`, is uniaxial stress):
//! every node of every z layer carries the velocity and displacement of the 2D (1D) node at
//! its place, every element the centre stress of the 2D element at its place, to 1e-12 of
//! their peaks. Linear elasticity on the stencil path (27-point in 3D) and on the Gauss
//! path, the fused and the two-phase step; J2 at the Gauss points (the 3D `σ_zz` against
//! the plane-strain one from `ε^p_zz`); Saint-Venant–Kirchhoff.
//!
//! Why they must agree: with `u_z = 0` and `∂/∂z = 0`, 3D elasticity is plane strain
//! (Timoshenko & Goodier 1970, §16); the hex8 shape functions are tensor products of the
//! quad4 ones and linear hats in z, whose gradients sum to zero over a z-invariant field,
//! and the lumped masses and the Gauss weights factor the same way (Hughes 1987, §3.5).
use impact_core::method::{MethodKind, Samples};
use impact_core::{Method, Problem, Scene, Tensor, Vector};
use impact_fem::Fem;
use std::collections::HashMap;

/// Element size (m) along every axis.
const H: f64 = 0.25;

fn material(model: &str, poisson: f64) -> (String, f64) {
    let common = format!("young = 2.0e11\npoisson = {poisson}\ndensity = 7800.0");
    match model {
        // "pressure": linear elastic under a pressure of 2e8 Pa instead of an impactor
        "elastic" | "pressure" => (format!("model = \"linear-elastic\"\n{common}"), 5.0),
        "j2" => (
            format!("model = \"j2\"\n{common}\nyield_stress = 4.0e8\nhardening = 2.0e10"),
            20.0,
        ),
        "svk" => (format!("model = \"svk\"\n{common}"), 100.0),
        _ => unreachable!("test scenes only"),
    }
}

fn text(dim: usize, lengths: String, cells: String, material: String, boundary: String) -> Scene {
    let text = format!(
        "name = \"reduction\"\ndim = {dim}\n[domain]\nlength = [{lengths}]\ncells = [{cells}]\n\
         [material]\n{material}\n[boundary]\n{boundary}\
         [time]\noutput_transits = [8]\n[fem]\ncourant = 0.9\n"
    );
    Scene::from_toml(&text, "reduction test").unwrap()
}

/// The 2D plate (4 m × 3 m, 16 × 12 elements, an impact on the lower third of the left
/// edge, symmetry below, free elsewhere), or its extrusion by `nz` elements with symmetry
/// z faces.
fn plate_scene(model: &str, nz: Option<usize>) -> Scene {
    let (material, speed) = material(model, 0.3);
    let (dim, lengths, cells, patch, z) = match nz {
        None => (
            2,
            "4.0, 3.0".into(),
            "16, 12".into(),
            "from = 0.0, to = 1.0".into(),
            "",
        ),
        Some(n) => {
            let lz = H * n as f64;
            (
                3,
                format!("4.0, 3.0, {lz}"),
                format!("16, 12, {n}"),
                format!("from = [0.0, 0.0], to = [1.0, {lz}]"),
                "z.low = { kind = \"symmetry\" }\nz.high = { kind = \"symmetry\" }\n",
            )
        }
    };
    let boundary = format!(
        "x.low = {{ kind = \"normal-velocity\", value = {speed}, {patch} }}\n\
         x.high = {{ kind = \"free\" }}\ny.low = {{ kind = \"symmetry\" }}\n\
         y.high = {{ kind = \"free\" }}\n{z}"
    );
    let boundary = if model == "pressure" {
        boundary.replace(
            "\"normal-velocity\", value = 5",
            "\"pressure\", value = 2.0e8",
        )
    } else {
        boundary
    };
    text(dim, lengths, cells, material, boundary)
}

/// The 1D bar (4 m, 16 elements, impact at the left end) or the 3D block `ny × nz`
/// elements across with symmetry on the four sides; Poisson's ratio 0.
fn bar_scene(model: &str, across: Option<(usize, usize)>) -> Scene {
    let (material, speed) = material(model, 0.0);
    let (dim, lengths, cells, sides) = match across {
        None => (1, "4.0".into(), "16".into(), String::new()),
        Some((ny, nz)) => (
            3,
            format!("4.0, {}, {}", H * ny as f64, H * nz as f64),
            format!("16, {ny}, {nz}"),
            ["y.low", "y.high", "z.low", "z.high"]
                .map(|s| format!("{s} = {{ kind = \"symmetry\" }}\n"))
                .concat(),
        ),
    };
    let boundary = format!(
        "x.low = {{ kind = \"normal-velocity\", value = {speed} }}\nx.high = {{ kind = \"free\" }}\n{sides}"
    );
    text(dim, lengths, cells, material, boundary)
}

/// How the internal force is formed.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Path {
    /// The node stencil, the nodal update fused into it (the default for linear elasticity).
    Fused,
    /// The node stencil, two phases.
    Stencil,
    /// The Gauss points.
    Gauss,
}

/// 40 steps of FEM on `scene` along `path` at `dt` (or its own stable step).
fn run<const D: usize>(scene: &Scene, path: Path, dt: Option<f64>) -> Fem<D> {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut fem = Fem::<D>::new(&problem, scene.method_config(MethodKind::Fem)).unwrap();
    match path {
        Path::Fused => {}
        Path::Stencil => fem.solver.set_fused_step(false),
        Path::Gauss => fem.solver.use_gauss_path(),
    }
    let dt = dt.unwrap_or(fem.stable_dt());
    for n in 0..40 {
        fem.step(n as f64 * dt, dt);
    }
    fem
}

/// The plane-strain `σ_zz` of sample `e` of a 2D run.
type OutOfPlane<'a, const L: usize> = dyn Fn(usize, &Samples<L>) -> f64 + 'a;

fn key<const D: usize>(x: &Vector<D>, d: usize) -> [i64; 2] {
    std::array::from_fn(|k| {
        if k < d {
            (x[k] * 1e9).round() as i64
        } else {
            0
        }
    })
}

fn embed<const L: usize>(v: &Vector<L>) -> Vector<3> {
    Vector::<3>::from_fn(|k, _| if k < L { v[k] } else { 0.0 })
}

/// The largest difference between the 3D run and the lower-dimensional one (`L` axes):
/// element centre stresses (the `L × L` block, and `σ_zz` against `zz(e)` of the 2D
/// element where given; the out-of-plane shear must vanish) relative to the peak stress;
/// nodal velocities relative to the peak velocity and displacements relative to the
/// peak displacement (components beyond `L` must vanish).
fn worst<const L: usize>(low: &Fem<L>, high: &Fem<3>, zz: Option<&OutOfPlane<L>>) -> f64 {
    let (mut a, mut b) = (Samples::<L>::default(), Samples::<3>::default());
    low.sample_into(&mut a);
    high.sample_into(&mut b);
    let peak = |s: &[Tensor<L>]| s.iter().map(|s| s.amax()).fold(0.0, f64::max);
    let scale_s = peak(&a.stress);
    assert!(scale_s > 1e6, "the wave must be there");
    let at: HashMap<_, _> = (0..a.len()).map(|e| (key(&a.reference[e], L), e)).collect();
    let mut worst: f64 = 0.0;
    for f in 0..b.len() {
        let e = at[&key(&b.reference[f], L)];
        let mut expected = Tensor::<3>::zeros();
        expected.view_mut((0, 0), (L, L)).copy_from(&a.stress[e]);
        let mut got = b.stress[f];
        match zz {
            Some(zz) => expected[(2, 2)] = zz(e, &a),
            None if L == 2 => got[(2, 2)] = 0.0,
            None => {}
        }
        worst = worst.max((got - expected).amax() / scale_s);
    }
    let (va, vb) = (low.nodal_velocities(), high.nodal_velocities());
    let (ua, ub) = (&low.state.displacement, &high.state.displacement);
    let scale_v = va.iter().map(|v| v.amax()).fold(0.0, f64::max);
    let scale_u = ua.iter().map(|u| u.amax()).fold(0.0, f64::max);
    let (ga, gb) = (low.solver.grid(), high.solver.grid());
    let at: HashMap<_, _> = (0..va.len())
        .map(|i| (key(&ga.vertex_position(i), L), i))
        .collect();
    for j in 0..vb.len() {
        let i = at[&key(&gb.vertex_position(j), L)];
        worst = worst.max((vb[j] - embed(&va[i])).amax() / scale_v);
        worst = worst.max((ub[j] - embed(&ua[i])).amax() / scale_u);
    }
    worst
}

fn assert_small(label: &str, worst: f64) {
    println!("{label}: {worst:.1e}");
    assert!(
        worst <= 1e-12,
        "{label}: 3D and its reduction differ by {worst:e}"
    );
}

/// Linear elasticity on every path, 1 to 3 elements through the thickness.
#[test]
fn a_z_invariant_block_is_the_plane_strain_plate_on_every_path() {
    let plate = plate_scene("elastic", None);
    let material = Problem::<2>::from_scene(&plate).unwrap().material;
    for (k, path) in [Path::Fused, Path::Stencil, Path::Gauss]
        .into_iter()
        .enumerate()
    {
        for nz in 1..=3 {
            let low = run::<2>(&plate, path, None);
            let high = run::<3>(&plate_scene("elastic", Some(nz)), path, None);
            assert_eq!(low.stable_dt(), high.stable_dt());
            assert_eq!(high.solver.uses_stencil(), path != Path::Gauss);
            let zz = |e: usize, s: &Samples<2>| material.out_of_plane_stress(&s.stress[e]);
            let label = format!("2D {path:?}, nz = {nz} ({k})");
            assert_small(&label, worst(&low, &high, Some(&zz)));
        }
    }
}

/// A pressure on a patch of the face: the nodes' tributary areas (lengths in 2D) and the
/// covered shares, on every path.
#[test]
fn a_z_invariant_block_under_a_pressure_patch_is_the_plane_strain_plate() {
    for path in [Path::Fused, Path::Stencil, Path::Gauss] {
        for nz in 1..=3 {
            let low = run::<2>(&plate_scene("pressure", None), path, None);
            let high = run::<3>(&plate_scene("pressure", Some(nz)), path, None);
            let label = format!("2D pressure {path:?}, nz = {nz}");
            assert_small(&label, worst(&low, &high, None));
        }
    }
}

/// J2 at the Gauss points (the element means of the Gauss stresses; `σ_zz` from the 2D
/// run's samples) and Saint-Venant–Kirchhoff.
#[test]
fn a_z_invariant_block_is_the_plane_strain_plate_in_j2_and_svk() {
    for nz in [1, 3] {
        let low = run::<2>(&plate_scene("j2", None), Path::Gauss, None);
        let high = run::<3>(&plate_scene("j2", Some(nz)), Path::Gauss, None);
        let mut samples = Samples::<2>::default();
        low.sample_into(&mut samples);
        let plastic = samples
            .plastic_strain
            .iter()
            .fold(0.0, |m: f64, e| m.max(*e));
        assert!(plastic > 1e-4, "J2 must yield ({plastic:e})");
        let zz = |e: usize, s: &Samples<2>| s.stress_zz[e];
        assert_small(&format!("2D J2, nz = {nz}"), worst(&low, &high, Some(&zz)));
        let low = run::<2>(&plate_scene("svk", None), Path::Gauss, None);
        let high = run::<3>(
            &plate_scene("svk", Some(nz)),
            Path::Gauss,
            Some(low.stable_dt()),
        );
        assert_small(&format!("2D SVK, nz = {nz}"), worst(&low, &high, None));
    }
}

/// Invariant along y and z with `ν = 0`: the 1D bar (linear elastic on every path,
/// Saint-Venant–Kirchhoff).
#[test]
fn a_y_and_z_invariant_block_with_no_poisson_effect_is_the_bar() {
    for path in [Path::Fused, Path::Stencil, Path::Gauss] {
        for across in [(1, 1), (2, 3)] {
            let low = run::<1>(&bar_scene("elastic", None), path, None);
            let high = run::<3>(&bar_scene("elastic", Some(across)), path, None);
            assert_eq!(low.stable_dt(), high.stable_dt());
            assert_small(
                &format!("1D {path:?}, {across:?}"),
                worst(&low, &high, None),
            );
        }
    }
    let low = run::<1>(&bar_scene("svk", None), Path::Gauss, None);
    let high = run::<3>(
        &bar_scene("svk", Some((2, 2))),
        Path::Gauss,
        Some(low.stable_dt()),
    );
    assert_small("1D SVK", worst(&low, &high, None));
}

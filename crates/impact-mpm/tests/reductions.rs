//! Reductions of 3D MPM to 2D and 1D (issue 24): a 3D scene invariant along z (symmetry on
//! both z faces, 1 to 3 cells through the thickness) is the 2D plane-strain run of the same
//! scene, and one invariant along y and z (symmetry on the four sides) with Poisson's ratio
//! 0 is the 1D run (uniaxial strain with `ν = 0`, `λ = 0`, `λ + 2μ = E`, is uniaxial
//! stress). Every point of every z layer carries the state of the 2D (1D) point at its
//! place: stresses and velocities to 1e-12 of their peaks, positions to 1e-12 m, for every
//! shape (hats, uGIMP, quadratic and cubic B-splines, CPDI with hexahedral domains), USL,
//! MUSL and USF, the total and the updated Lagrangian frames, J2 and Saint-Venant–Kirchhoff.
//!
//! Why they must agree: with `ε_zz = 0` and `∂/∂z = 0`, 3D linear elasticity gives the
//! plane-strain `σ_xx, σ_yy, σ_xy` and `σ_zz = λ tr ε` (Timoshenko & Goodier 1970, §16);
//! the shape functions are tensor products, so the z factors of a z-invariant field sum to
//! one at every point (partition of unity, `shape.rs`), and symmetry faces mirror the
//! padding nodes so that holds at the faces too (`edges.rs`).
use impact_core::method::{MethodConfig, MethodKind, MpmFrame, MpmShape, StressUpdate};
use impact_core::{Method, Problem, Scene, Tensor, Vector};
use impact_mpm::Mpm;
use std::collections::HashMap;

/// Cell size (m) along every axis.
const H: f64 = 0.25;

/// The material and the impact of a reduction scene: `(material TOML, impact speed m/s)`.
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

/// The 2D scene (a 4 m × 3 m plate, 16 × 12 cells, an impact on the lower third of the
/// left edge, symmetry below, free elsewhere) or its 3D extrusion by `nz` cells with
/// symmetry z faces.
fn plate_scene(model: &str, nz: Option<usize>) -> Scene {
    let (material, speed) = material(model, 0.3);
    let (dim, lengths, cells, patch, z) = match nz {
        None => (
            2,
            "4.0, 3.0".to_string(),
            "16, 12".to_string(),
            "from = 0.0, to = 1.0".to_string(),
            String::new(),
        ),
        Some(n) => {
            let lz = H * n as f64;
            (
                3,
                format!("4.0, 3.0, {lz}"),
                format!("16, 12, {n}"),
                format!("from = [0.0, 0.0], to = [1.0, {lz}]"),
                "z.low = { kind = \"symmetry\" }\nz.high = { kind = \"symmetry\" }\n".to_string(),
            )
        }
    };
    let text = format!(
        "name = \"reduction\"\ndim = {dim}\n[domain]\nlength = [{lengths}]\ncells = [{cells}]\n\
         [material]\n{material}\n[boundary]\n\
         x.low = {{ kind = \"normal-velocity\", value = {speed}, {patch} }}\n\
         x.high = {{ kind = \"free\" }}\ny.low = {{ kind = \"symmetry\" }}\n\
         y.high = {{ kind = \"free\" }}\n{z}\
         [time]\noutput_transits = [8]\n[mpm]\ncourant = 0.5\n"
    );
    let text = if model == "pressure" {
        text.replace(
            "\"normal-velocity\", value = 5",
            "\"pressure\", value = 2.0e8",
        )
    } else {
        text
    };
    Scene::from_toml(&text, "reduction test").unwrap()
}

/// The 1D bar (4 m, 16 cells, impact at the left end, free right end) or the 3D block
/// `ny × nz` cells across with symmetry on the four sides; Poisson's ratio 0.
fn bar_scene(model: &str, across: Option<(usize, usize)>) -> Scene {
    let (material, speed) = material(model, 0.0);
    let (dim, lengths, cells, sides) = match across {
        None => (1, "4.0".to_string(), "16".to_string(), String::new()),
        Some((ny, nz)) => (
            3,
            format!("4.0, {}, {}", H * ny as f64, H * nz as f64),
            format!("16, {ny}, {nz}"),
            ["y.low", "y.high", "z.low", "z.high"]
                .map(|s| format!("{s} = {{ kind = \"symmetry\" }}\n"))
                .concat(),
        ),
    };
    let text = format!(
        "name = \"reduction\"\ndim = {dim}\n[domain]\nlength = [{lengths}]\ncells = [{cells}]\n\
         [material]\n{material}\n[boundary]\n\
         x.low = {{ kind = \"normal-velocity\", value = {speed} }}\n\
         x.high = {{ kind = \"free\" }}\n{sides}\
         [time]\noutput_transits = [8]\n[mpm]\ncourant = 0.5\n"
    );
    Scene::from_toml(&text, "reduction test").unwrap()
}

/// Steps of MPM on `scene` with the options `edit` sets: 30 at its own stable time step,
/// or at `dt` (the lower-dimensional run's).
fn run<const D: usize>(scene: &Scene, edit: &dyn Fn(&mut MethodConfig), dt: Option<f64>) -> Mpm<D> {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    edit(&mut config);
    let mut mpm = Mpm::<D>::new(&problem, config).unwrap();
    let steps = 30;
    let dt = dt.unwrap_or(mpm.stable_dt());
    for n in 0..steps {
        mpm.step(n as f64 * dt, dt);
    }
    mpm
}

/// The key of a reference position along the first `d` axes (to 1e-9 m).
fn key<const D: usize>(x: &Vector<D>, d: usize) -> [i64; 2] {
    std::array::from_fn(|k| {
        if k < d {
            (x[k] * 1e9).round() as i64
        } else {
            0
        }
    })
}

/// The largest difference between the 3D run and the lower-dimensional one (`d` axes), over
/// every 3D point against the point at its place: stress (the `d × d` block; the 3D
/// `σ_zz` against the plane-strain one `zz(p)` of the 2D point where given; the shear
/// stresses out of the plane and the velocity components beyond `d`, which must vanish),
/// relative to the peaks; velocity relative to its peak; position in m.
fn worst<const L: usize>(low: &Mpm<L>, high: &Mpm<3>, zz: Option<&dyn Fn(usize) -> f64>) -> f64 {
    let (a, b) = (&low.state.points, &high.state.points);
    let at: HashMap<[i64; 2], usize> = (0..a.len()).map(|p| (key(&a.reference[p], L), p)).collect();
    let (scale_s, scale_v) = a.peaks();
    assert!(scale_s > 1e6 && scale_v > 1.0, "the wave must be there");
    assert_eq!(b.len() % a.len(), 0);
    let mut worst: f64 = 0.0;
    for q in 0..b.len() {
        let p = at[&key(&b.reference[q], L)];
        let full = |s: &Tensor<L>| {
            let mut t = Tensor::<3>::zeros();
            t.view_mut((0, 0), (L, L)).copy_from(s);
            t
        };
        let mut expected = full(&a.stress[p]);
        let mut got = b.stress[q];
        match zz {
            Some(zz) if L == 2 => expected[(2, 2)] = zz(p),
            // SVK: Π_zz has no 2D counterpart; 1D (ν = 0): σ_yy = σ_zz = 0 expected
            _ if L == 2 => got[(2, 2)] = 0.0,
            _ => {}
        }
        worst = worst.max((got - expected).amax() / scale_s);
        let mut v = Vector::<3>::zeros();
        let mut x = b.reference[q];
        for k in 0..L {
            v[k] = a.velocity[p][k];
            x[k] = a.position[p][k];
        }
        worst = worst.max((b.velocity[q] - v).amax() / scale_v);
        worst = worst.max((b.position[q] - x).amax());
    }
    worst
}

/// Every MPM option: shape × stress update × frame.
fn options() -> Vec<(String, MpmShape, StressUpdate, MpmFrame)> {
    let mut out = Vec::new();
    for shape in MpmShape::ALL {
        for update in [StressUpdate::Usl, StressUpdate::Musl, StressUpdate::Usf] {
            for frame in [MpmFrame::TotalLagrangian, MpmFrame::UpdatedLagrangian] {
                out.push((
                    format!("{shape:?} {update:?} {frame:?}"),
                    shape,
                    update,
                    frame,
                ));
            }
        }
    }
    out
}

fn set(shape: MpmShape, update: StressUpdate, frame: MpmFrame) -> impl Fn(&mut MethodConfig) {
    move |c: &mut MethodConfig| {
        let o = c.mpm_mut().unwrap();
        (o.shape, o.stress_update, o.frame) = (shape, update, frame);
    }
}

fn assert_small(label: &str, worst: f64) {
    println!("{label}: {worst:.1e}");
    assert!(
        worst <= 1e-12,
        "{label}: 3D and its reduction differ by {worst:e}"
    );
}

/// Linear elasticity, every shape, update and frame; 1, 2 and 3 cells through the
/// thickness in turn.
#[test]
fn a_z_invariant_block_is_the_plane_strain_plate_for_every_option() {
    let plate = plate_scene("elastic", None);
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let material = problem.material;
    for (k, (label, shape, update, frame)) in options().into_iter().enumerate() {
        let nz = 1 + k % 3;
        let edit = set(shape, update, frame);
        let low = run::<2>(&plate, &edit, None);
        let high = run::<3>(
            &plate_scene("elastic", Some(nz)),
            &edit,
            Some(low.stable_dt()),
        );
        assert_eq!(low.stable_dt(), high.stable_dt());
        let zz = |p: usize| material.out_of_plane_stress(&low.state.points.stress[p]);
        assert_small(
            &format!("2D {label}, nz = {nz}"),
            worst(&low, &high, Some(&zz)),
        );
    }
}

/// A pressure on a patch of the face (the points' face areas and covered shares): every
/// shape, both frames, USL and MUSL.
#[test]
fn a_z_invariant_block_under_a_pressure_patch_is_the_plane_strain_plate() {
    let plate = plate_scene("pressure", None);
    for shape in MpmShape::ALL {
        for (update, frame) in [
            (StressUpdate::Usl, MpmFrame::TotalLagrangian),
            (StressUpdate::Musl, MpmFrame::UpdatedLagrangian),
        ] {
            for nz in [1, 2] {
                let edit = set(shape, update, frame);
                let low = run::<2>(&plate, &edit, None);
                let high = run::<3>(
                    &plate_scene("pressure", Some(nz)),
                    &edit,
                    Some(low.stable_dt()),
                );
                let label = format!("2D pressure {shape:?} {update:?} {frame:?}, nz = {nz}");
                assert_small(&label, worst(&low, &high, None));
            }
        }
    }
}

/// Two points per cell and axis (4 per cell in 2D, 8 in 3D): uGIMP's smaller domains,
/// CPDI's, and the updated Lagrangian frame.
#[test]
fn a_z_invariant_block_with_two_points_per_axis_is_the_plane_strain_plate() {
    let plate = plate_scene("elastic", None);
    for shape in [MpmShape::Gimp, MpmShape::Cpdi, MpmShape::Bspline3] {
        for frame in [MpmFrame::TotalLagrangian, MpmFrame::UpdatedLagrangian] {
            let options = set(shape, StressUpdate::Usl, frame);
            let per_cell = |n: usize| {
                let options = &options;
                move |c: &mut MethodConfig| {
                    options(c);
                    c.points_per_cell = n;
                }
            };
            let low = run::<2>(&plate, &per_cell(4), None);
            let high = run::<3>(
                &plate_scene("elastic", Some(2)),
                &per_cell(8),
                Some(low.stable_dt()),
            );
            assert_eq!(high.state.points.len(), 4 * low.state.points.len());
            assert_small(
                &format!("2D, 2 per axis, {shape:?} {frame:?}"),
                worst(&low, &high, None),
            );
        }
    }
}

/// J2 (the plane-strain σ_zz from ε^p_zz) and Saint-Venant–Kirchhoff (total Lagrangian).
#[test]
fn a_z_invariant_block_is_the_plane_strain_plate_in_j2_and_svk() {
    let plate = plate_scene("j2", None);
    let j2 = match Problem::<2>::from_scene(&plate).unwrap().model {
        impact_core::method::Model::J2(j2) => j2,
        _ => unreachable!(),
    };
    for (k, (label, shape, update, frame)) in options().into_iter().enumerate().step_by(5) {
        let nz = 1 + k % 3;
        let edit = set(shape, update, frame);
        let low = run::<2>(&plate, &edit, None);
        let high = run::<3>(&plate_scene("j2", Some(nz)), &edit, Some(low.stable_dt()));
        let plastic = low
            .state
            .points
            .equivalent_plastic_strain
            .iter()
            .fold(0.0, |m: f64, e| m.max(*e));
        assert!(plastic > 1e-4, "J2 {label}: it must yield ({plastic:e})");
        let p = &low.state.points;
        let zz = |i: usize| j2.out_of_plane(p.stress[i].trace(), p.plastic_strain_zz[i]);
        assert_small(
            &format!("2D J2 {label}, nz = {nz}"),
            worst(&low, &high, Some(&zz)),
        );
    }
    for shape in MpmShape::ALL {
        for update in [StressUpdate::Usl, StressUpdate::Musl, StressUpdate::Usf] {
            let edit = set(shape, update, MpmFrame::TotalLagrangian);
            let low = run::<2>(&plate_scene("svk", None), &edit, None);
            let high = run::<3>(&plate_scene("svk", Some(2)), &edit, Some(low.stable_dt()));
            assert_small(
                &format!("2D SVK {shape:?} {update:?}"),
                worst(&low, &high, None),
            );
        }
    }
}

/// Invariant along y and z with `ν = 0`: the 1D bar, linear elastic (every option) and
/// Saint-Venant–Kirchhoff (`λ = 0`, `2μ = E`: the 1D `Π = E/2 F (F² − 1)`).
#[test]
fn a_y_and_z_invariant_block_with_no_poisson_effect_is_the_bar() {
    for (k, (label, shape, update, frame)) in options().into_iter().enumerate() {
        let across = (1 + k % 2, 1 + (k / 2) % 3);
        let edit = set(shape, update, frame);
        let low = run::<1>(&bar_scene("elastic", None), &edit, None);
        let high = run::<3>(
            &bar_scene("elastic", Some(across)),
            &edit,
            Some(low.stable_dt()),
        );
        assert_eq!(low.stable_dt(), high.stable_dt());
        assert_small(&format!("1D {label}, {across:?}"), worst(&low, &high, None));
    }
    for update in [StressUpdate::Usl, StressUpdate::Musl, StressUpdate::Usf] {
        let edit = set(MpmShape::Bspline2, update, MpmFrame::TotalLagrangian);
        let low = run::<1>(&bar_scene("svk", None), &edit, None);
        let high = run::<3>(
            &bar_scene("svk", Some((2, 1))),
            &edit,
            Some(low.stable_dt()),
        );
        assert_small(&format!("1D SVK {update:?}"), worst(&low, &high, None));
    }
}

//! DGMPM with `order = 2` in 3D (the limited wave corrections along each axis, and with CTU
//! their transverse and transverse-transverse split as Clawpack's `flux3` with
//! `method = (2, 22)`, `ctu3.rs`): a block invariant along y and z is the 1D order-2 bar,
//! a block invariant along z is the 2D order-2 plane-strain run (every limiter, donor-cell
//! and CTU), and on a free block under a partial impact the momentum equals the impulse.
use impact_core::method::{Integrator, MethodKind, SchemeOrder, TransverseFlux, WaveLimiter};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::Dgmpm;

const STEEL: &str = "model = \"linear-elastic\"\nyoung = 2.0e11\npoisson = 0.3\ndensity = 7800.0";

/// Set order 2 with `limiter`, `flux` and `integrator` on a scene's DGMPM configuration.
fn order_two(
    scene: &Scene,
    limiter: WaveLimiter,
    flux: TransverseFlux,
    integrator: Integrator,
    courant: f64,
) -> impact_core::method::MethodConfig {
    let mut c = scene.method_config(MethodKind::Dgmpm);
    c.courant = courant;
    let o = c.dgmpm_mut().unwrap();
    (o.order, o.limiter, o.flux, o.integrator) =
        (SchemeOrder::Second, Some(limiter), flux, integrator);
    c
}

/// A block invariant along y and z (symmetry on its four side faces), Poisson's ratio 0, at
/// order 2 is the 1D order-2 bar: `σ_xx` and `v_x` equal to 1e-12 of their peaks, every
/// other field zero; each limiter, Euler (donor-cell and CTU) and RK2 (donor-cell: CTU with
/// RK2 leaves a sub-cell mode on the invariant axes, `tests/reductions.rs`).
#[test]
fn order_two_invariant_along_y_and_z_is_the_order_two_bar() {
    let bar = |three: Option<(usize, usize)>| {
        let material = "[material]\nmodel = \"linear-elastic\"\nyoung = 2.0e11\npoisson = 0.0\ndensity = 7800.0\n";
        let tail = "[time]\noutput_transits = [8]\n";
        match three {
            None => format!(
                "name = \"bar\"\ndim = 1\n[domain]\nlength = [6.0]\ncells = [60]\n{material}\
                 [boundary]\nleft = {{ kind = \"pressure\", value = 1.0e9 }}\nright = {{ kind = \"free\" }}\n{tail}"
            ),
            Some((ny, nz)) => format!(
                "name = \"bar\"\ndim = 3\n[domain]\nlength = [6.0, {}, {}]\ncells = [60, {ny}, {nz}]\n\
                 {material}[boundary]\nx.low = {{ kind = \"pressure\", value = 1.0e9 }}\n\
                 x.high = {{ kind = \"free\" }}\ny.low = {{ kind = \"symmetry\" }}\n\
                 y.high = {{ kind = \"symmetry\" }}\nz.low = {{ kind = \"symmetry\" }}\n\
                 z.high = {{ kind = \"symmetry\" }}\n{tail}",
                0.1 * ny as f64,
                0.1 * nz as f64
            ),
        }
    };
    let mut worst_all: f64 = 0.0;
    for limiter in WaveLimiter::ALL {
        // donor-cell inside its 3D limit (the round-off on the invariant axes must not grow)
        for (flux, integrator, courant) in [
            (TransverseFlux::DonorCell, Integrator::Euler, 0.3),
            (TransverseFlux::Ctu, Integrator::Euler, 0.9),
            (TransverseFlux::DonorCell, Integrator::Rk2, 0.3),
        ] {
            // past the reflection at the free end (60 cells)
            let steps = (80.0 / courant) as usize;
            let scene1 = Scene::from_toml(&bar(None), "1d").unwrap();
            let config = order_two(&scene1, limiter, flux, integrator, courant);
            let problem1 = Problem::<1>::from_scene(&scene1).unwrap();
            let mut one = Dgmpm::<1>::new(&problem1, config).unwrap();
            let dt = one.stable_dt();
            for n in 0..steps {
                one.step(n as f64 * dt, dt);
            }
            let p1 = &one.state.points;
            let (ss, sv) = p1.peaks();
            assert!(ss > 1e8 && sv > 1.0, "the wave must be there");
            for (ny, nz) in [(1, 1), (2, 3)] {
                let scene3 = Scene::from_toml(&bar(Some((ny, nz))), "3d").unwrap();
                let config = order_two(&scene3, limiter, flux, integrator, courant);
                let problem = Problem::<3>::from_scene(&scene3).unwrap();
                let mut three = Dgmpm::<3>::new(&problem, config).unwrap();
                for n in 0..steps {
                    three.step(n as f64 * dt, dt);
                }
                let p3 = &three.state.points;
                let (mut worst, mut off): (f64, f64) = (0.0, 0.0);
                for (i, (q, v)) in p3.stress.iter().zip(&p3.velocity).enumerate() {
                    let j = i % 60;
                    worst = worst
                        .max((q[(0, 0)] - p1.stress[j][(0, 0)]).abs() / ss)
                        .max((v[0] - p1.velocity[j][0]).abs() / sv);
                    let others = q.iter().skip(1).fold(0.0_f64, |m, x| m.max(x.abs()));
                    off = off.max(others / ss).max(v[1].abs().max(v[2].abs()) / sv);
                }
                let what = format!("{limiter} {flux} {integrator} {ny}x{nz}");
                println!("bar {what}: {worst:.1e}, others {off:.1e}");
                assert!(worst <= 1e-12, "bar {what}: {worst:e}");
                assert!(off <= 1e-12, "bar {what}: other fields {off:e}");
                worst_all = worst_all.max(worst);
            }
        }
    }
    println!("largest difference to the 1D order-2 bar: {worst_all:.2e}");
}

/// A 2D scene (`edges`: left, right, bottom, top) and its extrusion along z by `nz` cells
/// (symmetry z faces).
fn plane(edges: [&str; 4], segment: bool, nz: Option<usize>) -> String {
    let (nx, ny) = (24, 18);
    let dz = 4.0 / nx as f64;
    let mut s = String::from("name = \"plane\"\n");
    s += &match nz {
        None => format!("dim = 2\n[domain]\nlength = [4.0, 3.0]\ncells = [{nx}, {ny}]\n"),
        Some(nz) => format!(
            "dim = 3\n[domain]\nlength = [4.0, 3.0, {}]\ncells = [{nx}, {ny}, {nz}]\n",
            dz * nz as f64
        ),
    };
    s += &format!("[material]\n{STEEL}\n[boundary]\n");
    let names = match nz {
        None => ["left", "right", "bottom", "top"],
        Some(_) => ["x.low", "x.high", "y.low", "y.high"],
    };
    for (k, (name, keys)) in names.iter().zip(edges).enumerate() {
        let patch = match (k == 0 && segment, nz) {
            (false, _) => String::new(),
            (true, None) => ", from = 0.0, to = 1.0".to_string(),
            (true, Some(nz)) => format!(", from = [0.0, 0.0], to = [1.0, {}]", dz * nz as f64),
        };
        s += &format!("{name} = {{ {keys}{patch} }}\n");
    }
    if nz.is_some() {
        s += "z.low = { kind = \"symmetry\" }\nz.high = { kind = \"symmetry\" }\n";
    }
    s + "[time]\noutput_transits = [8]\n"
}

/// A block invariant along z (symmetry z faces, 1-2 cells) at order 2 is the 2D order-2
/// plane-strain run: in-plane fields equal to 1e-12 of their peaks, out-of-plane ones
/// zero; the plane wave along x (symmetry top and bottom) and the partial impact on a free
/// plate (its ghost rows behind the free edges and the corners), each limiter, CTU with
/// Euler and donor-cell with Euler and RK2.
#[test]
fn order_two_invariant_along_z_is_the_order_two_plane_strain_run() {
    let velocity = "kind = \"normal-velocity\", value = 5.0";
    let (free, symmetry) = ("kind = \"free\"", "kind = \"symmetry\"");
    let scenes = [
        ([velocity, free, symmetry, symmetry], false),
        ([velocity, free, free, free], true),
    ];
    let steps = 30;
    let mut worst_all: f64 = 0.0;
    for (edges, segment) in scenes {
        for limiter in WaveLimiter::ALL {
            for (flux, integrator, courant) in [
                (TransverseFlux::Ctu, Integrator::Euler, 0.9),
                (TransverseFlux::DonorCell, Integrator::Euler, 0.45),
                (TransverseFlux::DonorCell, Integrator::Rk2, 0.45),
            ] {
                let scene2 = Scene::from_toml(&plane(edges, segment, None), "2d").unwrap();
                let config = order_two(&scene2, limiter, flux, integrator, courant);
                let mut two =
                    Dgmpm::<2>::new(&Problem::<2>::from_scene(&scene2).unwrap(), config).unwrap();
                let dt = two.stable_dt();
                for n in 0..steps {
                    two.step(n as f64 * dt, dt);
                }
                let p2 = &two.state.points;
                let (ss, sv) = p2.peaks();
                assert!(ss > 0.0 && sv > 0.0, "a wave must be there");
                for nz in [1, 2] {
                    let scene3 = Scene::from_toml(&plane(edges, segment, Some(nz)), "3d").unwrap();
                    let config = order_two(&scene3, limiter, flux, integrator, courant);
                    let problem3 = Problem::<3>::from_scene(&scene3).unwrap();
                    let mut three = Dgmpm::<3>::new(&problem3, config).unwrap();
                    for n in 0..steps {
                        three.step(n as f64 * dt, dt);
                    }
                    let p3 = &three.state.points;
                    let layer = p2.len();
                    let (mut worst, mut off): (f64, f64) = (0.0, 0.0);
                    for (i, (q, v)) in p3.stress.iter().zip(&p3.velocity).enumerate() {
                        let (q2, v2) = (p2.stress[i % layer], p2.velocity[i % layer]);
                        for (r, c) in [(0, 0), (1, 1), (0, 1), (1, 0)] {
                            worst = worst.max((q[(r, c)] - q2[(r, c)]).abs() / ss);
                        }
                        for r in 0..2 {
                            worst = worst.max((v[r] - v2[r]).abs() / sv);
                        }
                        off = off
                            .max(q[(0, 2)].abs().max(q[(1, 2)].abs()) / ss)
                            .max(v[2].abs() / sv);
                    }
                    let what = format!("{edges:?} {limiter} {flux} {integrator} nz {nz}");
                    println!("{what}: in-plane {worst:.1e}, out-of-plane {off:.1e}");
                    assert!(worst <= 1e-12, "{what}: {worst:e}");
                    assert!(off <= 1e-12, "{what}: out-of-plane {off:e}");
                    worst_all = worst_all.max(worst);
                }
            }
        }
    }
    println!("largest difference to the 2D order-2 run: {worst_all:.2e}");
}

/// A free block with an impactor on a patch of one face, CTU at order 2: the momentum
/// equals the impulse the impactor delivered, to round-off, with and without a limiter,
/// Euler at one point per cell (the cell path) and RK2 at 8 (the nodal phases); donor-cell
/// with RK2 likewise.
#[test]
fn block_momentum_equals_the_impulse_at_order_two() {
    let text = format!(
        "name = \"block\"\ndim = 3\n[domain]\nlength = [2.0, 1.5, 1.0]\ncells = [8, 6, 4]\n\
         [material]\n{STEEL}\n[boundary]\n\
         x.low = {{ kind = \"normal-velocity\", value = 20.0, from = [0.0, 0.0], to = [1.0, 0.5] }}\n\
         [time]\noutput_transits = [4]\n"
    );
    let scene = Scene::from_toml(&text, "block").unwrap();
    let problem = Problem::<3>::from_scene(&scene).unwrap();
    for (ppc, flux, integrator, courant) in [
        (1, TransverseFlux::Ctu, Integrator::Euler, 0.9),
        (8, TransverseFlux::Ctu, Integrator::Rk2, 0.5),
        (8, TransverseFlux::DonorCell, Integrator::Rk2, 0.5),
    ] {
        for limiter in [WaveLimiter::None, WaveLimiter::Mc] {
            let mut c = order_two(&scene, limiter, flux, integrator, courant);
            c.points_per_cell = ppc;
            let mut dg = Dgmpm::<3>::new(&problem, c).unwrap();
            let dt = dg.stable_dt();
            for step in 0..20 {
                dg.step(step as f64 * dt, dt);
            }
            let (p, i) = (dg.momentum(), dg.external_impulse());
            assert!(i.norm() > 0.0);
            let what = format!("{ppc} ppc {flux} {integrator} {limiter}");
            println!("{what}: |p − I|/|I| = {:.1e}", (p - i).norm() / i.norm());
            assert!(
                (p - i).norm() < 1e-10 * i.norm(),
                "{what}: momentum {p:?} vs impulse {i:?}"
            );
        }
    }
}

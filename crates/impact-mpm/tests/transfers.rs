//! MPM velocity transfers (issue 26; `impact_mpm`'s `transfer` and `affine` modules).
//!
//! - APIC conserves linear momentum `Σ_p m_p v_p` and angular momentum
//!   `L = Σ_p m_p (x_p × v_p + ε : (C_p D_p)ᵀ)` (Jiang et al. 2015) to round-off on a free,
//!   spinning and breathing elastic body (no loads, free edges, symmetric stress: no torque),
//!   in 2D and 3D: with every shape in the total Lagrangian frame (`x` is `X`, `D_p` fixed)
//!   and with the B-splines (constant `D_p`) in the updated one, under USL, MUSL and USF.
//! - The blend is FLIP at `α = 1` and PIC at `α = 0`, bit for bit.
//! - PIC dissipates the standing wave's energy, FLIP keeps it.
use impact_core::method::{
    MethodConfig, MethodKind, MpmFrame, MpmShape, MpmTransfer, StressUpdate,
};
use impact_core::{Method, Problem, Scene, Tensor, Vector};
use impact_mpm::shape::weight;
use impact_mpm::Mpm;

/// A free square (2D, 1 m, 8 × 8 cells) or cube (3D, 1 m, 4 × 4 × 4 cells) of steel,
/// spinning about its centre and breathing (a uniform expansion rate, which loads it):
/// `v = ω × (x − c) + 50 (x − c)` m/s, `ω = 200 rad/s` about z (2D) or
/// `(60, −80, 200) rad/s` (3D). With `model`, J2 where the expansion yields it.
fn spinning(dim: usize, model: &str) -> Scene {
    let (cells, lengths, velocity) = if dim == 2 {
        (
            "8, 8",
            "1.0, 1.0",
            r#"["-200*(y-0.5) + 50*(x-0.5)", "200*(x-0.5) + 50*(y-0.5)"]"#,
        )
    } else {
        (
            "4, 4, 4",
            "1.0, 1.0, 1.0",
            r#"["-80*(z-0.5) - 200*(y-0.5) + 50*(x-0.5)", "200*(x-0.5) - 60*(z-0.5) + 50*(y-0.5)", "60*(y-0.5) + 80*(x-0.5) + 50*(z-0.5)"]"#,
        )
    };
    let material = match model {
        "j2" => "model = \"j2\"\nyield_stress = 2.0e8\nhardening = 2.0e10\n",
        "svk" => "model = \"svk\"\n",
        _ => "model = \"linear-elastic\"\n",
    };
    let text = format!(
        "name = \"spinning\"\ndim = {dim}\n[domain]\nlength = [{lengths}]\ncells = [{cells}]\n\
         [material]\n{material}young = 2.0e11\npoisson = 0.3\ndensity = 7800.0\n\
         [initial]\nvelocity = {velocity}\n[boundary]\nx.low = {{ kind = \"free\" }}\n[time]\noutput_times = [1.0e-3]\n[mpm]\ncourant = 0.5\n"
    );
    Scene::from_toml(&text, "transfers test").unwrap()
}

/// `D_aa = Σ_i w_ip (x_i − x_p)_a²` of the shape at grid coordinate `u` (cells) along one
/// axis, in cells² (the 1D weights, so independent of the solver's own sums).
fn inertia_1d(shape: MpmShape, half: f64, u: f64) -> f64 {
    let first = u.floor() as i64 - 3;
    (first..first + 7)
        .map(|i| {
            let d = u - i as f64;
            weight(shape, half, d).0 * d * d
        })
        .sum()
}

/// `(Σ_p m_p v_p, L)`: linear momentum and angular momentum (the components of `x × v`
/// that exist: 1 in 2D, 3 in 3D) with the affine part `ε : (C_p D_p)ᵀ`, at the points'
/// current positions (updated Lagrangian) or reference ones (total Lagrangian).
fn momenta<const D: usize>(
    mpm: &Mpm<D>,
    shape: MpmShape,
    frame: MpmFrame,
    ppa: usize,
) -> (Vector<D>, [f64; 3]) {
    let p = &mpm.state.points;
    let h = 1.0 / if D == 2 { 8.0 } else { 4.0 };
    let mut linear = Vector::<D>::zeros();
    let mut angular = [0.0; 3];
    for q in 0..p.len() {
        let x = match frame {
            MpmFrame::TotalLagrangian => p.reference[q],
            MpmFrame::UpdatedLagrangian => p.position[q],
        };
        let m = p.mass[q];
        linear += p.velocity[q] * m;
        // D_p: the grid's nodes lie at multiples of h from the body's origin (0)
        let inertia =
            Vector::<D>::from_fn(|a, _| h * h * inertia_1d(shape, 0.5 / ppa as f64, x[a] / h));
        let b = match mpm.state.affine.get(q) {
            Some(c) => c * Tensor::<D>::from_diagonal(&inertia),
            None => Tensor::<D>::zeros(),
        };
        let v = p.velocity[q];
        // (x × v + the antisymmetric part of B) per plane (a, b) → component 3 − a − b
        for (k, (a, c)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
            if a < D && c < D {
                angular[k] += m * (x[a] * v[c] - x[c] * v[a] + b[(c, a)] - b[(a, c)]);
            }
        }
    }
    (linear, angular)
}

/// Steps `steps` of APIC on the spinning body and returns the largest drift of the linear
/// and the angular momentum, relative to `Σ m |v|` and to `|L(0)|`.
fn drift<const D: usize>(
    model: &str,
    (shape, update, frame): (MpmShape, StressUpdate, MpmFrame),
    ppc: usize,
    steps: usize,
    floor: Option<f64>,
    transfer: MpmTransfer,
) -> (f64, f64) {
    let scene = spinning(D, model);
    let problem = Problem::<D>::from_scene(&scene).unwrap();
    let mut config: MethodConfig = scene.method_config(MethodKind::Mpm);
    config.points_per_cell = ppc;
    let o = config.mpm_mut().unwrap();
    (o.shape, o.stress_update, o.frame, o.transfer) = (shape, update, frame, transfer);
    let mut mpm = Mpm::<D>::new(&problem, config).unwrap();
    if let Some(fraction) = floor {
        mpm.solver.set_empty_node_floor(fraction);
    }
    let ppa = (1..=ppc).find(|n| n.pow(D as u32) == ppc).unwrap();
    let (p0, l0) = momenta(&mpm, shape, frame, ppa);
    let speed: f64 = (0..mpm.state.points.len())
        .map(|q| mpm.state.points.mass[q] * mpm.state.points.velocity[q].norm())
        .sum();
    let l0_norm = l0.iter().map(|l| l * l).sum::<f64>().sqrt();
    assert!(l0_norm > 0.0 && p0.amax() <= 1e-12 * speed);
    let dt = mpm.stable_dt();
    let (mut worst_p, mut worst_l) = (0.0f64, 0.0f64);
    for n in 0..steps {
        mpm.step(n as f64 * dt, dt);
        mpm.check_finite().unwrap();
        let (p, l) = momenta(&mpm, shape, frame, ppa);
        worst_p = worst_p.max((p - p0).amax() / speed);
        for k in 0..3 {
            worst_l = worst_l.max((l[k] - l0[k]).abs() / l0_norm);
        }
    }
    let moved: f64 = (0..mpm.state.points.len())
        .map(|q| (mpm.state.points.position[q] - mpm.state.points.reference[q]).norm())
        .fold(0.0, f64::max);
    // (PIC damps the rotation: the body turns less)
    assert!(
        moved > 0.05 || transfer != MpmTransfer::Apic,
        "the body must turn: moved {moved} m"
    );
    (worst_p, worst_l)
}

#[test]
fn apic_conserves_linear_and_angular_momentum_of_a_spinning_body() {
    let updates = [StressUpdate::Usl, StressUpdate::Musl, StressUpdate::Usf];
    let mut cases = Vec::new();
    for update in updates {
        for shape in [
            MpmShape::Linear,
            MpmShape::Gimp,
            MpmShape::Bspline2,
            MpmShape::Bspline3,
        ] {
            cases.push((shape, update, MpmFrame::TotalLagrangian));
        }
        for shape in [MpmShape::Bspline2, MpmShape::Bspline3] {
            cases.push((shape, update, MpmFrame::UpdatedLagrangian));
        }
    }
    // In the updated frame the solver's empty-node floor (1e-10 of a cell's mass,
    // `EmptyNodes`) drops the internal force on stencil-edge nodes that the body's last
    // points weight below it, and with it a torque: a B-spline's gradient there is
    // O(w^{1/2}) (quadratic) or O(w^{2/3}) (cubic), so the drift is ~1e-10, not round-off.
    // With the floor at 1e-16 of a cell's mass the same runs conserve to round-off, which
    // shows the transfer itself conserves L.
    for (shape, update, frame) in cases {
        let moving = frame == MpmFrame::UpdatedLagrangian;
        let floor = moving.then_some(1e-16);
        let (p, l) = drift::<2>(
            "elastic",
            (shape, update, frame),
            4,
            150,
            floor,
            MpmTransfer::Apic,
        );
        println!("2D {shape} {update} {frame}: linear {p:.2e}, angular {l:.2e}");
        assert!(
            p < 1e-13 && l < 1e-13,
            "2D {shape} {update} {frame}: {p:e} {l:e}"
        );
        if moving {
            let (p, l) = drift::<2>(
                "elastic",
                (shape, update, frame),
                4,
                150,
                None,
                MpmTransfer::Apic,
            );
            println!("  with the default floor: linear {p:.2e}, angular {l:.2e}");
            assert!(
                p < 1e-13 && l < 1e-8,
                "2D {shape} {update} {frame}: {p:e} {l:e}"
            );
        }
    }
    // J2 (a symmetric stress too) and 3D
    let (p, l) = drift::<2>(
        "j2",
        (
            MpmShape::Bspline2,
            StressUpdate::Usl,
            MpmFrame::UpdatedLagrangian,
        ),
        4,
        150,
        Some(1e-16),
        MpmTransfer::Apic,
    );
    assert!(p < 1e-13 && l < 1e-13, "2D J2: {p:e} {l:e}");
    for (shape, frame) in [
        (MpmShape::Bspline2, MpmFrame::UpdatedLagrangian),
        (MpmShape::Linear, MpmFrame::TotalLagrangian),
    ] {
        let (p, l) = drift::<3>(
            "elastic",
            (shape, StressUpdate::Usl, frame),
            1,
            60,
            Some(1e-16),
            MpmTransfer::Apic,
        );
        println!("3D {shape} {frame}: linear {p:.2e}, angular {l:.2e}");
        assert!(p < 1e-13 && l < 1e-13, "3D {shape} {frame}: {p:e} {l:e}");
    }
}

/// Without the affine part the same body loses angular momentum: PIC's transfers filter
/// the rotation (Jiang et al. 2015, §1), so the test above can fail.
#[test]
fn pic_loses_the_angular_momentum_that_apic_keeps() {
    let shape = MpmShape::Bspline2;
    let (update, frame) = (StressUpdate::Usl, MpmFrame::UpdatedLagrangian);
    let (p, l) = drift::<2>(
        "elastic",
        (shape, update, frame),
        4,
        150,
        Some(1e-16),
        MpmTransfer::Pic,
    );
    println!("PIC: linear {p:.2e}, angular {l:.2e}");
    assert!(p < 1e-13 && l > 1e-2, "PIC: {p:e} {l:e}");
}

/// Steps of MPM on the shipped scene `name` with `edit`; the final points.
fn run<const D: usize>(name: &str, steps: usize, edit: impl Fn(&mut MethodConfig)) -> Mpm<D> {
    let scene = Scene::builtin(name).unwrap();
    let problem = Problem::<D>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    edit(&mut config);
    let mut mpm = Mpm::<D>::new(&problem, config).unwrap();
    let dt = mpm.stable_dt();
    for n in 0..steps {
        mpm.step(n as f64 * dt, dt);
    }
    mpm
}

/// The blend `α (v_p + Δv) + (1 − α) v_i` is FLIP at `α = 1` and PIC at `α = 0` bit for
/// bit (`1·a + 0·b = a` and `0·a + 1·b = b` in floating point for finite values): on the
/// loaded bar and plate, every shape, USL and MUSL, both frames.
#[test]
fn blend_is_flip_at_one_and_pic_at_zero_bit_for_bit() {
    fn same<const D: usize>(a: &Mpm<D>, b: &Mpm<D>) -> bool {
        let (a, b) = (&a.state.points, &b.state.points);
        a.velocity == b.velocity && a.position == b.position && a.stress == b.stress
    }
    fn check<const D: usize>(scene: &str) {
        for shape in MpmShape::ALL {
            for (update, frame) in [
                (StressUpdate::Usl, MpmFrame::TotalLagrangian),
                (StressUpdate::Musl, MpmFrame::UpdatedLagrangian),
            ] {
                let with = |transfer: MpmTransfer, alpha: Option<f64>| {
                    run::<D>(scene, 40, |c| {
                        let o = c.mpm_mut().unwrap();
                        (o.shape, o.stress_update, o.frame) = (shape, update, frame);
                        (o.transfer, o.flip_fraction) = (transfer, alpha);
                    })
                };
                let flip = with(MpmTransfer::Flip, None);
                let pic = with(MpmTransfer::Pic, None);
                assert!(
                    !same(&flip, &pic),
                    "{scene} {shape}: FLIP and PIC must differ"
                );
                assert!(
                    same(&flip, &with(MpmTransfer::Blend, Some(1.0))),
                    "{scene} {shape} {update}: α = 1"
                );
                assert!(
                    same(&pic, &with(MpmTransfer::Blend, Some(0.0))),
                    "{scene} {shape} {update}: α = 0"
                );
            }
        }
    }
    check::<1>("bar");
    check::<2>("plate");
}

/// The standing wave of `smooth-bar` (no loads, fixed ends: its energy is constant) after
/// four periods: FLIP keeps its energy within 0.5 %, PIC filters the velocity at every
/// step and loses more than ten times as much. The filter: at one point per cell at the
/// cell centres with hats, PIC's round trip multiplies the mode `sin kx` by
/// `r = cos²(kh/2)`; half of the energy being kinetic on average, the energy decays by
/// about `(1 − r²)/2` per step, `exp(−N (1 − r²)/2)` after `N` steps (0.76 for the 2400
/// steps of four periods at 150 cells and Courant 0.5): the measured ratio must lie within
/// 1 % of it (measured 0.76859 against 0.76861).
#[test]
fn pic_dissipates_the_standing_wave_and_flip_does_not() {
    let scene = Scene::builtin("smooth-bar").unwrap();
    let cells = scene.domain.cells[0] as f64;
    let (length, speed) = (scene.domain.length[0], (2.0e11f64 / 7800.0).sqrt());
    let period = 2.0 * length / speed;
    let dt = 0.5 * length / cells / speed;
    let steps = (4.0 * period / dt).round() as usize;
    let energy = |transfer: MpmTransfer| {
        let mpm = run::<1>("smooth-bar", steps, |c| {
            c.mpm_mut().unwrap().transfer = transfer
        });
        mpm.energy() / mpm.initial_energy()
    };
    let (flip, pic) = (energy(MpmTransfer::Flip), energy(MpmTransfer::Pic));
    let kh = std::f64::consts::PI / cells;
    let r = (kh / 2.0).cos().powi(2);
    let predicted = (-(steps as f64) * (1.0 - r * r) / 2.0).exp();
    println!("{steps} steps: E/E0 FLIP {flip:.5}, PIC {pic:.5}, PIC's filter {predicted:.5}");
    assert!((1.0 - flip).abs() < 5e-3, "FLIP: {flip}");
    assert!(
        1.0 - pic > 10.0 * (1.0 - flip).abs(),
        "PIC {pic} against FLIP {flip}"
    );
    assert!(
        (pic / predicted - 1.0).abs() < 0.05,
        "PIC {pic}, filter {predicted}"
    );
}

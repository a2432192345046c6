//! DGMPM with `order = 2` (the limited wave corrections, `wave_correction.rs`) in 1D: equal
//! to a hand-written Clawpack-form wave-propagation update (LeVeque 2002, eq. 6.59 and
//! §15.4; Clawpack classic `step1` with `limiter.f`) at one point per cell, conservative,
//! TVD with each limiter, and the same on every general step path.
use impact_core::method::{
    DgmpmOptions, Integrator, MethodConfig, MethodOptions, SchemeOrder, WaveLimiter,
};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::limiter::limiter_phi;
use impact_dgmpm::{Dgmpm, StepPath};

fn config(courant: f64, ppc: usize, integrator: Integrator, limiter: WaveLimiter) -> MethodConfig {
    MethodConfig {
        courant,
        points_per_cell: ppc,
        options: MethodOptions::Dgmpm(DgmpmOptions {
            integrator,
            order: SchemeOrder::Second,
            limiter: Some(limiter),
            ..DgmpmOptions::default()
        }),
    }
}

/// The bar (left end: step pressure `T`, right end free) with `cells` cells.
fn bar(cells: usize) -> (Problem<1>, f64) {
    let mut scene = Scene::builtin("bar").unwrap();
    scene.domain.cells = vec![cells];
    (Problem::<1>::from_scene(&scene).unwrap(), 1e9)
}

/// Clawpack's wave-propagation step on `q = (σ, ρv)` with two ghost cells each side
/// (mirrors through the ends: pressure `T` on the left `σ_g = −2T − σ`, free on the right
/// `σ_g = −σ`, velocity kept), the eigenvectors of `σ_t = E v_x`, `v_t = σ_x/ρ` worked by
/// hand: with `δ = q_R − q_L`, `α¹ = (δσ + Z δv)/(2Z)` along `r¹ = (Z, 1)` in `(σ, v)` at
/// `s¹ = −c`, `α² = (−δσ + Z δv)/(2Z)` along `r² = (−Z, 1)` at `s² = c`; the limiter reads `θ` from the
/// upwind face's wave; `q_i −= Δt/Δx (A⁺ΔQ_{i−½} + A⁻ΔQ_{i+½} + F̃_{i+½} − F̃_{i−½})`.
fn clawpack_step(
    sigma: &mut [f64],
    v: &mut [f64],
    (rho, young, load): (f64, f64, f64),
    dtdx: f64,
    limiter: WaveLimiter,
) {
    let n = sigma.len();
    let z = (rho * young).sqrt();
    let c = z / rho;
    // padded cells: 2 ghosts each side, in (σ, v)
    let mut q = vec![(0.0, 0.0); n + 4];
    for i in 0..n {
        q[i + 2] = (sigma[i], v[i]);
    }
    let second = |i: usize| if n > 1 { i } else { 0 };
    q[1] = (-2.0 * load - sigma[0], v[0]);
    q[0] = (-2.0 * load - sigma[second(1)], v[second(1)]);
    q[n + 2] = (-sigma[n - 1], v[n - 1]);
    q[n + 3] = (-sigma[n - 1 - second(1)], v[n - 1 - second(1)]);
    // waves at padded face j (between padded cells j - 1 and j), j = 1..n+3, as (σ, ρv)
    let mut waves = vec![[(0.0, 0.0); 2]; n + 4];
    for j in 1..n + 4 {
        let (ds, dv) = (q[j].0 - q[j - 1].0, q[j].1 - q[j - 1].1);
        let a1 = (ds + z * dv) / (2.0 * z);
        let a2 = (-ds + z * dv) / (2.0 * z);
        waves[j] = [(z * a1, rho * a1), (-z * a2, rho * a2)];
    }
    let speed = [-c, c];
    // the faces that update the interior: padded j = 2..=n+2
    let mut flux2 = vec![(0.0, 0.0); n + 4];
    for j in 2..=n + 2 {
        let mut f = (0.0, 0.0);
        for p in 0..2 {
            let w = waves[j][p];
            let up = if speed[p] > 0.0 {
                waves[j - 1][p]
            } else {
                waves[j + 1][p]
            };
            let norm = w.0 * w.0 + w.1 * w.1;
            if norm == 0.0 {
                continue;
            }
            let phi = limiter_phi(limiter, (up.0 * w.0 + up.1 * w.1) / norm);
            let k = 0.5 * speed[p].abs() * (1.0 - dtdx * speed[p].abs()) * phi;
            f = (f.0 + k * w.0, f.1 + k * w.1);
        }
        flux2[j] = f;
    }
    for i in 0..n {
        let (jl, jr) = (i + 2, i + 3);
        // A⁺ΔQ at the left face (its right-going wave times c), A⁻ΔQ at the right face
        let apdq = (c * waves[jl][1].0, c * waves[jl][1].1);
        let amdq = (-c * waves[jr][0].0, -c * waves[jr][0].1);
        let ds = dtdx * (apdq.0 + amdq.0 + flux2[jr].0 - flux2[jl].0);
        let dm = dtdx * (apdq.1 + amdq.1 + flux2[jr].1 - flux2[jl].1);
        sigma[i] -= ds;
        v[i] -= dm / rho;
    }
}

/// Lax-Wendroff (no limiter) and every limiter: DGMPM order 2 at one point per cell equals
/// the hand-written Clawpack update to round-off over 120 steps (through the reflection at
/// the free end), at Courant 0.8 and 0.5, on the cell path and the nodal phases.
#[test]
fn one_point_per_cell_equals_the_clawpack_wave_propagation_update() {
    let (problem, load) = bar(30);
    let m = problem.material;
    for limiter in WaveLimiter::ALL {
        for courant in [0.8, 0.5] {
            for path in [StepPath::Cell, StepPath::SinglePoint] {
                let mut dg =
                    Dgmpm::new(&problem, config(courant, 1, Integrator::Euler, limiter)).unwrap();
                dg.solver.set_step_path(path, &dg.state.points).unwrap();
                let dt = dg.stable_dt();
                let dtdx = dt / problem.grid.spacing[0];
                let n = problem.grid.cells[0];
                let (mut sigma, mut v) = (vec![0.0; n], vec![0.0; n]);
                for step in 0..120 {
                    dg.step(step as f64 * dt, dt);
                    clawpack_step(
                        &mut sigma,
                        &mut v,
                        (m.density, m.elastic.young, load),
                        dtdx,
                        limiter,
                    );
                }
                let p = &dg.state.points;
                let vscale = load / (m.density * m.elastic.young).sqrt();
                for i in 0..n {
                    let (ds, dv) = (
                        (p.stress[i][(0, 0)] - sigma[i]).abs() / load,
                        (p.velocity[i][0] - v[i]).abs() / vscale,
                    );
                    assert!(
                        ds < 1e-12 && dv < 1e-12,
                        "{limiter} C = {courant} {path:?} cell {i}: σ {ds:.2e}, v {dv:.2e}"
                    );
                }
            }
        }
    }
}

/// TVD: with every limiter the step load on the bar stays within the exact solution's range,
/// `[−T, 0]` in stress and `[0, 2T/Z]` in velocity (the free end doubles it), through the
/// reflection at the free end (no new extrema beyond round-off); Lax-Wendroff overshoots
/// (so the check can fail).
#[test]
fn limited_corrections_make_no_new_extrema_and_lax_wendroff_does() {
    let (problem, load) = bar(150);
    let m = problem.material;
    let vmax = load / (m.density * m.elastic.young).sqrt();
    for limiter in WaveLimiter::ALL {
        let mut dg = Dgmpm::new(&problem, config(0.5, 1, Integrator::Euler, limiter)).unwrap();
        let dt = dg.stable_dt();
        let mut worst: f64 = 0.0;
        // 400 steps: a transit at Courant 0.5 is 300 steps, so the front has reflected
        for step in 0..400 {
            dg.step(step as f64 * dt, dt);
            let p = &dg.state.points;
            for i in 0..p.len() {
                let s = p.stress[i][(0, 0)] / load;
                let v = p.velocity[i][0] / vmax;
                let outside = s.max(-1.0 - s).max(-v).max(v - 2.0).max(0.0);
                worst = worst.max(outside);
            }
        }
        if limiter == WaveLimiter::None {
            assert!(worst > 1e-2, "Lax-Wendroff overshoots: {worst:.2e}");
        } else {
            assert!(
                worst < 1e-12,
                "{limiter}: new extremum {worst:.2e} of the load"
            );
        }
    }
}

/// Momentum: with both ends free, an initial velocity pulse keeps the bar's momentum to
/// round-off with the corrections (they are flux differences, and carry no traction at a
/// free end), with Euler and RK2, at 1 and 4 points per cell.
#[test]
fn free_bar_conserves_momentum() {
    let mut scene = Scene::builtin("bar").unwrap();
    scene.domain.cells = vec![40];
    scene.boundary.left = scene.boundary.right.clone();
    let mut problem = Problem::<1>::from_scene(&scene).unwrap();
    problem.boundaries = [[impact_core::Boundary::Free; 2]];
    for (ppc, integrator) in [
        (1, Integrator::Euler),
        (1, Integrator::Rk2),
        (4, Integrator::Rk2),
    ] {
        for limiter in [WaveLimiter::None, WaveLimiter::Mc] {
            let mut dg = Dgmpm::new(&problem, config(0.6, ppc, integrator, limiter)).unwrap();
            dg.perturb_velocity(&mut |_, x| {
                impact_core::Vector::<1>::new(if (2.0..3.0).contains(&x[0]) { 3.0 } else { 0.0 })
            });
            let p0 = dg.momentum()[0];
            assert!(p0.abs() > 0.0);
            let dt = dg.stable_dt();
            for step in 0..300 {
                dg.step(step as f64 * dt, dt);
            }
            let p1 = dg.momentum()[0];
            assert!(
                (p1 - p0).abs() < 1e-12 * p0.abs(),
                "{ppc} ppc {integrator} {limiter}: {p0} -> {p1}"
            );
        }
    }
}

/// The rod's elastoplastic solver with order 2: the plastic wave (local Courant number
/// `c_t/c_0 ≈ 0.30` at the elastic Courant number 1) is sharpened by the corrections of its
/// own family. On `ep-bar` (pressure `2σ_y`) after 100 steps: the cells inside the plastic
/// front (stress between 10 % and 90 % of the way from the elastic precursor's `−σ_y` to the
/// plastic state) number fewer with each TVD limiter than at order 1, and the stress stays in
/// `[−T, 0]` (no overshoot).
#[test]
fn elastoplastic_waves_sharpen_the_plastic_front_without_overshoot() {
    use impact_core::method::RiemannSolver;
    let scene = Scene::builtin("ep-bar").unwrap();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let (load, yield_stress) = (8.0e8, 4.0e8);
    let front = |order: SchemeOrder, limiter: Option<WaveLimiter>| {
        let mut c = scene.method_config(impact_core::MethodKind::Dgmpm);
        let o = c.dgmpm_mut().unwrap();
        (o.riemann, o.order, o.limiter) = (RiemannSolver::Elastoplastic, order, limiter);
        let mut dg = Dgmpm::new(&problem, c).unwrap();
        let dt = dg.stable_dt();
        for step in 0..100 {
            dg.step(step as f64 * dt, dt);
        }
        let stress: Vec<f64> = dg.state.points.stress.iter().map(|s| s[(0, 0)]).collect();
        let plastic = stress[5];
        let (lo, hi) = (
            plastic + 0.1 * (-yield_stress - plastic),
            plastic + 0.9 * (-yield_stress - plastic),
        );
        let inside = stress.iter().filter(|&&s| s > lo && s < hi).count();
        let worst = stress
            .iter()
            .map(|&s| (s / load).max(-1.0 - s / load))
            .fold(0.0, f64::max);
        (inside, worst)
    };
    let (first, _) = front(SchemeOrder::First, None);
    for limiter in [
        WaveLimiter::Minmod,
        WaveLimiter::VanLeer,
        WaveLimiter::Mc,
        WaveLimiter::Superbee,
    ] {
        let (second, worst) = front(SchemeOrder::Second, Some(limiter));
        assert!(
            second < first,
            "{limiter}: {second} cells in the front vs {first} at order 1"
        );
        assert!(
            worst < 1e-12,
            "{limiter}: overshoot {worst:.2e} of the load"
        );
    }
}

/// 2D, CTU with order 2 on the paper's plate (restricted edges: free edges stay
/// traction-free): the momentum equals the impulse the impactor delivered, to round-off,
/// with and without a limiter, Euler at 1 point per cell and RK2 at 4.
#[test]
fn plate_momentum_equals_the_impulse() {
    let scene = Scene::builtin("plate").unwrap();
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    for (ppc, integrator, courant) in [(1, Integrator::Euler, 0.9), (4, Integrator::Rk2, 0.6)] {
        for limiter in [WaveLimiter::None, WaveLimiter::Mc] {
            let mut c = scene.method_config(impact_core::MethodKind::Dgmpm);
            c.courant = courant;
            c.points_per_cell = ppc;
            let o = c.dgmpm_mut().unwrap();
            (o.integrator, o.order, o.limiter) = (integrator, SchemeOrder::Second, Some(limiter));
            let mut dg = Dgmpm::<2>::new(&problem, c).unwrap();
            let dt = dg.stable_dt();
            for step in 0..30 {
                dg.step(step as f64 * dt, dt);
            }
            let (p, i) = (dg.momentum(), dg.external_impulse());
            assert!(i.norm() > 0.0);
            assert!(
                (p - i).norm() < 1e-10 * i.norm(),
                "{ppc} ppc {integrator} {limiter}: momentum {p:?} vs impulse {i:?}"
            );
        }
    }
}

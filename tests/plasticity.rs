//! Elastoplastic impact (issue 12): J2 with the return map at the points (DGMPM with the
//! elastic Riemann solver, MPM) and at the Gauss points (FEM), against the exact precursor
//! and plastic wave of `ep-bar` (rod) and `ep-plate-wave` (uniaxial strain).
use crate::common::{impact, text, tmp, vtu_text};
use impact::run::{run_method, Silent};
use impact_core::method::MethodKind;
use impact_core::reference::Reference;
use impact_core::{Method, Problem, Scene};

fn advance<const D: usize>(
    problem: &Problem<D>,
    scene: &Scene,
    kind: MethodKind,
    t: f64,
) -> Box<dyn Method<D>> {
    let mut m = impact::build(problem, scene.method_config(kind)).unwrap();
    let dt = m.stable_dt();
    let steps = (t / dt).round() as usize;
    for k in 0..steps {
        m.step(k as f64 * dt, dt);
    }
    m.check_finite().unwrap();
    m
}

/// The shipped scene `name` with `cells` cells along x (the others in proportion) and its
/// output times kept in seconds (transits scaled by the refinement).
fn refined(name: &str, cells: usize) -> Scene {
    let mut scene = Scene::builtin(name).unwrap();
    let ratio = cells as f64 / scene.domain.cells[0] as f64;
    scene
        .domain
        .cells
        .iter_mut()
        .for_each(|n| *n = (*n as f64 * ratio).round() as usize);
    scene.time.output_transits = scene
        .time
        .output_transits
        .map(|v| v.iter().map(|t| t * ratio).collect());
    scene
}

/// Momentum equals the impulse of the load (to round-off). The energy — kinetic, elastic
/// and the plastic work `∫ q dε̄` — balances the work the method's load did up to a defect
/// that shrinks under refinement: FEM about second order, MPM first, DGMPM about half order
/// (its upwind fluxes dissipate at the plastic shock, which the elastic Riemann solver
/// carries at an effective Courant number `c_t/c_0 = 0.30` on the rod). Measured on ep-bar
/// at 150, 300, 600 cells: DGMPM −4.4, −3.2, −2.3 %; MPM −0.16, −0.11, −0.064 %; FEM
/// −0.031, −0.015, −0.0074 %.
#[test]
fn momentum_and_energy_balance() {
    for (name, levels) in [
        ("ep-bar", &[150usize, 300, 600][..]),
        ("ep-plate-wave", &[32, 64][..]),
    ] {
        for kind in MethodKind::ALL {
            let mut defects = Vec::new();
            for &cells in levels {
                let scene = refined(name, cells);
                let (energy, work, p, j) = if scene.dim == 1 {
                    let problem = Problem::<1>::from_scene(&scene).unwrap();
                    let m = advance(&problem, &scene, kind, problem.t_end);
                    (
                        m.energy(),
                        m.external_work(),
                        m.momentum()[0],
                        m.external_impulse()[0],
                    )
                } else {
                    let problem = Problem::<2>::from_scene(&scene).unwrap();
                    let m = advance(&problem, &scene, kind, problem.t_end);
                    (
                        m.energy(),
                        m.external_work(),
                        m.momentum()[0],
                        m.external_impulse()[0],
                    )
                };
                let defect = energy / work - 1.0;
                println!(
                    "{name} {cells} {kind}: energy {energy:.6e}, work {work:.6e} ({defect:+.2e})"
                );
                assert!(
                    ((p - j) / j).abs() < 1e-9,
                    "{name} {kind}: momentum {p} vs impulse {j}"
                );
                assert!(
                    defect.abs() < 0.05,
                    "{name} {cells} {kind}: energy defect {defect}"
                );
                defects.push(defect.abs());
            }
            for pair in defects.windows(2) {
                assert!(
                    pair[1] < pair[0],
                    "{name} {kind}: the energy defect must shrink: {defects:?}"
                );
            }
        }
    }
}

/// Each method's leading front (the elastic precursor) is within one cell of its exact
/// position at every output (MPM: two), and so is the plastic wave (measured lags at
/// 0.79 ms: DGMPM 0.036 m, FEM 0.034 m, MPM 0.045 m: 0.9, 0.8 and 1.1 cells), and the L1 error against the exact two-wave solution stays
/// below 10 %.
#[test]
fn precursor_position_and_l1_on_the_rod() {
    both_fronts_within_a_cell::<1>(&Scene::builtin("ep-bar").unwrap());
}

/// Every method on `scene`: at every output, the precursor and the plastic wave (where the
/// profile crosses half its jump) within one cell of their exact positions (MPM: two), and
/// the L1 error against the exact two-wave solution below 10 %.
fn both_fronts_within_a_cell<const D: usize>(scene: &Scene) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let reference = Reference::for_problem(&problem).unwrap();
    let dx = problem.grid.spacing[0];
    for kind in MethodKind::ALL {
        let (rec, blowup) = run_method(
            &problem,
            scene.method_config(kind),
            Some(&reference),
            &mut Silent,
        )
        .unwrap();
        assert!(blowup.is_none(), "{kind}: {blowup:?}");
        // MPM's precursor lags by a growing distance (its lumped-mass dispersion slows the
        // short waves of a front: on ep-bar 0.013, 0.028, 0.047 m at 0.2, 0.4, 0.8 ms)
        let cells = if kind == MethodKind::Mpm { 2.0 } else { 1.0 };
        for t in &rec.times {
            let (at, exact) = (t.front_position.unwrap(), t.front_exact.unwrap());
            let (plastic_at, plastic_exact) = t.plastic_front_position.expect("a plastic wave");
            println!(
                "{} {kind} t = {:.3e}: L1 {:.3e}, precursor {at:.4} m ({exact:.4}), \
                 plastic wave {plastic_at:.4} m ({plastic_exact:.4})",
                scene.name, t.t, t.l1
            );
            assert!((at - exact).abs() <= cells * dx, "{kind}: {at} vs {exact}");
            assert!(
                (plastic_at - plastic_exact).abs() <= cells * dx,
                "{kind}: plastic wave at {plastic_at} vs {plastic_exact}"
            );
            assert!(t.l1 < 0.1, "{kind}: L1 {}", t.l1);
        }
    }
}

/// With a yield stress far above the load, J2 is linear elasticity: every method gives the
/// elastic bar's fields to round-off.
#[test]
fn unreachable_yield_is_linear_elasticity() {
    let mut plastic = Scene::builtin("ep-bar").unwrap();
    plastic.material.yield_stress = Some(1.9e11);
    let mut elastic = plastic.clone();
    elastic.material.model = impact_core::method::MaterialModel::LinearElastic;
    (elastic.material.yield_stress, elastic.material.hardening) = (None, None);
    let (pp, pe) = (
        Problem::<1>::from_scene(&plastic).unwrap(),
        Problem::<1>::from_scene(&elastic).unwrap(),
    );
    for kind in MethodKind::ALL {
        let (a, b) = (
            advance(&pp, &plastic, kind, pp.t_end),
            advance(&pe, &elastic, kind, pe.t_end),
        );
        let (mut sa, mut sb) = (Default::default(), Default::default());
        a.sample_into(&mut sa);
        b.sample_into(&mut sb);
        let sa: impact_core::Samples<1> = sa;
        let sb: impact_core::Samples<1> = sb;
        let worst = sa
            .stress
            .iter()
            .zip(&sb.stress)
            .map(|(x, y)| (x - y).abs().max())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-12 * 8e8, "{kind}: {worst} Pa");
    }
}

fn rod_errors(
    cells: usize,
    kind: MethodKind,
    riemann: Option<impact_core::method::RiemannSolver>,
) -> Vec<f64> {
    let scene = refined("ep-bar", cells);
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let reference = Reference::for_problem(&problem).unwrap();
    let mut config = scene.method_config(kind);
    if let (Some(r), Some(o)) = (riemann, config.dgmpm_mut()) {
        o.riemann = r;
    }
    let (rec, blowup) = run_method(&problem, config, Some(&reference), &mut Silent).unwrap();
    assert!(blowup.is_none());
    rec.times.iter().map(|t| t.l1).collect()
}

/// The elastoplastic Riemann solver (`--riemann elastoplastic`) against the elastic one
/// followed by the return map: a smaller L1 error at every output, and no overshoot behind
/// the plastic wave (measured 0.00 % at 150 cells; the elastic solver's L1 is 7.3e-2,
/// 5.7e-2, 4.0e-2 against 4.3e-2, 3.8e-2, 2.7e-2).
#[test]
fn elastoplastic_solver_beats_the_elastic_one_on_the_rod() {
    use impact_core::method::RiemannSolver;
    let elastic = rod_errors(150, MethodKind::Dgmpm, Some(RiemannSolver::Elastic));
    let plastic = rod_errors(150, MethodKind::Dgmpm, Some(RiemannSolver::Elastoplastic));
    println!("elastic solver L1 {elastic:?}, elastoplastic solver L1 {plastic:?}");
    for (e, p) in elastic.iter().zip(&plastic) {
        assert!(p < e, "{plastic:?} vs {elastic:?}");
    }
    // the fields of the elastoplastic run: peak compression within 1 % of the load
    let mut scene = Scene::builtin("ep-bar").unwrap();
    scene.dgmpm.riemann = Some(RiemannSolver::Elastoplastic);
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let m = advance(&problem, &scene, MethodKind::Dgmpm, problem.t_end);
    let mut samples = impact_core::Samples::<1>::default();
    m.sample_into(&mut samples);
    let peak = samples
        .stress
        .iter()
        .map(|s| -s[(0, 0)])
        .fold(0.0, f64::max);
    assert!(peak <= 1.01 * 8e8, "peak compression {peak}");
}

/// Every method converges on the rod under refinement (L1 at the last output, 150 to 600
/// cells). The solution is two jumps, so the L1 order is that of a scheme on a jump
/// (LeVeque 2002, §8.7): 1/2 for a first-order dissipative scheme, 2/3 for a second-order
/// one. DGMPM (first-order upwind): 1/2 ± 0.05 at each step (measured 0.52, 0.49). MPM
/// (second order in space, its velocity lagging by O(Δt)): between 1/2 and 2/3 in the mean
/// (measured 0.64, 0.54, mean 0.59). FEM (second order): 2/3 expected, measured 0.82, 0.44
/// (mean 0.63): the steps scatter as its dispersive wake behind the plastic shock samples
/// differently at each level, so only the mean is bounded, 2/3 ± 0.1.
#[test]
fn every_method_converges_on_the_rod() {
    for kind in MethodKind::ALL {
        let errors: Vec<f64> = [150, 300, 600]
            .iter()
            .map(|&n| *rod_errors(n, kind, None).last().unwrap())
            .collect();
        let orders = impact_core::metrics::observed_orders(&errors);
        let mean = (errors[0] / errors[2]).log2() / 2.0;
        println!("{kind}: L1 {errors:?}, orders {orders:.3?}, mean {mean:.3}");
        assert!(orders.iter().all(|&o| o > 0.0), "{kind}: {orders:?}");
        match kind {
            MethodKind::Dgmpm => {
                assert!(orders.iter().all(|o| (o - 0.5).abs() < 0.05), "{orders:?}")
            }
            MethodKind::Mpm => assert!(mean > 0.5 && mean < 2.0 / 3.0, "{mean}"),
            MethodKind::Fem => assert!((mean - 2.0 / 3.0).abs() < 0.1, "{mean}"),
        }
    }
}

/// Both fronts of ep-bar: with the elastoplastic Riemann solver DGMPM overshoots by less
/// than 1 % at the precursor and at the plastic wave at every output (the thesis's
/// finding); the elastic solver with the return map and MPM are printed beside it
/// (measured at 0.79 ms: MPM overshoots the plastic wave by 3.7 %; DGMPM's plastic wave is
/// wider, 11.8 cells against MPM's 5.9, since it moves at an effective Courant number of
/// `c_t/c_0 = 0.30`).
#[test]
fn elastoplastic_solver_has_no_overshoot_at_either_front() {
    use impact_core::method::RiemannSolver;
    let scene = Scene::builtin("ep-bar").unwrap();
    let problem = Problem::<1>::from_scene(&scene).unwrap();
    let reference = Reference::for_problem(&problem).unwrap();
    let run = |kind: MethodKind, riemann: Option<RiemannSolver>| {
        let mut config = scene.method_config(kind);
        if let (Some(r), Some(o)) = (riemann, config.dgmpm_mut()) {
            o.riemann = r;
        }
        run_method(&problem, config, Some(&reference), &mut Silent)
            .unwrap()
            .0
    };
    for (label, rec) in [
        (
            "dgmpm elastoplastic",
            run(MethodKind::Dgmpm, Some(RiemannSolver::Elastoplastic)),
        ),
        (
            "dgmpm elastic",
            run(MethodKind::Dgmpm, Some(RiemannSolver::Elastic)),
        ),
        ("mpm", run(MethodKind::Mpm, None)),
    ] {
        for t in &rec.times {
            let (o1, o2) = (t.overshoot_pct.unwrap(), t.plastic_overshoot_pct.unwrap());
            println!(
                "{label} t = {:.3e}: precursor {:.2} cells, {o1:.3} %; plastic wave {:.2} cells, {o2:.3} %",
                t.t,
                t.front_width_cells.unwrap_or(f64::NAN),
                t.plastic_front_width_cells.unwrap_or(f64::NAN)
            );
            if label == "dgmpm elastoplastic" {
                assert!(o1 < 1.0 && o2 < 1.0, "{label}: {o1} %, {o2} %");
            }
        }
    }
}

/// In plane strain the elastoplastic solver follows each side's uniaxial-strain path to the
/// yield surface (the Hugoniot elastic limit from rest) and then the plastic modulus. On the
/// plane wave (DCU at Courant 0.6: CTU's corrections are elastic and refused with it; the
/// wave is invariant along y, so the scheme is 1D Godunov with the exact piecewise-linear
/// Riemann solver, at Courant 0.6 for the precursor and `0.6 c_p/c_L = 0.48` for the
/// plastic wave) the physics guarantees at the last output (0.51 ms, before the precursor
/// reaches the free edge):
/// - no overshoot anywhere: both waves compress and accelerate towards the impactor, so
///   the exact profile is monotone between rest and the state behind the plastic wave, and
///   a first-order upwind (monotone) update creates no new extremum: every point's σ_xx and
///   v_x lie between rest and that state, within 0.1 % of its size (measured at 0.51 ms:
///   the largest compression 8.7482e8 Pa against 8.7448e8 behind, +0.039 %; v_x at most
///   20.006 m/s against 20, +0.03 %; the rod's plastic wave 0.000 %);
/// - momentum equals the load's impulse (conservation, to 1e-9).
///
/// The front positions are not asserted here: at Courant 0.6 the smeared fronts, 6.2 to
/// 18.6 cells apart, overlap, and the half-jump crossing of the plastic wave falls inside
/// the precursor's smear (measured at 0.17 ms: plastic wave at 0.7363 m against 0.8059 m,
/// and a 25 % "overshoot" in its window that is the precursor's ramp; `tests/plasticity.rs`
/// asserts the positions where the fronts are sharp: CTU at Courant 1, every method). The
/// L1 errors of the elastic solver (followed by the return map) and of the elastoplastic
/// one are printed, not ranked: they differ by 0.5 % only (8.295e-2, 5.966e-2, 4.933e-2
/// against 8.339e-2, 5.994e-2, 4.953e-2). CTU is refused with a message.
#[test]
fn plane_strain_elastoplastic_solver() {
    use impact_core::method::{RiemannSolver, TransverseFlux};
    let scene = Scene::builtin("ep-plate-wave").unwrap();
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    let reference = Reference::for_problem(&problem).unwrap();
    let Reference::Elastoplastic(exact) = &reference else {
        panic!("ep-plate-wave has the exact two-wave reference")
    };
    let config = |riemann: RiemannSolver| {
        let mut config = scene.method_config(MethodKind::Dgmpm);
        config.courant = 0.6;
        let o = config.dgmpm_mut().unwrap();
        (o.riemann, o.flux) = (riemann, TransverseFlux::DonorCell);
        config
    };
    let l1 = |riemann: RiemannSolver| {
        let (rec, blowup) =
            run_method(&problem, config(riemann), Some(&reference), &mut Silent).unwrap();
        assert!(blowup.is_none(), "{blowup:?}");
        rec.times.iter().map(|t| t.l1).collect::<Vec<f64>>()
    };
    println!(
        "plane wave, DCU 0.6: L1 elastic {:?}, elastoplastic {:?}",
        l1(RiemannSolver::Elastic),
        l1(RiemannSolver::Elastoplastic)
    );
    let mut m = impact::build(&problem, config(RiemannSolver::Elastoplastic)).unwrap();
    let dt = m.stable_dt();
    let steps = (problem.t_end / dt).round() as usize;
    for k in 0..steps {
        m.step(k as f64 * dt, dt);
    }
    let (p, j) = (m.momentum()[0], m.external_impulse()[0]);
    assert!(((p - j) / j).abs() < 1e-9, "momentum {p} vs impulse {j}");
    let mut samples = impact_core::Samples::<2>::default();
    m.sample_into(&mut samples);
    let (sigma, v) = (-exact.behind.0, exact.behind.1);
    let compression = samples.stress.iter().map(|s| -s[(0, 0)]);
    let velocity = samples.velocity.iter().map(|u| u[0]);
    let range = |it: &mut dyn Iterator<Item = f64>| {
        it.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)))
    };
    let (c, u) = (
        range(&mut compression.into_iter()),
        range(&mut velocity.into_iter()),
    );
    println!(
        "t = {:.3e}: compression in [{:.4e}, {:.4e}] Pa (behind: {sigma:.4e}), v_x in \
         [{:.4e}, {:.4e}] m/s (behind: {v:.4e})",
        problem.t_end, c.0, c.1, u.0, u.1
    );
    assert!(c.0 >= -1e-3 * sigma && c.1 <= sigma * (1.0 + 1e-3), "{c:?}");
    assert!(u.0 >= -1e-3 * v && u.1 <= v * (1.0 + 1e-3), "{u:?}");
    let mut refused = config(RiemannSolver::Elastoplastic);
    refused.dgmpm_mut().unwrap().flux = TransverseFlux::Ctu;
    let refused = impact::build(&problem, refused)
        .err()
        .expect("CTU is refused")
        .to_string();
    assert!(refused.contains("--flux dcu"), "{refused}");
}

/// Perfect plasticity (`H = 0`) is allowed in plane strain, where the plastic wave still
/// moves at `c_p = sqrt(K/ρ)`: on ep-plate-wave with `H = 0` every method puts both fronts
/// within a cell of the exact ones (MPM two) and keeps its L1 error below 10 %; the same
/// material in 1D is refused, since the rod's plastic wave would not move.
#[test]
fn perfectly_plastic_plane_wave() {
    let mut scene = Scene::builtin("ep-plate-wave").unwrap();
    scene.material.hardening = Some(0.0);
    scene.validate().unwrap();
    both_fronts_within_a_cell::<2>(&scene);
    let mut rod = Scene::builtin("ep-bar").unwrap();
    rod.material.hardening = Some(0.0);
    let refused = rod.validate().unwrap_err().to_string();
    assert!(refused.contains("material.hardening"), "{refused}");
}

/// `impact run ep-bar` writes the accumulated plastic strain: a CSV column and a VTU array
/// per method; behind DGMPM's plastic wave it is the exact `(p − σ_y)/H` = 0.02.
#[test]
fn elastoplastic_runs_write_the_plastic_strain() {
    let out = tmp("ep-bar");
    let o = impact(&["run", "ep-bar", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    for method in ["dgmpm", "mpm", "fem"] {
        let csv = std::fs::read_to_string(out.join(format!("{method}_t2.csv"))).unwrap();
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let column = header
            .iter()
            .position(|h| *h == "equivalent_plastic_strain")
            .unwrap_or_else(|| panic!("{method}: {header:?}"));
        let first: f64 = csv
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .nth(column)
            .unwrap()
            .parse()
            .unwrap();
        if method == "dgmpm" {
            assert!((first - 0.02).abs() < 1e-3, "{first}");
        }
        let vtu = vtu_text(out.join(format!("{method}_t2.vtu")));
        assert!(
            vtu.contains("Name=\"equivalent_plastic_strain\""),
            "{method}"
        );
    }
}

//! The smooth-solution convergence suite (`impact bench convergence`): observed orders on
//! the standing waves of `smooth-bar` and `smooth-plate` against their exact solution. The
//! expected orders and why some fall below the scheme's formal order are in the module doc
//! of `impact::convergence`.
use crate::common::{measured, order, Error};

#[test]
fn smooth_bar_orders() {
    let (fem, bspline, hat) = ("fem C0.9", "mpm bspline2 4ppc C0.5", "mpm 4ppc C0.5");
    let runs = measured::<1>("smooth-bar", &[fem, bspline, hat], 4);
    let pairs: [(Error, &str); 2] = [(|e| e.l2_stress, "L2 σ"), (|e| e.l2_velocity, "L2 v")];
    for (error, name) in pairs {
        let o = order(&runs, fem, error);
        assert!((1.9..2.2).contains(&o), "FEM {name}: order {o}");
    }
    let o = order(&runs, bspline, |e| e.l2_stress);
    assert!((1.8..2.3).contains(&o), "B-spline MPM L2 σ: order {o}");
    // velocity: first order for every shape (USL's O(Δt) lag, module doc)
    for label in [bspline, hat] {
        let o = order(&runs, label, |e| e.l1_velocity);
        assert!((0.9..1.5).contains(&o), "{label} L1 v: order {o}");
    }
}

#[test]
fn smooth_plate_orders() {
    let (fem, bspline, dgmpm) = (
        "fem C0.9",
        "mpm bspline2 4ppc C0.5",
        "dgmpm euler ctu 1ppc C1.0",
    );
    let runs = measured::<2>("smooth-plate", &[fem, bspline, dgmpm], 4);
    let o = order(&runs, fem, |e| e.l2_stress);
    assert!((1.9..2.2).contains(&o), "FEM L2 σ: order {o}");
    let o = order(&runs, bspline, |e| e.l2_stress);
    assert!((1.8..2.3).contains(&o), "B-spline MPM L2 σ: order {o}");
    let pairs: [(Error, &str); 2] = [(|e| e.l1_stress, "L1 σ"), (|e| e.l1_velocity, "L1 v")];
    for (error, name) in pairs {
        let o = order(&runs, dgmpm, error);
        assert!((0.85..1.4).contains(&o), "DGMPM {name}: order {o}");
    }
}

/// DGMPM order 2 (the wave corrections) at one point per cell: Lax-Wendroff (no limiter)
/// converges at order 2 in every norm on the standing wave (1.99-2.00 at 150-2400 cells,
/// docs/methods.md); MC's limiter clips the smooth extrema but keeps order 2 in L2. At several points
/// per cell (RK2) the corrections leave the order at about 1 (measured 1.07), the nodal
/// scheme's own limit: checked so that a change is seen.
#[test]
fn smooth_bar_order_two() {
    let (lw, mc, several) = (
        "dgmpm euler o2 none 1ppc C0.5",
        "dgmpm euler o2 mc 1ppc C0.5",
        "dgmpm rk2 o2 none 2ppc C0.9",
    );
    let runs = measured::<1>("smooth-bar", &[lw, mc, several], 4);
    let all: [(Error, &str); 4] = [
        (|e| e.l1_stress, "L1 σ"),
        (|e| e.l2_stress, "L2 σ"),
        (|e| e.l1_velocity, "L1 v"),
        (|e| e.l2_velocity, "L2 v"),
    ];
    for (error, name) in all {
        let o = order(&runs, lw, error);
        assert!((1.8..2.3).contains(&o), "Lax-Wendroff {name}: order {o}");
    }
    for (error, name) in [all[1], all[3]] {
        let o = order(&runs, mc, error);
        assert!((1.8..2.4).contains(&o), "MC {name}: order {o}");
    }
    let o = order(&runs, several, |e| e.l2_stress);
    assert!((0.8..1.4).contains(&o), "2 ppc RK2 L2 σ: order {o}");
}

/// DGMPM order 2 with CTU at one point per cell on the standing P mode of the plate
/// (against the exact solution): Lax-Wendroff converges at about 2 (docs/methods.md), order 1 at 1.
#[test]
fn smooth_plate_order_two() {
    let (lw, first) = (
        "dgmpm euler ctu o2 none 1ppc C0.9",
        "dgmpm euler ctu 1ppc C1.0",
    );
    let runs = measured::<2>("smooth-plate", &[lw, first], 3);
    let o = order(&runs, lw, |e| e.l2_stress);
    assert!((1.7..2.4).contains(&o), "order 2 L2 σ: order {o}");
}

/// DGMPM order 2 with CTU (Clawpack's `flux3` with `method = (2, 22)`: the corrections'
/// transverse and transverse-transverse split) at one point per cell on the standing mode
/// (1, 1, 1) of the cube (against the exact solution): Lax-Wendroff converges at about 2
/// (docs/methods.md), order 1 at about 1.
#[test]
fn smooth_block_order_two() {
    let (lw, first) = (
        "dgmpm euler ctu o2 none 1ppc C0.9",
        "dgmpm euler ctu 1ppc C1.0",
    );
    let runs = measured::<3>("smooth-block", &[lw, first], 3);
    let o = order(&runs, lw, |e| e.l2_stress);
    assert!((1.8..2.4).contains(&o), "order 2 L2 σ: order {o}");
    let o1 = order(&runs, first, |e| e.l2_stress);
    assert!(o > o1 + 0.5, "order 2 {o} against order 1 {o1}");
}

/// DGMPM order 2 at 4 points per cell (RK2, CTU at Courant 0.7) on the standing P mode of
/// the plate: as in 1D the corrections leave the nodal scheme's order about 1 (docs/methods.md),
/// against order 1 with the same integrator, flux and Courant number.
#[test]
fn smooth_plate_order_two_at_four_points_per_cell() {
    let (none, mc, first) = (
        "dgmpm rk2 ctu o2 none 4ppc C0.7",
        "dgmpm rk2 ctu o2 mc 4ppc C0.7",
        "dgmpm rk2 ctu 4ppc C0.7",
    );
    let runs = measured::<2>("smooth-plate", &[none, mc, first], 3);
    for label in [none, mc, first] {
        let o = order(&runs, label, |e| e.l2_stress);
        assert!((0.7..1.5).contains(&o), "{label} L2 σ: order {o}");
    }
}

/// MPM transfers on the standing wave (issue 26). APIC with quadratic B-splines at 4 points
/// per cell, and PIC with hats at 2 and 20 points per cell (the DGMPM author's set-up: his
/// published PIC rates are 0.94/0.85 in stress and 1.12/0.93 in velocity; docs/methods.md compares).
/// PIC's round trip filters the mode by `cos²(kh/2) = 1 − O(h²)` per step (hats at the cell
/// centres) over `O(1/h)` steps: an `O(h)` amplitude error, order 1 in both fields
/// (measured 1.00 at 150-1200 cells, both layouts). APIC with B-splines: stress at order 2
/// as FLIP's (measured 2.16 in L2), velocity at order 1 (1.01: USL's `O(Δt)` lag,
/// `impact::convergence`'s module doc).
#[test]
fn smooth_bar_transfers() {
    use impact::work_precision::Config;
    use impact_core::method::{MethodKind, MpmShape, MpmTransfer};
    let scene = impact_core::Scene::builtin("smooth-bar").unwrap();
    let configs: Vec<Config> = [
        (MpmTransfer::Apic, MpmShape::Bspline2, 4),
        (MpmTransfer::Pic, MpmShape::Linear, 2),
        (MpmTransfer::Pic, MpmShape::Linear, 20),
    ]
    .into_iter()
    .map(|(transfer, shape, ppc)| {
        let mut config = scene.method_config(MethodKind::Mpm);
        (config.points_per_cell, config.courant) = (ppc, 0.5);
        let o = config.mpm_mut().unwrap();
        (o.transfer, o.shape) = (transfer, shape);
        Config {
            label: format!("mpm {transfer} {shape} {ppc}ppc"),
            config,
            dim: 1,
        }
    })
    .collect();
    let runs = impact::convergence::ladder::<1>(&scene, &configs, 4).unwrap();
    print!("{}", impact::convergence::table(&runs));
    let all: [(Error, &str); 4] = [
        (|e| e.l1_stress, "L1 σ"),
        (|e| e.l2_stress, "L2 σ"),
        (|e| e.l1_velocity, "L1 v"),
        (|e| e.l2_velocity, "L2 v"),
    ];
    for c in &configs {
        for (error, name) in all {
            let o = order(&runs, &c.label, error);
            println!("{} {name}: order {o:.3}", c.label);
            let expected = match (c.config.mpm().unwrap().transfer, name) {
                (MpmTransfer::Apic, "L1 σ" | "L2 σ") => 1.8..2.4,
                (MpmTransfer::Apic, _) => 0.9..1.2,
                _ => 0.9..1.1,
            };
            assert!(expected.contains(&o), "{} {name}: order {o}", c.label);
        }
    }
}

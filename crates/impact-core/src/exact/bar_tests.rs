//! Tests of [`BarExact`]: hand-worked values for each end combination, averages against a
//! fine midpoint rule of the point values, energy against work plus initial energy.
use super::*;
use crate::initial::{Formula, InitialState};
use crate::load::LoadHistory;
use approx::assert_relative_eq;

const RHO: f64 = 7800.0;
const E: f64 = 2e11;

fn bar() -> BarExact {
    BarExact::new(6.0, RHO, E, 1e9)
}

fn ends(left: BarEnd, right: BarEnd) -> BarExact {
    BarExact::with_ends(6.0, RHO, E, [left, right])
}

fn pressure(p: f64, history: LoadHistory) -> BarEnd {
    BarEnd::Traction {
        pressure: p,
        history,
    }
}

fn velocity(v: f64, history: LoadHistory) -> BarEnd {
    BarEnd::Velocity {
        velocity: v,
        history,
    }
}

/// `v0 = formula`, unstressed.
fn moving(text: &str) -> InitialState {
    InitialState::Formula {
        velocity: vec![Formula::parse(text, 1).unwrap()],
        stress: vec![],
    }
}

/// Midpoint rule of the point values of `f` over `[x0, x1]`.
fn midpoint(f: impl Fn(f64) -> f64, x0: f64, x1: f64, n: usize) -> f64 {
    let dx = (x1 - x0) / n as f64;
    (0..n).map(|i| f(x0 + (i as f64 + 0.5) * dx)).sum::<f64>() / n as f64
}

/// `∫ ½ρv² + σ²/2E dX` from point values.
fn field_energy(b: &BarExact, t: f64) -> f64 {
    let n = 60_000;
    b.length
        * midpoint(
            |x| {
                let (s, v) = (b.stress(x, t), b.velocity(x, t));
                0.5 * RHO * v * v + 0.5 * s * s / E
            },
            0.0,
            b.length,
            n,
        )
}

#[test]
fn first_transit_is_a_step() {
    let b = bar();
    let t = 3.0 / b.speed;
    assert_eq!(b.stress(2.9, t), -1e9);
    assert_eq!(b.stress(3.1, t), 0.0);
    assert_relative_eq!(b.velocity(1.0, t), 1e9 / b.impedance);
    assert_relative_eq!(b.stress_average(2.9, 3.1, t), -0.5e9, max_relative = 1e-12);
}

#[test]
fn free_end_reflection_cancels_stress_and_doubles_velocity() {
    let b = bar();
    let t = 8.0 / b.speed; // front reflected, now at X = 4
    assert_eq!(b.stress(5.0, t), 0.0);
    assert_eq!(b.stress(3.0, t), -1e9);
    assert_relative_eq!(b.velocity(5.0, t), 2e9 / b.impedance);
    let f = b.leading_front(t).unwrap();
    assert_relative_eq!(f.position, 4.0, max_relative = 1e-12);
    assert_eq!((f.direction, f.ahead, f.behind), (-1.0, -1e9, 0.0));
}

#[test]
fn loaded_end_reflection_keeps_traction() {
    let b = bar();
    let t = 14.0 / b.speed; // after reflecting from X = 0 again, front at X = 2
    assert_relative_eq!(b.stress(1e-9, t), -1e9);
    assert_relative_eq!(b.stress(1.0, t), -1e9);
    assert_eq!(b.stress(3.0, t), 0.0);
    assert_relative_eq!(b.velocity(1.0, t), 3e9 / b.impedance);
}

#[test]
fn velocity_load_reflects_into_tension_at_the_bonded_end() {
    let b = BarExact::with_load(6.0, RHO, E, EndLoad::Velocity(5.0));
    let z = b.impedance;
    let t = 3.0 / b.speed;
    assert_relative_eq!(b.stress(1.0, t), -z * 5.0, max_relative = 1e-12);
    assert_relative_eq!(b.velocity(1.0, t), 5.0, max_relative = 1e-12);
    // after the free-end reflection: stress relieved, velocity doubled
    let t = 9.0 / b.speed;
    assert_eq!(b.stress(5.0, t), 0.0);
    assert_relative_eq!(b.velocity(5.0, t), 10.0, max_relative = 1e-12);
    // after the return to the bonded end: velocity back to v_d, tension Z v_d
    let t = 15.0 / b.speed;
    assert_relative_eq!(b.velocity(1.0, t), 5.0, max_relative = 1e-12);
    assert_relative_eq!(b.stress(1.0, t), z * 5.0, max_relative = 1e-12);
}

/// A fixed far end doubles the stress on reflection and stops the bar; back at the
/// loaded (traction) end the reflection keeps `Δv`: the bar moves back at `-p/Z`... and
/// the stress there returns to `-p`.
#[test]
fn fixed_far_end_doubles_the_stress() {
    let b = ends(pressure(1e9, LoadHistory::Step), BarEnd::FIXED);
    let z = b.impedance;
    let t = 9.0 / b.speed; // reflected at X = 6, front at X = 3 moving left
    assert_relative_eq!(b.stress(4.5, t), -2e9, max_relative = 1e-12);
    assert_eq!(b.velocity(4.5, t), 0.0);
    assert_relative_eq!(b.stress(1.0, t), -1e9, max_relative = 1e-12);
    assert_relative_eq!(b.velocity(1.0, t), 1e9 / z, max_relative = 1e-12);
    let f = b.leading_front(t).unwrap();
    assert_relative_eq!(f.position, 3.0, max_relative = 1e-12);
    assert_eq!((f.direction, f.ahead, f.behind), (-1.0, -1e9, -2e9));
    // back from the loaded end (traction: Δσ flips): σ = -2p + p = -p, v = -p/Z
    let t = 15.0 / b.speed; // front at X = 3 moving right
    assert_relative_eq!(b.stress(1.0, t), -1e9, max_relative = 1e-12);
    assert_relative_eq!(b.velocity(1.0, t), -1e9 / z, max_relative = 1e-12);
    assert_relative_eq!(b.stress(4.5, t), -2e9, max_relative = 1e-12);
    // the fixed end does no work; the load's work equals the energy
    assert_relative_eq!(b.work(t), field_energy(&b, t), max_relative = 1e-4);
}

/// A load on the right end mirrors the same load on the left: `σ_R(X) = σ_L(L - X)`,
/// `v_R(X) = -v_L(L - X)`, the same work, and the front moves left.
#[test]
fn right_end_load_mirrors_a_left_end_load() {
    for history in [LoadHistory::Step, LoadHistory::Pulse { duration: 0.3e-3 }] {
        for far in [BarEnd::FREE, BarEnd::FIXED] {
            let left = ends(pressure(1e9, history), far);
            let right = ends(far, pressure(1e9, history));
            let vleft = ends(velocity(4.0, history), far);
            let vright = ends(far, velocity(4.0, history));
            for t in [0.4e-3, 1.5e-3, 2.9e-3] {
                for (a, b) in [(&left, &right), (&vleft, &vright)] {
                    for x in [0.3, 2.0, 4.1, 5.9] {
                        let m = 6.0 - x;
                        assert_relative_eq!(b.stress(x, t), a.stress(m, t), epsilon = 1e-3);
                        assert_relative_eq!(b.velocity(x, t), -a.velocity(m, t), epsilon = 1e-9);
                        let (sa, sb) = (
                            a.stress_average(m - 0.1, m + 0.1, t),
                            b.stress_average(x - 0.1, x + 0.1, t),
                        );
                        assert_relative_eq!(sa, sb, epsilon = 1e-3);
                    }
                    assert_relative_eq!(a.work(t), b.work(t), max_relative = 1e-9);
                }
            }
        }
    }
    let b = ends(BarEnd::FREE, pressure(1e9, LoadHistory::Step));
    let f = b.leading_front(2.0 / b.speed).unwrap();
    assert_relative_eq!(f.position, 4.0, max_relative = 1e-12);
    assert_eq!((f.direction, f.ahead, f.behind), (-1.0, 0.0, -1e9));
}

/// In 1D a symmetry end (zero normal velocity) is a fixed end, and a velocity end at
/// rest; loads at both ends superpose (the problem is linear).
#[test]
fn loads_at_both_ends_superpose() {
    let ramp = LoadHistory::Ramp { rise: 0.2e-3 };
    let sine = LoadHistory::Sine { period: 0.7e-3 };
    let both = ends(pressure(1e9, ramp), velocity(-3.0, sine));
    let left_only = ends(pressure(1e9, ramp), velocity(0.0, LoadHistory::Step));
    let right_only = ends(BarEnd::FREE, velocity(-3.0, sine));
    for t in [0.5e-3, 1.7e-3, 3.1e-3] {
        for x in [0.2, 1.9, 3.3, 5.6] {
            let sum = left_only.stress_average(x, x + 0.04, t)
                + right_only.stress_average(x, x + 0.04, t);
            assert_relative_eq!(both.stress_average(x, x + 0.04, t), sum, epsilon = 1e-3);
            let sum = left_only.velocity(x, t) + right_only.velocity(x, t);
            assert_relative_eq!(both.velocity(x, t), sum, epsilon = 1e-12);
        }
        assert_relative_eq!(both.energy(t), field_energy(&both, t), max_relative = 1e-4);
        assert_eq!(both.leading_front(t), Err(NoFront::NotAStep));
    }
    let steps = ends(
        pressure(1e9, LoadHistory::Step),
        pressure(1e9, LoadHistory::Step),
    );
    assert_eq!(steps.leading_front(0.5e-3), Err(NoFront::Merged));
}

/// Averages against a fine midpoint rule of the point values (20,000 points: each jump
/// costs it up to 5e-5 of the scale), and energy = work +
/// initial energy against the fields' energy, for every end combination, history and
/// an initial state.
#[test]
fn averages_and_energy_for_every_end_combination() {
    let histories = [
        LoadHistory::Step,
        LoadHistory::Ramp { rise: 0.4e-3 },
        LoadHistory::Sine { period: 1.5e-3 },
        LoadHistory::Pulse { duration: 0.3e-3 },
    ];
    let kinds = |h: LoadHistory| {
        [
            BarEnd::FREE,
            BarEnd::FIXED,
            pressure(7e8, h),
            velocity(2.5, h),
        ]
    };
    let initial = moving("0.8*sin(PI*x/6) + 0.3");
    for h in histories {
        for left in kinds(h) {
            for right in kinds(h) {
                for start in [None, Some(&initial)] {
                    let mut b = ends(left, right);
                    if let Some(s) = start {
                        b = b.with_initial(s);
                    }
                    if b.pressure == 0.0 {
                        continue;
                    }
                    let t = 1.6e-3;
                    let (x0, x1) = (0.7, 1.3);
                    let mid = midpoint(|x| b.stress(x, t), x0, x1, 20_000);
                    let what = format!("{left:?} {right:?} {}", start.is_some());
                    assert!(
                        (b.stress_average(x0, x1, t) - mid).abs() < 3e-4 * b.pressure,
                        "{what}: {} against {mid}",
                        b.stress_average(x0, x1, t)
                    );
                    let mid = midpoint(|x| b.velocity(x, t), 5.1, 5.97, 20_000);
                    let scale = b.pressure / b.impedance;
                    assert!(
                        (b.velocity_average(5.1, 5.97, t) - mid).abs() < 3e-4 * scale,
                        "{what}: v {} against {mid}",
                        b.velocity_average(5.1, 5.97, t)
                    );
                    let fields = field_energy(&b, t);
                    assert!(
                        (b.energy(t) - fields).abs() <= 1e-4 * fields.abs().max(1e-6),
                        "{what}: energy {} against {fields}",
                        b.energy(t)
                    );
                }
            }
        }
    }
}

/// d'Alembert for an initial velocity: a free-free bar moving at `V` moves rigidly; a
/// fixed end stops it with a tension `Z V` behind the wave; the 1D standing mode with
/// symmetry ends is the exact standing wave.
#[test]
fn initial_velocity_by_dalembert() {
    let free = ends(BarEnd::FREE, BarEnd::FREE).with_initial(&moving("2"));
    let z = free.impedance;
    for t in [0.3e-3, 1.3e-3, 5.0e-3] {
        for x in [0.1, 3.0, 5.9] {
            assert_relative_eq!(free.velocity(x, t), 2.0, max_relative = 1e-12);
            assert!(free.stress(x, t).abs() < 1e-9 * z);
            assert_relative_eq!(free.displacement(x, t), 2.0 * t, max_relative = 1e-10);
        }
        assert_relative_eq!(free.energy(t), 0.5 * RHO * 4.0 * 6.0, max_relative = 1e-12);
        assert_eq!(free.work(t), 0.0);
    }
    let fixed = ends(BarEnd::FIXED, BarEnd::FREE).with_initial(&moving("2"));
    let t = 2.0 / fixed.speed; // the wave from the wall at X = 2
    assert_relative_eq!(fixed.stress(1.0, t), 2.0 * z, max_relative = 1e-12);
    assert!(fixed.velocity(1.0, t).abs() < 1e-12);
    assert_relative_eq!(fixed.velocity(3.0, t), 2.0, max_relative = 1e-12);
    assert!(fixed.stress(3.0, t).abs() < 1e-6);
    assert_eq!(fixed.leading_front(t), Err(NoFront::NotAStep));

    let material = crate::LinearElastic::new(E, 0.3, RHO);
    let wave = StandingWave::new(&material, 1, [6.0, 1.0, 1.0], [3, 0, 0], 1.5);
    let state = InitialState::StandingWave(wave);
    let b = ends(BarEnd::FIXED, BarEnd::FIXED).with_initial(&state);
    for t in [0.1e-3, 0.77e-3, 2.3e-3] {
        for x in [0.4, 2.5, 5.3] {
            assert_relative_eq!(
                b.velocity(x, t),
                wave.velocity([x, 0.0, 0.0], t)[0],
                epsilon = 1e-12
            );
            let s = wave.stress([x, 0.0, 0.0], t)[0];
            assert!(
                (b.stress(x, t) - s).abs() < 1e-9 * z,
                "{} against {s}",
                b.stress(x, t)
            );
        }
    }
}

/// A history load: point values follow `g` delayed by the travel time, averages agree
/// with a fine midpoint rule, the energy equals the work; a ramp or sine has no front, a
/// pulse's leading edge is one.
#[test]
fn history_loads_delay_the_end_history() {
    for history in [
        LoadHistory::Ramp { rise: 0.4e-3 },
        LoadHistory::Sine { period: 1.5e-3 },
        LoadHistory::Pulse { duration: 0.3e-3 },
    ] {
        let b = bar().with_history(history);
        let t = 1.6e-3; // after one reflection from the free end (L/c = 1.18 ms)
        let x = 1.0;
        let direct = -1e9 * history.factor(t - x / b.speed);
        let reflected = 1e9 * history.factor(t - (2.0 * b.length - x) / b.speed);
        assert_relative_eq!(b.stress(x, t), direct + reflected, epsilon = 1e-3);
        assert_relative_eq!(b.work(t), field_energy(&b, t), max_relative = 1e-4);
        match history {
            // a pulse's leading edge is a jump: reflected by the free end into tension,
            // measured up to its trailing edge c T behind
            LoadHistory::Pulse { duration } => {
                let f = b.leading_front(t).unwrap();
                let position = 2.0 * b.length - b.speed * t;
                assert_relative_eq!(f.position, position, max_relative = 1e-12);
                assert_eq!((f.direction, f.ahead, f.behind), (-1.0, 0.0, 1e9));
                assert_relative_eq!(
                    f.window.1,
                    position + b.speed * duration,
                    max_relative = 1e-12
                );
            }
            _ => assert_eq!(b.leading_front(t), Err(NoFront::NotAStep)),
        }
    }
}

#[test]
fn energy_balance_of_exact_solution() {
    for b in [
        bar(),
        BarExact::with_load(6.0, RHO, E, EndLoad::Velocity(5.0)),
    ] {
        for t in [0.4e-3, 1.0e-3, 1.9e-3, 3.3e-3] {
            assert_relative_eq!(field_energy(&b, t), b.work(t), max_relative = 1e-3);
        }
    }
}

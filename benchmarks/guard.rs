//! The cost of the stability guard's max-norm test (issue 23): the controller's loop on the
//! plate with the test on (`stress_scale > 0`: the samples copied and scanned every 100
//! steps and at the output) against the same loop with it off, 200 steps, interleaved in
//! one process on one thread, for DGMPM, MPM and FEM. `cargo bench --bench guard -- [NX
//! NY] [ROUNDS]` (default 1000×750, 5 rounds).
mod common;
use impact_core::controller::{run, Guard};
use impact_core::method::MethodKind;
use impact_core::{Method, Problem, Scene};

/// Seconds of 200 steps of `kind` on `problem` with the max-norm test `on` or off.
fn seconds(problem: &Problem<2>, kind: MethodKind, scene: &Scene, on: bool) -> f64 {
    let mut config = scene.method_config(kind);
    config.courant = config.courant.min(0.9);
    let mut method = impact::build(problem, config).expect("a valid configuration");
    let dt = method.stable_dt();
    let guard = Guard {
        stress_scale: if on { 2e8 } else { 0.0 },
        impedance: if on { 4e7 } else { 0.0 },
        ..Guard::default()
    };
    let stats = run::<2, dyn Method<2>, std::convert::Infallible>(
        method.as_mut(),
        &[200.0 * dt],
        guard,
        |_, _, _, _| Ok(()),
        |_| {},
    )
    .expect("a stable run");
    stats.wall_s
}

fn main() {
    let (cells, rest) = common::plate_arguments();
    let rounds = rest.first().copied().unwrap_or(5);
    let mut scene = Scene::builtin("plate").expect("shipped scene");
    scene.domain.cells = cells.clone();
    let problem = Problem::<2>::from_scene(&scene).expect("a valid scene");
    println!(
        "plate {}x{}, 200 steps, one thread, {} rounds interleaved (off, on)",
        cells[0], cells[1], rounds
    );
    println!(
        "{:<6} {:>12} {:>12} {:>8}",
        "method", "off_s", "on_s", "on/off"
    );
    for kind in MethodKind::ALL {
        let (mut off, mut on) = (Vec::new(), Vec::new());
        let pool = common::pool(1);
        for _ in 0..rounds {
            off.push(pool.install(|| seconds(&problem, kind, &scene, false)));
            on.push(pool.install(|| seconds(&problem, kind, &scene, true)));
        }
        let (off, on) = (common::median(off), common::median(on));
        println!(
            "{:<6} {:>12.4} {:>12.4} {:>8.3}",
            kind.name(),
            off,
            on,
            on / off
        );
    }
}

//! Heap bytes per cell of every method (issue 14): `cargo bench --bench memory`.
//!
//! A counting global allocator tracks the live heap. For each method (its scene
//! configuration, one point per cell; DGMPM also at 4 points per cell, MPM with
//! quadratic B-splines at 4) on the plane-wave plate at 1000×750 cells it reports
//! the bytes the built method holds (live heap after `build` minus before), the peak live
//! heap while building (transient buffers), and the peak over its first 5 steps (buffers a
//! step allocates lazily), per cell. Nothing else runs
//! meanwhile, so the figures are exact and repeatable (no timing involved).
use impact_core::method::{Integrator, MethodKind, MpmShape};
use impact_core::{Problem, Scene};

mod counting;
use counting::Counting;

#[global_allocator]
static GLOBAL: Counting = Counting;

fn main() {
    let mut scene = Scene::builtin("plate-wave").expect("shipped scene");
    scene.domain.cells = vec![1000, 750];
    let problem = Problem::<2>::from_scene(&scene).expect("valid scene");
    let cells = problem.grid.cell_count() as f64;
    println!("plate-wave 1000x750, one point per cell: heap bytes per cell");
    println!(
        "{:<34} {:>10} {:>16} {:>16}",
        "method", "held", "peak building", "peak in 5 steps"
    );
    let mut configs = vec![(
        "dgmpm (Euler, CTU: fused path)",
        scene.method_config(MethodKind::Dgmpm),
    )];
    let mut rk2 = scene.method_config(MethodKind::Dgmpm);
    if let Some(o) = rk2.dgmpm_mut() {
        o.integrator = Integrator::Rk2;
    }
    rk2.courant = 0.5;
    configs.push(("dgmpm (RK2, CTU: Heun cell sweeps)", rk2));
    let mut four = scene.method_config(MethodKind::Dgmpm);
    four.points_per_cell = 4;
    configs.push(("dgmpm (Euler, 4 ppc: fused nodal)", four));
    let mut four_rk2 = four;
    if let Some(o) = four_rk2.dgmpm_mut() {
        o.integrator = Integrator::Rk2;
    }
    four_rk2.courant = 0.5;
    configs.push(("dgmpm (RK2, 4 ppc: fused nodal)", four_rk2));
    configs.push(("mpm (USL, linear)", scene.method_config(MethodKind::Mpm)));
    let mut bsplines = scene.method_config(MethodKind::Mpm);
    bsplines.points_per_cell = 4;
    if let Some(o) = bsplines.mpm_mut() {
        o.shape = MpmShape::Bspline2;
    }
    configs.push(("mpm (USL, B-splines, 4 ppc)", bsplines));
    configs.push(("fem (Q4)", scene.method_config(MethodKind::Fem)));
    for (label, config) in configs {
        let before = counting::reset_peak();
        let mut method = impact::build(&problem, config).expect("builds");
        let held = counting::live() - before;
        let building = counting::peak() - before;
        counting::reset_peak();
        let dt = method.stable_dt();
        for k in 0..5 {
            method.step(k as f64 * dt, dt);
        }
        let peak = counting::peak() - before;
        println!(
            "{label:<34} {:>10.1} {:>16.1} {:>16.1}",
            held as f64 / cells,
            building as f64 / cells,
            peak as f64 / cells
        );
        drop(method);
    }
}

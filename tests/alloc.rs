//! No heap allocation inside the step loop of any method: a counting global allocator
//! watches 100 steps of each method and variant, on grids below the parallel threshold and,
//! for DGMPM, above it (rayon). The controller runs the step loop on a rayon worker and the
//! parallel loops fork onto the other workers, so the counter counts allocations made on
//! rayon's worker threads (all of them, the loop's own included) and ignores the test
//! harness's threads (which report finished tests while another one counts).
use impact_core::method::{
    Integrator, MethodKind, MpmFrame, MpmShape, MpmTransfer, PointUpdate, RiemannSolver,
    StressUpdate, TransverseFlux,
};
use impact_core::{Problem, Scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static COUNTING: AtomicBool = AtomicBool::new(false);
/// The counter is global: the tests of this binary take turns.
static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if counts() {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: forwarded to the system allocator with the caller's layout
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the pointer came from System.alloc with this layout
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if counts() {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: forwarded to the system allocator
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Counting is on and this thread is one of rayon's workers (a thread-local read).
fn counts() -> bool {
    COUNTING.load(Ordering::SeqCst) && rayon::current_thread_index().is_some()
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations during steps 21-120 of the controller's loop (the time loop every command
/// runs: steps, guard checks every 10 steps with the max-norm test, progress hook), after 20 warm-up steps: lazily
/// cached shape functions (MPM) are filled in the first step, and rayon's workers set up
/// their deques the first time each gets a job.
fn steps_allocate<const D: usize>(
    problem: &Problem<D>,
    config: impact_core::method::MethodConfig,
) -> usize {
    // every worker of the global pool started (its thread set up) before anything is
    // counted: a worker starting late, on a loaded machine, allocates its thread's state
    // on a rayon thread during the counted steps (seen once in 3D FEM's first case)
    rayon::broadcast(|_| ());
    steps_of_allocate(impact::build(problem, config).unwrap(), config)
}

/// [`steps_allocate`] of the method `m`, built.
fn steps_of_allocate<const D: usize>(
    mut m: Box<dyn impact_core::Method<D>>,
    config: impact_core::method::MethodConfig,
) -> usize {
    rayon::broadcast(|_| ());
    let dt = m.stable_dt();
    let mut steps = 0;
    ALLOCATIONS.store(0, Ordering::SeqCst);
    let result = impact_core::controller::run::<D, dyn impact_core::Method<D>, String>(
        m.as_mut(),
        &[125.0 * dt],
        // the guard as `impact run` sets it: the max-norm test samples the state at every
        // check into buffers allocated before the loop
        impact_core::controller::Guard {
            stress_scale: 1.0,
            impedance: 1.0,
            ..Default::default()
        },
        |_, _, _, _| Ok(()),
        |_| {
            // the loop must run on a rayon worker, or this test would not see its allocations
            assert!(
                rayon::current_thread_index().is_some(),
                "step loop off the pool"
            );
            steps += 1;
            COUNTING.store((20..120).contains(&steps), Ordering::SeqCst);
        },
    );
    COUNTING.store(false, Ordering::SeqCst);
    assert!(result.is_ok(), "{config:?}: the run must not blow up");
    assert!(steps >= 120);
    ALLOCATIONS.load(Ordering::SeqCst)
}

#[test]
fn no_allocation_in_the_step_loop() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    // the counter sees an allocation on a rayon worker, and none on this (harness) thread
    COUNTING.store(true, Ordering::SeqCst);
    ALLOCATIONS.store(0, Ordering::SeqCst);
    let outside = std::hint::black_box(vec![1u8; 64]);
    let outside_count = ALLOCATIONS.load(Ordering::SeqCst);
    let probe = rayon::scope(|_| std::hint::black_box(vec![1u8; 64]));
    COUNTING.store(false, Ordering::SeqCst);
    assert_eq!(outside_count, 0);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) >= 1 && probe.len() + outside.len() == 128);
    let mut cases = 0;
    for name in ["bar", "svk-bar"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        for kind in MethodKind::ALL {
            for (integrator, update, stress_update, riemann) in [
                (
                    Integrator::Euler,
                    PointUpdate::Nodal,
                    StressUpdate::Usl,
                    RiemannSolver::Approximate,
                ),
                (
                    Integrator::Rk2,
                    PointUpdate::Increment,
                    StressUpdate::Musl,
                    RiemannSolver::Exact,
                ),
                (
                    Integrator::Euler,
                    PointUpdate::Nodal,
                    StressUpdate::Usf,
                    RiemannSolver::Exact,
                ),
            ] {
                let mut c = scene.method_config(kind);
                let options = impact::Overrides {
                    integrator: Some(integrator),
                    update: Some(update),
                    stress_update: Some(stress_update),
                    riemann: Some(riemann),
                    courant: Some(0.5),
                    ..Default::default()
                };
                options.apply_to_config(&mut c);
                let n = steps_allocate(&problem, c);
                assert_eq!(n, 0, "{n} allocations: {name} {kind:?} {c:?}");
                cases += 1;
            }
        }
    }
    // MPM's transfers (issue 26): PIC, the blend and APIC (hats and the quadratic
    // B-spline, both frames), USL and MUSL, linear elastic and SVK
    for name in ["bar", "svk-bar"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        for (transfer, alpha, shape, stress_update, frame) in [
            (
                MpmTransfer::Pic,
                None,
                MpmShape::Linear,
                StressUpdate::Usl,
                MpmFrame::TotalLagrangian,
            ),
            (
                MpmTransfer::Blend,
                Some(0.9),
                MpmShape::Gimp,
                StressUpdate::Musl,
                MpmFrame::TotalLagrangian,
            ),
            (
                MpmTransfer::Apic,
                None,
                MpmShape::Linear,
                StressUpdate::Usl,
                MpmFrame::TotalLagrangian,
            ),
            (
                MpmTransfer::Apic,
                None,
                MpmShape::Bspline2,
                StressUpdate::Musl,
                MpmFrame::TotalLagrangian,
            ),
            (
                MpmTransfer::Apic,
                None,
                MpmShape::Bspline2,
                StressUpdate::Usf,
                MpmFrame::UpdatedLagrangian,
            ),
        ] {
            if name == "svk-bar" && frame == MpmFrame::UpdatedLagrangian {
                continue; // SVK is total Lagrangian
            }
            let mut c = scene.method_config(MethodKind::Mpm);
            let options = impact::Overrides {
                transfer: Some(transfer),
                flip_fraction: alpha,
                shape: Some(shape),
                stress_update: Some(stress_update),
                frame: Some(frame),
                ..Default::default()
            };
            options.apply_to_config(&mut c);
            let n = steps_allocate(&problem, c);
            assert_eq!(n, 0, "{n} allocations: {name} {c:?}");
            cases += 1;
        }
    }
    // DGMPM order 2 (the wave corrections, 1D; SVK's acoustic waves): the cell path, RK2
    // and several points per cell on the nodal phases
    for name in ["bar", "svk-bar"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        for (integrator, ppc) in [
            (Integrator::Euler, 1),
            (Integrator::Rk2, 1),
            (Integrator::Euler, 2),
        ] {
            let mut c = scene.method_config(MethodKind::Dgmpm);
            let options = impact::Overrides {
                integrator: Some(integrator),
                points_per_cell: Some(ppc),
                order: Some(impact_core::method::SchemeOrder::Second),
                limiter: Some(impact_core::method::WaveLimiter::Mc),
                courant: Some(0.5),
                ..Default::default()
            };
            options.apply_to_config(&mut c);
            let n = steps_allocate(&problem, c);
            assert_eq!(n, 0, "{n} allocations: {name} order 2 {c:?}");
            cases += 1;
        }
    }
    for name in ["plate", "svk-plate"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        for kind in MethodKind::ALL {
            for flux in [TransverseFlux::DonorCell, TransverseFlux::Ctu] {
                let mut c = scene.method_config(kind);
                if let Some(o) = c.dgmpm_mut() {
                    o.flux = flux;
                }
                c.courant = 0.5;
                if name == "svk-plate" && flux == TransverseFlux::Ctu {
                    continue; // CTU is linear-elastic only
                }
                assert_eq!(steps_allocate(&problem, c), 0, "{name} {kind:?} {flux:?}");
                cases += 1;
                // order 2 (the wave corrections; with CTU their transverse split): Euler
                // with CTU, RK2 with donor-cell (Euler is unstable there)
                if kind == MethodKind::Dgmpm && name == "plate" {
                    let mut c2 = c;
                    if let Some(o) = c2.dgmpm_mut() {
                        o.order = impact_core::method::SchemeOrder::Second;
                        o.limiter = Some(impact_core::method::WaveLimiter::Mc);
                        if flux == TransverseFlux::DonorCell {
                            o.integrator = Integrator::Rk2;
                        }
                    }
                    assert_eq!(steps_allocate(&problem, c2), 0, "{name} order 2 {flux:?}");
                    cases += 1;
                }
            }
        }
    }
    // 3D DGMPM: donor-cell and CTU (its per-cell transverse sources), Euler (the cell
    // path) and RK2 (the nodal phases)
    let scene = Scene::from_toml(include_str!("../scenes/block-wave.toml"), "block-wave").unwrap();
    let problem = Problem::<3>::from_scene(&scene).unwrap();
    for flux in [TransverseFlux::DonorCell, TransverseFlux::Ctu] {
        for integrator in [Integrator::Euler, Integrator::Rk2] {
            let mut c = scene.method_config(MethodKind::Dgmpm);
            if let Some(o) = c.dgmpm_mut() {
                (o.flux, o.integrator) = (flux, integrator);
            }
            c.courant = 0.4;
            assert_eq!(steps_allocate(&problem, c), 0, "3D {flux:?} {integrator:?}");
            cases += 1;
            // order 2 (the wave corrections; with CTU their transverse split, `ctu3.rs`)
            if let Some(o) = c.dgmpm_mut() {
                o.order = impact_core::method::SchemeOrder::Second;
                o.limiter = Some(impact_core::method::WaveLimiter::Mc);
            }
            c.courant = 0.3;
            let what = format!("3D order 2 {flux:?} {integrator:?}");
            assert_eq!(steps_allocate(&problem, c), 0, "{what}");
            cases += 1;
        }
    }
    assert_eq!(cases, 18 + 9 + 3 + 3 + 9 + 2 + 4 + 4);
}

/// DGMPM's rayon loops (grids from 4,096 cells on): the cell path (CTU, donor-cell, SVK) and
/// the nodal phases (RK2, 4 points per cell), in 1D and 2D.
#[test]
fn no_allocation_in_the_parallel_step_loop() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let mut cases = 0;
    for (name, cells) in [("bar", vec![6000]), ("svk-bar", vec![6000])] {
        let mut scene = Scene::builtin(name).unwrap();
        scene.domain.cells = cells;
        let problem = Problem::<1>::from_scene(&scene).unwrap();
        for integrator in [Integrator::Euler, Integrator::Rk2] {
            let mut c = scene.method_config(MethodKind::Dgmpm);
            c.dgmpm_mut().unwrap().integrator = integrator;
            c.courant = 0.5;
            let n = steps_allocate(&problem, c);
            assert_eq!(n, 0, "{n} allocations: {name} {integrator:?}");
            cases += 1;
        }
    }
    for name in ["plate", "svk-plate"] {
        let mut scene = Scene::builtin(name).unwrap();
        scene.domain.cells = vec![80, 60];
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        for (flux, integrator, ppc) in [
            (TransverseFlux::Ctu, Integrator::Euler, 1),
            (TransverseFlux::DonorCell, Integrator::Euler, 1),
            (TransverseFlux::Ctu, Integrator::Rk2, 1),
            (TransverseFlux::DonorCell, Integrator::Euler, 4),
            (TransverseFlux::Ctu, Integrator::Rk2, 4),
        ] {
            if name == "svk-plate" && flux == TransverseFlux::Ctu {
                continue; // CTU is linear-elastic only
            }
            let mut c = scene.method_config(MethodKind::Dgmpm);
            let o = c.dgmpm_mut().unwrap();
            (o.flux, o.integrator) = (flux, integrator);
            c.points_per_cell = ppc;
            c.courant = 0.5;
            assert_eq!(
                steps_allocate(&problem, c),
                0,
                "{name} {flux:?} {integrator:?} {ppc}"
            );
            cases += 1;
        }
    }
    assert_eq!(cases, 4 + 5 + 2);
}

/// A 3D block (an impact on a patch of one face, symmetry and free faces) from a TOML
/// string: `model` is the `[material]` table's body.
fn block(cells: [usize; 3], model: &str) -> Problem<3> {
    let text = format!(
        "name = \"block\"\ndim = 3\n[domain]\nlength = [2.0, 1.5, 1.0]\ncells = {cells:?}\n\
         [material]\n{model}\nyoung = 2.0e11\npoisson = 0.3\ndensity = 7800.0\n[boundary]\n\
         x.low = {{ kind = \"normal-velocity\", value = 20.0, from = [0.0, 0.0], to = [1.0, 0.5] }}\n\
         y.low = {{ kind = \"symmetry\" }}\nz.low = {{ kind = \"symmetry\" }}\n\
         [time]\noutput_transits = [4]\n"
    );
    Problem::<3>::from_scene(&Scene::from_toml(&text, "3D alloc test").unwrap()).unwrap()
}

/// MPM (every shape, USL/MUSL/USF, the updated Lagrangian frame, J2, SVK), FEM (the
/// 27-point stencil, the Gauss path with J2 and SVK) and DGMPM's fused 3D sweep
/// (donor-cell and CTU, linear and J2) in 3D, serial and, on 4,608 cells, on rayon.
#[test]
fn no_allocation_in_the_3d_step_loop() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let elastic = "model = \"linear-elastic\"";
    let j2 = "model = \"j2\"\nyield_stress = 4.0e8\nhardening = 2.0e10";
    let svk = "model = \"svk\"";
    let mut cases = 0;
    for cells in [[8, 6, 4], [24, 16, 12]] {
        for model in [elastic, j2, svk] {
            let problem = block(cells, model);
            let scene_config = |kind| {
                let mut c = impact_core::method::MethodConfig::new(kind, 0.5, 1);
                if let Some(o) = c.mpm_mut() {
                    *o = Default::default();
                }
                c
            };
            let mut configs = vec![scene_config(MethodKind::Fem)];
            for (shape, update, frame) in [
                (
                    MpmShape::Linear,
                    StressUpdate::Usl,
                    MpmFrame::TotalLagrangian,
                ),
                (
                    MpmShape::Gimp,
                    StressUpdate::Musl,
                    MpmFrame::UpdatedLagrangian,
                ),
                (
                    MpmShape::Bspline2,
                    StressUpdate::Usf,
                    MpmFrame::TotalLagrangian,
                ),
                (
                    MpmShape::Bspline3,
                    StressUpdate::Usl,
                    MpmFrame::UpdatedLagrangian,
                ),
                (
                    MpmShape::Cpdi,
                    StressUpdate::Musl,
                    MpmFrame::UpdatedLagrangian,
                ),
            ] {
                if model == svk && frame == MpmFrame::UpdatedLagrangian {
                    continue; // SVK is total Lagrangian
                }
                let mut c = scene_config(MethodKind::Mpm);
                let o = c.mpm_mut().unwrap();
                (o.shape, o.stress_update, o.frame) = (shape, update, frame);
                configs.push(c);
            }
            // the transfers (issue 26): APIC with hats (total Lagrangian) and with the
            // quadratic B-spline (updated), PIC with CPDI
            for (transfer, shape, frame) in [
                (
                    MpmTransfer::Apic,
                    MpmShape::Linear,
                    MpmFrame::TotalLagrangian,
                ),
                (MpmTransfer::Pic, MpmShape::Cpdi, MpmFrame::TotalLagrangian),
                (
                    MpmTransfer::Apic,
                    MpmShape::Bspline2,
                    MpmFrame::UpdatedLagrangian,
                ),
                (
                    MpmTransfer::Apic,
                    MpmShape::Gimp,
                    MpmFrame::UpdatedLagrangian,
                ),
            ] {
                if model == svk && frame == MpmFrame::UpdatedLagrangian {
                    continue;
                }
                let mut c = scene_config(MethodKind::Mpm);
                let o = c.mpm_mut().unwrap();
                (o.shape, o.transfer, o.frame) = (shape, transfer, frame);
                configs.push(c);
            }
            if model != svk {
                // DGMPM's fused 3D sweep (linear elasticity, Euler): donor-cell and CTU
                for flux in [TransverseFlux::DonorCell, TransverseFlux::Ctu] {
                    let mut c = scene_config(MethodKind::Dgmpm);
                    let o = c.dgmpm_mut().unwrap();
                    o.flux = flux;
                    if model == j2 {
                        o.riemann = RiemannSolver::Elastic;
                    }
                    c.courant = 0.45;
                    configs.push(c);
                }
            }
            for c in configs {
                let n = steps_allocate(&problem, c);
                assert_eq!(n, 0, "{n} allocations: 3D {cells:?} {model} {c:?}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 2 * (12 + 12 + 5));
}

/// MPM's migrating slab (updated Lagrangian, `impact_mpm::migrate`) on one rank: packing,
/// sorting and unpacking every point each step reuse their buffers (the messages between
/// ranks are the comm's: MPI's send from the buffers, the test's thread ranks copy).
#[test]
fn no_allocation_in_the_migrating_step_loop() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let scene = Scene::builtin("ep-plate").unwrap();
    let problem = Problem::<2>::from_scene(&scene).unwrap();
    for transfer in [MpmTransfer::Flip, MpmTransfer::Apic] {
        let mut config = scene.method_config(MethodKind::Mpm);
        let o = config.mpm_mut().unwrap();
        o.frame = MpmFrame::UpdatedLagrangian;
        o.stress_update = StressUpdate::Musl;
        o.transfer = transfer;
        let comm = std::sync::Arc::new(impact_core::comm::SerialComm);
        let m = impact_mpm::migrate::MigratingMpm::<2>::new(&problem, config, comm).unwrap();
        let count = steps_of_allocate(Box::new(m), config);
        assert_eq!(count, 0, "{transfer:?}: {count} allocations in 100 steps");
    }
}

//! No heap allocation inside the step loop of any method: a counting global allocator
//! watches 100 steps of each method and variant (grids below the parallel threshold; the
//! rayon paths of large grids are not covered here).
use impact_core::method::{
    Integrator, MethodKind, PointUpdate, RiemannSolver, StressUpdate, TransverseFlux,
};
use impact_core::{Problem, Scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static COUNTING: AtomicBool = AtomicBool::new(false);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::SeqCst) {
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
        if COUNTING.load(Ordering::SeqCst) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: forwarded to the system allocator
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn steps_allocate<const D: usize>(
    problem: &Problem<D>,
    config: impact_core::method::MethodConfig,
) -> usize {
    let mut m = impact::build(problem, config).unwrap();
    let dt = m.stable_dt();
    m.step(0.0, dt); // first step: lazily cached shape functions (MPM) are filled here
    ALLOCATIONS.store(0, Ordering::SeqCst);
    COUNTING.store(true, Ordering::SeqCst);
    for k in 1..=100 {
        m.step(k as f64 * dt, dt);
    }
    COUNTING.store(false, Ordering::SeqCst);
    ALLOCATIONS.load(Ordering::SeqCst)
}

#[test]
fn no_allocation_in_the_step_loop() {
    // the counter sees an allocation when there is one
    COUNTING.store(true, Ordering::SeqCst);
    ALLOCATIONS.store(0, Ordering::SeqCst);
    let probe = std::hint::black_box(vec![1u8; 64]);
    COUNTING.store(false, Ordering::SeqCst);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) >= 1 && probe.len() == 64);
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
                let mut c = impact::scene_config(&scene, kind);
                (c.integrator, c.update, c.stress_update, c.riemann) =
                    (integrator, update, stress_update, riemann);
                c.courant = 0.5;
                assert_eq!(steps_allocate(&problem, c), 0, "{name} {kind:?} {c:?}");
                cases += 1;
            }
        }
    }
    for name in ["plate", "svk-plate"] {
        let scene = Scene::builtin(name).unwrap();
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        for kind in MethodKind::ALL {
            for flux in [TransverseFlux::DonorCell, TransverseFlux::Ctu] {
                let mut c = impact::scene_config(&scene, kind);
                c.flux = flux;
                c.courant = 0.5;
                if name == "svk-plate" && flux == TransverseFlux::Ctu {
                    continue; // CTU is linear-elastic only
                }
                assert_eq!(steps_allocate(&problem, c), 0, "{name} {kind:?} {flux:?}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 18 + 9);
}

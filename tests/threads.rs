//! Parallel loops give the serial results: every method on the plate (4,800 cells, above
//! the parallel threshold) stepped in a 1-thread and a 2-thread rayon pool agrees to
//! round-off (the scatters of MPM and FEM add partial sums in another order).
use impact_core::method::{MethodKind, Samples};
use impact_core::{Problem, Scene};

fn run_in(threads: usize, kind: MethodKind, steps: usize) -> Samples<2> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut scene = Scene::builtin("plate").unwrap();
        scene.domain.cells = vec![80, 60];
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        let mut m = impact::build(&problem, scene.method_config(kind)).unwrap();
        let dt = m.stable_dt();
        for n in 0..steps {
            m.step(n as f64 * dt, dt);
        }
        let mut s = Samples::default();
        m.sample_into(&mut s);
        s
    })
}

#[test]
fn one_and_two_threads_agree_to_round_off() {
    for kind in MethodKind::ALL {
        let (a, b) = (run_in(1, kind, 60), run_in(2, kind, 60));
        let scale_s = a.stress.iter().map(|s| s.abs().max()).fold(0.0, f64::max);
        let scale_v = a.velocity.iter().map(|v| v.abs().max()).fold(0.0, f64::max);
        assert!(
            scale_s > 1e6 && scale_v > 0.1,
            "{kind:?}: the wave must be there"
        );
        let mut worst: f64 = 0.0;
        for i in 0..a.len() {
            worst = worst.max((a.stress[i] - b.stress[i]).abs().max() / scale_s);
            worst = worst.max((a.velocity[i] - b.velocity[i]).abs().max() / scale_v);
        }
        println!("{kind:?}: largest relative difference 1 vs 2 threads {worst:.1e}");
        assert!(worst <= 1e-12, "{kind:?}: {worst:e}");
    }
}

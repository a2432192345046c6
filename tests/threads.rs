//! Parallel loops give the serial results: every method on the plate (4,800 cells, above
//! the parallel threshold) stepped in a 1-thread and a 2-thread rayon pool agrees to
//! round-off (MPM's serial scatter adds layer by layer and FEM's Gauss path element by
//! element, the parallel ones by colour; FEM's stencil and its fused step in bands, bit
//! for bit). MPM is also checked with the widest stencil (cubic B-splines, 4 node layers per
//! colour band) in the updated Lagrangian frame, where points change cells.
use impact_core::method::{MethodConfig, MethodKind, MpmFrame, MpmShape, Samples};
use impact_core::{Problem, Scene};

fn run_in(threads: usize, kind: MethodKind, steps: usize) -> Samples<2> {
    run_with(threads, kind, steps, |_| {})
}

fn run_with(
    threads: usize,
    kind: MethodKind,
    steps: usize,
    edit: impl Fn(&mut MethodConfig) + Send + Sync,
) -> Samples<2> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut scene = Scene::builtin("plate").unwrap();
        scene.domain.cells = vec![80, 60];
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        let mut config = scene.method_config(kind);
        edit(&mut config);
        let mut m = impact::build(&problem, config).unwrap();
        let dt = m.stable_dt();
        for n in 0..steps {
            m.step(n as f64 * dt, dt);
        }
        let mut s = Samples::default();
        m.sample_into(&mut s);
        s
    })
}

fn assert_agree(kind: MethodKind, a: &Samples<2>, b: &Samples<2>) {
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

#[test]
fn one_and_two_threads_agree_to_round_off() {
    for kind in MethodKind::ALL {
        let (a, b) = (run_in(1, kind, 60), run_in(2, kind, 60));
        assert_agree(kind, &a, &b);
    }
    let cubic = |c: &mut MethodConfig| {
        let o = c.mpm_mut().unwrap();
        (o.shape, o.frame) = (MpmShape::Bspline3, MpmFrame::UpdatedLagrangian);
    };
    let (a, b) = (
        run_with(1, MethodKind::Mpm, 60, cubic),
        run_with(2, MethodKind::Mpm, 60, cubic),
    );
    assert_agree(MethodKind::Mpm, &a, &b);
}

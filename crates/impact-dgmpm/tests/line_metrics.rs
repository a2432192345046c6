//! The metrics of a run split over 2 to 4 ranks (threads as ranks, [`ThreadComm`]) equal
//! the serial run's: `Reference::evaluate` on ranks gathers only the measuring line's
//! samples and reduces the body's extent and volume (`impact_core::comm_line`), and the
//! errors, fronts and overshoots come out bit for bit; the energy error to round-off (the
//! energy is summed per rank, then in rank order). Slabs and boxes, on the plate, the bar,
//! the elastic-plastic plate and the 3D block, and on a line through the body's middle and
//! on its high face (the line that needs the body's upper corner).
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::comm_line::{gather_line, BodyMeasures};
use impact_core::line::MeasureLine;
use impact_core::method::{MethodKind, Samples};
use impact_core::reference::{line_samples, Reference, TimeMetrics};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::slab::SlabDgmpm;
use impact_dgmpm::Dgmpm;

fn scene(name: &str) -> Scene {
    Scene::builtin(name).unwrap()
}

/// The scene's exact reference, or (the plate, the block: none exact) the plate-wave's
/// plane wave: any reference exercises the gathered line.
fn reference_for<const D: usize>(problem: &Problem<D>) -> Reference {
    Reference::for_problem(problem).unwrap_or_else(|| {
        let wave = Problem::<2>::from_scene(&scene("plate-wave")).unwrap();
        Reference::for_problem(&wave).expect("the plate-wave has an exact reference")
    })
}

/// The metrics with the energy error set apart: `(every other field, energy error)`.
fn split(m: &TimeMetrics) -> (String, f64) {
    let mut rest = *m;
    rest.energy_error = 0.0;
    (format!("{rest:?}"), m.energy_error)
}

/// `m` after `steps` of its stable step, then its metrics along `line` at that time.
fn metrics_after<const D: usize>(
    m: &mut dyn Method<D>,
    reference: &Reference,
    line: &MeasureLine,
    dx: f64,
    steps: usize,
) -> TimeMetrics {
    let dt = m.stable_dt();
    for k in 0..steps {
        m.step(k as f64 * dt, dt);
    }
    let t = steps as f64 * dt;
    reference.evaluate(m, &mut Samples::default(), (t, line, dx), None)
}

/// `scene_name` (cells `cells` where given) on each rank grid: every rank's metrics equal
/// the serial run's, the line's gathered samples are the serial line's in its order, and
/// the reduced extent is the serial body's.
fn check<const D: usize>(scene_name: &str, cells: Option<Vec<usize>>, grids: &[&[usize]]) {
    let mut s = scene(scene_name);
    if let Some(cells) = cells {
        s.domain.cells = cells;
    }
    let problem = Problem::<D>::from_scene(&s).unwrap();
    let config = s.method_config(MethodKind::Dgmpm);
    let reference = reference_for(&problem);
    let bottom = MeasureLine::of(&problem);
    // the same line on the body's high face (y = its top): picked with the body's upper
    // corner, which no rank but the top one sees alone
    let mut top = bottom;
    if let Some(k) = impact_core::Grid::<D>::tangent_axes(bottom.axis).next() {
        top.offset[0] = problem.grid.upper()[k];
    }
    let dx = problem.grid.spacing[bottom.axis];
    let steps = 30;
    let lines = if D > 1 {
        vec![bottom, top]
    } else {
        vec![bottom]
    };
    for line in &lines {
        let mut serial_method = Dgmpm::<D>::new(&problem, config).unwrap();
        let serial = metrics_after(&mut serial_method, &reference, line, dx, steps);
        let mut whole = Samples::default();
        serial_method.sample_into(&mut whole);
        let serial_line: Vec<_> = line_samples(&whole, line)
            .into_iter()
            .map(|i| whole.reference[i])
            .collect();
        assert!(
            !serial_line.is_empty(),
            "{scene_name}: the line holds samples"
        );
        let (serial_rest, serial_energy) = split(&serial);
        assert!(
            serial.l1 > 0.0 && serial.l1.is_finite(),
            "{scene_name}: an error to compare ({serial:?})"
        );
        for parts in grids {
            let ranks: usize = parts.iter().product();
            let grid = RankGrid(parts.to_vec());
            let label = format!("{scene_name} on {parts:?}, line {:?}", line.offset);
            let ends = ThreadComm::on_ranks(ranks, |comm| {
                let mut m = SlabDgmpm::<D>::on_grid(&problem, config, comm, &grid).unwrap();
                let metrics = metrics_after(&mut m, &reference, line, dx, steps);
                let (mut owned, mut on_line) = (Samples::default(), Samples::default());
                let body = gather_line(&m, line, &mut owned, &mut on_line);
                (metrics, body, on_line.reference)
            });
            for (rank, (metrics, body, on_line)) in ends.iter().enumerate() {
                let (rest, energy) = split(metrics);
                assert_eq!(rest, serial_rest, "{label}, rank {rank}: the metrics");
                assert!(
                    (energy - serial_energy).abs() <= 1e-12 * serial_energy.abs().max(1e-300),
                    "{label}, rank {rank}: energy error {energy} against {serial_energy}"
                );
                assert_eq!(on_line, &serial_line, "{label}, rank {rank}: the line");
                let whole_body = BodyMeasures::of(&whole);
                assert_eq!(
                    (body.lower, body.upper),
                    (whole_body.lower, whole_body.upper),
                    "{label}, rank {rank}: the extent"
                );
                assert!(
                    (body.volume - whole_body.volume).abs() <= 1e-12 * whole_body.volume,
                    "{label}, rank {rank}: the volume"
                );
            }
        }
    }
}

#[test]
fn metrics_on_ranks_equal_the_serial_runs() {
    check::<1>("bar", None, &[&[2], &[3], &[4]]);
    check::<2>(
        "plate",
        None,
        &[&[1, 2], &[1, 3], &[1, 4], &[2, 2], &[3, 1]],
    );
    check::<2>("ep-plate", None, &[&[1, 2], &[1, 4], &[2, 2]]);
    check::<3>(
        "block",
        Some(vec![10, 8, 12]),
        &[&[1, 1, 2], &[1, 1, 3], &[2, 2, 1], &[1, 2, 2]],
    );
}

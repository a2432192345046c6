//! What the decomposed FEM tests share (`slab.rs`, `boxes.rs`): a run on thread ranks
//! split as a rank grid says, compared with the one-rank run. (Each test file uses part.)
#![allow(dead_code)]
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::comm_box::lexicographic;
use impact_core::method::{MethodConfig, MethodKind};
use impact_core::slab_method::owned_in_rank_order;
use impact_core::{Method, Problem, Samples, Scene, Vector};
use impact_fem::slab::SlabFem;
use impact_fem::Fem;

/// The plate with a sine pressure of period 0.2 ms on its whole left face.
pub fn sine_pressure_plate() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/plate.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let left = text
        .lines()
        .find(|l| l.starts_with("left ="))
        .unwrap()
        .to_string();
    let loaded =
        r#"left = { kind = "pressure", value = 1.0e8, history = "sine", duration = 2.0e-4 }"#;
    Scene::parse_toml(&text.replace(&left, loaded), "plate, sine pressure").unwrap()
}

pub fn scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(format!("{name}.toml"));
    Scene::parse_file(&path).unwrap()
}

/// What a run ends with: samples, the nodal fields of its piece of the mesh (the owned
/// elements' nodes) and the global sums.
pub struct End<const D: usize> {
    samples: Samples<D>,
    owned: Samples<D>,
    nodal: (Vec<Vector<D>>, Vec<Vector<D>>),
    /// The global index of each node of `nodal` (filled in by the caller).
    piece_nodes: Vec<usize>,
    energy: f64,
    work: f64,
    momentum: Vector<D>,
    impulse: Vector<D>,
}

pub fn finish<const D: usize>(m: &dyn Method<D>) -> End<D> {
    let (mut samples, mut owned) = (Samples::default(), Samples::default());
    m.sample_into(&mut samples);
    m.owned_samples_into(&mut owned);
    End {
        samples,
        owned,
        nodal: m.piece_nodal_fields().unwrap(),
        piece_nodes: Vec::new(),
        energy: m.energy(),
        work: m.external_work(),
        momentum: m.momentum(),
        impulse: m.external_impulse(),
    }
}

pub fn steps<const D: usize>(m: &mut dyn Method<D>, n: usize) {
    let dt = m.stable_dt();
    for k in 0..n {
        m.step(k as f64 * dt, dt);
    }
}

/// The path a run takes (applied to the serial FEM and to each rank's local one).
#[derive(Clone, Copy, Debug)]
pub enum Path {
    /// The default: the stencil fused for linear elasticity, Gauss points otherwise.
    Default,
    /// The stencil's two phases.
    TwoPhases,
    /// The Gauss-point path for linear elasticity.
    Gauss,
}

pub fn take_path<const D: usize>(fem: &mut Fem<D>, path: Path) {
    match path {
        Path::Default => {}
        Path::TwoPhases => fem.solver.set_fused_step(false),
        Path::Gauss => fem.solver.use_gauss_path(),
    }
}

/// `ranked == serial` bit for bit, or a panic naming the first differing index and how
/// many differ.
pub fn same<T: PartialEq + std::fmt::Debug>(ranked: &[T], serial: &[T], what: &str) {
    assert_eq!(ranked.len(), serial.len(), "{what}: lengths");
    let differ: Vec<usize> = (0..serial.len())
        .filter(|&i| ranked[i] != serial[i])
        .collect();
    if let Some(&i) = differ.first() {
        panic!(
            "{what}: {} of {} differ, first at {i}: {:?} against {:?}",
            differ.len(),
            serial.len(),
            ranked[i],
            serial[i]
        );
    }
}

/// The global indices of the nodes of the elements `owned` (per axis) of a mesh of `cells`
/// elements per axis, in lexicographic order (axis 0 fastest): a rank's piece of the mesh.
pub fn piece_nodes(owned: &[std::ops::Range<usize>], cells: &[usize]) -> Vec<usize> {
    let nodes: Vec<_> = owned.iter().map(|r| r.start..r.end + 1).collect();
    let counts: Vec<usize> = cells.iter().map(|n| n + 1).collect();
    lexicographic(&nodes, &counts)
}

pub fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Compare the runs on each of `grids` (rank grid, rank count) with the serial run after
/// `n` steps: samples bit for bit in the global order, each rank's piece of the nodal fields
/// (its owned elements' nodes) the serial nodes' bit for bit, every node in a piece, every sample owned
/// once (on slabs: the own samples in rank order are the whole body's), sums to 1e-12
/// relative, the momentum balance as on one rank.
pub fn check_on<const D: usize>(
    label: &str,
    scene: &Scene,
    path: Path,
    n: usize,
    grids: &[(RankGrid, usize)],
) {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let config: MethodConfig = scene.method_config(MethodKind::Fem);
    let mut serial = Fem::<D>::new(&problem, config).unwrap();
    take_path(&mut serial, path);
    steps(&mut serial, n);
    let serial = finish(&serial);
    let s = &serial.samples;
    let peak_s = s.stress.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let peak_v = s.velocity.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    assert!(
        peak_s > 1e5 && peak_v > 1e-3,
        "{label}: the wave must be there"
    );
    let p = serial.momentum.norm().max(serial.impulse.norm());
    assert!(p > 0.0, "{label}: a load must act");
    // central differences: Σ m v^{n+1/2} = p(0) + impulse (from rest), to round-off
    let balance = (serial.momentum - serial.impulse).norm();
    assert!(
        balance <= 1e-12 * p,
        "{label}: serial momentum balance {balance}"
    );
    for (grid, ranks) in grids {
        let ends = ThreadComm::on_ranks(*ranks, |comm| {
            let mut m = SlabFem::<D>::on_grid(&problem, config, comm, grid).unwrap();
            take_path(&mut m.local, path);
            steps(&mut m, n);
            let mut end = finish(&m);
            end.piece_nodes = piece_nodes(&m.rank_box().owned, &problem.grid.cells);
            end
        });
        let on = format!("{label}, rank grid {:?} on {ranks} ranks", grid.0);
        let owned: Vec<_> = ends.iter().map(|e| &e.owned).collect();
        let count: usize = owned.iter().map(|o| o.len()).sum();
        assert_eq!(count, s.len(), "{on}: every element owned once");
        let mut covered = vec![false; serial.nodal.0.len()];
        for &i in ends.iter().flat_map(|e| &e.piece_nodes) {
            covered[i] = true;
        }
        assert!(covered.iter().all(|&c| c), "{on}: a node in no piece");
        if grid.is_slabs(D) {
            assert!(
                owned_in_rank_order(&owned, s),
                "{on}: the own samples in rank order are not the whole body's"
            );
        }
        for (rank, end) in ends.iter().enumerate() {
            let at = format!("{on}, rank {rank}");
            let e = &end.samples;
            assert_eq!(e.len(), s.len(), "{at}");
            same(
                &e.reference,
                &s.reference,
                &format!("{at}: reference positions"),
            );
            same(&e.position, &s.position, &format!("{at}: positions"));
            same(&e.stress, &s.stress, &format!("{at}: stress"));
            same(&e.velocity, &s.velocity, &format!("{at}: velocity"));
            same(&e.plastic_strain, &s.plastic_strain, &format!("{at}: ε̄"));
            same(&e.stress_zz, &s.stress_zz, &format!("{at}: σ_zz"));
            let at_piece = |all: &[Vector<D>]| -> Vec<Vector<D>> {
                end.piece_nodes.iter().map(|&i| all[i]).collect()
            };
            same(
                &end.nodal.0,
                &at_piece(&serial.nodal.0),
                &format!("{at}: nodal velocity of the piece"),
            );
            same(
                &end.nodal.1,
                &at_piece(&serial.nodal.1),
                &format!("{at}: nodal displacement of the piece"),
            );
            let tol = 1e-12;
            assert!(relative(end.energy, serial.energy) < tol, "{at}: energy");
            assert!(relative(end.work, serial.work) < tol, "{at}: work");
            let momentum = (end.momentum - serial.momentum).norm();
            assert!(momentum <= tol * p, "{at}: momentum");
            let impulse = (end.impulse - serial.impulse).norm();
            assert!(impulse <= tol * p, "{at}: impulse");
            let balance = (end.momentum - end.impulse).norm();
            assert!(balance <= 1e-12 * p, "{at}: momentum balance {balance}");
        }
    }
}

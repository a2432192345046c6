//! FEM split in slabs over 1 to 4 ranks ([`SlabFem`], ranks as threads through
//! [`ThreadComm`]) equals the one-rank run: the sampled fields and the mesh's nodal fields
//! bit for bit on every path (stencil fused and in two phases, Gauss points, J2 with its
//! Gauss-point history, Saint-Venant–Kirchhoff; a pressure, prescribed velocities and
//! symmetry edges, on the cut axis too), in 1D, 2D and 3D, since every owned node is formed
//! by the same operations on the same bits (`slab.rs`); energy, work, momentum and impulse
//! to round-off (summed per rank, then in rank order), and the momentum balance holds on
//! the ranks as on one. A non-finite state on one rank is reported identically by every
//! rank at its global place; more ranks than layers and box decompositions (`--ranks-grid`
//! other than slabs) are refused on every rank.
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::method::{MethodConfig, MethodKind};
use impact_core::slab_method::{blowup_on_ranks, owned_in_rank_order, refusal_on_ranks};
use impact_core::{Method, Problem, Samples, Scene, Vector};
use impact_fem::slab::SlabFem;
use impact_fem::Fem;

fn scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(format!("{name}.toml"));
    Scene::parse_file(&path).unwrap()
}

/// What a run ends with: samples, the mesh's nodal fields and the global sums.
struct End<const D: usize> {
    samples: Samples<D>,
    owned: Samples<D>,
    nodal: (Vec<Vector<D>>, Vec<Vector<D>>),
    energy: f64,
    work: f64,
    momentum: Vector<D>,
    impulse: Vector<D>,
}

fn finish<const D: usize>(m: &dyn Method<D>) -> End<D> {
    let (mut samples, mut owned) = (Samples::default(), Samples::default());
    m.sample_into(&mut samples);
    m.owned_samples_into(&mut owned);
    End {
        samples,
        owned,
        nodal: m.mesh_nodal_fields().unwrap(),
        energy: m.energy(),
        work: m.external_work(),
        momentum: m.momentum(),
        impulse: m.external_impulse(),
    }
}

fn steps<const D: usize>(m: &mut dyn Method<D>, n: usize) {
    let dt = m.stable_dt();
    for k in 0..n {
        m.step(k as f64 * dt, dt);
    }
}

/// The path a run takes (applied to the serial FEM and to each rank's local one).
#[derive(Clone, Copy, Debug)]
enum Path {
    /// The default: the stencil fused for linear elasticity, Gauss points otherwise.
    Default,
    /// The stencil's two phases.
    TwoPhases,
    /// The Gauss-point path for linear elasticity.
    Gauss,
}

fn take_path<const D: usize>(fem: &mut Fem<D>, path: Path) {
    match path {
        Path::Default => {}
        Path::TwoPhases => fem.solver.set_fused_step(false),
        Path::Gauss => fem.solver.use_gauss_path(),
    }
}

/// `ranked == serial` bit for bit, or a panic naming the first differing index and how
/// many differ.
fn same<T: PartialEq + std::fmt::Debug>(ranked: &[T], serial: &[T], what: &str) {
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

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Compare `ranks` = 1..=4 with the serial run after `n` steps: samples and nodal fields
/// bit for bit, sums to 1e-12 relative, the momentum balance as on one rank.
fn check<const D: usize>(label: &str, scene: &Scene, path: Path, n: usize) {
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
    for ranks in 1..=4 {
        let ends = ThreadComm::on_ranks(ranks, |comm| {
            let mut m = SlabFem::<D>::new(&problem, config, comm).unwrap();
            take_path(&mut m.local, path);
            steps(&mut m, n);
            finish(&m)
        });
        let owned: Vec<_> = ends.iter().map(|e| &e.owned).collect();
        assert!(
            owned_in_rank_order(&owned, s),
            "{label}, {ranks} ranks: the own samples in rank order are not the whole body's"
        );
        for (rank, end) in ends.iter().enumerate() {
            let at = format!("{label}, {ranks} ranks, rank {rank}");
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
            same(
                &end.nodal.0,
                &serial.nodal.0,
                &format!("{at}: nodal velocity"),
            );
            same(
                &end.nodal.1,
                &serial.nodal.1,
                &format!("{at}: nodal displacement"),
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

#[test]
fn bar_on_slabs_equals_one_rank() {
    // the pressure on the end node of the cut axis
    let bar = scene("bar");
    check::<1>("bar", &bar, Path::Default, 60);
    check::<1>("bar, two phases", &bar, Path::TwoPhases, 60);
    check::<1>("bar, Gauss points", &bar, Path::Gauss, 60);
    // one element layer per rank on 4 ranks: every node of a middle rank is next to a cut
    let mut short = bar.clone();
    short.domain.cells = vec![4];
    check::<1>("bar of 4 elements", &short, Path::Default, 20);
    check::<1>("bar of 4 elements, Gauss", &short, Path::Gauss, 20);
}

#[test]
fn plate_on_slabs_equals_one_rank() {
    // the impactor's nodes (y ≤ 1 m) span two slabs on 3 and 4 ranks
    let plate = scene("plate");
    check::<2>("plate", &plate, Path::Default, 60);
    check::<2>("plate, two phases", &plate, Path::TwoPhases, 60);
    check::<2>("plate, Gauss points", &plate, Path::Gauss, 60);
    // symmetry edges on the cut axis (bottom and top)
    check::<2>("plate-wave", &scene("plate-wave"), Path::Default, 60);
    check::<2>("plate-wave, Gauss", &scene("plate-wave"), Path::Gauss, 60);
}

#[test]
fn plastic_and_large_strain_plates_on_slabs_equal_one_rank() {
    check::<2>("ep-plate", &scene("ep-plate"), Path::Default, 60);
    check::<2>("svk-plate", &scene("svk-plate"), Path::Default, 60);
}

/// 3D: the block (the impactor's square patch) on slabs along z.
#[test]
fn block_on_slabs_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![10, 8, 12];
    check::<3>("block", &block, Path::Default, 30);
    check::<3>("block, Gauss points", &block, Path::Gauss, 30);
    let mut ep = scene("ep-block");
    ep.domain.cells = vec![10, 8, 12];
    check::<3>("ep-block", &ep, Path::Default, 30);
}

/// A NaN planted in one rank's slab is reported by every rank, once, at its global place.
#[test]
fn a_blowup_on_one_rank_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let mut serial = Fem::<2>::new(&problem, config).unwrap();
    let bad = serial.state.velocity_half.len() - 40; // in the last rank's slab
    serial.state.velocity_half[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let reports = blowup_on_ranks(3, bad, |comm| {
        SlabFem::<2>::new(&problem, config, comm).unwrap()
    });
    assert!(
        reports.iter().all(|state| state == &expected),
        "{reports:?}"
    );
}

/// More ranks than layers: every rank refuses with the same message.
#[test]
fn too_many_ranks_are_refused_on_every_rank() {
    let mut short = scene("bar");
    short.domain.cells = vec![3];
    let problem = Problem::<1>::from_scene(&short).unwrap();
    let config = short.method_config(MethodKind::Fem);
    let message = refusal_on_ranks(4, |comm| SlabFem::<1>::new(&problem, config, comm));
    assert!(
        message.contains("4 ranks cannot share the 3 layers"),
        "{}",
        message
    );
    // boxes are not the FEM's yet: refused on every rank
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let boxes = RankGrid(vec![2, 2]);
    let message = refusal_on_ranks(4, |comm| {
        SlabFem::<2>::on_grid(&problem, config, comm, &boxes)
    });
    assert!(
        message.contains("FEM on the rank grid 2,2 (boxes) does not run on 4 ranks yet"),
        "{message}"
    );
}

/// The halo message per step: one node layer each way per neighbour, `u`, `v`, `a` (6
/// values per node in 2D), so 34 × 6 × 8 B per neighbour on the 33 × 25 plate.
#[test]
fn halo_bytes_per_step_are_one_node_layer_per_neighbour() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let bytes = ThreadComm::on_ranks(3, |comm| {
        SlabFem::<2>::new(&problem, config, comm)
            .unwrap()
            .bytes_per_step()
    });
    let layer = 34 * 6 * 8;
    assert_eq!(bytes, vec![layer, 2 * layer, layer]);
}

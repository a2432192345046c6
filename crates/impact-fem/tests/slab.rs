//! FEM split in slabs over 1 to 4 ranks ([`SlabFem`], ranks as threads through
//! [`ThreadComm`]) equals the one-rank run: the sampled fields and the mesh's nodal fields
//! bit for bit on every path (stencil fused and in two phases, Gauss points, J2 with its
//! Gauss-point history, Saint-Venant–Kirchhoff; a pressure, prescribed velocities and
//! symmetry edges, on the cut axis too), in 1D, 2D and 3D, since every owned node is formed
//! by the same operations on the same bits (`slab.rs`); energy, work, momentum and impulse
//! to round-off (summed per rank, then in rank order), and the momentum balance holds on
//! the ranks as on one. A non-finite state on one rank is reported identically by every
//! rank at its global place; more ranks than layers are refused on every rank. (Boxes:
//! `boxes.rs`.)
use impact_core::comm::ThreadComm;
use impact_core::method::MethodKind;
use impact_core::slab_method::{blowup_on_ranks, refusal_on_ranks, slab_grids};
use impact_core::{Method, Problem, Scene};
use impact_fem::slab::SlabFem;
use impact_fem::Fem;

use crate::decomposed::{check_on, scene, sine_pressure_plate, Path};

/// [`check_on`] on slabs over 1 to 4 ranks.
fn check<const D: usize>(label: &str, scene: &Scene, path: Path, n: usize) {
    check_on::<D>(label, scene, path, n, &slab_grids(4));
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
    // a pressure whose step mean changes every step on the left face, across the cuts
    check::<2>(
        "plate, sine pressure",
        &sine_pressure_plate(),
        Path::Default,
        60,
    );
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

/// More ranks than layers: every rank refuses with the same message (boxes: `boxes.rs`).
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

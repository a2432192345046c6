//! DGMPM split in slabs over 1 to 4 ranks ([`SlabDgmpm`], ranks as threads through
//! [`ThreadComm`]) equals the one-rank run: the sampled fields bit for bit on the cell and
//! fused paths (the same operations on the same bits, `slab.rs`), to round-off on the
//! nodal paths (shape functions formed from the slab's origin); energy, work, momentum and
//! impulse to round-off (summed per rank, then in rank order). A non-finite state on one
//! rank is reported identically by every rank at its global place; more ranks than layers
//! are refused on every rank with the most that fit.
use impact_core::comm::{Comm, RankGrid, ThreadComm};
use impact_core::method::{Integrator, MethodConfig, MethodKind, SchemeOrder, TransverseFlux};
use impact_core::slab_method::{
    blowup_on_ranks, owned_in_rank_order, refusal_on_ranks, slab_grids,
};
use impact_core::{Method, Problem, Scene};
use impact_dgmpm::slab::SlabDgmpm;
use impact_dgmpm::Dgmpm;
use std::sync::Arc;

use crate::decomposed::{runs, scene};

/// `body` on `ranks` thread ranks, its results in rank order.
fn on_ranks<T: Send>(ranks: usize, body: impl Fn(Arc<dyn Comm>) -> T + Sync) -> Vec<T> {
    ThreadComm::on_ranks(ranks, body)
}

/// Compare slabs on 1 to 4 ranks with the serial run (`crate::decomposed::check_on`).
fn check<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    exact: bool,
) {
    crate::decomposed::check_on::<D>(label, scene, edit, exact, &slab_grids(4));
}

#[test]
fn bar_on_slabs_equals_one_rank() {
    let bar = scene("bar");
    check::<1>("bar", &bar, |_| {}, true);
    check::<1>("bar, Courant 0.6", &bar, |c| c.courant = 0.6, true);
}

#[test]
fn plate_on_slabs_equals_one_rank() {
    let plate = scene("plate");
    check::<2>("plate, CTU", &plate, |_| {}, true);
    check::<2>(
        "plate, donor-cell",
        &plate,
        |c| {
            c.dgmpm_mut().unwrap().flux = TransverseFlux::DonorCell;
            c.courant = 0.6;
        },
        true,
    );
    check::<2>(
        "plate, order 2",
        &plate,
        |c| {
            c.dgmpm_mut().unwrap().order = SchemeOrder::Second;
            c.courant = 0.9;
        },
        true,
    );
    // the nodal paths: shape functions from the slab's origin (round-off)
    check::<2>(
        "plate, RK2, 4 points per cell",
        &plate,
        |c| {
            c.dgmpm_mut().unwrap().integrator = Integrator::Rk2;
            (c.points_per_cell, c.courant) = (4, 0.5);
        },
        false,
    );
}

#[test]
fn plastic_and_large_strain_plates_on_slabs_equal_one_rank() {
    check::<2>("ep-plate", &scene("ep-plate"), |_| {}, true);
    // RK2 on the nodal path: shape functions from the slab's origin (round-off)
    check::<2>("svk-plate", &scene("svk-plate"), |_| {}, false);
    check::<2>(
        "svk-plate, Euler",
        &scene("svk-plate"),
        |c| {
            c.dgmpm_mut().unwrap().integrator = Integrator::Euler;
            c.courant = 0.5;
        },
        true,
    );
}

/// A NaN planted in one rank's slab is reported by every rank, once, at its global place.
#[test]
fn a_blowup_on_one_rank_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    let mut serial = Dgmpm::<2>::new(&problem, config).unwrap();
    let bad = serial.state.points.len() - 40; // in the last rank's slab
    serial.state.points.velocity[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let reports = blowup_on_ranks(3, bad, |comm| {
        SlabDgmpm::<2>::new(&problem, config, comm).unwrap()
    });
    assert!(
        reports.iter().all(|state| state == &expected),
        "{reports:?}"
    );
}

/// More ranks than the layers allow: every rank refuses with the same message.
#[test]
fn too_many_ranks_are_refused_on_every_rank() {
    let bar = scene("bar");
    let mut short = bar.clone();
    short.domain.cells = vec![3];
    let problem = Problem::<1>::from_scene(&short).unwrap();
    let config = short.method_config(MethodKind::Dgmpm);
    let message = refusal_on_ranks(4, |comm| SlabDgmpm::<1>::new(&problem, config, comm));
    assert!(
        message.contains("4 ranks cannot share the 3 layers"),
        "{}",
        message
    );
    assert!(message.contains("at most 3 ranks"), "{}", message);
}

/// 3D: the block (CTU, transverse-transverse corrections) on slabs along z.
#[test]
fn block_on_slabs_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![10, 8, 12];
    check::<3>("block, CTU", &block, |_| {}, true);
    check::<3>(
        "block, donor-cell",
        &block,
        |c| {
            c.dgmpm_mut().unwrap().flux = TransverseFlux::DonorCell;
            c.courant = 0.45;
        },
        true,
    );
}

/// The halo message per step: one layer of points each way per neighbour, 8 values per
/// point in 2D (position, velocity, σ), so 33 × 8 × 8 B per neighbour on the plate.
#[test]
fn halo_bytes_per_step_are_one_layer_per_neighbour() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    let bytes = on_ranks(3, |comm| {
        SlabDgmpm::<2>::new(&problem, config, comm)
            .unwrap()
            .bytes_per_step()
    });
    let layer = 33 * 8 * 8;
    assert_eq!(bytes, vec![layer, 2 * layer, layer]);
}

/// A rank seeds only its stored layers' points (`material_points_of_box`): the same
/// bits as the whole body's points cut to those layers, for every layout-relevant scene
/// (initial states, J2 history, SVK's `F`, 3D) and 1 or 4 points per cell. (`Debug`
/// prints each `f64` in its shortest round-trip form, so equal text is equal bits.)
#[test]
fn stored_layers_are_seeded_with_the_whole_bodys_bits() {
    let cases: [(&str, usize); 5] = [
        ("plate-wave", 1),
        ("plate-wave", 4),
        ("ep-plate", 1),
        ("svk-plate", 4),
        ("oblique-plate-wave", 1),
    ];
    for (name, ppc) in cases {
        let scene = scene(name);
        let problem = Problem::<2>::from_scene(&scene).unwrap();
        let mut config = scene.method_config(MethodKind::Dgmpm);
        config.points_per_cell = ppc;
        let grid = &problem.grid;
        let whole = problem.material_points(grid, &config).unwrap();
        let per_layer = grid.cells[0] * ppc;
        let layers = grid.cells[1];
        for range in [0..1, 0..layers, 3..7, layers - 2..layers] {
            let part = problem
                .material_points_of_box(grid, &config, &[0..grid.cells[0], range.clone()])
                .unwrap();
            let cut = whole.select(range.start * per_layer..range.end * per_layer);
            assert_eq!(part.len(), range.len() * per_layer, "{name}");
            assert_eq!(format!("{part:?}"), format!("{cut:?}"), "{name}, {range:?}");
        }
    }
    let mut block = scene("block-wave");
    block.domain.cells = vec![6, 5, 9];
    let problem = Problem::<3>::from_scene(&block).unwrap();
    let config = block.method_config(MethodKind::Dgmpm);
    let whole = problem.material_points(&problem.grid, &config).unwrap();
    let part = problem
        .material_points_of_box(&problem.grid, &config, &[0..6, 0..5, 2..5])
        .unwrap();
    let cut = whole.select(2 * 30..5 * 30);
    assert_eq!(format!("{part:?}"), format!("{cut:?}"), "block-wave");
    // a box: the whole body's points of its cells, in the whole body's relative order
    let cells = [1..4, 2..5, 3..7];
    let part = problem
        .material_points_of_box(&problem.grid, &config, &cells)
        .unwrap();
    let per_cell = whole.len() / problem.grid.cell_count();
    let mut expected = Vec::new();
    for c in 0..problem.grid.cell_count() {
        let idx = problem.grid.cell_multi_index(c);
        if (0..3).all(|k| cells[k].contains(&idx[k])) {
            expected.extend(c * per_cell..(c + 1) * per_cell);
        }
    }
    let picked: Vec<_> = expected.iter().map(|&i| whole.reference[i]).collect();
    assert_eq!(part.reference, picked, "block-wave, a box");
}

/// Each rank's owned samples (its output piece), concatenated in rank order, are the
/// whole body's samples, on 1 to 3 ranks.
#[test]
fn owned_samples_in_rank_order_are_the_gathered_ones() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    for ranks in 1..=3 {
        let (serial, ends) = runs(&problem, config, &RankGrid::automatic(), ranks, 20);
        let owned: Vec<_> = ends.iter().map(|e| &e.owned).collect();
        assert!(
            owned_in_rank_order(&owned, &serial.samples),
            "{ranks} ranks"
        );
        assert!(ends
            .iter()
            .all(|e| e.owned.len() < serial.samples.len() || ranks == 1));
    }
}

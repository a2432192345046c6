//! FEM split in boxes over a grid of ranks (`--ranks-grid`, [`RankBox`]; ranks as threads
//! through `ThreadComm`) equals the one-rank run: the sampled fields and the mesh's nodal
//! fields bit for bit in the global order on every path (stencil fused and in two phases,
//! Gauss points, J2 with its Gauss-point history, Saint-Venant–Kirchhoff), since every owned
//! node is formed by the same operations on the same bits (`slab.rs`: a halo of one element
//! layer along every axis, its edges and corners filled by the axis-by-axis exchange); energy,
//! work, momentum and impulse to round-off (summed per rank, then in rank order). The bar is
//! 1D: its only rank grid is the slab one (`slab.rs`). Bad rank grids are refused on every
//! rank alike.
use impact_core::comm::{RankBox, RankGrid, ThreadComm};
use impact_core::method::MethodKind;
use impact_core::slab_method::{blowup_on_ranks, box_grids, refusal_on_ranks};
use impact_core::{Method, Problem};
use impact_fem::slab::{describe, SlabFem};
use impact_fem::Fem;

use crate::decomposed::{check_on, scene, sine_pressure_plate, Path};

/// The 2D rank grids of the brief: 2×2, 3×1, 1×3.
const PLATE_GRIDS: [&[usize]; 3] = [&[2, 2], &[3, 1], &[1, 3]];

#[test]
fn plates_on_boxes_equal_one_rank() {
    // the impactor's nodes (y ≤ 1 m) on the left face, cut along y on 2×2 and 1×3
    let grids = box_grids(&PLATE_GRIDS);
    let plate = scene("plate");
    check_on::<2>("plate", &plate, Path::Default, 60, &grids);
    check_on::<2>("plate, two phases", &plate, Path::TwoPhases, 60, &grids);
    check_on::<2>("plate, Gauss points", &plate, Path::Gauss, 60, &grids);
    // symmetry edges (bottom and top) cut along x on 2×2 and 3×1
    let wave = scene("plate-wave");
    check_on::<2>("plate-wave", &wave, Path::Default, 60, &grids);
    check_on::<2>("plate-wave, Gauss", &wave, Path::Gauss, 60, &grids);
}

/// A pressure whose step mean changes every step (a sine) on the left face, which the cuts
/// along y cross: the halo nodes on it move by `f Δḡ / m` with their whole-mesh mass, as on
/// one rank (`build.rs`).
#[test]
fn a_varying_pressure_across_the_cuts_equals_one_rank() {
    let pressure = sine_pressure_plate();
    let grids = box_grids(&[&[2, 2], &[1, 3]]);
    check_on::<2>("plate, sine pressure", &pressure, Path::Default, 60, &grids);
    check_on::<2>(
        "plate, sine pressure, Gauss",
        &pressure,
        Path::Gauss,
        60,
        &grids,
    );
}

#[test]
fn plastic_and_large_strain_plates_on_boxes_equal_one_rank() {
    let grids = box_grids(&[&[2, 2], &[3, 1]]);
    check_on::<2>("ep-plate", &scene("ep-plate"), Path::Default, 60, &grids);
    check_on::<2>("svk-plate", &scene("svk-plate"), Path::Default, 60, &grids);
}

/// 3D: the block (the impactor's square patch on x = 0) on 2×2×1 and 1×2×2.
#[test]
fn block_on_boxes_equals_one_rank() {
    let grids = box_grids(&[&[2, 2, 1], &[1, 2, 2]]);
    let mut block = scene("block");
    block.domain.cells = vec![10, 8, 12];
    check_on::<3>("block", &block, Path::Default, 30, &grids);
    check_on::<3>("block, Gauss points", &block, Path::Gauss, 30, &grids);
    let mut ep = scene("ep-block");
    ep.domain.cells = vec![10, 8, 12];
    check_on::<3>(
        "ep-block",
        &ep,
        Path::Default,
        30,
        &box_grids(&[&[2, 2, 1]]),
    );
}

/// A NaN planted in one box is reported by every rank, once, at its global place.
#[test]
fn a_blowup_in_one_box_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let mut serial = Fem::<2>::new(&problem, config).unwrap();
    // node (5, 20) of the 34 × 26: inside the upper-left box of 2×2
    let bad = 20 * 34 + 5;
    serial.state.velocity_half[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let grid = RankGrid(vec![2, 2]);
    let reports = blowup_on_ranks(4, bad, |comm| {
        SlabFem::<2>::on_grid(&problem, config, comm, &grid).unwrap()
    });
    assert!(reports.iter().all(|s| s == &expected), "{reports:?}");
}

/// Rank grids that do not fit are refused with one message on every rank.
#[test]
fn bad_rank_grids_are_refused_on_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let refuse = |parts: Vec<usize>, ranks: usize| {
        refusal_on_ranks(ranks, |comm| {
            SlabFem::<2>::on_grid(&problem, config, comm, &RankGrid(parts.clone()))
        })
    };
    let product = refuse(vec![2, 2], 3);
    assert!(
        product.contains("--ranks-grid 2,2: its product is 4 but the run has 3 ranks"),
        "{product}"
    );
    let mut narrow = plate.clone();
    narrow.domain.cells = vec![3, 25];
    let problem = Problem::<2>::from_scene(&narrow).unwrap();
    let thin = refusal_on_ranks(4, |comm| {
        SlabFem::<2>::on_grid(&problem, config, comm, &RankGrid(vec![4, 1]))
    });
    assert!(
        thin.contains("4 ranks cannot share the 3 layers of cells along axis 0"),
        "{thin}"
    );
}

/// The halo bytes per step of a 2×2 plate: along x one node column of the owned node rows
/// (the top one too where the box reaches it), along y one node row across the stored
/// columns (the corner), each `u`, `v`, `a` (6 values).
#[test]
fn box_halo_bytes_cover_faces_and_corners() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Fem);
    let grid = RankGrid(vec![2, 2]);
    let bytes = ThreadComm::on_ranks(4, |comm| {
        SlabFem::<2>::on_grid(&problem, config, comm, &grid)
            .unwrap()
            .bytes_exchanged_per_step()
    });
    for (rank, sent) in bytes.into_iter().enumerate() {
        let b = RankBox::new(&problem.grid.cells, &grid, 4, rank, 1).unwrap();
        let top = usize::from(b.owned[1].end == 25);
        let nodes = (b.owned[1].len() + top) + (b.stored[0].len() + 1);
        assert_eq!(sent, nodes * 6 * 8, "rank {rank}");
    }
}

/// The summary names the rank grid.
#[test]
fn describe_names_the_rank_grid() {
    let problem = Problem::<2>::from_scene(&scene("plate")).unwrap();
    let text = describe(&problem.grid, 4, &RankGrid(vec![2, 2]));
    assert!(text.contains("4 boxes (rank grid 2 × 2"), "{text}");
    let slabs = describe(&problem.grid, 3, &RankGrid::automatic());
    assert!(slabs.contains("3 slabs along axis 1"), "{slabs}");
}

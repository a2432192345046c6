//! DGMPM split in boxes over a grid of ranks (`--ranks-grid`, [`RankBox`]; ranks as threads
//! through `ThreadComm`) equals the one-rank run: the gathered fields bit for bit in the
//! global point order on the cell and fused paths (each owned cell formed by the same
//! operations on the same bits: the halo along every axis, its edges and corners filled by
//! the axis-by-axis exchange), to round-off on the nodal paths (shape functions from the
//! box's origin, as on slabs); energy, work, momentum and impulse to round-off (summed per
//! rank, then in rank order). Bad rank grids are refused on every rank alike.
use impact_core::comm::{RankBox, RankGrid};
use impact_core::method::{Integrator, MethodKind, SchemeOrder};
use impact_core::slab_method::{blowup_on_ranks, refusal_on_ranks};
use impact_core::{Method, Problem};
use impact_dgmpm::slab::SlabDgmpm;
use impact_dgmpm::Dgmpm;

use crate::decomposed::{check_on, scene};
use impact_core::slab_method::box_grids as boxes;

/// The 2D rank grids of the brief: 2×2, 3×1, 1×3, 2×1.
const PLATE_GRIDS: [&[usize]; 4] = [&[2, 2], &[3, 1], &[1, 3], &[2]];

#[test]
fn bar_on_a_rank_grid_equals_one_rank() {
    // 1D: the rank grid is the slab one, `N`
    check_on::<1>("bar", &scene("bar"), |_| {}, true, &boxes(&[&[2], &[3]]));
}

#[test]
fn plates_on_boxes_equal_one_rank() {
    let grids = boxes(&PLATE_GRIDS);
    check_on::<2>("plate, CTU", &scene("plate"), |_| {}, true, &grids);
    check_on::<2>("plate-wave", &scene("plate-wave"), |_| {}, true, &grids);
    check_on::<2>(
        "plate, order 2",
        &scene("plate"),
        |c| {
            c.dgmpm_mut().unwrap().order = SchemeOrder::Second;
            c.courant = 0.9;
        },
        true,
        &boxes(&[&[2, 2]]),
    );
}

#[test]
fn plastic_and_large_strain_plates_on_boxes_equal_one_rank() {
    let square = boxes(&[&[2, 2]]);
    check_on::<2>("ep-plate", &scene("ep-plate"), |_| {}, true, &square);
    // RK2 on the nodal path: shape functions from the box's origin (round-off, as slabs)
    check_on::<2>("svk-plate", &scene("svk-plate"), |_| {}, false, &square);
}

/// The nodal paths on 2×2: RK2 and 4 points per cell (round-off, as on slabs).
#[test]
fn rk2_and_four_points_per_cell_on_boxes() {
    check_on::<2>(
        "plate, RK2, 4 points per cell",
        &scene("plate"),
        |c| {
            c.dgmpm_mut().unwrap().integrator = Integrator::Rk2;
            (c.points_per_cell, c.courant) = (4, 0.5);
        },
        false,
        &boxes(&[&[2, 2]]),
    );
}

/// 3D: the block (CTU, transverse-transverse corrections reach the edge and corner
/// neighbours) on 2×2×1 and 1×2×2.
#[test]
fn block_on_boxes_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![10, 8, 12];
    check_on::<3>(
        "block, CTU",
        &block,
        |_| {},
        true,
        &boxes(&[&[2, 2, 1], &[1, 2, 2]]),
    );
}

/// A NaN planted in one box is reported by every rank, once, at its global place.
#[test]
fn a_blowup_in_one_box_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    let mut serial = Dgmpm::<2>::new(&problem, config).unwrap();
    let bad = serial.state.points.len() / 2 + 3; // inside the upper-left box
    serial.state.points.velocity[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let grid = RankGrid(vec![2, 2]);
    let reports = blowup_on_ranks(4, bad, |comm| {
        SlabDgmpm::<2>::on_grid(&problem, config, comm, &grid).unwrap()
    });
    assert!(reports.iter().all(|s| s == &expected), "{reports:?}");
}

/// Rank grids that do not fit are refused with one message on every rank.
#[test]
fn bad_rank_grids_are_refused_on_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    let refuse = |parts: Vec<usize>, ranks: usize| {
        let grid = RankGrid(parts);
        refusal_on_ranks(ranks, |comm| {
            SlabDgmpm::<2>::on_grid(&problem, config, comm, &grid)
        })
    };
    let product = refuse(vec![2, 2], 3);
    assert!(
        product.contains("--ranks-grid 2,2: its product is 4 but the run has 3 ranks"),
        "{product}"
    );
    let entries = refuse(vec![1, 1, 2], 2);
    assert!(
        entries.contains("3 entries but the grid is 2D"),
        "{entries}"
    );
    // order 2: a halo of 3 cells, wider than the halves of 5 cells across
    let mut narrow = plate.clone();
    narrow.domain.cells = vec![5, 12];
    let problem = Problem::<2>::from_scene(&narrow).unwrap();
    let mut config = narrow.method_config(MethodKind::Dgmpm);
    config.dgmpm_mut().unwrap().order = SchemeOrder::Second;
    let thin = refusal_on_ranks(4, |comm| {
        SlabDgmpm::<2>::on_grid(&problem, config, comm, &RankGrid(vec![2, 2]))
    });
    assert!(
        thin.contains(
            "2 ranks cannot share the 5 layers of cells along axis 0: each rank \
                       needs at least 3 (its halo width); run on at most 1 ranks along that axis"
        ),
        "{thin}"
    );
}

/// The halo bytes per step of a 2×2 plate: each box sends its own cells next to its two
/// cuts, the second axis's message extended over the first axis's halo (the corner).
#[test]
fn box_halo_bytes_cover_faces_and_corners() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Dgmpm);
    let grid = RankGrid(vec![2, 2]);
    let bytes = decomposed_bytes(&problem, config, &grid);
    for (rank, sent) in bytes.into_iter().enumerate() {
        let b = RankBox::new(&problem.grid.cells, &grid, 4, rank, 1).unwrap();
        // axis 0: one column of its own rows; axis 1: one row of its stored columns
        let cells = b.owned[1].len() + b.stored[0].len();
        assert_eq!(sent, cells * 8 * 8, "rank {rank}");
    }
}

fn decomposed_bytes(
    problem: &Problem<2>,
    config: impact_core::method::MethodConfig,
    grid: &RankGrid,
) -> Vec<usize> {
    impact_core::comm::ThreadComm::on_ranks(4, |comm| {
        let m = SlabDgmpm::<2>::on_grid(problem, config, comm, grid).unwrap();
        m.bytes_exchanged_per_step()
    })
}

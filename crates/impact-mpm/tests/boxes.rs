//! MPM (total Lagrangian) split in boxes over a grid of ranks (`--ranks-grid`, [`RankBox`];
//! ranks as threads through [`ThreadComm`]) equals the one-rank run: the gathered fields bit
//! for bit in the global point order for every transfer, stress update, shape and model
//! (each own point formed by the same operations on the same bits: the halo along every
//! axis, its edges and corners filled by the axis-by-axis exchange; the box's nodes in the
//! whole grid's relative order, `build.rs`), each rank's own samples covering every point
//! once; energy, work, momentum and impulse to round-off (summed per rank, then in rank
//! order). A non-finite state in one box is reported identically by every rank at its
//! global place; the updated Lagrangian frame is refused on boxes.
use impact_core::comm::{Comm, RankBox, RankGrid, ThreadComm};
use impact_core::method::{MethodKind, MpmFrame, MpmShape, MpmTransfer, StressUpdate};
use impact_core::slab_method::{blowup_on_ranks, box_grids as boxes, refusal_on_ranks};
use impact_core::{Boundary, Load, Method, Problem};
use impact_mpm::slab::{halo_layers, SlabMpm};
use impact_mpm::Mpm;
use std::sync::Arc;

use crate::decomposed::{check, check_scene, options, scene};

/// The 2D rank grids of the brief: 2×2, 3×1, 1×3.
const PLATE_GRIDS: [&[usize]; 3] = [&[2, 2], &[3, 1], &[1, 3]];

#[test]
fn plates_on_boxes_equal_one_rank() {
    check_scene::<2>("plate", &scene("plate"), |_| {}, &boxes(&PLATE_GRIDS));
    // symmetry on both faces of both axes: the mirrored padding on the boxes at the ends
    check_scene::<2>(
        "plate-wave",
        &scene("plate-wave"),
        |_| {},
        &boxes(&PLATE_GRIDS),
    );
}

#[test]
fn stress_updates_and_transfers_on_boxes_equal_one_rank() {
    let plate = scene("plate");
    let square = boxes(&[&[2, 2]]);
    check_scene::<2>(
        "plate, MUSL",
        &plate,
        |c| {
            options(c).stress_update = StressUpdate::Musl;
        },
        &square,
    );
    check_scene::<2>(
        "plate, USF, PIC",
        &plate,
        |c| {
            options(c).stress_update = StressUpdate::Usf;
            options(c).transfer = MpmTransfer::Pic;
        },
        &square,
    );
    check_scene::<2>(
        "plate, APIC",
        &plate,
        |c| {
            options(c).transfer = MpmTransfer::Apic;
        },
        &square,
    );
    check_scene::<2>(
        "plate, MUSL, APIC",
        &plate,
        |c| {
            options(c).stress_update = StressUpdate::Musl;
            options(c).transfer = MpmTransfer::Apic;
        },
        &square,
    );
}

#[test]
fn shapes_on_boxes_equal_one_rank() {
    let plate = scene("plate");
    let square = boxes(&[&[2, 2]]);
    check_scene::<2>(
        "plate, GIMP",
        &plate,
        |c| options(c).shape = MpmShape::Gimp,
        &square,
    );
    check_scene::<2>(
        "plate, quadratic B-splines",
        &plate,
        |c| {
            options(c).shape = MpmShape::Bspline2;
        },
        &square,
    );
    check_scene::<2>(
        "plate-wave, cubic B-splines",
        &scene("plate-wave"),
        |c| {
            options(c).shape = MpmShape::Bspline3;
        },
        &boxes(&[&[2, 2], &[3, 1]]),
    );
    check_scene::<2>(
        "plate, CPDI, 4 points per cell",
        &plate,
        |c| {
            options(c).shape = MpmShape::Cpdi;
            c.points_per_cell = 4;
        },
        &square,
    );
}

#[test]
fn plastic_and_large_strain_plates_on_boxes_equal_one_rank() {
    let square = boxes(&[&[2, 2]]);
    check_scene::<2>("ep-plate", &scene("ep-plate"), |_| {}, &square);
    check_scene::<2>(
        "ep-plate, GIMP, MUSL",
        &scene("ep-plate"),
        |c| {
            options(c).shape = MpmShape::Gimp;
            options(c).stress_update = StressUpdate::Musl;
        },
        &square,
    );
    check_scene::<2>("svk-plate", &scene("svk-plate"), |_| {}, &square);
}

/// A pressure on the left edge (loaded points in the halo of the boxes beside the cut
/// along y: their work and impulse count once, on their owner), and a plate large enough
/// for the parallel coloured scatter (from 4096 points, when rayon has more than one
/// thread), whose blocks must follow the whole grid's layers in every box.
#[test]
fn loads_across_cuts_and_the_coloured_scatter_equal_one_rank() {
    let plate = scene("plate");
    let mut problem = Problem::<2>::from_scene(&plate).unwrap();
    problem.boundaries[0][0] = Boundary::Pressure(Load::step(2e8));
    let config = plate.method_config(MethodKind::Mpm);
    check::<2>(
        "plate, pressure on the left",
        &problem,
        config,
        &boxes(&PLATE_GRIDS),
        40,
    );
    let mut large = plate.clone();
    large.domain.cells = vec![70, 61];
    let problem = Problem::<2>::from_scene(&large).unwrap();
    let mut config = large.method_config(MethodKind::Mpm);
    options(&mut config).shape = MpmShape::Bspline2;
    check::<2>(
        "plate 70 × 61, quadratic B-splines",
        &problem,
        config,
        &boxes(&[&[2, 2]]),
        30,
    );
}

/// 3D: the block on 2×2×1 and 1×2×2, hats and quadratic B-splines under MUSL.
#[test]
fn block_on_boxes_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![12, 12, 12];
    let grids: [&[usize]; 2] = [&[2, 2, 1], &[1, 2, 2]];
    check_scene::<3>("block", &block, |_| {}, &boxes(&grids));
    check_scene::<3>(
        "block, quadratic B-splines, MUSL",
        &block,
        |c| {
            options(c).shape = MpmShape::Bspline2;
            options(c).stress_update = StressUpdate::Musl;
        },
        &boxes(&grids[..1]),
    );
}

/// A NaN planted in one box is reported by every rank, once, at its global place.
#[test]
fn a_blowup_in_one_box_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Mpm);
    let mut serial = Mpm::<2>::new(&problem, config).unwrap();
    let bad = serial.state.points.len() / 2 + 3; // inside the upper-left box
    serial.state.points.velocity[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let grid = RankGrid(vec![2, 2]);
    let reports = blowup_on_ranks(4, bad, |comm| {
        SlabMpm::<2>::on_grid(&problem, config, comm, &grid).unwrap()
    });
    assert!(reports.iter().all(|s| s == &expected), "{reports:?}");
}

/// The updated Lagrangian frame (points migrating) is refused on boxes by every rank with
/// the same message; so is a rank grid whose parts are thinner than the halo.
#[test]
fn updated_frame_and_thin_boxes_are_refused_on_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let grid = RankGrid(vec![2, 2]);
    let mut config = plate.method_config(MethodKind::Mpm);
    options(&mut config).frame = MpmFrame::UpdatedLagrangian;
    let message = refusal_on_ranks(4, |comm| {
        SlabMpm::<2>::on_grid(&problem, config, comm, &grid)
    });
    assert!(
        message.contains("updated Lagrangian") && message.contains("4 ranks"),
        "{message}"
    );
    // MUSL with B-splines needs 6 cells per part: 33 columns in 6 parts do not fit
    let mut config = plate.method_config(MethodKind::Mpm);
    options(&mut config).shape = MpmShape::Bspline2;
    options(&mut config).stress_update = StressUpdate::Musl;
    let message = refusal_on_ranks(6, |comm| {
        SlabMpm::<2>::on_grid(&problem, config, comm, &RankGrid(vec![6, 1]))
    });
    assert!(
        message.contains("along axis 0") && message.contains("at most 5 ranks"),
        "{message}"
    );
}

/// The halo bytes per step of a 2×2 plate: each box sends the points of its own cells next
/// to its two cuts, the second axis's message extended over the first axis's halo (the
/// corner): 8 values per point in 2D (position, velocity, σ), one cell wide with hats.
#[test]
fn box_halo_bytes_cover_faces_and_corners() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Mpm);
    let grid = RankGrid(vec![2, 2]);
    let halo = halo_layers(config.mpm().unwrap());
    let bytes = ThreadComm::on_ranks(4, |comm: Arc<dyn Comm>| {
        SlabMpm::<2>::on_grid(&problem, config, comm, &grid)
            .unwrap()
            .bytes_exchanged_per_step()
    });
    for (rank, sent) in bytes.into_iter().enumerate() {
        let b = RankBox::new(&problem.grid.cells, &grid, 4, rank, halo).unwrap();
        let cells = b.owned[1].len() + b.stored[0].len();
        assert_eq!(sent, cells * 8 * 8, "rank {rank}");
    }
}

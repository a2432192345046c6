//! MPM split in slabs over 1 to 4 ranks ([`SlabMpm`], ranks as threads through
//! [`ThreadComm`]) equals the one-rank run: the sampled fields bit for bit for every
//! transfer, stress update, shape and model (the same operations on the same bits,
//! `slab.rs`); energy, work, momentum and impulse to round-off (summed per rank, then in rank
//! order). A non-finite state on one rank is reported identically by every rank at its
//! global place; the updated Lagrangian frame is refused by this fixed-halo slab on more than
//! one rank (`tests/migrate.rs` runs it on the migrating slab). Boxes: `tests/boxes.rs`.
use impact_core::comm::{Comm, ThreadComm};
use impact_core::method::{
    MethodConfig, MethodKind, MpmFrame, MpmShape, MpmTransfer, StressUpdate,
};
use impact_core::slab_method::{blowup_on_ranks, refusal_on_ranks};
use impact_core::{Boundary, Load, Method, Problem, Scene};
use impact_mpm::slab::SlabMpm;
use impact_mpm::Mpm;
use std::sync::Arc;

use crate::decomposed::{options, scene, slabs};

/// `body` on `ranks` thread ranks, its results in rank order.
fn on_ranks<T: Send>(ranks: usize, body: impl Fn(Arc<dyn Comm>) -> T + Sync) -> Vec<T> {
    ThreadComm::on_ranks(ranks, body)
}

/// Compare slabs on 1 to 4 ranks with the serial run after `n` steps (`crate::decomposed::check`).
fn check<const D: usize>(label: &str, problem: &Problem<D>, config: MethodConfig, n: usize) {
    crate::decomposed::check::<D>(label, problem, config, &slabs(), n);
}

/// `scene`'s MPM configuration edited by `edit`, on slabs on 1 to 4 ranks.
fn check_scene<const D: usize>(label: &str, scene: &Scene, edit: impl Fn(&mut MethodConfig)) {
    crate::decomposed::check_scene::<D>(label, scene, edit, &slabs());
}

#[test]
fn bar_on_slabs_equals_one_rank() {
    let bar = scene("bar");
    check_scene::<1>("bar", &bar, |_| {});
    check_scene::<1>("bar, cubic B-splines, MUSL", &bar, |c| {
        options(c).shape = MpmShape::Bspline3;
        options(c).stress_update = StressUpdate::Musl;
    });
}

#[test]
fn plates_on_slabs_equal_one_rank() {
    check_scene::<2>("plate", &scene("plate"), |_| {});
    // symmetry on both cut-axis faces: the mirrored padding at the first and last ranks
    check_scene::<2>("plate-wave", &scene("plate-wave"), |_| {});
    check_scene::<2>("plate-wave, GIMP", &scene("plate-wave"), |c| {
        options(c).shape = MpmShape::Gimp;
    });
}

#[test]
fn plastic_and_large_strain_plates_on_slabs_equal_one_rank() {
    check_scene::<2>("ep-plate", &scene("ep-plate"), |_| {});
    check_scene::<2>("svk-plate", &scene("svk-plate"), |_| {});
}

#[test]
fn options_on_slabs_equal_one_rank() {
    let plate = scene("plate");
    check_scene::<2>("plate, GIMP", &plate, |c| options(c).shape = MpmShape::Gimp);
    check_scene::<2>("plate, quadratic B-splines", &plate, |c| {
        options(c).shape = MpmShape::Bspline2;
    });
    check_scene::<2>("plate, APIC", &plate, |c| {
        options(c).transfer = MpmTransfer::Apic;
    });
    check_scene::<2>("plate, PIC, USF", &plate, |c| {
        options(c).transfer = MpmTransfer::Pic;
        options(c).stress_update = StressUpdate::Usf;
    });
    check_scene::<2>("plate, MUSL, APIC", &plate, |c| {
        options(c).stress_update = StressUpdate::Musl;
        options(c).transfer = MpmTransfer::Apic;
    });
    check_scene::<2>("plate, 4 points per cell", &plate, |c| {
        c.points_per_cell = 4
    });
    check_scene::<2>("plate, CPDI, 4 points per cell", &plate, |c| {
        options(c).shape = MpmShape::Cpdi;
        c.points_per_cell = 4;
    });
}

/// A pressure on the left edge (every layer of the cut axis carries loaded points, halo
/// ones too: their work and impulse count once, on their owner), and a plate large enough
/// for the parallel coloured scatter (from 4096 points, when rayon has more than one
/// thread), whose blocks must follow the whole grid's layers on every slab.
#[test]
fn loads_across_the_cut_and_the_coloured_scatter_equal_one_rank() {
    let plate = scene("plate");
    let mut problem = Problem::<2>::from_scene(&plate).unwrap();
    problem.boundaries[0][0] = Boundary::Pressure(Load::step(2e8));
    let config = plate.method_config(MethodKind::Mpm);
    check::<2>("plate, pressure on the left edge", &problem, config, 40);
    let mut large = plate.clone();
    large.domain.cells = vec![70, 61];
    let problem = Problem::<2>::from_scene(&large).unwrap();
    let mut config = large.method_config(MethodKind::Mpm);
    check::<2>("plate 70 × 61", &problem, config, 30);
    options(&mut config).shape = MpmShape::Bspline2;
    check::<2>("plate 70 × 61, quadratic B-splines", &problem, config, 30);
}

/// A NaN planted in one rank's slab is reported by every rank, once, at its global place.
#[test]
fn a_blowup_on_one_rank_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Mpm);
    let mut serial = Mpm::<2>::new(&problem, config).unwrap();
    let bad = serial.state.points.len() - 40; // in the last rank's slab
    serial.state.points.velocity[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    let reports = blowup_on_ranks(3, bad, |comm| {
        SlabMpm::<2>::new(&problem, config, comm).unwrap()
    });
    assert!(
        reports.iter().all(|state| state == &expected),
        "{reports:?}"
    );
}

/// The updated Lagrangian frame (points migrating between ranks: `MigratingMpm`) is refused by `SlabMpm` on more than
/// one rank, by every rank with the same message; more ranks than the halo allows too.
#[test]
fn updated_frame_and_too_many_ranks_are_refused_on_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let mut config = plate.method_config(MethodKind::Mpm);
    options(&mut config).frame = MpmFrame::UpdatedLagrangian;
    let message = refusal_on_ranks(2, |comm| SlabMpm::<2>::new(&problem, config, comm));
    assert!(
        message.contains("updated Lagrangian") && message.contains("2 ranks"),
        "{message}"
    );
    // and on one rank it runs
    on_ranks(1, |comm| SlabMpm::<2>::new(&problem, config, comm).unwrap());
    // MUSL with B-splines needs 6 layers per rank: 25 layers on 5 ranks do not fit
    let mut config = plate.method_config(MethodKind::Mpm);
    options(&mut config).shape = MpmShape::Bspline2;
    options(&mut config).stress_update = StressUpdate::Musl;
    let message = refusal_on_ranks(5, |comm| SlabMpm::<2>::new(&problem, config, comm));
    assert!(message.contains("at most 4 ranks"), "{message}");
}

/// The halo message per step: `halo` layers of points each way per neighbour, 8 values per
/// point in 2D (position, velocity, σ): 1 layer with hats under USL, so 33 × 8 × 8 B per
/// neighbour on the plate; 3 layers and 3 more values (J2's history) on ep-plate with GIMP.
#[test]
fn halo_bytes_per_step_follow_the_stencil() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let config = plate.method_config(MethodKind::Mpm);
    let bytes = on_ranks(3, |comm| {
        SlabMpm::<2>::new(&problem, config, comm)
            .unwrap()
            .bytes_per_step()
    });
    let layer = 33 * 8 * 8;
    assert_eq!(bytes, vec![layer, 2 * layer, layer]);
    let ep = scene("ep-plate");
    let problem = Problem::<2>::from_scene(&ep).unwrap();
    let mut config = ep.method_config(MethodKind::Mpm);
    options(&mut config).shape = MpmShape::Gimp;
    let bytes = on_ranks(2, |comm| {
        SlabMpm::<2>::new(&problem, config, comm)
            .unwrap()
            .bytes_per_step()
    });
    assert_eq!(bytes, vec![3 * 33 * 11 * 8; 2]);
}

/// 3D: the block on slabs along z, hats and quadratic B-splines under MUSL.
#[test]
fn block_on_slabs_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![8, 6, 24];
    check_scene::<3>("block", &block, |_| {});
    check_scene::<3>("block, quadratic B-splines, MUSL", &block, |c| {
        options(c).shape = MpmShape::Bspline2;
        options(c).stress_update = StressUpdate::Musl;
    });
}

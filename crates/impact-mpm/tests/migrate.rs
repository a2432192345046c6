//! MPM in the updated Lagrangian frame on 1 to 4 slab ranks and on boxes (2 × 2, 1 × 3,
//! 3 × 1; the 3D block on 2 × 2 × 1 and 1 × 2 × 2; [`MigratingMpm`], ranks as threads
//! through [`ThreadComm`]), points crossing the rank faces (and, on boxes, the corners),
//! equals the one-rank run: the sampled fields (gathered in the global order) bit for bit, every point owned
//! by exactly one rank with its mass unchanged, energy and momentum to round-off (sums in
//! rank order). J2's history and APIC's affine velocity travel with their points (a field
//! left behind would change the fields after the crossing). A point that jumps past the
//! halo in one step fails the run with the step and the point; CPDI's domains, deforming
//! with the flow, cross with their points, and one stretched past the halo fails the run.
use impact_core::comm::{RankGrid, ThreadComm};
use impact_core::method::{
    MethodConfig, MethodKind, MpmFrame, MpmShape, MpmTransfer, StressUpdate,
};
use impact_core::slab_method::{assert_matches_serial, blowup_on_ranks, RunEnd};
use impact_core::{Method, Problem, Scene, Vector};
use impact_mpm::migrate::MigratingMpm;
use impact_mpm::Mpm;

fn scene(name: &str) -> Scene {
    Scene::builtin(name).unwrap()
}

/// How a comparison's points are kicked (`kick`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kick {
    Shear,
    Scrambled,
    Diagonal,
    /// `Diagonal`, every CPDI domain made 1.8 cells tall along the last axis: each point's
    /// stencil starts a cell below its cell and its 4 nodes along that axis weigh.
    TallDomains,
}

/// Every point's CPDI domain made 1.8 cells tall along the last axis (`Kick::TallDomains`).
fn make_tall<const D: usize>(m: &mut Mpm<D>, spacing: f64) {
    for r in &mut m.state.points.domain {
        r[(D - 1, D - 1)] = 0.9 * spacing;
    }
}

/// `problem`'s points kicked along the last axis by `speed · (½ + X₀/L₀)` (a shear across
/// the cut faces in 2D, a rigid translation on top of the impact in 1D), as every run of a
/// comparison gets it (`Kick::Shear`); with `Kick::Scrambled`, every other column of cells (along the first axis)
/// by `speed`, the others not at all: a column overtakes its neighbours by more than a
/// cell, so points of one layer sharing nodes are no longer in the order of their numbers
/// along the cut axis (the scatters must add them in the global order, not in a rank's
/// stored one).
fn kick<const D: usize>(m: &mut dyn Method<D>, speed: f64, length: f64, kind: Kick) {
    m.perturb_velocity(&mut |_, x| {
        let mut v = Vector::<D>::zeros();
        if kind == Kick::Diagonal || kind == Kick::TallDomains {
            // the whole plate along the diagonal, through the faces along both axes
            return Vector::<D>::from_element(speed);
        }
        v[D - 1] = if kind == Kick::Scrambled {
            speed * ((x[0] / length * 33.0).floor() % 2.0) // the plate's 33 columns
        } else if D == 1 {
            speed
        } else {
            speed * (0.5 + x[0] / length)
        };
        v
    });
}

/// `scene` in the updated frame, edited by `edit`, on 1..=4 slab ranks for `steps` steps,
/// against one rank ([`check_on`]).
fn check<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    steps: usize,
    scrambled: bool,
) {
    let kind = if scrambled {
        Kick::Scrambled
    } else {
        Kick::Shear
    };
    let slabs: Vec<(usize, RankGrid)> = (1..=4).map(|n| (n, RankGrid::automatic())).collect();
    check_on::<D>(label, scene, edit, steps, kind, &slabs);
}

/// `scene` in the updated frame, edited by `edit`, kicked as `kind`, on each `(ranks, rank
/// grid)` for `steps` steps, against one rank: bit for bit, points and masses conserved,
/// energy and momentum to round-off (`assert_matches_serial`), points really migrating.
/// Returns, per rank grid, the global numbers of each rank's own points at the end.
fn check_on<const D: usize>(
    label: &str,
    scene: &Scene,
    edit: impl Fn(&mut MethodConfig),
    steps: usize,
    kind: Kick,
    grids: &[(usize, RankGrid)],
) -> Vec<Vec<Vec<usize>>> {
    let problem = Problem::<D>::from_scene(scene).unwrap();
    let mut config = scene.method_config(MethodKind::Mpm);
    config.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian;
    edit(&mut config);
    let (speed, length) = (0.12 * problem.max_wave_speed(), scene.domain.length[0]);
    let mut one = Mpm::<D>::new(&problem, config).unwrap();
    kick::<D>(&mut one, speed, length, kind);
    let spacing = problem.grid.spacing[D - 1];
    if kind == Kick::TallDomains {
        make_tall(&mut one, spacing);
    }
    let serial = RunEnd::after_steps(&mut one, steps);
    let s = &serial.samples;
    let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
    assert!(
        s.position.iter().all(|x| finite(x.as_slice()))
            && s.stress.iter().all(|x| finite(x.as_slice())),
        "{label}: the serial run must stay finite"
    );
    let peak = s.stress.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    assert!(peak > 1e5, "{label}: the wave must be there");
    let total_mass: f64 = one.state.points.mass.iter().sum();
    let mut owners = Vec::new();
    for (ranks, grid) in grids {
        let ranks = *ranks;
        let ends = ThreadComm::on_ranks(ranks, |comm| {
            let mut m = MigratingMpm::<D>::on_grid(&problem, config, comm, grid).unwrap();
            kick::<D>(&mut m, speed, length, kind);
            if kind == Kick::TallDomains {
                make_tall(&mut m.local, spacing);
            }
            let end = RunEnd::after_steps(&mut m, steps);
            let own = m.local.owned_points();
            let masses: Vec<(usize, f64)> = (m.owned_ids().iter().copied())
                .zip(m.local.state.points.mass[own].iter().copied())
                .collect();
            (end, masses, m.migrated())
        });
        let at = format!("{label}, {ranks} ranks ({grid:?})");
        let migrated: usize = ends.iter().map(|e| e.2).sum();
        assert!(
            ranks == 1 || migrated > 0,
            "{at}: no point crossed a rank face"
        );
        let mut masses: Vec<(usize, f64)> = ends.iter().flat_map(|e| e.1.clone()).collect();
        masses.sort_by_key(|e| e.0);
        let expected: Vec<(usize, f64)> =
            one.state.points.mass.iter().copied().enumerate().collect();
        assert_eq!(
            masses, expected,
            "{at}: every point owned once, its mass unchanged"
        );
        let mass: f64 = masses.iter().map(|e| e.1).sum();
        assert_eq!(mass, total_mass, "{at}: Σ m");
        let runs: Vec<RunEnd<D>> = ends.iter().map(|e| e.0.clone()).collect();
        assert_matches_serial(&at, &serial, &runs, true);
        owners.push(
            ends.iter()
                .map(|e| e.1.iter().map(|m| m.0).collect())
                .collect(),
        );
    }
    owners
}

#[test]
fn a_moving_bar_migrates_and_equals_one_rank() {
    check::<1>("bar", &scene("bar"), |_| {}, 40, false);
    check::<1>(
        "bar, quadratic B-splines, MUSL",
        &scene("bar"),
        |c| {
            let o = c.mpm_mut().unwrap();
            o.shape = MpmShape::Bspline2;
            o.stress_update = StressUpdate::Musl;
        },
        40,
        false,
    );
}

#[test]
fn a_sheared_plate_migrates_and_equals_one_rank() {
    check::<2>("plate", &scene("plate"), |_| {}, 30, false);
    check::<2>(
        "plate, GIMP, USF",
        &scene("plate"),
        |c| {
            let o = c.mpm_mut().unwrap();
            o.shape = MpmShape::Gimp;
            o.stress_update = StressUpdate::Usf;
        },
        30,
        false,
    );
    check::<2>(
        "plate, quadratic B-splines",
        &scene("plate"),
        |c| c.mpm_mut().unwrap().shape = MpmShape::Bspline2,
        30,
        false,
    );
}

/// 3D: the block on slabs along z, sheared along z, hats and quadratic B-splines (MUSL:
/// under USL the serial run itself blows up, a node losing its last point).
#[test]
fn a_sheared_block_migrates_and_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![8, 6, 24];
    check::<3>(
        "block, MUSL",
        &block,
        |c| c.mpm_mut().unwrap().stress_update = StressUpdate::Musl,
        30,
        false,
    );
    check::<3>(
        "block, quadratic B-splines, MUSL",
        &block,
        |c| {
            let o = c.mpm_mut().unwrap();
            o.shape = MpmShape::Bspline2;
            o.stress_update = StressUpdate::Musl;
        },
        30,
        false,
    );
}

/// Neighbours overtaking each other across the cut faces: a layer's points arrive from
/// both sides out of the order of their numbers.
#[test]
fn scrambled_points_are_added_in_the_global_order() {
    check::<2>(
        "scrambled plate, MUSL",
        &scene("plate"),
        |c| c.mpm_mut().unwrap().stress_update = StressUpdate::Musl,
        30,
        true,
    );
    check::<2>(
        "scrambled plate, quadratic B-splines, MUSL",
        &scene("plate"),
        |c| {
            let o = c.mpm_mut().unwrap();
            o.shape = MpmShape::Bspline2;
            o.stress_update = StressUpdate::Musl;
        },
        30,
        true,
    );
    // large enough for the parallel coloured scatter (from 4096 points, with more than one
    // rayon thread), whose blocks follow the whole grid's layers on every slab
    let mut large = scene("plate");
    large.domain.cells = vec![70, 61];
    check::<2>(
        "plate 70 × 61, MUSL",
        &large,
        |c| c.mpm_mut().unwrap().stress_update = StressUpdate::Musl,
        30,
        true,
    );
}

/// Boxes: the plate moving along the diagonal (at 0.12 of the wave speed, about two cells
/// in 40 steps), its points crossing the faces along both axes and the boxes' corners, on
/// 2 × 2, 1 × 3 (the slabs) and 3 × 1 ranks, hats and quadratic B-splines (a halo of 6
/// cells) under MUSL (under USL the serial run itself blows up: a node losing its last
/// point), and J2 with APIC (quadratic B-splines: with hats the serial run blows up too):
/// bit for bit against one rank. On 2 × 2, points of rank 0's box end on rank 3 (across
/// the corner).
#[test]
fn a_diagonally_moving_plate_migrates_between_boxes_and_equals_one_rank() {
    let grids = [
        (4, RankGrid(vec![2, 2])),
        (3, RankGrid(vec![1, 3])),
        (3, RankGrid(vec![3, 1])),
    ];
    let mut plate = scene("plate");
    plate.domain.cells = vec![40, 30];
    let owners = check_on::<2>(
        "moving plate, MUSL",
        &plate,
        |c| c.mpm_mut().unwrap().stress_update = StressUpdate::Musl,
        40,
        Kick::Diagonal,
        &grids,
    );
    // the points seeded in rank 0's own cells (below 20 × 15) that rank 3 owns at the end
    let per_cell = plate.method_config(MethodKind::Mpm).points_per_cell;
    let across_the_corner = owners[0][3]
        .iter()
        .filter(|&&id| (id / per_cell % 40) < 20 && (id / per_cell / 40) < 15)
        .count();
    assert!(
        across_the_corner > 0,
        "no point crossed the corner from rank 0 to rank 3"
    );
    check_on::<2>(
        "moving plate, quadratic B-splines, MUSL",
        &plate,
        |c| {
            let o = c.mpm_mut().unwrap();
            o.shape = MpmShape::Bspline2;
            o.stress_update = StressUpdate::Musl;
        },
        40,
        Kick::Diagonal,
        &grids,
    );
    check_on::<2>(
        "moving ep-plate, APIC, quadratic B-splines, MUSL",
        &scene("ep-plate"),
        |c| {
            let o = c.mpm_mut().unwrap();
            o.transfer = MpmTransfer::Apic;
            o.shape = MpmShape::Bspline2;
            o.stress_update = StressUpdate::Musl;
        },
        40,
        Kick::Diagonal,
        &grids,
    );
}

/// 3D boxes: the block (its impactor patch holding the points of the x.low face) moving
/// along the diagonal (the same velocity along every axis, through the faces along both
/// split axes and the boxes' edges), 12 × 12 × 12 cells, on 2 × 2 × 1 and 1 × 2 × 2 ranks,
/// hats under MUSL: bit for bit against one rank, every point owned once with its mass,
/// energy and momentum to round-off. On both grids points of rank 0's box end on rank 3
/// (across the boxes' common edge).
#[test]
fn a_diagonally_moving_block_migrates_between_boxes_and_equals_one_rank() {
    let mut block = scene("block");
    block.domain.cells = vec![12, 12, 12];
    let grids = [(4, RankGrid(vec![2, 2, 1])), (4, RankGrid(vec![1, 2, 2]))];
    let owners = check_on::<3>(
        "moving block, MUSL",
        &block,
        |c| c.mpm_mut().unwrap().stress_update = StressUpdate::Musl,
        40,
        Kick::Diagonal,
        &grids,
    );
    let per_cell = block.method_config(MethodKind::Mpm).points_per_cell;
    let cell = |id: usize| {
        let c = id / per_cell;
        [c % 12, c / 12 % 12, c / 144]
    };
    for (owners, (_, grid)) in owners.iter().zip(&grids) {
        // seeded in rank 0's own cells (the lower half along each split axis)
        let in_rank_0 = |id: &&usize| {
            let c = cell(**id);
            (0..3).all(|k| grid.0[k] == 1 || c[k] < 6)
        };
        assert!(
            owners[3].iter().filter(in_rank_0).count() > 0,
            "{grid:?}: no point crossed the edge from rank 0 to rank 3"
        );
    }
}

/// J2's plastic history and APIC's affine velocity cross with their points.
#[test]
fn plastic_history_and_apic_migrate_with_their_points() {
    check::<2>(
        "ep-plate, APIC",
        &scene("ep-plate"),
        |c| c.mpm_mut().unwrap().transfer = MpmTransfer::Apic,
        30,
        false,
    );
}

/// A point kicked past the halo in one step (along the last axis on slabs, the diagonal on
/// 2 × 2 boxes) stops the run with the step and the point, on every rank.
#[test]
fn a_jump_past_the_halo_fails() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let mut config = plate.method_config(MethodKind::Mpm);
    config.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian;
    let fast = 40.0 * problem.max_wave_speed();
    let reports = ThreadComm::on_ranks(3, |comm| {
        let mut m = MigratingMpm::<2>::new(&problem, config, comm).unwrap();
        m.perturb_velocity(&mut |i, _| Vector::<2>::new(0.0, if i == 400 { fast } else { 0.0 }));
        let dt = m.stable_dt();
        m.step(0.0, dt);
        m.check_finite().unwrap_err()
    });
    let boxes = ThreadComm::on_ranks(4, |comm| {
        let mut m =
            MigratingMpm::<2>::on_grid(&problem, config, comm, &RankGrid(vec![2, 2])).unwrap();
        m.perturb_velocity(&mut |i, _| {
            Vector::<2>::from_element(if i == 400 { fast } else { 0.0 })
        });
        let dt = m.stable_dt();
        m.step(0.0, dt);
        m.check_finite().unwrap_err()
    });
    for reports in [reports, boxes] {
        let reason = &reports[0].reason;
        assert!(
            reason.contains("step 1,")
                && reason.contains("material point")
                && reason.contains("halo"),
            "{reason}"
        );
        assert!(reports.iter().all(|r| r == &reports[0]), "{reports:?}");
    }
}

/// CPDI with 2 × 2 points per cell, stresses updated as `update`.
fn cpdi(update: StressUpdate) -> impl Fn(&mut MethodConfig) {
    move |c| {
        c.points_per_cell = 4;
        let o = c.mpm_mut().unwrap();
        o.shape = MpmShape::Cpdi;
        o.stress_update = update;
    }
}

/// CPDI (2 × 2 points per cell, MUSL: a halo of 8 cells) on the plate moving along the
/// diagonal, 40 × 30 cells, its points and their deforming domains crossing the faces, on
/// 2 and 3 slabs and 2 × 2 boxes: bit for bit against one rank, every point owned once with
/// its mass, energy and momentum to round-off; under USL (a halo of 4 cells); and with
/// every domain 1.8 cells tall (`Kick::TallDomains`) on 3 and 4 slabs and 2 × 2 boxes;
/// and the plate's domains sheared hard (`Kick::Scrambled`, 33 × 25 cells, MUSL).
#[test]
fn cpdi_in_the_updated_frame_migrates_and_equals_one_rank() {
    let grids = [
        (2, RankGrid::automatic()),
        (3, RankGrid::automatic()),
        (4, RankGrid(vec![2, 2])),
    ];
    let mut plate = scene("plate");
    plate.domain.cells = vec![40, 30];
    for update in [StressUpdate::Musl, StressUpdate::Usl] {
        check_on::<2>(
            &format!("moving plate, CPDI, 2 × 2 points per cell, {update:?}"),
            &plate,
            cpdi(update),
            40,
            Kick::Diagonal,
            &grids,
        );
    }
    // every domain 1.8 cells tall: each stencil starts a cell below its point's cell and
    // its 4 nodes along the cut axis weigh (the domains' reach the halo's extra cell is for)
    check_on::<2>(
        "moving plate, CPDI, domains 1.8 cells tall, USL",
        &plate,
        cpdi(StressUpdate::Usl),
        40,
        Kick::TallDomains,
        &[
            (3, RankGrid::automatic()),
            (4, RankGrid::automatic()),
            (4, RankGrid(vec![2, 2])),
        ],
    );
    // domains sheared hard: every other column of cells kicked along the cut axis, so the
    // domains at the columns' sides shear and their stencils start below their cells
    check_on::<2>(
        "scrambled plate, CPDI, 2 × 2 points per cell, MUSL",
        &scene("plate"),
        cpdi(StressUpdate::Musl),
        30,
        Kick::Scrambled,
        &grids,
    );
}

/// A CPDI domain stretched past what the halo covers: a domain whose CPDI stencil fits
/// starts at most one cell below its point's cell (it is symmetric about the point and the
/// stencil spans 3 cells), which the halo covers, so a larger one leaves the stencil. One
/// point's domain made 3.2 cells tall (past the stencil) fails the run after the step on every rank, on 2
/// slabs and on 2 × 2 boxes, as one rank reports it (the same point and reason); no panic,
/// no answer.
#[test]
fn a_cpdi_domain_stretched_past_the_halo_fails_on_every_rank() {
    let mut plate = scene("plate");
    plate.domain.cells = vec![20, 20];
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let mut config = plate.method_config(MethodKind::Mpm);
    config.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian;
    cpdi(StressUpdate::Usl)(&mut config);
    // a point of the cell (10, 10), in the middle of the plate, on rank 1 of 2 slabs and
    // rank 3 of 2 × 2 boxes
    let target = (10 * 20 + 10) * 4;
    let tall = 1.6 * problem.grid.spacing[1];
    let stretch = |ids: &[usize], m: &mut Mpm<2>| {
        if let Some(i) = ids.iter().position(|&id| id == target) {
            m.state.points.domain[i][(1, 1)] = tall;
        }
    };
    let mut one = Mpm::<2>::new(&problem, config).unwrap();
    let ids: Vec<usize> = (0..one.state.points.len()).collect();
    stretch(&ids, &mut one);
    let dt = one.stable_dt();
    one.step(0.0, dt);
    let expected = one.check_finite().unwrap_err();
    assert!(
        expected.reason.contains("stencil left the background grid"),
        "{expected:?}"
    );
    for (ranks, grid) in [(2, RankGrid::automatic()), (4, RankGrid(vec![2, 2]))] {
        let reports = ThreadComm::on_ranks(ranks, |comm| {
            let mut m = MigratingMpm::<2>::on_grid(&problem, config, comm, &grid).unwrap();
            let ids = m.owned_ids().to_vec();
            stretch(&ids, &mut m.local);
            let dt = m.stable_dt();
            m.step(0.0, dt);
            m.check_finite().unwrap_err()
        });
        assert!(
            reports.iter().all(|r| r == &expected),
            "{grid:?}: {reports:?}"
        );
    }
}

/// A NaN planted in one point is reported by every rank, once, as one rank reports it, on
/// slabs and on 2 × 2 boxes.
#[test]
fn a_blowup_on_one_rank_is_seen_by_every_rank() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    let mut config = plate.method_config(MethodKind::Mpm);
    config.mpm_mut().unwrap().frame = MpmFrame::UpdatedLagrangian;
    let mut serial = Mpm::<2>::new(&problem, config).unwrap();
    let bad = serial.state.points.len() - 40; // in the last rank's slab
    serial.state.points.velocity[bad][1] = f64::NAN;
    let expected = serial.check_finite().unwrap_err();
    for (ranks, grid) in [(3, RankGrid::automatic()), (4, RankGrid(vec![2, 2]))] {
        let reports = blowup_on_ranks(ranks, bad, |comm| {
            MigratingMpm::<2>::on_grid(&problem, config, comm, &grid).unwrap()
        });
        assert!(
            reports.iter().all(|state| state == &expected),
            "{grid:?}: {reports:?}"
        );
    }
}

//! A point method on one rank's slab or box as a [`Method`] whose values are global (issue
//! 27): [`OnSlab`] wraps the method's solver built on the box's stored cells (its own cells
//! plus the halo, [`RankBox`]; a slab is the box `1 × … × 1 × N`), exchanges the halo's
//! point state once per step before the step ([`PointHalo`]), and reduces what the
//! controller reads over the ranks. Shared by
//! the point methods (DGMPM's `SlabDgmpm`, MPM's `SlabMpm`), which say how to build their
//! solver on a slab ([`SlabBuild`]) and which points it owns ([`SlabLocal`]).
//!
//! Reductions: the time step is the minimum over the ranks; the energy, work, momentum and
//! impulse are each rank's own sums added in rank order ([`crate::comm`]: equal to one
//! rank's to round-off); samples are gathered in the global point order, the
//! first failure and the fastest point found over the ranks ([`crate::comm_gather`]).
use crate::comm::{Comm, RankBox, RankGrid, ThreadComm};
use crate::comm_gather;
use crate::comm_halo::PointHalo;
use crate::method::{BadState, Method, MethodConfig, Samples};
use crate::points::MaterialPoints;
use crate::{CoreError, Problem, Tensor, Vector};
use std::sync::Arc;

/// A point method's solver on a slab's stored layers, as [`OnSlab`] reads it: its values
/// (energy, momentum, samples, checks) cover its own points only.
pub trait SlabLocal<const D: usize>: Method<D> {
    /// The stored points (layer by layer).
    fn points(&self) -> &MaterialPoints<D>;
    /// The stored points and the extra tensor per point the halo carries (empty if none).
    fn halo_state(&mut self) -> (&mut MaterialPoints<D>, &mut [Tensor<D>]);
    /// The points this solver owns, as runs of local indices in order (its own cells').
    fn owned_runs(&self) -> Vec<std::ops::Range<usize>>;
}

/// What [`SlabBuild::on_slab`] returns: the local solver and where it lies.
#[derive(Debug)]
pub struct SlabParts<M> {
    /// The solver on the stored cells.
    pub local: M,
    /// The box.
    pub rank_box: RankBox,
    /// Points per cell (stored cell by cell).
    pub per_cell: usize,
    /// The whole run's [`Method::cells`] and [`Method::updates_per_step`].
    pub cells: usize,
    /// See `cells`.
    pub updates_per_step: usize,
}

/// How a point method builds its solver on one rank's box.
pub trait SlabBuild<const D: usize>: SlabLocal<D> + Sized {
    /// This rank's solver of `problem` on its box of `rank_grid` (every rank builds its
    /// own; a bad input is refused on every rank alike, before any communication).
    fn on_slab(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: &dyn Comm,
        rank_grid: &RankGrid,
    ) -> Result<SlabParts<Self>, CoreError>;
}

/// A point method on one rank's slab, a [`Method`] whose values are global (module doc).
#[derive(Debug)]
pub struct OnSlab<const D: usize, M> {
    /// The box's solver (own cells and halo).
    pub local: M,
    comm: Arc<dyn Comm>,
    rank_box: RankBox,
    per_cell: usize,
    /// The global index of each own point, in local order (empty on slabs, whose own
    /// points in rank order are the global order).
    sample_order: Vec<usize>,
    cells: usize,
    updates_per_step: usize,
    initial_energy: f64,
    halo: PointHalo,
}

impl<const D: usize, M: SlabBuild<D>> OnSlab<D, M> {
    /// This rank's slab of `problem` (the automatic rank grid, [`Self::on_grid`]).
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
    ) -> Result<Self, CoreError> {
        Self::on_grid(problem, config, comm, &RankGrid::automatic())
    }

    /// This rank's box of `problem` split as `rank_grid` says ([`SlabBuild::on_slab`]).
    pub fn on_grid(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
        rank_grid: &RankGrid,
    ) -> Result<Self, CoreError> {
        let mut parts = M::on_slab(problem, config, comm.as_ref(), rank_grid)?;
        let initial_energy = comm.all_reduce_sum(parts.local.initial_energy());
        let (points, extra) = parts.local.halo_state();
        let halo = PointHalo::new(&parts.rank_box, parts.per_cell, points, extra);
        let sample_order = if parts.rank_box.is_slabs() {
            Vec::new()
        } else {
            let global = |i: usize| global_point(&parts.rank_box, parts.per_cell, i);
            parts
                .local
                .owned_runs()
                .into_iter()
                .flatten()
                .map(global)
                .collect()
        };
        Ok(Self {
            local: parts.local,
            comm,
            rank_box: parts.rank_box,
            per_cell: parts.per_cell,
            sample_order,
            cells: parts.cells,
            updates_per_step: parts.updates_per_step,
            initial_energy,
            halo,
        })
    }
}

/// The global index of the stored point `local` of `rank_box` (`per_cell` points a cell,
/// stored cell by cell in both numberings).
fn global_point(rank_box: &RankBox, per_cell: usize, local: usize) -> usize {
    rank_box.global_cell(local / per_cell) * per_cell + local % per_cell
}

impl<const D: usize, M> OnSlab<D, M> {
    /// The box this rank stores.
    pub fn rank_box(&self) -> &RankBox {
        &self.rank_box
    }

    /// Bytes this rank sends per step (the halo's point state, every neighbour).
    pub fn bytes_per_step(&self) -> usize {
        self.halo.bytes_per_step()
    }

    /// The global index of each own sample (empty: rank order is the global order).
    pub fn sample_order(&self) -> &[usize] {
        &self.sample_order
    }
}

impl<const D: usize, M: SlabLocal<D>> Method<D> for OnSlab<D, M> {
    fn step(&mut self, t: f64, dt: f64) {
        let (points, extra) = self.local.halo_state();
        self.halo.exchange(self.comm.as_ref(), points, extra);
        self.local.step(t, dt);
    }
    crate::reduced_over_ranks!();
    fn hottest_place(&self) -> Vector<D> {
        let p = self.local.points();
        // the last of equals, as one rank's `max_by`
        let mine = (p.hottest_in(self.local.owned_runs().into_iter().flatten()))
            .map(|i| (p.velocity[i].norm(), p.reference[i]));
        comm_gather::hottest_place(self.comm.as_ref(), mine)
    }
    fn cells(&self) -> usize {
        self.cells
    }
    fn updates_per_step(&self) -> usize {
        self.updates_per_step
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let (rank_box, per_cell) = (&self.rank_box, self.per_cell);
        self.local
            .perturb_velocity(&mut |i, x| kick(global_point(rank_box, per_cell, i), x));
    }
}

/// The samples and global sums a run ends with: what a decomposed run is compared on
/// against one rank (the point methods' slab tests).
#[derive(Debug, Clone)]
pub struct RunEnd<const D: usize> {
    /// The sampled fields.
    pub samples: Samples<D>,
    /// This rank's own samples ([`Method::owned_samples_into`]).
    pub owned: Samples<D>,
    /// [`Method::energy`].
    pub energy: f64,
    /// [`Method::external_work`].
    pub work: f64,
    /// [`Method::momentum`].
    pub momentum: Vector<D>,
    /// [`Method::external_impulse`].
    pub impulse: Vector<D>,
}

impl<const D: usize> RunEnd<D> {
    /// `m` after `steps` steps of its stable time step from `t = 0`.
    pub fn after_steps(m: &mut dyn Method<D>, steps: usize) -> Self {
        let dt = m.stable_dt();
        for k in 0..steps {
            m.step(k as f64 * dt, dt);
        }
        let (mut samples, mut owned) = (Samples::default(), Samples::default());
        m.sample_into(&mut samples);
        m.owned_samples_into(&mut owned);
        Self {
            samples,
            owned,
            energy: m.energy(),
            work: m.external_work(),
            momentum: m.momentum(),
            impulse: m.external_impulse(),
        }
    }
}

/// Whether the ranks' own samples, concatenated in rank order, are the whole body's
/// samples `whole` (reference positions, positions, stress, velocity, bit for bit): each
/// rank's output piece and the guard's reductions cover every carrier once.
pub fn owned_in_rank_order<const D: usize>(owned: &[&Samples<D>], whole: &Samples<D>) -> bool {
    let joined = |field: fn(&Samples<D>) -> &[Vector<D>]| -> Vec<Vector<D>> {
        owned
            .iter()
            .flat_map(|s| field(s).iter().copied())
            .collect()
    };
    let stress: Vec<Tensor<D>> = owned.iter().flat_map(|s| s.stress.clone()).collect();
    joined(|s| &s.reference) == whole.reference
        && joined(|s| &s.position) == whole.position
        && joined(|s| &s.velocity) == whole.velocity
        && stress == whole.stress
}

/// The failure each of `ranks` thread ranks reports when the velocity of carrier `bad` (a
/// global index) of the method `build` makes on it is NaN ([`Method::perturb_velocity`],
/// [`Method::check_finite`]): the slab tests assert that every rank's equals the one-rank
/// method's (one message, one global place).
pub fn blowup_on_ranks<const D: usize, M: Method<D>>(
    ranks: usize,
    bad: usize,
    build: impl Fn(Arc<dyn Comm>) -> M + Sync,
) -> Vec<BadState<D>> {
    ThreadComm::on_ranks(ranks, |comm| {
        let mut m = build(comm);
        m.perturb_velocity(&mut |i, _| {
            Vector::<D>::from_fn(|k, _| {
                if i == bad && k == D - 1 {
                    f64::NAN
                } else {
                    0.0
                }
            })
        });
        m.check_finite()
            .expect_err("a NaN velocity must fail the check")
    })
}

/// The message every one of `ranks` thread ranks refuses `build` with, which must be the
/// same on every rank (a bad decomposition is refused identically, before any message).
pub fn refusal_on_ranks<const D: usize, M: Method<D>, E: std::fmt::Display>(
    ranks: usize,
    build: impl Fn(Arc<dyn Comm>) -> Result<M, E> + Sync,
) -> String {
    let messages = ThreadComm::on_ranks(ranks, |comm| match build(comm) {
        Ok(_) => "(built)".to_string(),
        Err(e) => e.to_string(),
    });
    assert!(
        messages.iter().all(|m| m == &messages[0]),
        "the ranks refuse differently: {messages:?}"
    );
    messages[0].clone()
}

/// Slabs (the automatic rank grid) on 1 to `most` ranks, each with its rank count: the
/// decompositions the slab tests run.
pub fn slab_grids(most: usize) -> Vec<(RankGrid, usize)> {
    (1..=most).map(|r| (RankGrid::automatic(), r)).collect()
}

/// The rank grids `parts`, each with its rank count (the product of its parts): the
/// decompositions the box tests run.
pub fn box_grids(parts: &[&[usize]]) -> Vec<(RankGrid, usize)> {
    parts
        .iter()
        .map(|p| (RankGrid(p.to_vec()), p.iter().product()))
        .collect()
}

/// Assert that the runs `ends` of each rank of a decomposed run equal the one-rank run
/// `serial` (the point methods' slab and box tests): every point owned once (the ranks'
/// own samples add up to the whole body's), and each rank's gathered fields, in the global
/// point order, bit for bit (`exact`) or within 1e-13 of their peaks (stress and velocity);
/// the energy, work, momentum and impulse, sums per rank added in rank order, to 1e-12
/// (the work relative to the larger of the work and the energy, the momentum and impulse
/// to the larger of their norms). Panics with `label` and the rank on a mismatch.
pub fn assert_matches_serial<const D: usize>(
    label: &str,
    serial: &RunEnd<D>,
    ends: &[RunEnd<D>],
    exact: bool,
) {
    let s = &serial.samples;
    let peak = |v: &[Vector<D>]| v.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let peak_s = s.stress.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let peak_v = peak(&s.velocity);
    assert!(
        peak_s > 1e5 && peak_v > 1e-3,
        "{label}: the wave must be there"
    );
    let owned: usize = ends.iter().map(|e| e.owned.len()).sum();
    assert_eq!(owned, s.len(), "{label}: every point owned once");
    let tol = 1e-12;
    let relative = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    for (rank, end) in ends.iter().enumerate() {
        let (e, at) = (&end.samples, format!("{label}, rank {rank}"));
        assert_eq!(e.len(), s.len(), "{at}");
        assert_eq!(e.reference, s.reference, "{at}: reference positions");
        if exact {
            assert_eq!(e.stress, s.stress, "{at}: stress bit for bit");
            assert_eq!(e.velocity, s.velocity, "{at}: velocity bit for bit");
            assert_eq!(e.position, s.position, "{at}: position bit for bit");
            assert_eq!(e.plastic_strain, s.plastic_strain, "{at}: plastic strain");
            assert_eq!(e.stress_zz, s.stress_zz, "{at}: out-of-plane stress");
        } else {
            for i in 0..s.len() {
                let stress = (e.stress[i] - s.stress[i]).amax();
                assert!(stress <= 1e-13 * peak_s, "{at}: stress at {i}");
                let velocity = (e.velocity[i] - s.velocity[i]).amax();
                assert!(velocity <= 1e-13 * peak_v, "{at}: velocity at {i}");
            }
        }
        assert!(relative(end.energy, serial.energy) < tol, "{at}: energy");
        assert!(
            (end.work - serial.work).abs() <= tol * serial.work.abs().max(serial.energy),
            "{at}: work {} against {}",
            end.work,
            serial.work
        );
        let p = serial.momentum.norm().max(serial.impulse.norm());
        assert!(
            (end.momentum - serial.momentum).norm() <= tol * p,
            "{at}: momentum {} against {}",
            end.momentum,
            serial.momentum
        );
        assert!(
            (end.impulse - serial.impulse).norm() <= tol * p,
            "{at}: impulse {} against {}",
            end.impulse,
            serial.impulse
        );
    }
}

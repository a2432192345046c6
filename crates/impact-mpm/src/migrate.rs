//! MPM in the updated Lagrangian frame on a rank's box (issue 27): points move through the
//! grid, so a rank's points change. [`MigratingMpm`] is the [`Method`] of one rank.
//!
//! **Ownership by the current cell.** A rank owns the points whose current cell (along
//! every axis; a point beyond the body's grid counts in its first or last cell there) lies
//! in its own box (a [`RankBox`] of the rank grid, `--ranks-grid px,py[,pz]`; the slabs
//! `1 × … × N` are the special case, on the same code path), and stores besides them its
//! neighbours' points in its halo cells: the whole body's points cut to its stored box, as
//! the total Lagrangian box (`slab.rs`, whose module doc shows why the own points are then
//! exact after a step: the stencils are evaluated at the step's start, so the argument
//! holds for the current cells). CPDI is refused on several ranks here: its domains deform
//! with the body and may reach past the halo that argument sizes.
//!
//! **After each step** ([`MigratingMpm::step`]), two rounds of exchanges with the
//! neighbours, axis by axis, each of messages of any length
//! (`impact_core::comm_migrate::exchange_varying`):
//! 1. migration: along axis 0, then 1, …, each point held as own whose cell along that axis
//!    left the own range goes to the neighbour along it owning that cell, with its whole
//!    state: one row of every per-point array of
//!    [`MaterialPoints`](impact_core::points::MaterialPoints) (`impact_core::comm_migrate::point_columns`, a list that does not
//!    compile when a field is added to the struct and not to it), APIC's affine velocity
//!    and the point's global number; what arrives is held as own and routed along the next
//!    axes. A point crossing an edge or a corner of the box reaches its owner in up to `D`
//!    hops within the step's `D` exchanges (a point received along axis `k` lies in the
//!    own range along the axes before `k`: its sender's, which are this rank's);
//! 2. halo: along axis 0, 1, …, each rank sends the rows it holds (its own points and the
//!    halo received along the earlier axes) whose cell along that axis lies in the
//!    neighbour's stored range there: the earlier axes' halo travels on, which fills the
//!    stored box's edges and corners, as the total Lagrangian box's exchange
//!    (`impact_core::comm_box`). The stored points become the own points in the global
//!    order, then the halo; the nodal constraints' point lists, the loads and the weights'
//!    buffers follow.
//!
//! A point moves less than a cell per step at a stable Courant number; one that moves more
//! cells along an axis than the halo is reported: the run fails at its next check with the
//! step, the time and the point ([`Method::check_finite`]); it is sent on only where a
//! neighbour owns its cell and kept where it is otherwise. The parts hold at least `halo`
//! cells along a split axis ([`RankBox::new`]), so a point moving at most `halo` cells
//! along an axis lands in the own range or the neighbour's there.
//!
//! **Bit for bit.** The scatters add a node's points layer by layer (by the layer of their
//! stencil's base node), and within a layer in the order of `Place::scatter_order` (here:
//! the global order); one rank adds them in its own order, the global one. The gathers and
//! the stress updates are per point, and the loads are applied in the whole body's order.
//! So the own points are formed by the same operations on the same bits as on one rank,
//! and the samples (gathered, then put in the global order) equal the one-rank run's bit
//! for bit on slabs and boxes (`tests/migrate.rs`); the energy and momentum are sums in
//! rank order, equal to round-off; the point count and the mass are exact.
//!
//! Building reads the whole body once on every rank (its loads and prescribed point
//! velocities, listed by global number, travel with nothing: every rank holds the list).
use crate::edges::SurfaceLoad;
use crate::migrate_rows::{columns, Buffers, Cells, Neighbour, Received, COLUMNS};
use crate::slab::halo_layers;
use crate::Mpm;
use impact_core::comm::{Comm, CommError, RankBox, RankGrid};
use impact_core::comm_gather::{first_bad, gather_samples, hottest_place};
use impact_core::comm_migrate::Column;
use impact_core::method::{BadState, Method, MethodConfig, MpmShape, Samples};
use impact_core::{Constraint, CoreError, Problem, Vector};
use std::sync::Arc;

/// MPM in the updated Lagrangian frame on one rank's box, points migrating (module doc).
#[derive(Debug)]
pub struct MigratingMpm<const D: usize> {
    /// The box's solver (own points, then the halo).
    pub local: Mpm<D>,
    comm: Arc<dyn Comm>,
    rank_box: RankBox,
    /// Per axis, the neighbours along it (low, high).
    neighbours: [[Option<Neighbour>; 2]; D],
    /// Global number of each stored point.
    ids: Vec<usize>,
    /// Which columns travel (the arrays the model fills).
    present: [bool; COLUMNS],
    /// Floats per row.
    width: usize,
    /// The body's cells, which decide a point's owner.
    cells_of: Cells<D>,
    /// The whole body's loads and prescribed point velocities (by global number).
    loads: Vec<SurfaceLoad<D>>,
    constraints: Vec<Constraint>,
    /// Local index of each global number (valid where `ids` agrees).
    local_of: Vec<usize>,
    /// The own points' cells at the step's start.
    before: Vec<[usize; D]>,
    buffers: Buffers,
    migrated: usize,
    bytes: usize,
    steps: usize,
    failure: Option<BadState<D>>,
    cells: usize,
    initial_energy: f64,
}

impl<const D: usize> MigratingMpm<D> {
    /// This rank's slab of `problem` (the automatic rank grid `1 × … × N`): [`Self::on_grid`].
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
    ) -> Result<Self, CoreError> {
        Self::on_grid(problem, config, comm, &RankGrid::automatic())
    }

    /// This rank's box of `problem` on `rank_grid` (module doc). Refused: a configuration
    /// that is not MPM in the updated frame, CPDI on several ranks, a rank grid that is not
    /// one for the ranks or whose parts hold fewer cells than the halo.
    pub fn on_grid(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
        rank_grid: &RankGrid,
    ) -> Result<Self, CoreError> {
        let options = *config.mpm().ok_or_else(|| CoreError::Unsupported {
            method: "mpm".into(),
            message: "not an MPM configuration".into(),
        })?;
        if options.shape == MpmShape::Cpdi && comm.size() > 1 {
            return Err(CommError::Unsupported {
                what: "MPM with CPDI in the updated Lagrangian frame".into(),
                ranks: comm.size(),
                allowed: "its deformed domains may reach past the halo; run it on one rank, \
                          or another shape (hats, GIMP, B-splines) on several"
                    .into(),
            }
            .into());
        }
        problem.check_config(&config)?;
        let grid = &problem.grid;
        let rank_box =
            RankBox::for_rank(&grid.cells, rank_grid, comm.as_ref(), halo_layers(&options))?;
        let whole = Mpm::build(problem, config, None)?;
        let mut local = Mpm::build(problem, config, Some(&rank_box))?;
        // the box's points are its stored cells' seeding, cell by cell (`build.rs`)
        let per_cell = whole.state.points.len() / grid.cell_count();
        let mut ids: Vec<usize> = (0..local.state.points.len())
            .map(|p| rank_box.global_cell(p / per_cell) * per_cell + p % per_cell)
            .collect();
        let present = columns(&mut ids, &mut local.state).map(|c| !c.is_empty());
        let widths = columns(&mut ids, &mut local.state).map(|c| c.width());
        let width = (0..COLUMNS)
            .filter(|&k| present[k])
            .map(|k| widths[k])
            .sum();
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let neighbours = std::array::from_fn(|axis| {
            rank_box
                .neighbours(axis)
                .map(|rank| Neighbour::along(&rank_box, rank, axis))
        });
        let mut m = Self {
            neighbours,
            local_of: vec![0; whole.state.points.len()],
            loads: whole.solver.loads,
            constraints: whole.solver.point_constraints,
            cells_of: Cells {
                origin: std::array::from_fn(|k| grid.origin[k]),
                spacing: std::array::from_fn(|k| grid.spacing[k]),
                count: grid.cells,
            },
            local,
            comm,
            rank_box,
            ids,
            present,
            width,
            before: Vec::new(),
            buffers: Buffers::default(),
            migrated: 0,
            bytes: 0,
            steps: 0,
            failure: None,
            cells: grid.cell_count(),
            initial_energy,
        };
        // the stored points split by their cells into own (in the global order) and halo
        let b = &mut m.buffers;
        b.keep.clear();
        b.halo.clear();
        let stored = m.ids.len();
        let cols = columns(&mut m.ids, &mut m.local.state);
        let mut row = Vec::with_capacity(width);
        for i in 0..stored {
            row.clear();
            for (c, _) in cols.iter().zip(present).filter(|(_, p)| *p) {
                c.pack(i, &mut row);
            }
            let cell = m.cells_of.of_row(&row);
            let own = (0..D).all(|k| m.rank_box.owned[k].contains(&cell[k]));
            if own { &mut b.keep } else { &mut b.halo }.extend_from_slice(&row);
        }
        b.sort_own(width);
        m.store();
        Ok(m)
    }

    /// The box this rank stores.
    pub fn rank_box(&self) -> &RankBox {
        &self.rank_box
    }

    /// The global numbers of the own points (in the order of `local`'s own points).
    pub fn owned_ids(&self) -> &[usize] {
        &self.ids[self.local.owned_points()]
    }

    /// Bytes this rank sent in the last step (the messages vary with the points crossing
    /// and in the halo).
    pub fn bytes_per_step(&self) -> usize {
        self.bytes
    }

    /// Hops of points from this rank to a neighbour since the start (a point crossing a
    /// box's edge or corner counts once per axis it crossed).
    pub fn migrated(&self) -> usize {
        self.migrated
    }

    /// Move the own points that left the own box to their new owners, then refresh the
    /// halo (module doc). `t` is the time reached.
    fn migrate(&mut self, t: f64) {
        let (w, halo, cells_of) = (self.width, self.rank_box.halo, self.cells_of);
        let owned = self.local.owned_points();
        let b = &mut self.buffers;
        b.keep.clear();
        let cols = columns(&mut self.ids, &mut self.local.state);
        for (k, i) in owned.enumerate() {
            let start = b.keep.len();
            for (c, _) in cols.iter().zip(self.present).filter(|(_, p)| *p) {
                c.pack(i, &mut b.keep);
            }
            let cell = cells_of.of_row(&b.keep[start..]);
            let (axis, moved) = (0..D)
                .map(|along| (along, cell[along].abs_diff(self.before[k][along])))
                .fold((0, 0), |m, e| if e.1 > m.1 { e } else { m });
            if moved > halo && self.failure.is_none() {
                self.failure = Some(BadState {
                    place: Vector::<D>::from_column_slice(&b.keep[start + 1..start + 1 + D]),
                    reason: format!(
                        "step {}, t = {t:e}: material point {} moved {moved} cells along \
                         axis {axis} in one step, more than the halo of {halo} cells \
                         between ranks (an unstable step: lower the Courant number)",
                        self.steps, b.keep[start] as usize
                    ),
                });
            }
        }
        // migration, axis by axis: a point goes to the neighbour owning its cell
        self.bytes = 0;
        for (axis, [low, high]) in self.neighbours.iter().enumerate() {
            if self.rank_box.parts[axis] == 1 {
                continue;
            }
            let own = &self.rank_box.owned[axis];
            b.send_low.clear();
            b.send_high.clear();
            b.staying.clear();
            for row in b.keep.chunks_exact(w) {
                let cell = cells_of.of_row(row)[axis];
                let owns =
                    |n: &Option<Neighbour>| n.as_ref().is_some_and(|n| n.owned.contains(&cell));
                let destination = if cell < own.start && owns(low) {
                    &mut b.send_low
                } else if cell >= own.end && owns(high) {
                    &mut b.send_high
                } else {
                    &mut b.staying
                };
                destination.extend_from_slice(row);
            }
            self.migrated += (b.send_low.len() + b.send_high.len()) / w;
            let neighbours = self.rank_box.neighbours(axis);
            self.bytes += b.exchange(self.comm.as_ref(), neighbours, Received::Staying);
            std::mem::swap(&mut b.keep, &mut b.staying);
        }
        b.sort_own(w);
        // the halo, axis by axis: the rows held in a neighbour's stored range
        b.halo.clear();
        for (axis, neighbours) in self.neighbours.iter().enumerate() {
            if self.rank_box.parts[axis] == 1 {
                continue;
            }
            b.send_low.clear();
            b.send_high.clear();
            for row in b.own.chunks_exact(w).chain(b.halo.chunks_exact(w)) {
                let cell = cells_of.of_row(row)[axis];
                for (send, neighbour) in [&mut b.send_low, &mut b.send_high]
                    .into_iter()
                    .zip(neighbours)
                {
                    if neighbour.as_ref().is_some_and(|n| n.stored.contains(&cell)) {
                        send.extend_from_slice(row);
                    }
                }
            }
            let neighbours = self.rank_box.neighbours(axis);
            self.bytes += b.exchange(self.comm.as_ref(), neighbours, Received::Halo);
        }
        self.store();
    }

    /// Unpack the own rows, then the halo's, into the stored points, and install them.
    fn store(&mut self) {
        let (b, w) = (&self.buffers, self.width);
        let mut cols = columns(&mut self.ids, &mut self.local.state);
        cols.iter_mut().for_each(Column::clear);
        for rows in [&b.own, &b.halo] {
            for row in rows.chunks_exact(w) {
                let mut at = 0;
                for (c, _) in cols.iter_mut().zip(self.present).filter(|(_, p)| *p) {
                    c.push(&row[at..at + c.width()]);
                    at += c.width();
                }
            }
        }
        let own = b.own.len() / w;
        self.install(0..own);
    }

    /// Point the solver at the stored points: `owned` (local indices) are its own; the
    /// scatter order, the loads, the prescribed point velocities and the weights' buffers
    /// follow the stored points.
    fn install(&mut self, owned: std::ops::Range<usize>) {
        let count = self.ids.len();
        let ids = &self.ids;
        for (p, &id) in ids.iter().enumerate() {
            self.local_of[id] = p;
        }
        let here = |id: usize| {
            let p = self.local_of[id];
            (p < count && ids[p] == id).then_some(p)
        };
        let solver = &mut self.local.solver;
        // (one run, its buffer kept: no allocation in the step)
        solver.place.owned_runs.clear();
        solver.place.owned_runs.push(owned);
        let order = &mut solver.place.scatter_order;
        order.clear();
        order.extend(0..count);
        order.sort_unstable_by_key(|&p| ids[p]);
        solver.loads.clear();
        solver.loads.extend(
            self.loads
                .iter()
                .filter_map(|l| here(l.point).map(|point| SurfaceLoad { point, ..*l })),
        );
        solver.point_constraints.clear();
        solver.point_constraints.extend(
            self.constraints
                .iter()
                .filter_map(|c| here(c.carrier).map(|carrier| Constraint { carrier, ..*c })),
        );
        let nodes = solver.weight_stride;
        solver.point_base.resize(count, 0);
        solver.shape.resize(count * nodes, 0.0);
        solver
            .shape_gradient
            .resize(count * nodes, Vector::<D>::zeros());
    }
}

impl<const D: usize> Method<D> for MigratingMpm<D> {
    fn step(&mut self, t: f64, dt: f64) {
        let owned = self.local.owned_points();
        self.before.clear();
        let position = &self.local.state.points.position;
        let cells_of = self.cells_of;
        self.before.extend(
            owned.map(|i| std::array::from_fn(|axis| cells_of.along(axis, position[i][axis]))),
        );
        self.local.step(t, dt);
        self.steps += 1;
        self.migrate(t + dt);
    }
    /// The samples of every rank's own points, in the global order (as one rank's).
    fn sample_into(&self, out: &mut Samples<D>) {
        let mut mine = Samples::<D>::default();
        self.local.sample_into(&mut mine);
        gather_samples(self.comm.as_ref(), &mine, self.owned_ids(), out);
    }
    fn owned_sample_order(&self) -> &[usize] {
        self.owned_ids()
    }
    impact_core::reduced_sums_over_ranks!();
    fn check_finite(&self) -> Result<(), BadState<D>> {
        let local = match &self.failure {
            Some(failure) => Err(failure.clone()),
            None => self.local.check_finite(),
        };
        first_bad(self.comm.as_ref(), local)
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.local.state.points;
        let mine = p
            .hottest_in(self.local.owned_points())
            .map(|i| (p.velocity[i].norm(), p.reference[i]));
        hottest_place(self.comm.as_ref(), mine)
    }
    fn cells(&self) -> usize {
        self.cells
    }
    fn updates_per_step(&self) -> usize {
        self.local_of.len()
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let ids = &self.ids;
        self.local.perturb_velocity(&mut |i, x| kick(ids[i], x));
    }
}

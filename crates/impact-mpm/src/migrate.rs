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
//! holds for the current cells).
//!
//! **CPDI's deforming domains** (`cpdi.rs`: `R ← (I + Δt ∇v) R`): a point's stencil, 4
//! nodes per axis from the node below its domain's lowest corner, may start below the
//! point's cell `j`, at `j − a`. A missing point beyond a lower cut at `s` (cell `< s`,
//! start `≤` its cell) spoils nodes up to `s + 2`, read by the stored points of cells up to
//! `s + 2 + a`; beyond an upper cut at `e` (start `≥ e − a`), nodes from `e − a`, read by
//! the points from cell `e − a − 3`: `3 + a` cells a round (counting the stencil's nodes,
//! zero weights included, as `slab.rs` does; by the weighing nodes alone 3 would do, and
//! `tests/migrate.rs` passes with `rounds × 3` too, but a spoiled value times a zero weight
//! may still flip a zero's sign or carry a non-finite value). The halo is sized for
//! `a ≤` [`CPDI_DOMAIN_REACH`](crate::slab::CPDI_DOMAIN_REACH)` = 1` (`halo_layers`:
//! `rounds × 4`), every domain the stencil holds: a domain is symmetric about its point,
//! `x ± e` along an axis, and 3 cells from `first = ⌊x − e⌋` hold `x + e` only if
//! `x − first < 1.5`, so `j − first ≤ 1`; a larger domain leaves the stencil and fails the
//! run as on one rank ("stencil left the background grid"). The point's cell (body grid)
//! and the corner (padded grid) round separately, so after each step every own point's next
//! stencil start is checked (`Cells::cpdi_stencil_past_halo`; an axis along which the point
//! lies beyond the body's grid, with no cut, is skipped): one outside `j − 1 ..= j` fails
//! the run at its next check with the step, the time, the point's global number and
//! position, the cells below, the halo and what to do (fewer ranks along that axis, or
//! another shape), as a point moving past the halo does (below). The domains travel with
//! their points (a column of the rows) and in the halo.
//!
//! **After each step** ([`MigratingMpm::step`]), two rounds of exchanges with the
//! neighbours, axis by axis, each of messages of any length
//! (`impact_core::comm_migrate::exchange_varying`); the own points stay where they are in
//! the stored arrays, and only those that leave or arrive are copied:
//! 1. migration: along axis 0, then 1, …, each point held as own whose cell along that axis
//!    left the own range (found among the own points whose cell left the own box, listed
//!    in one pass over the cells) goes to the neighbour along it owning that cell, with
//!    its whole state: one row of every per-point array of
//!    [`MaterialPoints`](impact_core::points::MaterialPoints)
//!    (`impact_core::comm_migrate::point_columns`, a list that does not compile when a
//!    field is added to the struct and not to it), APIC's affine velocity and the point's
//!    global number; what arrives is appended to the own points and routed along the next
//!    axes, and a point sent away is removed, the last own point taking its place (the own
//!    points are then in no particular order). A point crossing an edge or a corner of the
//!    box reaches its owner in up to `D` hops within the step's `D` exchanges (a point received along axis `k` lies in the
//!    own range along the axes before `k`: its sender's, which are this rank's);
//! 2. halo: along axis 0, 1, …, each rank sends the rows it holds (its own points and the
//!    halo received along the earlier axes) whose cell along that axis lies in the
//!    neighbour's stored range there: the earlier axes' halo travels on, which fills the
//!    stored box's edges and corners, as the total Lagrangian box's exchange
//!    (`impact_core::comm_box`). The stored points are the own points, then the halo; the
//!    scatter order (the stored points sorted by global number), the nodal constraints'
//!    point lists, the loads (found by binary search of the sorted numbers: no rank holds
//!    an index of every point) and the weights' buffers follow.
//!
//! A point moves less than a cell per step at a stable Courant number; one that moves more
//! cells along an axis than the halo is reported: the run fails at its next check with the
//! step, the time and the point ([`Method::check_finite`]); it is sent on only where a
//! neighbour owns its cell and kept where it is otherwise. The parts hold at least `halo`
//! cells along a split axis ([`RankBox::new`]), so a point moving at most `halo` cells
//! along an axis lands in the own range or the neighbour's there.
//!
//! **Bit for bit.** The scatters add a node's points layer by layer (by the layer of their
//! stencil's base node, found on the whole padded grid from the point's position and, with
//! CPDI, its domain: the same bits on every rank), and within a layer in the order of `Place::scatter_order` (here:
//! the global order); one rank adds them in its own order, the global one. The gathers and
//! the stress updates are per point, and the loads are applied in the whole body's order.
//! The first failing point and the hottest one are looked for among the own points in the
//! global order too (as one rank's, and a slab's before the own points were unordered).
//! So the own points are formed by the same operations on the same bits as on one rank,
//! and the samples (gathered, then put in the global order) equal the one-rank run's bit
//! for bit on slabs and boxes (`tests/migrate.rs`); the energy and momentum are sums in
//! rank order, equal to round-off; the point count and the mass are exact.
//!
//! Building seeds the rank's stored box only, and the cell layers of the body's loaded and
//! held faces: the loads and prescribed point velocities acting on points, listed by
//! global number (`face_lists.rs`), travel with nothing: every rank holds the lists, a
//! face's worth of points.
use crate::edges::SurfaceLoad;
use crate::migrate_rows::{columns, cpdi_reach_reason, Buffers, Cells, Neighbour, COLUMNS};
use crate::slab::halo_layers;
use crate::Mpm;
use impact_core::comm::{Comm, RankBox, RankGrid};
use impact_core::comm_gather::{first_bad, gather_samples, hottest_place};
use impact_core::comm_migrate::Column;
use impact_core::method::{BadState, Method, MethodConfig, Samples};
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
    /// The own points' cells (at the step's start, then after it while migrating).
    own_cells: Vec<[usize; D]>,
    /// The own points whose cell lies outside the own box, with that cell, while
    /// migrating.
    leaving: Vec<(usize, [usize; D])>,
    /// The own points sent away in this step's migration.
    sent: Vec<usize>,
    buffers: Buffers,
    migrated: usize,
    bytes: usize,
    steps: usize,
    failure: Option<BadState<D>>,
    cells: usize,
    points: usize,
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
    /// that is not MPM in the updated frame, a rank grid that is not one for the ranks or
    /// whose parts hold fewer cells than the halo.
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
        problem.check_config(&config)?;
        let grid = &problem.grid;
        let rank_box =
            RankBox::for_rank(&grid.cells, rank_grid, comm.as_ref(), halo_layers(&options))?;
        let (loads, constraints) = crate::face_lists::by_global_number(problem, &config)?;
        let mut local = Mpm::build(problem, config, Some(&rank_box))?;
        // the box's points are its stored cells' seeding, cell by cell (`build.rs`)
        let stored_cells: usize = rank_box.stored.iter().map(|r| r.len()).product();
        let per_cell = local.state.points.len() / stored_cells;
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
            loads,
            constraints,
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
            own_cells: Vec::new(),
            leaving: Vec::new(),
            sent: Vec::new(),
            buffers: Buffers::default(),
            migrated: 0,
            bytes: 0,
            steps: 0,
            failure: None,
            cells: grid.cell_count(),
            points: per_cell * grid.cell_count(),
            initial_energy,
        };
        // the stored points split in place by their cells into own (first, in the global
        // order: the box's cells in order) and halo (after them, in any order)
        let stored = m.ids.len();
        for i in 0..stored {
            let x = m.local.state.points.position[i];
            let cell: [usize; D] = std::array::from_fn(|k| m.cells_of.along(k, x[k]));
            if (0..D).all(|k| m.rank_box.owned[k].contains(&cell[k])) {
                let own = m.own_cells.len();
                let mut cols = columns(&mut m.ids, &mut m.local.state);
                (cols.iter_mut().zip(present).filter(|(_, p)| *p))
                    .for_each(|(c, _)| c.swap(own, i));
                m.own_cells.push(cell);
            }
        }
        let own = m.own_cells.len();
        m.install(0..own);
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

    /// The own points in the order of their global numbers (the scatter order without the
    /// halo).
    fn own_in_global_order(&self) -> impl Iterator<Item = usize> + '_ {
        let own = self.local.owned_points().end;
        let order = &self.local.solver.place.scatter_order;
        order.iter().copied().filter(move |&p| p < own)
    }

    /// The own points' cells now, and those of them outside the own box (`leaving`); an
    /// own point that moved more cells along an axis than the halo is the run's failure.
    fn find_leaving(&mut self, t: f64) {
        let (halo, cells_of) = (self.rank_box.halo, self.cells_of);
        let points = &self.local.state.points;
        let position = &points.position;
        self.leaving.clear();
        for (i, cell) in self.own_cells.iter_mut().enumerate() {
            let now: [usize; D] = std::array::from_fn(|k| cells_of.along(k, position[i][k]));
            let (axis, moved) = (0..D)
                .map(|along| (along, now[along].abs_diff(cell[along])))
                .fold((0, 0), |m, e| if e.1 > m.1 { e } else { m });
            if moved > halo && self.failure.is_none() {
                self.failure = Some(BadState {
                    place: self.local.state.points.reference[i],
                    reason: format!(
                        "step {}, t = {t:e}: material point {} moved {moved} cells along \
                         axis {axis} in one step, more than the halo of {halo} cells \
                         between ranks (an unstable step: lower the Courant number)",
                        self.steps, self.ids[i]
                    ),
                });
            }
            if let (Some(domain), None) = (points.domain.get(i), &self.failure) {
                let past =
                    cells_of.cpdi_stencil_past_halo(&self.local.solver, &position[i], domain, now);
                self.failure = past.map(|reach| BadState {
                    place: points.reference[i],
                    reason: cpdi_reach_reason(
                        (self.steps, t),
                        self.ids[i],
                        &position[i],
                        reach,
                        halo,
                    ),
                });
            }
            *cell = now;
            if !(0..D).all(|k| self.rank_box.owned[k].contains(&now[k])) {
                self.leaving.push((i, now));
            }
        }
    }

    /// Move the own points that left the own box to their new owners, then refresh the
    /// halo (module doc). `t` is the time reached.
    fn migrate(&mut self, t: f64) {
        let own = self.local.owned_points().end;
        let w = self.width;
        // the halo is sent again below: dropped
        columns(&mut self.ids, &mut self.local.state)
            .iter_mut()
            .for_each(|c| c.truncate(own));
        self.find_leaving(t);
        // migration, axis by axis: a point goes to the neighbour owning its cell
        let b = &mut self.buffers;
        let mut cols = columns(&mut self.ids, &mut self.local.state);
        let present = self.present;
        self.bytes = 0;
        self.sent.clear();
        for (axis, [low, high]) in self.neighbours.iter().enumerate() {
            if self.rank_box.parts[axis] == 1 {
                continue;
            }
            let range = &self.rank_box.owned[axis];
            b.send_low.clear();
            b.send_high.clear();
            let sent = &mut self.sent;
            self.leaving.retain(|&(i, cell)| {
                let c = cell[axis];
                let owns = |n: &Option<Neighbour>| n.as_ref().is_some_and(|n| n.owned.contains(&c));
                let send = if c < range.start && owns(low) {
                    &mut b.send_low
                } else if c >= range.end && owns(high) {
                    &mut b.send_high
                } else {
                    return true;
                };
                for (column, _) in cols.iter().zip(present).filter(|(_, p)| *p) {
                    column.pack(i, send);
                }
                sent.push(i);
                false
            });
            self.migrated += (b.send_low.len() + b.send_high.len()) / w;
            let neighbours = self.rank_box.neighbours(axis);
            self.bytes += b.exchange(self.comm.as_ref(), neighbours);
            // what arrives is own, routed on along the next axes where it lies outside
            for received in [&b.receive_low, &b.receive_high] {
                push_rows(&mut cols, present, received, w);
            }
            for row in b
                .receive_low
                .chunks_exact(w)
                .chain(b.receive_high.chunks_exact(w))
            {
                let i = self.own_cells.len();
                let cell = self.cells_of.of_row(row);
                self.own_cells.push(cell);
                if !(0..D).all(|k| self.rank_box.owned[k].contains(&cell[k])) {
                    self.leaving.push((i, cell));
                }
            }
        }
        // the points sent away, the last ones first: each takes the last own point's place
        self.sent.sort_unstable();
        for &i in self.sent.iter().rev() {
            cols.iter_mut()
                .zip(present)
                .filter(|(_, p)| *p)
                .for_each(|(c, _)| c.swap_remove(i));
            self.own_cells.swap_remove(i);
        }
        let own = self.own_cells.len();
        // the halo, axis by axis: the rows held in a neighbour's stored range
        b.halo.clear();
        for (axis, neighbours) in self.neighbours.iter().enumerate() {
            if self.rank_box.parts[axis] == 1 {
                continue;
            }
            b.send_low.clear();
            b.send_high.clear();
            let sends = [&mut b.send_low, &mut b.send_high];
            for (send, neighbour) in sends.into_iter().zip(neighbours) {
                let Some(n) = neighbour else { continue };
                for (i, cell) in self.own_cells.iter().enumerate() {
                    if n.stored.contains(&cell[axis]) {
                        for (column, _) in cols.iter().zip(present).filter(|(_, p)| *p) {
                            column.pack(i, send);
                        }
                    }
                }
                for row in b.halo.chunks_exact(w) {
                    if n.stored.contains(&self.cells_of.of_row(row)[axis]) {
                        send.extend_from_slice(row);
                    }
                }
            }
            let neighbours = self.rank_box.neighbours(axis);
            self.bytes += b.exchange(self.comm.as_ref(), neighbours);
            b.halo.extend_from_slice(&b.receive_low);
            b.halo.extend_from_slice(&b.receive_high);
        }
        self.store_halo(own);
    }

    /// Append the halo's rows after the `own` points, and install them.
    fn store_halo(&mut self, own: usize) {
        let mut cols = columns(&mut self.ids, &mut self.local.state);
        push_rows(&mut cols, self.present, &self.buffers.halo, self.width);
        self.install(0..own);
    }

    /// Point the solver at the stored points: `owned` (local indices) are its own; the
    /// scatter order, the loads, the prescribed point velocities and the weights' buffers
    /// follow the stored points.
    fn install(&mut self, owned: std::ops::Range<usize>) {
        let count = self.ids.len();
        let ids = &self.ids;
        let solver = &mut self.local.solver;
        // (one run, its buffer kept: no allocation in the step)
        solver.place.owned_runs.clear();
        solver.place.owned_runs.push(owned);
        let order = &mut solver.place.scatter_order;
        order.clear();
        order.extend(0..count);
        order.sort_unstable_by_key(|&p| ids[p]);
        let order = &solver.place.scatter_order;
        // the stored point of global number `id`, by binary search of the sorted numbers
        let here =
            |id: usize| (order.binary_search_by_key(&id, |&p| ids[p]).ok()).map(|k| order[k]);
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

/// Append `rows` (of `width` floats, the `present` columns' values in turn) to the columns.
fn push_rows<const D: usize>(
    cols: &mut [Column<'_, D>; COLUMNS],
    present: [bool; COLUMNS],
    rows: &[f64],
    width: usize,
) {
    for row in rows.chunks_exact(width) {
        let mut at = 0;
        for (c, _) in cols.iter_mut().zip(present).filter(|(_, p)| *p) {
            c.push(&row[at..at + c.width()]);
            at += c.width();
        }
    }
}

impl<const D: usize> Method<D> for MigratingMpm<D> {
    fn step(&mut self, t: f64, dt: f64) {
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
            // the first failing own point in the global order, as one rank's
            None => self.local.check_finite().map_err(|any| {
                (self.own_in_global_order())
                    .find_map(|i| self.local.point_failure(i))
                    .unwrap_or(any)
            }),
        };
        first_bad(self.comm.as_ref(), local)
    }
    fn hottest_place(&self) -> Vector<D> {
        let p = &self.local.state.points;
        // the last of equals in the global order, as one rank's
        let mine = (p.hottest_in(self.own_in_global_order()))
            .map(|i| (p.velocity[i].norm(), p.reference[i]));
        hottest_place(self.comm.as_ref(), mine)
    }
    fn cells(&self) -> usize {
        self.cells
    }
    fn updates_per_step(&self) -> usize {
        self.points
    }
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        let ids = &self.ids;
        self.local.perturb_velocity(&mut |i, x| kick(ids[i], x));
    }
}

//! MPM in the updated Lagrangian frame on slabs (issue 27): points move through the grid,
//! so a rank's points change. [`MigratingMpm`] is the [`Method`] of one rank.
//!
//! **Ownership by the current cell.** A rank owns the points whose current cell's layer
//! (along the last axis; a point beyond the body's grid counts in its first or last layer)
//! is one of its own layers (a [`RankBox`] of the slab rank grid `1 × … × N`), and stores besides them its neighbours' points in
//! its halo layers: the whole body's points cut to its stored layers, as the total
//! Lagrangian slab (`slab.rs`, whose module doc shows why the own points are then exact
//! after a step: the stencils are evaluated at the step's start, so the argument holds for
//! the current cells). CPDI is refused on several ranks here: its domains deform with the
//! body and may reach past the halo that argument sizes.
//!
//! **After each step** ([`MigratingMpm::step`]), two exchanges with the neighbours, each of
//! messages of any length (`impact_core::comm_migrate::exchange_varying`):
//! 1. migration: each own point whose cell left the own layers goes to the neighbour owning
//!    its new layer, with its whole state: one row of every per-point array of
//!    [`MaterialPoints`](impact_core::points::MaterialPoints) (`impact_core::comm_migrate::point_columns`, a list that does not
//!    compile when a field is added to the struct and not to it), APIC's affine velocity
//!    and the point's global number;
//! 2. halo: each rank sends its (new) own points in a neighbour's stored layers to it; the
//!    stored points become the lower halo, the own points and the upper halo, each in the
//!    global order, and the nodal constraints' point lists, the loads and the weights'
//!    buffers follow.
//!
//! A point moves less than a cell per step at a stable Courant number; one that moves more
//! layers than the halo (or to a rank that is no neighbour) is kept where it is and the run
//! fails at its next check with the step, the time and the point ([`Method::check_finite`]).
//!
//! **Bit for bit.** The scatters add a node's points layer by layer (by the layer of their
//! stencil's base node), and within a layer in the order of `Place::scatter_order` (here:
//! the global order); one rank adds them in its own order, the global one. The gathers and
//! the stress updates are per point, and the loads are applied in the whole body's order.
//! So the own points are formed by the same operations on the same bits as on one rank,
//! and the samples (gathered, then put in the global order) equal the one-rank run's bit
//! for bit (`tests/migrate.rs`); the energy and momentum are sums in rank order, equal to
//! round-off; the point count and the mass are exact.
//!
//! Building reads the whole body once on every rank (its loads and prescribed point
//! velocities, listed by global number, travel with nothing: every rank holds the list).
use crate::edges::SurfaceLoad;
use crate::slab::halo_layers;
use crate::{Mpm, MpmState};
use impact_core::comm::{Comm, CommError, RankBox, RankGrid};
use impact_core::comm_gather::{first_bad, gather_samples, hottest_place};
use impact_core::comm_migrate::{exchange_varying, point_columns, Column};
use impact_core::method::{BadState, Method, MethodConfig, MpmShape, Samples};
use impact_core::{Constraint, CoreError, Problem, Vector};
use std::sync::Arc;

/// Columns of a point's row: its global number, the 12 arrays of `MaterialPoints`, the
/// affine velocity.
const COLUMNS: usize = 14;

/// The messages of one rank's migration, kept between steps (no allocation once grown).
/// The body's layers of cells along the last axis, which decide a point's owner.
#[derive(Debug, Clone, Copy)]
struct Layers {
    /// The body's lower edge (m).
    origin: f64,
    /// Cell size (m).
    spacing: f64,
    /// Number of layers.
    count: usize,
}

impl Layers {
    /// The layer of the cell of a point whose last coordinate is `x`; beyond the body, its
    /// first or last layer.
    fn of(&self, x: f64) -> usize {
        (((x - self.origin) / self.spacing).floor() as usize).min(self.count - 1)
    }
}

#[derive(Debug, Default)]
struct Buffers {
    keep: Vec<f64>,
    send_low: Vec<f64>,
    send_high: Vec<f64>,
    receive_low: Vec<f64>,
    receive_high: Vec<f64>,
    own: Vec<f64>,
    /// `(global number, source buffer, row)` of the own rows, sorted.
    order: Vec<(usize, usize, usize)>,
}

/// MPM in the updated Lagrangian frame on one rank's slab, points migrating (module doc).
#[derive(Debug)]
pub struct MigratingMpm<const D: usize> {
    /// The slab's solver (own points and halo).
    pub local: Mpm<D>,
    comm: Arc<dyn Comm>,
    slab: RankBox,
    /// The neighbours' slabs (below, above).
    neighbours: [Option<RankBox>; 2],
    /// Global number of each stored point.
    ids: Vec<usize>,
    /// Which columns travel (the arrays the model fills).
    present: [bool; COLUMNS],
    /// Floats per row, and where the position's last coordinate is in it.
    width: usize,
    last_coordinate: usize,
    /// The body's layers of cells along the last axis.
    layers: Layers,
    /// The whole body's loads and prescribed point velocities (by global number).
    loads: Vec<SurfaceLoad<D>>,
    constraints: Vec<Constraint>,
    /// Local index of each global number (valid where `ids` agrees).
    local_of: Vec<usize>,
    /// The own points' layers at the step's start.
    before: Vec<usize>,
    buffers: Buffers,
    migrated: usize,
    bytes: usize,
    steps: usize,
    failure: Option<BadState<D>>,
    cells: usize,
    initial_energy: f64,
}

/// The row columns of a rank's stored state: the global numbers, the points' arrays, APIC's
/// affine velocities (the state is destructured without `..`: a per-point array added to
/// [`MpmState`] does not compile until it is listed here).
fn columns<'a, const D: usize>(
    ids: &'a mut Vec<usize>,
    state: &'a mut MpmState<D>,
) -> [Column<'a, D>; COLUMNS] {
    let MpmState {
        points,
        affine,
        work: _,
        impulse: _,
        initial_energy: _,
    } = state;
    let [c0, c1, c2, c3, c4, c5, c6, c7, c8, c9, c10, c11] = point_columns(points);
    [
        Column::Index(ids),
        c0,
        c1,
        c2,
        c3,
        c4,
        c5,
        c6,
        c7,
        c8,
        c9,
        c10,
        c11,
        Column::Tensor(affine),
    ]
}

impl<const D: usize> MigratingMpm<D> {
    /// This rank's share of `problem` (module doc). Refused: a configuration that is not
    /// MPM in the updated frame, CPDI on several ranks, more ranks than the halo allows.
    pub fn new(
        problem: &Problem<D>,
        config: MethodConfig,
        comm: Arc<dyn Comm>,
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
        let layers = problem.grid.cells[D - 1];
        let (ranks, rank, halo) = (comm.size(), comm.rank(), halo_layers(&options));
        let cells = &problem.grid.cells;
        let slabs = RankGrid::automatic();
        let slab = RankBox::new(cells, &slabs, ranks, rank, halo)?;
        let whole = Mpm::build(problem, config, None)?;
        let mut local = Mpm::build(problem, config, Some(&slab))?;
        let per_layer = whole.state.points.len() / layers;
        let first = slab.stored[D - 1].start * per_layer;
        let mut ids: Vec<usize> = (first..first + local.state.points.len()).collect();
        let present = columns(&mut ids, &mut local.state).map(|c| !c.is_empty());
        let widths = columns(&mut ids, &mut local.state).map(|c| c.width());
        let width = (0..COLUMNS)
            .filter(|&k| present[k])
            .map(|k| widths[k])
            .sum();
        // the position is column 2, after the number (1) and the reference (D)
        let last_coordinate = 1 + D + D - 1;
        let initial_energy = comm.all_reduce_sum(local.state.initial_energy);
        let neighbour =
            |r: Option<usize>| r.and_then(|r| RankBox::new(cells, &slabs, ranks, r, halo).ok());
        let mut m = Self {
            neighbours: [
                neighbour(rank.checked_sub(1)),
                neighbour((rank + 1 < ranks).then_some(rank + 1)),
            ],
            local_of: vec![0; whole.state.points.len()],
            loads: whole.solver.loads,
            constraints: whole.solver.point_constraints,
            layers: Layers {
                origin: problem.grid.origin[D - 1],
                spacing: problem.grid.spacing[D - 1],
                count: layers,
            },
            local,
            comm,
            slab,
            ids,
            present,
            width,
            last_coordinate,
            before: Vec::new(),
            buffers: Buffers::default(),
            migrated: 0,
            bytes: 0,
            steps: 0,
            failure: None,
            cells: problem.grid.cell_count(),
            initial_energy,
        };
        let (below, own) = (
            m.slab.halo_width(D - 1, 0) * per_layer,
            m.slab.owned[D - 1].len() * per_layer,
        );
        m.install(below..below + own);
        Ok(m)
    }

    /// The slab this rank stores.
    pub fn slab(&self) -> &RankBox {
        &self.slab
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

    /// Points this rank has sent to a neighbour's ownership since the start.
    pub fn migrated(&self) -> usize {
        self.migrated
    }

    /// Move the own points that left the own layers to their new owners, then refresh the
    /// halo (module doc). `t` is the time reached.
    fn migrate(&mut self, t: f64) {
        let (w, halo, layers) = (self.width, self.slab.halo, self.layers);
        let owned = self.local.owned_points();
        let own_layers = self.slab.owned[D - 1].clone();
        // where each own point goes: 0 kept, 1 below, 2 above
        let b = &mut self.buffers;
        b.keep.clear();
        b.send_low.clear();
        b.send_high.clear();
        for (k, i) in owned.clone().enumerate() {
            let x = self.local.state.points.position[i][D - 1];
            let layer = layers.of(x);
            let moved = layer.abs_diff(self.before[k]);
            let destination = if moved > halo {
                if self.failure.is_none() {
                    self.failure = Some(BadState {
                        place: self.local.state.points.reference[i],
                        reason: format!(
                            "step {}, t = {t:e}: material point {} moved {moved} layers of \
                             cells in one step, more than the halo of {halo} layers between \
                             ranks (an unstable step: lower the Courant number)",
                            self.steps, self.ids[i]
                        ),
                    });
                }
                &mut b.keep
            } else if layer < own_layers.start {
                &mut b.send_low
            } else if layer >= own_layers.end {
                &mut b.send_high
            } else {
                &mut b.keep
            };
            let cols = columns(&mut self.ids, &mut self.local.state);
            for (c, _) in cols.iter().zip(self.present).filter(|(_, p)| *p) {
                c.pack(i, destination);
            }
        }
        self.migrated += (b.send_low.len() + b.send_high.len()) / w;
        self.bytes = exchange_varying(
            self.comm.as_ref(),
            &b.send_low,
            &b.send_high,
            &mut b.receive_low,
            &mut b.receive_high,
        );
        // the own points in the global order
        b.order.clear();
        for (source, rows) in [&b.keep, &b.receive_low, &b.receive_high]
            .into_iter()
            .enumerate()
        {
            let rows = rows.chunks_exact(w).enumerate();
            b.order
                .extend(rows.map(|(k, row)| (row[0] as usize, source, k)));
        }
        b.order.sort_unstable();
        b.own.clear();
        for &(_, source, k) in &b.order {
            let rows = [&b.keep, &b.receive_low, &b.receive_high][source];
            b.own.extend_from_slice(&rows[k * w..(k + 1) * w]);
        }
        // the halo: own points in a neighbour's stored layers
        b.send_low.clear();
        b.send_high.clear();
        for row in b.own.chunks_exact(w) {
            let layer = layers.of(row[self.last_coordinate]);
            for (send, neighbour) in [&mut b.send_low, &mut b.send_high]
                .into_iter()
                .zip(&self.neighbours)
            {
                if neighbour
                    .as_ref()
                    .is_some_and(|n| n.stored[D - 1].contains(&layer))
                {
                    send.extend_from_slice(row);
                }
            }
        }
        self.bytes += exchange_varying(
            self.comm.as_ref(),
            &b.send_low,
            &b.send_high,
            &mut b.receive_low,
            &mut b.receive_high,
        );
        // stored: the halo below, the own points, the halo above
        let mut cols = columns(&mut self.ids, &mut self.local.state);
        cols.iter_mut().for_each(Column::clear);
        for rows in [&b.receive_low, &b.own, &b.receive_high] {
            for row in rows.chunks_exact(w) {
                let mut at = 0;
                for (c, _) in cols.iter_mut().zip(self.present).filter(|(_, p)| *p) {
                    c.push(&row[at..at + c.width()]);
                    at += c.width();
                }
            }
        }
        let (below, own) = (b.receive_low.len() / w, b.own.len() / w);
        self.install(below..below + own);
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
        for i in owned {
            let layer = self.layers.of(self.local.state.points.position[i][D - 1]);
            self.before.push(layer);
        }
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

//! The rows that [`crate::migrate::MigratingMpm`] sends between ranks: a stored point's
//! whole state as one row of floats ([`columns`]), the body's cells that decide a point's
//! owner ([`Cells`]), a neighbour's box along one axis ([`Neighbour`]) and the messages kept
//! between steps ([`Buffers`]).
use crate::MpmState;
use impact_core::comm::{Comm, RankBox};
use impact_core::comm_migrate::{exchange_varying, point_columns, Column};
use std::ops::Range;

/// Columns of a point's row: its global number, the 12 arrays of `MaterialPoints`, the
/// affine velocity.
pub(crate) const COLUMNS: usize = 14;

/// The row columns of a rank's stored state: the global numbers, the points' arrays, APIC's
/// affine velocities (the state is destructured without `..`: a per-point array added to
/// [`MpmState`] does not compile until it is listed here).
pub(crate) fn columns<'a, const D: usize>(
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

/// Where a row's position starts: after the global number (1) and the reference
/// position (`D`).
pub(crate) const fn position_at(dim: usize) -> usize {
    1 + dim
}

/// The body's cells per axis, which decide a point's owner.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cells<const D: usize> {
    /// The body's lower corner (m).
    pub origin: [f64; D],
    /// Cell size per axis (m).
    pub spacing: [f64; D],
    /// Cells per axis.
    pub count: [usize; D],
}

impl<const D: usize> Cells<D> {
    /// The cell index along `axis` of a point whose coordinate there is `x`; beyond the
    /// body, its first or last cell (a negative quotient saturates to 0).
    pub fn along(&self, axis: usize, x: f64) -> usize {
        (((x - self.origin[axis]) / self.spacing[axis]).floor() as usize).min(self.count[axis] - 1)
    }

    /// The cell indices of the point of `row` (a packed row).
    pub fn of_row(&self, row: &[f64]) -> [usize; D] {
        let at = position_at(D);
        std::array::from_fn(|axis| self.along(axis, row[at + axis]))
    }
}

/// A neighbour along one axis: along that axis, the cells it owns and stores (along the
/// other axes its box is this rank's).
#[derive(Debug, Clone)]
pub(crate) struct Neighbour {
    pub owned: Range<usize>,
    pub stored: Range<usize>,
}

impl Neighbour {
    /// Rank `rank`'s box along `axis` (`None` where there is no such rank).
    pub fn along(rank_box: &RankBox, rank: Option<usize>, axis: usize) -> Option<Self> {
        let rank = rank?;
        let other = RankBox::new(
            &rank_box.cells,
            &impact_core::comm::RankGrid(rank_box.parts.clone()),
            rank_box.ranks,
            rank,
            rank_box.halo,
        )
        .ok()?;
        Some(Self {
            owned: other.owned[axis].clone(),
            stored: other.stored[axis].clone(),
        })
    }
}

/// The messages of one rank's migration and halo, kept between steps (no allocation once
/// grown).
#[derive(Debug, Default)]
pub(crate) struct Buffers {
    pub send_low: Vec<f64>,
    pub send_high: Vec<f64>,
    pub receive_low: Vec<f64>,
    pub receive_high: Vec<f64>,
    /// The halo's rows (the neighbours' points in the stored box), in the order received.
    pub halo: Vec<f64>,
}

impl Buffers {
    /// Send `send_low` and `send_high` to the `neighbours` along one axis (lower, upper)
    /// and receive theirs into `receive_low` and `receive_high`. Returns the bytes sent.
    pub fn exchange(&mut self, comm: &dyn Comm, neighbours: [Option<usize>; 2]) -> usize {
        exchange_varying(
            comm,
            neighbours,
            &self.send_low,
            &self.send_high,
            &mut self.receive_low,
            &mut self.receive_high,
        )
    }
}

//! The rows that [`crate::migrate::MigratingMpm`] sends between ranks: a stored point's
//! whole state as one row of floats ([`columns`]), the body's cells that decide a point's
//! owner ([`Cells`]), a neighbour's box along one axis ([`Neighbour`]) and the messages kept
//! between steps ([`Buffers`]).
use crate::slab::CPDI_DOMAIN_REACH;
use crate::{MpmSolver, MpmState, PADDING};
use impact_core::comm::{Comm, RankBox};
use impact_core::comm_migrate::{exchange_varying, point_columns, Column};
use impact_core::{Tensor, Vector};
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

    /// Where the next step's CPDI stencil of the point at `x` with `domain`, whose cell is
    /// `cell`, starts outside the cells the halo covers (`migrate.rs`): along the first such
    /// axis, `(axis, cells the stencil starts below the point's cell)`, for a start more
    /// than [`CPDI_DOMAIN_REACH`] cells below it or above it. Axes along which the point
    /// lies beyond the body's grid are skipped (a physical edge there, no cut), and so is a
    /// stencil that does not fit the grid (`check_finite` reports it).
    pub fn cpdi_stencil_past_halo(
        &self,
        solver: &MpmSolver<D>,
        x: &Vector<D>,
        domain: &Tensor<D>,
        cell: [usize; D],
    ) -> Option<(usize, isize)> {
        let start = solver
            .stencil
            .domain_start(&solver.place.whole, x, domain)?;
        (0..D).find_map(|k| {
            let u = (x[k] - self.origin[k]) / self.spacing[k];
            if !(0.0..self.count[k] as f64).contains(&u) {
                return None;
            }
            // the whole padded grid's node `start` is the body's node `start − PADDING`
            let below = cell[k] as isize - (start[k] as isize - PADDING as isize);
            (!(0..=CPDI_DOMAIN_REACH as isize).contains(&below)).then_some((k, below))
        })
    }

    /// The cell indices of the point of `row` (a packed row).
    pub fn of_row(&self, row: &[f64]) -> [usize; D] {
        let at = position_at(D);
        std::array::from_fn(|axis| self.along(axis, row[at + axis]))
    }
}

/// Why the run fails when an own point's next CPDI stencil starts `below` cells below its
/// cell along `axis` (`reach`, from [`Cells::cpdi_stencil_past_halo`]) after step `step`
/// at time `t`: the point's global number `id` and position `x`, the reach, the `halo`
/// and what to do.
pub(crate) fn cpdi_reach_reason<const D: usize>(
    (step, t): (usize, f64),
    id: usize,
    x: &Vector<D>,
    (axis, below): (usize, isize),
    halo: usize,
) -> String {
    format!(
        "step {step}, t = {t:e}: material point {id} at x = {:?}: its CPDI domain's stencil \
         starts {below} cells below the point's cell along axis {axis}, where the halo of \
         {halo} cells between ranks covers 0 to {CPDI_DOMAIN_REACH} (a domain stretched or \
         sheared by the flow: run on fewer ranks along axis {axis}, or with another shape: \
         hats, GIMP, B-splines)",
        x.as_slice()
    )
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

#[cfg(test)]
mod tests {
    use crate::Mpm;
    use impact_core::method::{MethodKind, MpmFrame, MpmShape};
    use impact_core::{Problem, Scene, Tensor, Vector};

    /// The CPDI reach check: a stencil starting 0 or 1 cells below the point's cell passes,
    /// 2 below or 1 above fails along that axis; a point beyond the body's grid along an
    /// axis, and a domain too large for the stencil (`check_finite`'s), are not its
    /// business. (A symmetric domain whose stencil fits starts at most one cell below its
    /// point: only a disagreement of the floors, emulated here by the cell passed, reaches 2.)
    #[test]
    fn a_cpdi_stencil_past_the_halo_is_found_along_its_axis() {
        let plate = Scene::builtin("plate").unwrap();
        let problem = Problem::<2>::from_scene(&plate).unwrap();
        let mut config = plate.method_config(MethodKind::Mpm);
        let o = config.mpm_mut().unwrap();
        o.frame = MpmFrame::UpdatedLagrangian;
        o.shape = MpmShape::Cpdi;
        let m = Mpm::<2>::new(&problem, config).unwrap();
        let g = &problem.grid;
        let cells = super::Cells::<2> {
            origin: [g.origin[0], g.origin[1]],
            spacing: [g.spacing[0], g.spacing[1]],
            count: g.cells,
        };
        let h = g.spacing;
        let at = |i: f64, j: f64| g.origin + Vector::<2>::new(i * h[0], j * h[1]);
        let rest = Tensor::<2>::new(0.25 * h[0], 0.0, 0.0, 0.25 * h[1]);
        let x = at(10.5, 10.5);
        let check = |x: &Vector<2>, r: &Tensor<2>, cell| {
            cells.cpdi_stencil_past_halo(&m.solver, x, r, cell)
        };
        assert_eq!(check(&x, &rest, [10, 10]), None);
        assert_eq!(check(&x, &rest, [10, 11]), None);
        assert_eq!(check(&x, &rest, [10, 12]), Some((1, 2)));
        assert_eq!(check(&x, &rest, [10, 9]), Some((1, -1)));
        assert_eq!(check(&x, &rest, [12, 10]), Some((0, 2)));
        // a domain stretched to 0.9 cells: its stencil starts one cell below, covered
        let stretched = Tensor::<2>::new(0.25 * h[0], 0.0, 0.0, 0.9 * h[1]);
        assert_eq!(check(&x, &stretched, [10, 10]), None);
        // beyond the body's grid along axis 1 (cell clamped to 0): skipped there
        assert_eq!(check(&at(10.5, -1.5), &rest, [10, 0]), None);
        assert_eq!(check(&at(12.5, -1.5), &rest, [14, 0]), Some((0, 2)));
        // too large for the stencil: check_finite's failure
        let tall = Tensor::<2>::new(0.25 * h[0], 0.0, 0.0, 1.6 * h[1]);
        assert_eq!(check(&x, &tall, [10, 10]), None);
        let reason = super::cpdi_reach_reason((7, 0.5), 1234, &x, (1, 2), 4);
        assert!(
            reason.starts_with("step 7, t = 5e-1: material point 1234 at x = [")
                && reason.contains("starts 2 cells below the point's cell along axis 1")
                && reason.contains("halo of 4 cells between ranks covers 0 to 1")
                && reason.contains("fewer ranks along axis 1"),
            "{reason}"
        );
    }
}

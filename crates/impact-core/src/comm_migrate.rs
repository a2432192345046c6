//! What a point method needs to move points between ranks ([`crate::comm`]) when the
//! points move through the grid (MPM's updated Lagrangian frame, issue 27): messages of a
//! length the receiver does not know ([`exchange_varying`]), and every per-point array of
//! [`MaterialPoints`] as one list of columns ([`point_columns`]), from which a point's row
//! of values is packed and unpacked, so a field added to `MaterialPoints` cannot be left
//! behind (the list destructures the struct without `..`: a new field does not compile
//! until it is listed).
use crate::comm::Comm;
use crate::points::MaterialPoints;
use crate::{Tensor, Vector};

/// [`Comm::exchange`] with the `neighbours` along one axis (lower, upper; `None` where
/// there is none) with messages of any length: each rank first sends the lengths of its
/// two messages (one value each way per neighbour), then the messages, into `from_lower`
/// and `from_upper` (resized; emptied where there is no neighbour). Two rounds of the
/// fixed-length exchange, so every [`Comm`] (serial, threads, MPI) has it without a method
/// of its own. Returns the bytes this rank sent.
pub fn exchange_varying(
    comm: &dyn Comm,
    neighbours: [Option<usize>; 2],
    to_lower: &[f64],
    to_upper: &[f64],
    from_lower: &mut Vec<f64>,
    from_upper: &mut Vec<f64>,
) -> usize {
    let (low, high) = (
        usize::from(neighbours[0].is_some()),
        usize::from(neighbours[1].is_some()),
    );
    let (mut length_low, mut length_high) = ([0.0], [0.0]);
    comm.exchange(
        neighbours,
        &[to_lower.len() as f64][..low],
        &[to_upper.len() as f64][..high],
        &mut length_low[..low],
        &mut length_high[..high],
    );
    from_lower.clear();
    from_lower.resize(length_low[0] as usize * low, 0.0);
    from_upper.clear();
    from_upper.resize(length_high[0] as usize * high, 0.0);
    let (to_lower, to_upper) = (
        &to_lower[..to_lower.len() * low],
        &to_upper[..to_upper.len() * high],
    );
    comm.exchange(neighbours, to_lower, to_upper, from_lower, from_upper);
    8 * (low + high + to_lower.len() + to_upper.len())
}

/// One per-point array: its values per point are `width()` floats of a point's row.
#[derive(Debug)]
pub enum Column<'a, const D: usize> {
    /// One value per point.
    Scalar(&'a mut Vec<f64>),
    /// An index per point (a global point number: exact as a float below 2⁵³).
    Index(&'a mut Vec<usize>),
    /// A vector per point.
    Vector(&'a mut Vec<Vector<D>>),
    /// A tensor per point.
    Tensor(&'a mut Vec<Tensor<D>>),
}

impl<const D: usize> Column<'_, D> {
    /// Floats per point.
    pub fn width(&self) -> usize {
        match self {
            Column::Scalar(_) | Column::Index(_) => 1,
            Column::Vector(_) => D,
            Column::Tensor(_) => D * D,
        }
    }

    /// Whether the array is empty (a field the model does not use).
    pub fn is_empty(&self) -> bool {
        match self {
            Column::Scalar(v) => v.is_empty(),
            Column::Index(v) => v.is_empty(),
            Column::Vector(v) => v.is_empty(),
            Column::Tensor(v) => v.is_empty(),
        }
    }

    /// Append point `i`'s values to `row`.
    pub fn pack(&self, i: usize, row: &mut Vec<f64>) {
        match self {
            Column::Scalar(v) => row.push(v[i]),
            Column::Index(v) => row.push(v[i] as f64),
            Column::Vector(v) => row.extend_from_slice(v[i].as_slice()),
            Column::Tensor(v) => row.extend_from_slice(v[i].as_slice()),
        }
    }

    /// Append a point whose values are `values` (`width()` floats).
    pub fn push(&mut self, values: &[f64]) {
        match self {
            Column::Scalar(v) => v.push(values[0]),
            Column::Index(v) => v.push(values[0] as usize),
            Column::Vector(v) => v.push(Vector::<D>::from_column_slice(values)),
            Column::Tensor(v) => v.push(Tensor::<D>::from_column_slice(values)),
        }
    }

    /// Keep the first `len` points (keeping the capacity).
    pub fn truncate(&mut self, len: usize) {
        match self {
            Column::Scalar(v) => v.truncate(len),
            Column::Index(v) => v.truncate(len),
            Column::Vector(v) => v.truncate(len),
            Column::Tensor(v) => v.truncate(len),
        }
    }

    /// Exchange points `a` and `b`.
    pub fn swap(&mut self, a: usize, b: usize) {
        match self {
            Column::Scalar(v) => v.swap(a, b),
            Column::Index(v) => v.swap(a, b),
            Column::Vector(v) => v.swap(a, b),
            Column::Tensor(v) => v.swap(a, b),
        }
    }

    /// Remove point `i`, the last point taking its place (`Vec::swap_remove`).
    pub fn swap_remove(&mut self, i: usize) {
        match self {
            Column::Scalar(v) => {
                v.swap_remove(i);
            }
            Column::Index(v) => {
                v.swap_remove(i);
            }
            Column::Vector(v) => {
                v.swap_remove(i);
            }
            Column::Tensor(v) => {
                v.swap_remove(i);
            }
        }
    }

    /// Remove every point (keeping the capacity).
    pub fn clear(&mut self) {
        match self {
            Column::Scalar(v) => v.clear(),
            Column::Index(v) => v.clear(),
            Column::Vector(v) => v.clear(),
            Column::Tensor(v) => v.clear(),
        }
    }
}

/// Every per-point array of `points`, in a fixed order (module doc). The arrays a model
/// leaves empty (deformation gradient, CPDI domains, plastic history, compacted
/// half-sizes) are listed too: the caller decides once which ones travel.
/// `uniform_half_size` is one value for all points, not a column.
pub fn point_columns<const D: usize>(points: &mut MaterialPoints<D>) -> [Column<'_, D>; 12] {
    let MaterialPoints {
        reference,
        position,
        mass,
        volume,
        velocity,
        stress,
        half_size,
        uniform_half_size: _,
        deformation,
        domain,
        equivalent_plastic_strain,
        plastic_strain_zz,
        plastic_work,
    } = points;
    [
        Column::Vector(reference),
        Column::Vector(position),
        Column::Scalar(mass),
        Column::Scalar(volume),
        Column::Vector(velocity),
        Column::Tensor(stress),
        Column::Vector(half_size),
        Column::Tensor(deformation),
        Column::Tensor(domain),
        Column::Scalar(equivalent_plastic_strain),
        Column::Scalar(plastic_strain_zz),
        Column::Scalar(plastic_work),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::comm::ThreadComm;

    /// Messages of every length (empty too) reach the neighbours whole, on 1 to 3 ranks.
    #[test]
    fn varying_messages_reach_the_neighbours() {
        for ranks in 1..=3 {
            let got = ThreadComm::on_ranks(ranks, |comm| {
                let r = comm.rank();
                let to_lower = vec![r as f64; r];
                let to_upper = vec![10.0 + r as f64; 2 * r + 1];
                let (mut from_lower, mut from_upper) = (vec![7.0], vec![7.0]);
                let neighbours = [r.checked_sub(1), (r + 1 < ranks).then_some(r + 1)];
                exchange_varying(
                    comm.as_ref(),
                    neighbours,
                    &to_lower,
                    &to_upper,
                    &mut from_lower,
                    &mut from_upper,
                );
                (from_lower, from_upper)
            });
            for (r, (from_lower, from_upper)) in got.into_iter().enumerate() {
                let below = if r > 0 {
                    vec![10.0 + (r - 1) as f64; 2 * (r - 1) + 1]
                } else {
                    vec![]
                };
                let above = if r + 1 < ranks {
                    vec![(r + 1) as f64; r + 1]
                } else {
                    vec![]
                };
                assert_eq!(
                    (from_lower, from_upper),
                    (below, above),
                    "{ranks} ranks, rank {r}"
                );
            }
        }
    }

    /// A point packed from every column and pushed back is the same point.
    #[test]
    fn a_row_round_trips_every_column() {
        let grid = crate::Grid::<2> {
            origin: Vector::<2>::zeros(),
            spacing: Vector::<2>::new(1.0, 1.0),
            cells: [2, 2],
        };
        let mut points = MaterialPoints::<2>::regular(&grid, 1, 3.0)
            .with_plasticity()
            .with_domains()
            .with_deformation();
        points.plastic_work[2] = 0.5;
        points.velocity[2] = Vector::<2>::new(1.0, -2.0);
        let mut row = Vec::new();
        point_columns(&mut points)
            .iter()
            .for_each(|c| c.pack(2, &mut row));
        let mut copy = points.select(0..0);
        let mut k = 0;
        for column in point_columns(&mut copy).iter_mut() {
            column.push(&row[k..k + column.width()]);
            k += column.width();
        }
        assert_eq!(k, row.len());
        let one = points.select(2..3);
        assert_eq!(copy.position, one.position);
        assert_eq!(copy.velocity, one.velocity);
        assert_eq!(copy.plastic_work, one.plastic_work);
        assert_eq!(copy.domain, one.domain);
        assert_eq!(copy.deformation, one.deformation);
    }
}

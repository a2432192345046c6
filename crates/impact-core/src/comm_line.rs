//! What the metrics and the profiles of one output time need from a body split over ranks,
//! gathered without gathering the whole body (issue 27: a 512³ body does not fit one
//! machine, so no rank may hold every sample): the samples on the measuring line
//! ([`MeasureLine::holds`]), in the global order, on every rank, and the body's extent and
//! volume ([`BodyMeasures`]), reduced.
//!
//! **Algorithm.** Each rank takes its owned samples ([`Method::owned_samples_into`]) and
//! their extent `[min (X − h), max (X + h)]` and volume `Σ Π 2h`; one all-gather of these
//! `2D + 1` numbers per rank gives every rank the body's extent (min and max: exact, the
//! serial values) and volume (summed in rank order: the serial sum to round-off, like the
//! energy). With the body's upper corner each rank picks its owned samples on the line
//! (the test of [`crate::reference::line_samples`], which needs the body's upper corner
//! for a line on the body's high face), and these alone are all-gathered
//! ([`gather_samples`]), put in the global order by [`Method::owned_sample_order`]. Every
//! sample is owned by exactly one rank, so the gathered line samples are the serial run's
//! line samples in the serial order: the profile and its metrics are the serial ones bit
//! for bit.
//!
//! **Why on every rank, not rank 0 only.** The metrics are computed on every rank from the
//! same gathered bits, so every rank holds the same [`crate::reference::TimeMetrics`]
//! without a second message (a broadcast of the metrics), and every rank's controller sees
//! the same values; the line's samples are a cross-section's worth (`n^{1/D}` of `n`
//! samples), so holding them on every rank costs nothing that matters.
use crate::comm::Comm;
use crate::comm_gather::gather_samples;
use crate::line::MeasureLine;
use crate::method::{Method, Samples};
use crate::Vector;

/// The whole body's extent and volume, from every rank's owned samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMeasures<const D: usize> {
    /// The lowest corner of the samples' regions, `min_i (X_i − h_i)` per axis.
    pub lower: Vector<D>,
    /// The highest corner, `max_i (X_i + h_i)` per axis.
    pub upper: Vector<D>,
    /// `Σ_i Π_k 2 h_ik`: the total volume (length in 1D, area in 2D) of the regions.
    pub volume: f64,
}

impl<const D: usize> BodyMeasures<D> {
    /// The measures of `samples` alone (one rank's).
    pub fn of(samples: &Samples<D>) -> Self {
        let mut lower = Vector::<D>::repeat(f64::MAX);
        let mut upper = Vector::<D>::repeat(f64::MIN);
        let mut volume = 0.0;
        for (x, h) in samples.reference.iter().zip(&samples.half_size) {
            lower = lower.inf(&(x - h));
            upper = upper.sup(&(x + h));
            volume += h.iter().map(|v| 2.0 * v).product::<f64>();
        }
        Self {
            lower,
            upper,
            volume,
        }
    }

    /// Every rank's measures combined (collective): min and max per axis, the volumes added
    /// in rank order.
    pub fn over_ranks(self, comm: &(impl Comm + ?Sized)) -> Self {
        if comm.size() == 1 {
            return self;
        }
        let mut mine: Vec<f64> = self
            .lower
            .iter()
            .chain(self.upper.iter())
            .copied()
            .collect();
        mine.push(self.volume);
        let all = comm.all_gather(&mine);
        let width = 2 * D + 1;
        let mut body = Self {
            lower: Vector::<D>::repeat(f64::MAX),
            upper: Vector::<D>::repeat(f64::MIN),
            volume: 0.0,
        };
        for rank in all.chunks_exact(width) {
            body.lower = body.lower.inf(&Vector::<D>::from_column_slice(&rank[..D]));
            body.upper = body
                .upper
                .sup(&Vector::<D>::from_column_slice(&rank[D..2 * D]));
            body.volume += rank[2 * D];
        }
        body
    }

    /// The body's cross-section normal to x: its extent along every axis but x multiplied
    /// (1 in 1D).
    pub fn cross_section(&self) -> f64 {
        (1..D).map(|k| self.upper[k] - self.lower[k]).product()
    }
}

/// Append sample `i` of `from` to `to` (the optional arrays where `from` has them).
fn push_sample<const D: usize>(from: &Samples<D>, i: usize, to: &mut Samples<D>) {
    to.reference.push(from.reference[i]);
    to.position.push(from.position[i]);
    to.half_size.push(from.half_size[i]);
    to.stress.push(from.stress[i]);
    to.velocity.push(from.velocity[i]);
    if let Some(&e) = from.plastic_strain.get(i) {
        to.plastic_strain.push(e);
    }
    if let Some(&zz) = from.stress_zz.get(i) {
        to.stress_zz.push(zz);
    }
}

/// The samples of `method` on `line`, in the global order, into `out` on every rank, and
/// the body's measures (collective; module doc). `owned` is a buffer (this rank's owned
/// samples when it returns). The bytes this rank receives are
/// `8 (2D + 1) · ranks + 8 · width · line samples` (`width` = `4D + D²` plus the plastic
/// strain and `σ_zz` where present), plus 8 per line sample for the order on boxes.
pub fn gather_line<const D: usize, M: Method<D> + ?Sized>(
    method: &M,
    line: &MeasureLine,
    owned: &mut Samples<D>,
    out: &mut Samples<D>,
) -> BodyMeasures<D> {
    let comm = method.comm();
    method.owned_samples_into(owned);
    let body = BodyMeasures::of(owned).over_ranks(comm);
    let order = method.owned_sample_order();
    let mut on_line = Samples::<D>::default();
    let mut global_index = Vec::new();
    for i in 0..owned.len() {
        let (x, h) = (owned.reference[i], owned.half_size[i]);
        if line.holds(&(x - h), &(x + h), &body.upper) {
            push_sample(owned, i, &mut on_line);
            if let Some(&g) = order.get(i) {
                global_index.push(g);
            }
        }
    }
    gather_samples(comm, &on_line, &global_index, out);
    body
}

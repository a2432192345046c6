//! The reference a scene is measured against, and the per-output-time metrics of a method.
//!
//! - 1D linear elasticity (any end conditions, any load histories, any initial state):
//!   the exact d'Alembert solution with images [`BarExact`]; the profile is `σ_xx`
//!   sampled where each method stores it against the exact average over the region each
//!   sample stands for.
//! - plane wave (2D, symmetry top and bottom, any conditions on the whole left and right
//!   edges, at rest): the same solution in uniaxial strain, `c_p = sqrt((λ+2μ)/ρ)`, with
//!   `σ_yy = λ/(λ+2μ) σ_xx`.
//! - [`Reference::exact`] says why a scene has no exact reference.
//! - otherwise (the partial impact of §5.2): a converged numerical solution tabulated on a
//!   finer grid ([`Converged`], computed by the caller, e.g. DGMPM on a refined grid). The
//!   samples are compared with its averages over their regions; the front is at `c_p t`
//!   from the loaded face along the measuring line (file `converged.rs`).
//!
//! Profiles, errors and fronts are measured along the measuring line ([`MeasureLine`]):
//! the normal stress along it at the samples whose region it crosses. The exact solutions
//! above are plane waves along x, measured along x.
use crate::comm_line::gather_line;
pub use crate::converged::Converged;
use crate::exact::{
    BarExact, ElastoplasticWave, Front, NoFront, PlaneWave, StandingWave, SvkBarExact,
};
use crate::interior::Interior;
use crate::line::MeasureLine;
use crate::method::{Method, Samples};
use crate::metrics::{energy_error, FrontStatus, Profile, ProfileMetrics};
use crate::problem::Problem;
pub use crate::time_metrics::TimeMetrics;
use crate::Vector;

/// A scene's reference solution.
#[derive(Debug, Clone)]
pub enum Reference {
    /// Exact solution of the loaded elastic bar (1D) or plane wave (2D).
    Bar(BarExact),
    /// A converged numerical solution on a finer grid.
    Converged(Box<Converged>),
    /// Exact fan or shock of the Saint-Venant–Kirchhoff bar (until it reaches the free end).
    SvkBar(SvkBarExact),
    /// The standing P mode of a box with `symmetry` edges (smooth; no front).
    Standing(StandingWave),
    /// A travelling plane pulse (smooth; no front), exact in the clean interior.
    Plane(PlaneWave),
    /// The elastic precursor and plastic wave of a J2 rod or plane wave (until the
    /// precursor reaches the far end); the front is the precursor.
    Elastoplastic(ElastoplasticWave),
}

impl Reference {
    /// The reference of `problem`, if it has an exact solution ([`Self::exact`], in
    /// `exact/select.rs`, says why not).
    pub fn for_problem<const D: usize>(problem: &Problem<D>) -> Option<Self> {
        Self::exact(problem).ok()
    }

    /// Average of `σ_xx` and `v_x` over the box `[lo, hi]` (only x matters for the exact
    /// solutions) at `t`.
    pub fn averages<const D: usize>(&self, lo: &Vector<D>, hi: &Vector<D>, t: f64) -> (f64, f64) {
        match self {
            Reference::Bar(b) => (
                b.stress_average(lo[0], hi[0], t),
                b.velocity_average(lo[0], hi[0], t),
            ),
            Reference::SvkBar(b) => b.averages(lo[0], hi[0], t),
            Reference::Elastoplastic(w) => w.averages(lo[0], hi[0], t),
            Reference::Standing(w) => w.averages(pad(lo, 0.0), pad(hi, 1.0), t),
            Reference::Plane(w) => w.averages(pad(lo, 0.0), pad(hi, 0.0), t),
            Reference::Converged(c) => {
                let (lo, hi) = fine_box(c, lo, hi);
                (
                    c.average(&c.stress, lo, hi, t),
                    c.average(&c.velocity, lo, hi, t),
                )
            }
        }
    }

    /// The second reference's averages of `σ_aa` and `v_a` over `[lo, hi]` at `t` (the
    /// spread of [`crate::converged::Spread`]): `None` for an exact solution or a converged
    /// reference without a second one.
    pub fn spread_averages<const D: usize>(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        t: f64,
    ) -> Option<(f64, f64)> {
        match self {
            Reference::Converged(c) => {
                let (lo, hi) = fine_box(c, lo, hi);
                c.spread_averages(lo, hi, t)
            }
            _ => None,
        }
    }

    /// The leading front at `t`, or why there is none.
    pub fn front(&self, t: f64) -> Result<Front, NoFront> {
        match self {
            Reference::Bar(b) => b.leading_front(t),
            Reference::SvkBar(b) => b.leading_front(t),
            Reference::Standing(_) | Reference::Plane(_) => Err(NoFront::NotAStep),
            Reference::Elastoplastic(w) => {
                if t <= w.valid_until {
                    Ok(w.fronts(t)[0])
                } else {
                    Err(NoFront::PastValidity)
                }
            }
            Reference::Converged(c) => c.front(t),
        }
    }

    /// Work done by the loads up to `t` (per unit thickness), if the reference knows it.
    pub fn work(&self, t: f64) -> Option<f64> {
        match self {
            Reference::Bar(b) => Some(b.work(t)),
            Reference::SvkBar(b) => Some(b.work(t)),
            Reference::Standing(_) => Some(0.0),
            // the boundaries may work on the pulse's tails
            Reference::Plane(_) => None,
            // W = p u(0, t) (rod) or V (−σ_xx) t per unit area: the state at X = 0 is
            // constant behind the plastic wave
            Reference::Elastoplastic(w) => Some(-w.behind.0 * w.behind.1 * t),
            Reference::Converged(c) => c.work_at(t),
        }
    }

    /// What the errors are measured against.
    pub fn describe(&self) -> String {
        match self {
            Reference::Bar(b) => format!(
                "exact solution (averages over each sample's region): d'Alembert with images, \
                 {}",
                b.describe()
            ),
            Reference::SvkBar(b) => format!(
                "exact SVK {} (averages over each sample's region; valid until t = {:.4e} s)",
                if b.is_shock() { "shock" } else { "centred fan" },
                b.valid_until()
            ),
            Reference::Elastoplastic(w) => format!(
                "exact elastic precursor at {:.1} m/s and plastic wave at {:.1} m/s (averages \
                 over each sample's region; valid until t = {:.4e} s)",
                w.elastic_speed, w.plastic_speed, w.valid_until
            ),
            Reference::Standing(w) => format!(
                "exact standing P mode, ω = {:.6e} rad/s (averages over each sample's region)",
                w.frequency
            ),
            Reference::Plane(w) => format!(
                "exact plane {} pulse along n = [{:.4}, {:.4}, {:.4}] at {:.1} m/s (averages over \
                 each sample's region, in the clean interior no boundary can have reached)",
                if w.is_shear() { "S" } else { "P" },
                w.direction[0],
                w.direction[1],
                w.direction[2],
                w.speed
            ),
            Reference::Converged(c) => c.description.clone(),
        }
    }

    /// Stress scale for relative errors when the exact field vanishes.
    pub fn scale(&self) -> f64 {
        match self {
            Reference::Bar(b) => b.pressure.abs(),
            Reference::SvkBar(b) => b.pressure.abs(),
            Reference::Standing(w) => w.peak_stress_xx(),
            Reference::Plane(w) => w.stress_scale(),
            Reference::Elastoplastic(w) => w.behind.0.abs(),
            Reference::Converged(c) => c.peak_stress(),
        }
    }

    /// The profile of the normal stress `σ_aa` along `line` (axis `a`) of `samples` (at
    /// their reference positions) with the reference's averages over each sample's region;
    /// with `interior`, only the samples whose region lies in it.
    pub fn profile<const D: usize>(
        &self,
        samples: &Samples<D>,
        t: f64,
        line: &MeasureLine,
        interior: Option<&Interior<D>>,
    ) -> Profile {
        self.profile_at(samples, line_samples(samples, line), t, line.axis, interior)
    }

    /// [`Self::profile`] of the samples `on_line` of `samples` (the line's axis `a`).
    fn profile_at<const D: usize>(
        &self,
        samples: &Samples<D>,
        on_line: impl IntoIterator<Item = usize>,
        t: f64,
        a: usize,
        interior: Option<&Interior<D>>,
    ) -> Profile {
        let mut p = Profile::default();
        for i in on_line {
            let (x, h) = (samples.reference[i], samples.half_size[i]);
            if interior.is_some_and(|box_| !box_.holds(&x, &h)) {
                continue;
            }
            p.x.push(x[a]);
            p.width.push(2.0 * h[a]);
            p.value.push(samples.stress[i][(a, a)]);
            p.exact.push(self.averages(&(x - h), &(x + h), t).0);
            if let Reference::Converged(c) = self {
                let (lo, hi) = fine_box(c, &(x - h), &(x + h));
                if let Some(second) = c.spread_average(lo, hi, t) {
                    p.second.push(second);
                }
            }
        }
        p.sort();
        p
    }

    /// Scale the exact profile lengths: in 2D the exact plane-wave work is per unit height.
    fn work_scale<const D: usize>(samples: &Samples<D>) -> f64 {
        // the cross-section: the body's extent along every axis but x
        (1..D)
            .map(|k| {
                let (mut lo, mut hi) = (f64::MAX, f64::MIN);
                for i in 0..samples.len() {
                    lo = lo.min(samples.reference[i][k] - samples.half_size[i][k]);
                    hi = hi.max(samples.reference[i][k] + samples.half_size[i][k]);
                }
                hi - lo
            })
            .product()
    }

    /// All metrics of `method` at time `t` along `line` (`samples` is a reusable buffer;
    /// front widths in cells of the grid's size along the line); with `interior`, the
    /// profile keeps to the samples in it (the energy stays the whole body's). On one rank
    /// every sample is taken ([`Method::sample_into`]); on several, only the line's samples
    /// are gathered, with the body's extent and volume reduced
    /// ([`crate::comm_line::gather_line`]): the same profile and metrics bit for bit (the
    /// volume of the standing mode's energy to round-off, like the energy itself), on every
    /// rank.
    pub fn evaluate<const D: usize, M: Method<D> + ?Sized>(
        &self,
        method: &M,
        samples: &mut Samples<D>,
        (t, line, dx): (f64, &MeasureLine, f64),
        interior: Option<&Interior<D>>,
    ) -> TimeMetrics {
        let (profile, body) = if method.comm().size() == 1 {
            method.sample_into(samples);
            (self.profile(samples, t, line, interior), None)
        } else {
            let mut owned = Samples::default();
            let body = gather_line(method, line, &mut owned, samples);
            let on_line = 0..samples.len();
            let profile = self.profile_at(samples, on_line, t, line.axis, interior);
            (profile, Some(body))
        };
        let work_scale = || body.map_or_else(|| Self::work_scale(samples), |b| b.cross_section());
        let volume = || body.map_or_else(|| total_volume(samples), |b| b.volume);
        // a front without a jump (a zero load) has nothing to measure
        let front = self.front(t).and_then(|f| {
            if f.behind != f.ahead {
                Ok(f)
            } else {
                Err(NoFront::JumpTooSmall)
            }
        });
        let front_reason = front.err();
        let front = front.ok();
        let ProfileMetrics {
            l1_rel,
            linf_rel,
            front_width_cells,
            overshoot_pct,
            errors,
        } = profile.metrics(front.as_ref(), dx, self.scale());
        let l1_spread = profile.spread(self.scale());
        // the energy the discrete state should hold, E* = W + E_0 (`energy_error`): the
        // work done on it plus its initial energy; the exact plane-wave work and energy are
        // per unit height, the converged work is the total (its run starts from the same
        // initial state, whose energy the method holds at t = 0); the standing mode (no
        // load) keeps its constant energy
        let expected = match self {
            Reference::Bar(b) => Some(b.energy(t) * work_scale()),
            Reference::SvkBar(_) | Reference::Elastoplastic(_) => {
                self.work(t).map(|w| w * work_scale())
            }
            Reference::Standing(w) => Some(w.energy(volume())),
            Reference::Plane(_) => None,
            Reference::Converged(_) => self.work(t).map(|w| w + method.initial_energy()),
        }
        .unwrap_or(method.external_work() + method.initial_energy());
        let front_position = front.as_ref().and_then(|f| profile.crossing(f, 0.5, dx));
        let status = match (&front, front_width_cells, front_position) {
            (None, _, _) => FrontStatus::NoFront,
            (Some(_), Some(_), Some(_)) => FrontStatus::Measured,
            (Some(_), _, _) => FrontStatus::NotCrossed,
        };
        let (energy_error, energy_relative) = energy_error(method.energy(), expected);
        // the plastic wave of an elastoplastic reference: the second front
        let (plastic_front_width_cells, plastic_overshoot_pct, plastic_front_position) = match self
        {
            Reference::Elastoplastic(w) if w.is_plastic() && t <= w.valid_until => {
                let second = w.fronts(t)[1];
                let (width, overshoot) = profile.front(&second, dx);
                let at = profile
                    .crossing(&second, 0.5, dx)
                    .map(|x| (x, second.position));
                (width, overshoot, at)
            }
            _ => (None, None, None),
        };
        TimeMetrics {
            plastic_front_width_cells,
            plastic_overshoot_pct,
            plastic_front_position,
            t,
            l1: l1_rel,
            linf: linf_rel,
            errors,
            l1_spread,
            front_width_cells,
            overshoot_pct,
            front_position,
            front_exact: front.map(|f| f.position),
            front: status,
            front_reason,
            energy_error,
            energy_relative,
        }
    }
}

/// The box `[lo, hi]` in the converged reference's three axes: beyond dimension `D` it
/// spans the reference's one cell (`[0, h]`).
fn fine_box<const D: usize>(
    c: &crate::converged::Converged,
    lo: &Vector<D>,
    hi: &Vector<D>,
) -> ([f64; 3], [f64; 3]) {
    let hi = std::array::from_fn(|l| if l < D { hi[l] } else { c.spacing[l] });
    (pad(lo, 0.0), hi)
}

/// `v` with `default` beyond dimension `D`.
fn pad<const D: usize>(v: &Vector<D>, default: f64) -> [f64; 3] {
    std::array::from_fn(|l| if l < D { v[l] } else { default })
}

/// Total volume (length in 1D, area in 2D) of the samples' regions.
fn total_volume<const D: usize>(samples: &Samples<D>) -> f64 {
    samples
        .half_size
        .iter()
        .map(|h| h.iter().map(|x| 2.0 * x).product::<f64>())
        .sum()
}

/// The samples on `line` ([`MeasureLine::holds`]), in storage order.
pub fn line_samples<const D: usize>(samples: &Samples<D>, line: &MeasureLine) -> Vec<usize> {
    let mut upper = Vector::<D>::repeat(f64::MIN);
    for i in 0..samples.len() {
        let hi = samples.reference[i] + samples.half_size[i];
        upper = upper.sup(&hi);
    }
    (0..samples.len())
        .filter(|&i| {
            let (x, h) = (samples.reference[i], samples.half_size[i]);
            line.holds(&(x - h), &(x + h), &upper)
        })
        .collect()
}

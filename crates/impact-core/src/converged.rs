//! A converged numerical reference: a finer run tabulated per fine cell, for the scenes
//! without an exact solution (the partial impact of §5.2, any plate a user writes).
//!
//! It stores the normal stress `σ_aa` and velocity `v_a` along the axis `a` of the
//! measuring line ([`crate::line`]). Its front is the leading P front sent by the load into
//! the body along the line: at distance `c_p t` from the line's start (the loaded face),
//! moving along the line; the jump is from the state at rest ahead (0) to the reference's
//! average over the coarse cell just behind the front, in the band of the coarse row the
//! line runs in (from the reference one cell ahead instead of 0 when the body does not start
//! at rest). The front is not measured ([`NoFront`]) when:
//! - the load is zero or not a step (a ramp or a sine sends no jump);
//! - the line does not start on a loaded edge (a stated line drawn from the other side);
//! - the edge at the line's other end is loaded too and the two fronts are within
//!   [`FRONT_WINDOW_CELLS`] cells of each other (merged);
//! - it lies within 1.5 coarse cells of the face (not yet resolved), or has reached the
//!   line's end (left the body);
//! - the jump is under [`MIN_JUMP`] of the load's stress scale (`p`, or `Z v_d` for an
//!   impactor): a weak wave, e.g. the diffracted wave along a row far from the impact,
//!   against which an overshoot in % is meaningless;
//! - the reference 2 and 3 cells behind the front differs from the value just behind by
//!   more than [`PLATEAU_TOLERANCE`] of the jump: no plateau to measure a width between.
use crate::exact::{Front, NoFront};
use crate::line::MeasureLine;
use crate::metrics::FRONT_WINDOW_CELLS;

/// Smallest measurable jump across a front, as a fraction of the load's stress scale.
pub const MIN_JUMP: f64 = 0.05;
/// Largest variation of the reference over the 2 cells behind the front, as a fraction
/// of the jump, for a plateau.
pub const PLATEAU_TOLERANCE: f64 = 0.5;

/// A converged numerical solution: `σ_aa` and `v_a` per cell of a fine regular grid at
/// each output time (module doc).
#[derive(Debug, Clone)]
pub struct Converged {
    /// What it is (printed in the output).
    pub description: String,
    /// Cells per axis of the fine grid (`[nx, ny, nz]`; 1 beyond the scene's dimension).
    pub cells: [usize; 3],
    /// Fine cell size per axis (1 beyond the scene's dimension).
    pub spacing: [f64; 3],
    /// Output times.
    pub times: Vec<f64>,
    /// `σ_aa` per fine cell (x fastest) per output time, `a` the line's axis.
    pub stress: Vec<Vec<f64>>,
    /// `v_a` per fine cell per output time.
    pub velocity: Vec<Vec<f64>>,
    /// Speed of the leading front (`c_p`).
    pub speed: f64,
    /// The measuring line of the coarse problem.
    pub line: MeasureLine,
    /// Coarse cell size along the line.
    pub coarse_dx: f64,
    /// The band `[lo, hi]` across the line of the coarse row it runs in, along each of
    /// the line's other axes (`MeasureLine::offset` order; `[0, spacing]` of an axis
    /// beyond the scene's dimension).
    pub band: [[f64; 2]; 2],
    /// Stress scale of the load (`p`, or `Z v_d`; 0 with no load).
    pub load_scale: f64,
    /// Whether the load is a step (a jump at `t = 0`).
    pub step_load: bool,
    /// Whether the line starts on a loaded edge.
    pub from_load: bool,
    /// Whether the edge at the line's end is loaded too (a front comes from there).
    pub opposite_load: bool,
    /// Whether the body starts at rest (the state ahead of the front is 0).
    pub rest: bool,
    /// Work done by the loads at each output time, per the reference run.
    pub work: Vec<f64>,
    /// The second, independent reference on the same fine grid: its distance from this one
    /// is the uncertainty of every error measured against this one.
    pub spread: Option<Spread>,
}

/// A second converged reference (another method) on the same fine grid as [`Converged`].
///
/// For a run's profile `f_h` measured against the reference `f_A` and the second one `f_B`
/// (each averaged over every sample's region), the triangle inequality bounds how much the
/// relative L1 error depends on which reference judges:
/// `|Σ w|f_h − f_A| − Σ w|f_h − f_B|| ≤ Σ w|f_A − f_B|`, so the spread
/// `Σ w|f_A − f_B| / Σ w|f_A|` is reported beside the error `Σ w|f_h − f_A| / Σ w|f_A|`
/// as its uncertainty ([`crate::metrics::Profile::spread`]).
#[derive(Debug, Clone)]
pub struct Spread {
    /// What it is (printed in the output).
    pub description: String,
    /// `σ_aa` per fine cell per output time (the layout of [`Converged::stress`]).
    pub stress: Vec<Vec<f64>>,
    /// `v_a` per fine cell per output time (the layout of [`Converged::velocity`]).
    pub velocity: Vec<Vec<f64>>,
}

impl Converged {
    /// The index of output time `t`, if it is one.
    fn time_index(&self, t: f64) -> Option<usize> {
        self.times
            .iter()
            .position(|&s| (s - t).abs() <= 1e-9 * t.abs().max(1e-300))
    }

    /// Average of `field` over the box `[lo, hi]` (x, y, z) at output time `t`
    /// (overlap-weighted; NaN off the output times or outside the grid).
    pub fn average(&self, field: &[Vec<f64>], lo: [f64; 3], hi: [f64; 3], t: f64) -> f64 {
        let Some(k) = self.time_index(t) else {
            return f64::NAN;
        };
        let values = &field[k];
        let range = |l: usize| {
            let a = ((lo[l] / self.spacing[l]).floor().max(0.0)) as usize;
            let b = ((hi[l] / self.spacing[l]).ceil() as usize).min(self.cells[l]);
            a..b
        };
        let (mut sum, mut weight) = (0.0, 0.0);
        for m in range(2) {
            let wz = overlap(m, self.spacing[2], lo[2], hi[2]);
            for j in range(1) {
                let wy = wz * overlap(j, self.spacing[1], lo[1], hi[1]);
                for i in range(0) {
                    let w = wy * overlap(i, self.spacing[0], lo[0], hi[0]);
                    sum += w * values[(m * self.cells[1] + j) * self.cells[0] + i];
                    weight += w;
                }
            }
        }
        if weight > 0.0 {
            sum / weight
        } else {
            f64::NAN
        }
    }

    /// Average of the second reference's `σ_aa` over the box `[lo, hi]` at `t` (`None`
    /// without a second reference).
    pub fn spread_average(&self, lo: [f64; 3], hi: [f64; 3], t: f64) -> Option<f64> {
        self.spread
            .as_ref()
            .map(|s| self.average(&s.stress, lo, hi, t))
    }

    /// Averages of the second reference's `σ_aa` and `v_a` over the box `[lo, hi]` at `t`
    /// (`None` without a second reference).
    pub fn spread_averages(&self, lo: [f64; 3], hi: [f64; 3], t: f64) -> Option<(f64, f64)> {
        self.spread.as_ref().map(|s| {
            (
                self.average(&s.stress, lo, hi, t),
                self.average(&s.velocity, lo, hi, t),
            )
        })
    }

    /// Average of `σ_aa` over `[a, b]` along the line, across the line's band.
    fn along(&self, a: f64, b: f64, t: f64) -> f64 {
        let (a, b) = (a.min(b), a.max(b));
        let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
        lo[self.line.axis] = a;
        hi[self.line.axis] = b;
        let others = (0..3).filter(|&k| k != self.line.axis);
        for (slot, k) in others.enumerate() {
            lo[k] = self.band[slot][0];
            hi[k] = self.band[slot][1];
        }
        self.average(&self.stress, lo, hi, t)
    }

    /// The leading front at `t`, or why it is not measured (module doc).
    pub fn front(&self, t: f64) -> Result<Front, NoFront> {
        if self.load_scale == 0.0 || !self.step_load {
            return Err(NoFront::NotAStep);
        }
        if !self.from_load {
            return Err(NoFront::NotFromLoad);
        }
        let distance = self.speed * t;
        let dx = self.coarse_dx;
        if distance <= 1.5 * dx {
            return Err(NoFront::NotYetFormed);
        }
        if distance >= self.line.length() {
            return Err(NoFront::LeftTheBody);
        }
        if self.opposite_load && self.line.length() - 2.0 * distance < FRONT_WINDOW_CELLS * dx {
            return Err(NoFront::Merged);
        }
        let direction = self.line.direction();
        let position = self.line.start + direction * distance;
        // the coarse cell `k` cells behind the front
        let behind_by = |k: f64| {
            self.along(
                position - direction * (k + 0.5) * dx,
                position - direction * (k - 0.5) * dx,
                t,
            )
        };
        let behind = behind_by(1.0);
        if !behind.is_finite() {
            return Err(NoFront::NoReference);
        }
        let ahead = if self.rest { 0.0 } else { behind_by(-1.0) };
        let jump = behind - ahead;
        if jump.abs() < MIN_JUMP * self.load_scale {
            return Err(NoFront::JumpTooSmall);
        }
        for k in [2.0, 3.0] {
            if distance > (k + 0.5) * dx
                && (behind_by(k) - behind).abs() > PLATEAU_TOLERANCE * jump.abs()
            {
                return Err(NoFront::NoPlateau);
            }
        }
        Ok(Front {
            position,
            direction,
            ahead,
            behind,
            window: self.line.span(),
        })
    }

    /// Work done by the loads at output time `t`, per the reference run.
    pub fn work_at(&self, t: f64) -> Option<f64> {
        self.time_index(t).map(|k| self.work[k])
    }

    /// Largest `|σ_aa|` of the reference at any output time.
    pub fn peak_stress(&self) -> f64 {
        self.stress
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()))
    }
}

fn overlap(i: usize, h: f64, lo: f64, hi: f64) -> f64 {
    let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
    (b.min(hi) - a.max(lo)).max(0.0)
}

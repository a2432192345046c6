//! d'Alembert for the initial state of the elastic bar `0 < X < L` with unloaded ends
//! (the loads' waves superpose: the problem is linear; [`super::BarExact`]).
//!
//! With `ρ v_t = σ_X`, `σ_t = M v_X`, `c = sqrt(M/ρ)`, `Z = ρ c`, the characteristic
//! variables `R = v - σ/Z` (carried to the right, `R(X,t) = R̃(X - ct)`) and
//! `L = v + σ/Z` (carried to the left) give `v = (R + L)/2`, `σ = Z (L - R)/2`. At
//! `t = 0`, `R = R₀ = v₀ - σ₀/Z` and `L = L₀ = v₀ + σ₀/Z` on `[0, L]`. An unloaded end
//! reflects: a traction-free end (`σ = 0`) sends back `R = L` (sign `e = +1`), a
//! velocity end at rest (fixed, symmetry: `v = 0`) sends back `R = -L` (`e = -1`). With
//! `e₀`, `e₁` the signs of the ends at `X = 0` and `X = L` the images extend `R̃` to the
//! line:
//!
//! `R̃(s) = R₀(s)` on `[0, L)`, `R̃(s) = e₀ L₀(-s)` on `[-L, 0)`,
//! `R̃(s - 2L) = e₀ e₁ R̃(s)`, and `L(X,t) = e₀ R̃(-X - ct)`,
//!
//! which satisfies both end conditions for all `t` (Graff, *Wave motion in elastic
//! solids*, §1.1; the method of images). Averages over `[x0, x1]` and the displacement
//! `u = ∫ v dt` need `J(a, b) = ∫_a^b R̃(s) ds`: `∫ R dx = J(x0 - ct, x1 - ct)`,
//! `∫ L dx = e₀ J(-x1 - ct, -x0 - ct)`, `∫_0^t R(X,s) ds = J(X - ct, X)/c`.
//!
//! `J` splits `[a, b]` at the multiples of `L` (where the image pieces meet and `R̃` may
//! jump) and integrates each piece of the initial formulas by 8-point Gauss–Legendre on
//! sub-intervals of at most `L/64`: exact for polynomials of degree 15, and for a formula
//! analytic on a piece the error is of order `(h/2)^16 f^(16)/16!` (below round-off for
//! `sin(k π X/L)` up to `k` of about 100); a formula with a kink or jump inside `(0, L)`
//! (`abs`, a step) is integrated to `O(h²)` on the sub-interval that holds it.
use crate::initial::InitialState;
use crate::Vector;

/// 8-point Gauss–Legendre nodes on `[-1, 1]` (positive half) and weights.
const GAUSS_NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GAUSS_WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// `∫_a^b f` by 8-point Gauss–Legendre on `pieces` equal sub-intervals.
pub(crate) fn gauss(a: f64, b: f64, pieces: usize, mut f: impl FnMut(f64) -> f64) -> f64 {
    let pieces = pieces.max(1);
    let h = (b - a) / pieces as f64;
    let mut sum = 0.0;
    for k in 0..pieces {
        let mid = a + (k as f64 + 0.5) * h;
        let half = 0.5 * h;
        for (x, w) in GAUSS_NODES.iter().zip(GAUSS_WEIGHTS) {
            sum += w * half * (f(mid - half * x) + f(mid + half * x));
        }
    }
    sum
}

/// The initial state's waves (module doc).
#[derive(Debug, Clone)]
pub struct InitialWaves {
    state: InitialState,
    length: f64,
    impedance: f64,
    /// `e₀`, `e₁`: +1 for a traction end, -1 for a velocity end.
    ends: [f64; 2],
}

impl InitialWaves {
    /// The waves of `state` (read along `X` at `Y = 0`) on a bar of `length` and
    /// `impedance` with end signs `ends` (module doc).
    pub fn new(state: InitialState, length: f64, impedance: f64, ends: [f64; 2]) -> Self {
        Self {
            state,
            length,
            impedance,
            ends,
        }
    }

    /// `(v₀(X), σ₀(X))` on `[0, L]`.
    pub fn at_start(&self, x: f64) -> (f64, f64) {
        let at = Vector::<1>::new(x);
        (
            self.state.velocity::<1>(&at)[0],
            self.state.stress::<1>(&at)[(0, 0)],
        )
    }

    /// `R₀` (`right`) or `L₀` at `X` in `[0, L]`.
    fn invariant(&self, x: f64, right: bool) -> f64 {
        let (v, s) = self.at_start(x);
        if right {
            v - s / self.impedance
        } else {
            v + s / self.impedance
        }
    }

    /// Image block of `s`: `s = s' + 2kL` with `s'` in `[-L, L)`; returns `(s', sign)`,
    /// `sign = (e₀ e₁)^k`.
    fn reduce(&self, s: f64) -> (f64, f64) {
        let period = 2.0 * self.length;
        let k = ((s + self.length) / period).floor();
        let base = s - k * period;
        let sign = if (k as i64).rem_euclid(2) == 0 {
            1.0
        } else {
            self.ends[0] * self.ends[1]
        };
        (base, sign)
    }

    /// `R̃(s)`.
    fn extended(&self, s: f64) -> f64 {
        let (base, sign) = self.reduce(s);
        if base >= 0.0 {
            sign * self.invariant(base.min(self.length), true)
        } else {
            sign * self.ends[0] * self.invariant((-base).min(self.length), false)
        }
    }

    /// `J(a, b) = ∫_a^b R̃` (module doc).
    fn integral(&self, a: f64, b: f64) -> f64 {
        if b < a {
            return -self.integral(b, a);
        }
        let l = self.length;
        let mut total = 0.0;
        let mut lo = a;
        while lo < b {
            // the next multiple of L: the pieces of R̃ meet there
            let mut hi = ((lo / l).floor() + 1.0) * l;
            if hi <= lo {
                hi = lo + l;
            }
            let hi = hi.min(b);
            if hi > lo {
                // one piece: evaluate at its middle to find which, then integrate
                let mid = 0.5 * (lo + hi);
                let (base_mid, sign) = self.reduce(mid);
                let shift = base_mid - mid;
                let right = base_mid >= 0.0;
                let pieces = ((hi - lo) / (l / 64.0)).ceil() as usize;
                let f = |s: f64| {
                    let base = (s + shift).clamp(-l, l);
                    if right {
                        self.invariant(base.max(0.0), true)
                    } else {
                        self.ends[0] * self.invariant((-base).max(0.0), false)
                    }
                };
                total += sign * gauss(lo, hi, pieces, f);
            }
            lo = hi;
        }
        total
    }

    /// `(v, σ)` at `X`, `t`.
    pub fn point(&self, x: f64, t: f64, speed: f64) -> (f64, f64) {
        let r = self.extended(x - speed * t);
        let left = self.ends[0] * self.extended(-x - speed * t);
        (0.5 * (r + left), 0.5 * self.impedance * (left - r))
    }

    /// Averages of `(v, σ)` over `[x0, x1]` at `t`.
    pub fn average(&self, x0: f64, x1: f64, t: f64, speed: f64) -> (f64, f64) {
        let ct = speed * t;
        let r = self.integral(x0 - ct, x1 - ct);
        let left = self.ends[0] * self.integral(-x1 - ct, -x0 - ct);
        let len = x1 - x0;
        (
            0.5 * (r + left) / len,
            0.5 * self.impedance * (left - r) / len,
        )
    }

    /// `(∫_0^t v(X,s) ds, ∫_0^t σ(X,s) ds)`: the displacement and the stress impulse.
    pub fn time_integrals(&self, x: f64, t: f64, speed: f64) -> (f64, f64) {
        let ct = speed * t;
        let r = self.integral(x - ct, x) / speed;
        let left = self.ends[0] * self.integral(-x - ct, -x) / speed;
        (0.5 * (r + left), 0.5 * self.impedance * (left - r))
    }

    /// Energy per unit area at `t = 0`, `∫_0^L ½ρ v₀² + σ₀²/(2M) dX` (Gauss–Legendre as
    /// `J`), with `ρ = Z/c`, `M = Z c`.
    pub fn energy(&self, speed: f64) -> f64 {
        let (rho, modulus) = (self.impedance / speed, self.impedance * speed);
        gauss(0.0, self.length, 64, |x| {
            let (v, s) = self.at_start(x);
            0.5 * rho * v * v + 0.5 * s * s / modulus
        })
    }

    /// Largest of `|σ₀|` and `Z |v₀|` at the quadrature nodes: the state's stress scale.
    pub fn stress_scale(&self) -> f64 {
        let mut peak = 0.0f64;
        gauss(0.0, self.length, 64, |x| {
            let (v, s) = self.at_start(x);
            peak = peak.max(s.abs()).max(self.impedance * v.abs());
            0.0
        });
        peak
    }
}

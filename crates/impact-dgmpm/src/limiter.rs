//! Wave limiters of the second-order corrections (LeVeque 2002, §6.9 and §6.12, table 6.1;
//! Clawpack classic `limiter.f`, whose formulas and θ these are, term for term).
//!
//! Each wave `W^p` of a face is replaced by `W̃^p = φ(θ^p) W^p` with
//!
//! `θ^p = (W^p_upwind · W^p) / (W^p · W^p)`,
//!
//! `W^p_upwind` the wave of the same family on the upwind neighbour face (the face behind
//! it, `i − 1` for `s^p > 0`, `i + 1` otherwise), both unlimited; the dot product runs over
//! every component of the conserved vector, as in Clawpack. A face's wave of zero norm is
//! left as it is (it corrects nothing). The limiter functions (`θ` real):
//!
//! - none (Lax-Wendroff): `φ = 1`;
//! - minmod: `φ = max(0, min(1, θ))`;
//! - superbee: `φ = max(0, min(1, 2θ), min(2, θ))`;
//! - van Leer: `φ = (θ + |θ|)/(1 + |θ|)`;
//! - MC (monotonized centred): `φ = max(0, min((1 + θ)/2, 2, 2θ))`.
//!
//! All but `none` lie in the TVD region of Sweby (LeVeque 2002, eq. 6.44): `φ = 0` for
//! `θ ≤ 0`, `φ ≤ min(2θ, 2)`.
use crate::riemann::Conserved;
use impact_core::method::WaveLimiter;

/// `φ(θ)` of `limiter` (module doc).
#[inline]
pub fn limiter_phi(limiter: WaveLimiter, theta: f64) -> f64 {
    match limiter {
        WaveLimiter::None => 1.0,
        WaveLimiter::Minmod => theta.clamp(0.0, 1.0),
        WaveLimiter::Superbee => 0.0f64.max((2.0 * theta).min(1.0)).max(theta.min(2.0)),
        WaveLimiter::VanLeer => (theta + theta.abs()) / (1.0 + theta.abs()),
        WaveLimiter::Mc => {
            let centred = 0.5 * (1.0 + theta);
            0.0f64.max(centred.min(2.0).min(2.0 * theta))
        }
    }
}

/// `a · b` over every component (tensor and momentum parts).
#[inline]
pub fn wave_dot<const D: usize>(a: &Conserved<D>, b: &Conserved<D>) -> f64 {
    a.tensor.dot(&b.tensor) + a.momentum.dot(&b.momentum)
}

/// `θ = (W_upwind · W)/(W · W)` (module doc); `None` for a wave of zero norm.
#[inline]
pub fn wave_ratio<const D: usize>(upwind: &Conserved<D>, wave: &Conserved<D>) -> Option<f64> {
    let norm2 = wave_dot(wave, wave);
    (norm2 != 0.0).then(|| wave_dot(upwind, wave) / norm2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_core::{Tensor, Vector};

    /// Hand-worked values of each limiter (LeVeque 2002, table 6.1 and fig. 6.6).
    #[test]
    fn limiters_at_hand_worked_ratios() {
        use WaveLimiter::*;
        // (θ, none, minmod, superbee, vanleer, mc)
        let rows: [(f64, [f64; 5]); 8] = [
            (-1.0, [1.0, 0.0, 0.0, 0.0, 0.0]),
            (0.0, [1.0, 0.0, 0.0, 0.0, 0.0]),
            (0.25, [1.0, 0.25, 0.5, 0.4, 0.5]),
            (0.5, [1.0, 0.5, 1.0, 2.0 / 3.0, 0.75]),
            (1.0, [1.0, 1.0, 1.0, 1.0, 1.0]),
            (1.5, [1.0, 1.0, 1.5, 1.2, 1.25]),
            (3.0, [1.0, 1.0, 2.0, 1.5, 2.0]),
            (100.0, [1.0, 1.0, 2.0, 200.0 / 101.0, 2.0]),
        ];
        for (theta, expected) in rows {
            for (limiter, phi) in [None, Minmod, Superbee, VanLeer, Mc]
                .into_iter()
                .zip(expected)
            {
                let got = limiter_phi(limiter, theta);
                assert!(
                    (got - phi).abs() < 1e-15,
                    "{limiter} at θ = {theta}: {got} vs {phi}"
                );
            }
        }
    }

    /// Every limiter but `none` is in Sweby's TVD region: `0 ≤ φ ≤ min(2θ, 2)`, 0 for θ ≤ 0,
    /// and second order where smooth: `φ(1) = 1`.
    #[test]
    fn limiters_lie_in_the_tvd_region() {
        for limiter in WaveLimiter::ALL
            .into_iter()
            .filter(|l| *l != WaveLimiter::None)
        {
            for k in -200..=400 {
                let theta = k as f64 * 0.05;
                let phi = limiter_phi(limiter, theta);
                assert!(phi >= 0.0 && phi <= (2.0 * theta).clamp(0.0, 2.0) + 1e-15);
            }
            assert_eq!(limiter_phi(limiter, 1.0), 1.0);
        }
    }

    /// θ of a wave against a multiple of itself is the multiple, over every component.
    #[test]
    fn ratio_of_parallel_waves_is_their_multiple() {
        let w = Conserved::<1> {
            tensor: Tensor::<1>::new(3.0e8),
            momentum: Vector::<1>::new(-4.0e4),
        };
        let up = Conserved::<1> {
            tensor: w.tensor * -0.5,
            momentum: w.momentum * -0.5,
        };
        assert!((wave_ratio(&up, &w).unwrap() + 0.5).abs() < 1e-15);
        assert_eq!(wave_ratio(&w, &Conserved::zeros()), Option::None);
    }
}

//! Numerics of Lamb's problem (`lamb.rs`): complete elliptic integrals by Carlson's
//! symmetric forms, adaptive Gauss–Kronrod quadrature with end-point smoothing, and a fixed
//! Gauss–Legendre rule for patch averages.
//!
//! - `R_F(x, y, z) = ½∫_0^∞ dt/√((t+x)(t+y)(t+z))` and
//!   `R_J(x, y, z, p) = (3/2)∫_0^∞ dt/((t+p)√((t+x)(t+y)(t+z)))` by Carlson's duplication
//!   (B. C. Carlson, "Numerical computation of real or complex elliptic integrals",
//!   Numer. Algorithms 10 (1995) 13–26, algorithms for `R_F`, `R_C`, `R_J` with `p > 0`);
//!   truncation error ≈ `tol⁶/4` with `tol = 10⁻³`, i.e. round-off.
//! - `K(m) = R_F(0, 1−m, 1)` and, in Kausel's convention (parameter with a plus sign),
//!   `Π̃(N | m) = ∫_0^{π/2} dθ / ((1 + N sin²θ)√(1 − m sin²θ))
//!   = R_F(0, 1−m, 1) − (N/3) R_J(0, 1−m, 1, 1+N)` for `N > −1`, `0 ≤ m < 1`
//!   (DLMF 19.25.1–2 with `n = −N`).
//! - Adaptive 7/15-point Gauss–Kronrod (QUADPACK's `qk15` nodes and weights) with the
//!   error estimate `|K15 − G7|`, on `σ = a + (b−a)(3u² − 2u³)`: `dσ/du = 6u(1−u)(b−a)`
//!   vanishes at both ends, so an end-point singularity `|σ − a|^{−1/2}` (the Rayleigh
//!   arrival of the step responses) becomes bounded and smooth, a logarithm `u log u`.

/// Convergence threshold of Carlson's duplication (error ≈ tol⁶/4 ≈ 2.5e-19).
const CARLSON_TOL: f64 = 1e-3;

/// `R_C(x, y) = ½∫_0^∞ dt/((t+y)√(t+x))`, `x ≥ 0`, `y > 0` (Carlson 1995).
fn carlson_rc(mut x: f64, mut y: f64) -> f64 {
    loop {
        let lambda = 2.0 * x.sqrt() * y.sqrt() + y;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        let mean = (x + 2.0 * y) / 3.0;
        let s = (y - mean) / mean;
        if s.abs() < CARLSON_TOL {
            return (1.0 + s * s * (0.3 + s * (1.0 / 7.0 + s * (0.375 + s * 9.0 / 22.0))))
                / mean.sqrt();
        }
    }
}

/// `R_F(x, y, z)`, `x, y, z ≥ 0`, at most one zero (Carlson 1995).
pub(crate) fn carlson_rf(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    loop {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        let mean = (x + y + z) / 3.0;
        let (dx, dy, dz) = ((mean - x) / mean, (mean - y) / mean, (mean - z) / mean);
        if dx.abs().max(dy.abs()).max(dz.abs()) < CARLSON_TOL {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                / mean.sqrt();
        }
    }
}

/// `R_J(x, y, z, p)`, `x, y, z ≥ 0` (at most one zero), `p > 0` (Carlson 1995).
pub(crate) fn carlson_rj(mut x: f64, mut y: f64, mut z: f64, mut p: f64) -> f64 {
    let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 3.0, 3.0 / 22.0, 3.0 / 26.0);
    let (c5, c6, c7, c8) = (0.75 * c3, 1.5 * c4, 0.5 * c2, 2.0 * c3);
    let (mut sum, mut factor) = (0.0, 1.0);
    loop {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        let alpha = (p * (sx + sy + sz) + sx * sy * sz).powi(2);
        let beta = p * (p + lambda).powi(2);
        sum += factor * carlson_rc(alpha, beta);
        factor *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        p = 0.25 * (p + lambda);
        let mean = 0.2 * (x + y + z + 2.0 * p);
        let (dx, dy, dz) = ((mean - x) / mean, (mean - y) / mean, (mean - z) / mean);
        let dp = (mean - p) / mean;
        if dx.abs().max(dy.abs()).max(dz.abs()).max(dp.abs()) < CARLSON_TOL {
            let ea = dx * (dy + dz) + dy * dz;
            let eb = dx * dy * dz;
            let ec = dp * dp;
            let ed = ea - 3.0 * ec;
            let ee = eb + 2.0 * dp * (ea - ec);
            let series = 1.0
                + ed * (-c1 + c5 * ed - c6 * ee)
                + eb * (c7 + dp * (-c8 + dp * c4))
                + dp * ea * (c2 - dp * c3)
                - c2 * dp * ec;
            return 3.0 * sum + factor * series / (mean * mean.sqrt());
        }
    }
}

/// `K(m) = ∫_0^{π/2} dθ/√(1 − m sin²θ)`, `0 ≤ m < 1`.
pub(crate) fn elliptic_k(m: f64) -> f64 {
    carlson_rf(0.0, 1.0 - m, 1.0)
}

/// `Π̃(N | m) = ∫_0^{π/2} dθ/((1 + N sin²θ)√(1 − m sin²θ))`, `N > −1`, `0 ≤ m < 1`
/// (module doc).
pub(crate) fn elliptic_pi_plus(n: f64, m: f64) -> f64 {
    carlson_rf(0.0, 1.0 - m, 1.0) - n / 3.0 * carlson_rj(0.0, 1.0 - m, 1.0, 1.0 + n)
}

/// QUADPACK `qk15`: Kronrod nodes (descending, the last is 0) and weights.
const KRONROD_NODES: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const KRONROD_WEIGHTS: [f64; 8] = [
    0.022_935_322_010_529_225,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];
/// 7-point Gauss weights on the odd Kronrod nodes (1, 3, 5, 7).
const GAUSS7_WEIGHTS: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// `(K15, |K15 − G7|)` on `[a, b]`.
fn kronrod(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let centre = f(mid);
    let (mut k, mut g) = (KRONROD_WEIGHTS[7] * centre, GAUSS7_WEIGHTS[3] * centre);
    for j in 0..7 {
        let pair = f(mid - half * KRONROD_NODES[j]) + f(mid + half * KRONROD_NODES[j]);
        k += KRONROD_WEIGHTS[j] * pair;
        if j % 2 == 1 {
            g += GAUSS7_WEIGHTS[j / 2] * pair;
        }
    }
    (k * half, ((k - g) * half).abs())
}

/// `∫_a^b f` by global adaptive bisection (QUADPACK `qag`): the piece with the largest
/// `|K15 − G7|` is halved until the sum of the estimates is at most `tol`, or at most 400
/// pieces (the estimate then at round-off).
pub(crate) fn adaptive(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let (value, error) = kronrod(f, a, b);
    let mut pieces = vec![(a, b, value, error)];
    while pieces.len() < 400 {
        let total: f64 = pieces.iter().map(|p| p.3).sum();
        if total <= tol {
            break;
        }
        let worst = (0..pieces.len())
            .max_by(|&i, &j| pieces[i].3.total_cmp(&pieces[j].3))
            .unwrap_or(0);
        let (lo, hi, _, _) = pieces[worst];
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break; // the piece cannot be halved in floating point
        }
        let (left, left_error) = kronrod(f, lo, mid);
        let (right, right_error) = kronrod(f, mid, hi);
        pieces[worst] = (lo, mid, left, left_error);
        pieces.push((mid, hi, right, right_error));
    }
    pieces.iter().map(|p| p.2).sum()
}

/// `∫_a^b f` on `σ = a + (b−a)(3u² − 2u³)` (module doc): integrable end-point
/// singularities `|σ − a|^{−1/2}`, `|b − σ|^{−1/2}` and logarithms allowed.
pub(crate) fn adaptive_smoothed(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let width = b - a;
    let mut g = |u: f64| {
        let sigma = a + width * u * u * (3.0 - 2.0 * u);
        f(sigma.clamp(a, b)) * 6.0 * u * (1.0 - u) * width
    };
    adaptive(&mut g, 0.0, 1.0, tol)
}

/// 6-point Gauss–Legendre nodes and weights on `[−1, 1]` (exact to degree 11).
pub(crate) const GAUSS6: [(f64, f64); 6] = [
    (-0.932_469_514_203_152, 0.171_324_492_379_170_35),
    (-0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (-0.238_619_186_083_196_9, 0.467_913_934_572_691),
    (0.238_619_186_083_196_9, 0.467_913_934_572_691),
    (0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (0.932_469_514_203_152, 0.171_324_492_379_170_35),
];

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The Kronrod rule integrates `x^k` exactly up to degree 22, Gauss–Legendre (6) up to 11.
    #[test]
    fn rules_are_exact_for_polynomials() {
        for k in 0..=22 {
            let (value, _) = kronrod(&mut |x: f64| x.powi(k), 0.0, 1.0);
            let exact = 1.0 / (k as f64 + 1.0);
            assert!((value - exact).abs() < 1e-15, "x^{k}: {value}");
        }
        for k in 0..=11 {
            let value: f64 = GAUSS6.iter().map(|&(x, w)| w * x.powi(k)).sum();
            let exact = if k % 2 == 0 {
                2.0 / (k as f64 + 1.0)
            } else {
                0.0
            };
            assert!((value - exact).abs() < 1e-14, "x^{k}: {value}");
        }
    }

    /// End-point singularities: `∫_0^1 x^{−1/2} = ∫_0^1 (1−x)^{−1/2} = 2`,
    /// `∫_0^1 log x = −1`.
    #[test]
    fn smoothing_handles_inverse_square_roots_and_logs() {
        let v = adaptive_smoothed(&mut |x: f64| 1.0 / x.sqrt(), 0.0, 1.0, 1e-13);
        assert!((v - 2.0).abs() < 1e-11, "{v}");
        let v = adaptive_smoothed(&mut |x: f64| 1.0 / (1.0 - x).sqrt(), 0.0, 1.0, 1e-13);
        assert!((v - 2.0).abs() < 1e-11, "{v}");
        let v = adaptive_smoothed(&mut |x: f64| x.ln(), 0.0, 1.0, 1e-13);
        assert!((v + 1.0).abs() < 1e-11, "{v}");
    }

    /// `K` and `Π̃` against their defining integrals (the integrand is smooth in θ), and
    /// `Π̃(N | 0) = π/(2√(1+N))`.
    #[test]
    fn elliptic_integrals_match_their_definitions() {
        for &m in &[0.0, 0.1, 0.5, 0.78, 0.95, 0.999] {
            let k = adaptive(
                &mut |t: f64| 1.0 / (1.0 - m * t.sin().powi(2)).sqrt(),
                0.0,
                0.5 * PI,
                1e-14,
            );
            assert!((elliptic_k(m) - k).abs() < 1e-13 * k, "K({m})");
            for &n in &[-0.9, -0.78, 0.0, 0.5, 8.0, 40.8] {
                let pi = adaptive(
                    &mut |t: f64| {
                        let s = t.sin().powi(2);
                        1.0 / ((1.0 + n * s) * (1.0 - m * s).sqrt())
                    },
                    0.0,
                    0.5 * PI,
                    1e-14,
                );
                let value = elliptic_pi_plus(n, m);
                assert!((value - pi).abs() < 1e-12 * pi, "Π({n}|{m}) {value} {pi}");
            }
        }
        let n = 3.0_f64;
        assert!((elliptic_pi_plus(n, 0.0) - 0.5 * PI / (1.0 + n).sqrt()).abs() < 1e-15);
    }
}

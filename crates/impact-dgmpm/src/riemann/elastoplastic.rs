//! The exact elastoplastic Riemann solver of the rod (uniaxial stress, J2 with linear
//! isotropic hardening; Wang 2011, ch. 3 and 5; the wave-curve construction of Heuzé 2017,
//! §3, for the elastic-plastic face problem).
//!
//! **Derivation.** Across a wave of speed `s` the jumps obey `ρ s [v] = −[σ]`. A state
//! `(σ, v)` with current yield `Y = σ_y + H ε̄` connects to the star state through a
//! left-going (`s < 0`) or right-going (`s > 0`) wave. While `|σ| ≤ Y` the material is
//! elastic and the wave is an elastic shock of impedance `Z_0 = ρ c_0`; loading beyond
//! `±Y` splits it into the elastic precursor up to `±Y` followed by a plastic shock of
//! impedance `Z_t = ρ c_t`, `c_t = sqrt(E_t/ρ)`, `E_t = E H/(E + H)` (the tangent is
//! constant, so the plastic part is a shock, not a fan). Unloading is elastic. So the
//! left state's wave curve is the piecewise-linear, increasing
//!
//! `σ_L(v) = σ_L + Z_0 (v − v_L)` while `|σ_L(v)| ≤ Y_L`, and beyond it
//! `σ_L(v) = ±Y_L + Z_t (v − v_±)`, `v_± = v_L + (±Y_L − σ_L)/Z_0`,
//!
//! (a left state already at `±Y_L` loads plastically at once), and the right state's is the
//! decreasing mirror `σ_R(v) = σ_R − Z_0 (v − v_R)`, plastic beyond `±Y_R` with slope
//! `−Z_t`. The star state is their unique intersection: `g(v) = σ_L(v) − σ_R(v)` is
//! continuous, piecewise linear and strictly increasing, so it is found exactly from the
//! sorted breakpoints (at most four) and one linear solve. With `Y → ∞` it is the linear
//! solver's star state. The boundary half problems solve `σ_L(v*) = t` (traction) or take
//! `σ* = σ_L(v_d)` (velocity) on the interior's curve, oriented by the outward normal.
//!
//! Stress is positive in tension; `σ` is the face traction along `+x`.

/// A side of the face problem: normal stress, normal velocity and the elastic range of the
/// normal stress, `[lower, upper]` (the rod: `[−Y, Y]`, `Y = σ_y + H ε̄`; plane strain:
/// where the uniaxial-strain path from the state meets the yield surface,
/// [`uniaxial_strain_bounds`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlasticSide {
    /// `σ`.
    pub stress: f64,
    /// `v`.
    pub velocity: f64,
    /// Lowest normal stress reached elastically (compression side, ≤ `stress`).
    pub lower: f64,
    /// Highest normal stress reached elastically (tension side, ≥ `stress`).
    pub upper: f64,
}

impl PlasticSide {
    /// A rod state with current yield stress `yield_stress`: the range `[−Y, Y]`.
    pub fn rod(stress: f64, velocity: f64, yield_stress: f64) -> Self {
        Self {
            stress,
            velocity,
            lower: -yield_stress,
            upper: yield_stress,
        }
    }
}

/// The elastic range of the normal stress `σ_nn` of a 3D stress state `stress` loaded in
/// uniaxial strain along `n` (plane strain: `n` in the plane), for the current yield `y`,
/// `lame = (λ, μ)`. Along the path `Δσ = Δε (λ 1 + 2μ n⊗n)` the deviator moves by
/// `2μ Δε N`, `N = n⊗n − 1/3` (`|N|² = 2/3`), so `q² = 3/2 |s + 2μΔε N|² = y²` is the
/// quadratic `4μ² Δε² + 6μ (s:N) Δε + (3/2 |s|² − y²) = 0`; its roots bound the elastic
/// strains and `σ_nn ± = σ_nn + (λ + 2μ) Δε±`. A state on the surface to round-off (`q² − y²`
/// within `1e-12 y²`: where a return leaves it) is taken on it (one bound at its own
/// stress, the other across the elastic range); one further outside gets an empty range at
/// its own stress. At rest the bounds are the Hugoniot
/// elastic limit `± y (λ + 2μ)/(2μ)`.
pub fn uniaxial_strain_bounds(
    stress: &impact_core::plasticity::Tensor3,
    n: &nalgebra::Vector3<f64>,
    y: f64,
    lame: (f64, f64),
) -> (f64, f64) {
    let (lambda, mu) = lame;
    let p = stress.trace() / 3.0;
    let s = stress - impact_core::plasticity::Tensor3::identity() * p;
    let nn = n * n.transpose() - impact_core::plasticity::Tensor3::identity() / 3.0;
    let a = 4.0 * mu * mu;
    let b = 6.0 * mu * s.dot(&nn);
    // a state on the surface to round-off (the return map leaves `q = y` within a few ulps,
    // on either side) is on it: loading is plastic at once, unloading elastic
    let c = match 1.5 * s.norm_squared() - y * y {
        c if c > 0.0 && c <= ON_SURFACE * y * y => 0.0,
        c => c,
    };
    let normal = n.dot(&(stress * n));
    let discriminant = b * b - 4.0 * a * c;
    if c > 0.0 || discriminant < 0.0 {
        return (normal, normal);
    }
    let root = discriminant.sqrt();
    let (low, high) = ((-b - root) / (2.0 * a), (-b + root) / (2.0 * a));
    let modulus = lambda + 2.0 * mu;
    (normal + modulus * low, normal + modulus * high)
}

/// Relative tolerance on `q² − y²` within which [`uniaxial_strain_bounds`] takes a state for
/// one on the yield surface.
const ON_SURFACE: f64 = 1e-12;

/// Impedances `Z_0 = ρ c_0` and `Z_t = ρ c_t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodImpedances {
    /// Elastic.
    pub elastic: f64,
    /// Plastic (tangent).
    pub plastic: f64,
}

/// `σ` on the wave curve of `side` at velocity `v`; `direction` is `+1` for the left
/// state's (left-going wave, increasing in `v`) and `−1` for the right state's.
#[inline]
fn curve(side: &PlasticSide, z: RodImpedances, direction: f64, v: f64) -> f64 {
    let elastic = side.stress + direction * z.elastic * (v - side.velocity);
    if elastic >= side.lower && elastic <= side.upper {
        return elastic;
    }
    let bound = if elastic > side.upper {
        side.upper
    } else {
        side.lower
    };
    // the velocity at which the elastic part reaches the bound (the state itself when it
    // is already there: plastic at once)
    let reach = side.velocity + direction * (bound - side.stress) / z.elastic;
    bound + direction * z.plastic * (v - reach)
}

/// The velocities where the side's curve changes slope.
fn breakpoints(side: &PlasticSide, z: RodImpedances, direction: f64) -> [f64; 2] {
    [side.upper, side.lower]
        .map(|bound| side.velocity + direction * (bound - side.stress) / z.elastic)
}

/// Star state `(σ*, v*)` of the face between `left` and `right` (module doc).
pub fn elastoplastic_star_1d(
    left: &PlasticSide,
    right: &PlasticSide,
    z: RodImpedances,
) -> (f64, f64) {
    let g = |v: f64| curve(left, z, 1.0, v) - curve(right, z, -1.0, v);
    let mut points = [0.0; 4];
    points[..2].copy_from_slice(&breakpoints(left, z, 1.0));
    points[2..].copy_from_slice(&breakpoints(right, z, -1.0));
    points.sort_by(f64::total_cmp);
    // bracket the root between consecutive breakpoints (or beyond the outer ones), where
    // g is linear
    let solve_on = |a: f64, b: f64| {
        let (ga, gb) = (g(a), g(b));
        a - ga * (b - a) / (gb - ga)
    };
    let mut v = None;
    if g(points[0]) >= 0.0 {
        v = Some(solve_on(points[0] - 1.0, points[0]));
    }
    for pair in points.windows(2) {
        if v.is_none() && g(pair[1]) >= 0.0 && pair[1] > pair[0] {
            v = Some(solve_on(pair[0], pair[1]));
        }
    }
    let v = v.unwrap_or_else(|| solve_on(points[3], points[3] + 1.0));
    (0.5 * (curve(left, z, 1.0, v) + curve(right, z, -1.0, v)), v)
}

/// A boundary condition of the half problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RodBoundary {
    /// Prescribed traction along the outward normal, `σ n_out = t`.
    Traction(f64),
    /// Prescribed velocity along the outward normal, `v n_out = v_d`.
    Velocity(f64),
}

/// Star state `(σ*, v*)` at a boundary face with the outward normal `outward` (±1) and the
/// interior state `interior` (module doc).
pub fn elastoplastic_boundary_1d(
    interior: &PlasticSide,
    outward: f64,
    condition: RodBoundary,
    z: RodImpedances,
) -> (f64, f64) {
    // the interior is on the left of a right boundary (its wave goes left: increasing
    // curve), on the right of a left boundary (decreasing curve)
    let direction = outward;
    match condition {
        RodBoundary::Velocity(v_out) => {
            let v = v_out * outward;
            (curve(interior, z, direction, v), v)
        }
        RodBoundary::Traction(t_out) => {
            let sigma = t_out * outward;
            // invert the monotone curve: bracket by its breakpoints, then solve linearly
            let h = |v: f64| direction * (curve(interior, z, direction, v) - sigma);
            let mut points = breakpoints(interior, z, direction);
            points.sort_by(f64::total_cmp);
            let solve_on = |a: f64, b: f64| a - h(a) * (b - a) / (h(b) - h(a));
            let v = if h(points[0]) >= 0.0 {
                solve_on(points[0] - 1.0, points[0])
            } else if h(points[1]) >= 0.0 {
                solve_on(points[0], points[1])
            } else {
                solve_on(points[1], points[1] + 1.0)
            };
            (sigma, v)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const RHO: f64 = 7800.0;
    const E: f64 = 2e11;
    const H: f64 = 2e10;

    fn z() -> RodImpedances {
        let et = E * H / (E + H);
        RodImpedances {
            elastic: (RHO * E).sqrt(),
            plastic: (RHO * et).sqrt(),
        }
    }

    fn side(stress: f64, velocity: f64) -> PlasticSide {
        PlasticSide::rod(stress, velocity, 4e8)
    }

    /// Elastic only: the linear solver's star state.
    #[test]
    fn elastic_states_give_the_linear_star() {
        let (l, r) = (side(1e8, 2.0), side(-5e7, -1.0));
        let (s, v) = elastoplastic_star_1d(&l, &r, z());
        let z0 = z().elastic;
        assert_relative_eq!(
            v,
            0.5 * (2.0 - 1.0) + (-5e7 - 1e8) / (2.0 * z0),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            s,
            0.5 * (1e8 - 5e7) + 0.5 * z0 * (-1.0 - 2.0),
            max_relative = 1e-12
        );
        assert!(s.abs() < 4e8);
    }

    /// Equal states: the star state is the state itself, elastic or at yield.
    #[test]
    fn equal_states_are_their_own_star() {
        for st in [side(0.0, 0.0), side(-4e8, 3.0), side(2e8, -1.0)] {
            let (s, v) = elastoplastic_star_1d(&st, &st, z());
            assert_relative_eq!(s, st.stress, epsilon = 1e-6);
            assert_relative_eq!(v, st.velocity, epsilon = 1e-12);
        }
    }

    /// Plastic on one side: a compressive state at yield on the left (`Y = 4e8`) closing at
    /// 20 m/s on a hardened state at rest (`Y = 8e8`) on the right. Hand-worked: the left
    /// wave loads plastically at once (`σ = −Y + Z_t (v − 20)`), the right one stays
    /// elastic (`σ = −Z_0 v`), so `v* = (Y + 20 Z_t)/(Z_t + Z_0)` and `|σ*| < 8e8`.
    #[test]
    fn plastic_on_one_side() {
        let (zz, l) = (z(), side(-4e8, 20.0));
        let r = PlasticSide::rod(0.0, 0.0, 8e8);
        let (s, v) = elastoplastic_star_1d(&l, &r, zz);
        let v_hand = (4e8 + zz.plastic * 20.0) / (zz.plastic + zz.elastic);
        assert!(v_hand < 20.0 && zz.elastic * v_hand < 8e8);
        assert_relative_eq!(v, v_hand, max_relative = 1e-12);
        assert_relative_eq!(s, -zz.elastic * v_hand, max_relative = 1e-12);
    }

    /// Plastic on both sides: two rest states hit each other at ±V (symmetric impact):
    /// `v* = 0`, and `σ* = −Y − Z_t (V − Y/Z_0)` when `V > Y/Z_0`.
    #[test]
    fn plastic_on_both_sides() {
        let zz = z();
        let speed = 60.0;
        let (s, v) = elastoplastic_star_1d(&side(0.0, speed), &side(0.0, -speed), zz);
        assert!(v.abs() < 1e-12);
        let expected = -4e8 - zz.plastic * (speed - 4e8 / zz.elastic);
        assert_relative_eq!(s, expected, max_relative = 1e-12);
    }

    /// At rest the uniaxial-strain range is the Hugoniot elastic limit; a state already
    /// compressed to it has no room left on the compression side.
    #[test]
    fn uniaxial_strain_bounds_at_rest_are_the_hugoniot_elastic_limit() {
        use impact_core::plasticity::Tensor3;
        let (lambda, mu) = (1.1538e11, 7.6923e10);
        let n = nalgebra::Vector3::new(1.0, 0.0, 0.0);
        let hel = 4e8 * (lambda + 2.0 * mu) / (2.0 * mu);
        let (lo, hi) = uniaxial_strain_bounds(&Tensor3::zeros(), &n, 4e8, (lambda, mu));
        assert_relative_eq!(lo, -hel, max_relative = 1e-12);
        assert_relative_eq!(hi, hel, max_relative = 1e-12);
        // the state at −HEL in uniaxial strain: σ_yy = σ_zz = λ/(λ+2μ) σ_xx
        let mut at = Tensor3::zeros();
        at[(0, 0)] = -hel;
        at[(1, 1)] = -hel * lambda / (lambda + 2.0 * mu);
        at[(2, 2)] = at[(1, 1)];
        let (lo, hi) = uniaxial_strain_bounds(&at, &n, 4e8, (lambda, mu));
        assert_relative_eq!(lo, -hel, max_relative = 1e-9);
        assert_relative_eq!(hi, hel, max_relative = 1e-9);
    }

    /// As a boundary half problem on the rod at rest: a pressure p > σ_y gives the exact
    /// solution's state behind the plastic wave, `v = σ_y/Z_0 + (p − σ_y)/Z_t`; a velocity
    /// gives back the stress that reaches it; below yield, the elastic values.
    #[test]
    fn boundary_half_problems_give_the_exact_rod_states() {
        let zz = z();
        let rest = side(0.0, 0.0);
        let p = 8e8;
        // left end (outward −1): traction along the outward normal is −σ n... σ* = −p
        let (s, v) = elastoplastic_boundary_1d(&rest, -1.0, RodBoundary::Traction(p), zz);
        assert_relative_eq!(s, -p, max_relative = 1e-12);
        assert_relative_eq!(
            v,
            4e8 / zz.elastic + (p - 4e8) / zz.plastic,
            max_relative = 1e-12
        );
        let (s2, v2) = elastoplastic_boundary_1d(&rest, -1.0, RodBoundary::Velocity(-v), zz);
        assert_relative_eq!(s2, -p, max_relative = 1e-12);
        assert_relative_eq!(v2, v, max_relative = 1e-12);
        let (s3, v3) = elastoplastic_boundary_1d(&rest, -1.0, RodBoundary::Traction(1e8), zz);
        assert_relative_eq!(s3, -1e8, max_relative = 1e-12);
        assert_relative_eq!(v3, 1e8 / zz.elastic, max_relative = 1e-12);
        // right end (outward +1) pulled: tension p
        let (s4, v4) = elastoplastic_boundary_1d(&rest, 1.0, RodBoundary::Traction(p), zz);
        assert_relative_eq!(s4, p, max_relative = 1e-12);
        assert_relative_eq!(
            v4,
            4e8 / zz.elastic + (p - 4e8) / zz.plastic,
            max_relative = 1e-12
        );
    }
}

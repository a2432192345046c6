//! Tests of Lamb's problem (`lamb.rs`).
use super::lamb::{gamma, radial_elliptic, radial_kernel, vertical_kernel, Lamb, LambError};
use super::lamb_quadrature::adaptive_smoothed;
use crate::load::LoadHistory;
use crate::material::LinearElastic;
use std::f64::consts::PI;

/// Steel-like, `ν = 1/4`: `μ = 80 GPa`, `ρ = 7800`, `F = 1 kN`.
fn steel() -> Lamb {
    Lamb::from_material(&LinearElastic::new(200e9, 0.25, 7800.0), 1e3).unwrap()
}

/// `c_R` solves the Rayleigh equation `(2 − ξ)² = 4√(1 − ξ/3)√(1 − ξ)`, `ξ = c_R²/c_s²`,
/// is 0.9194 c_s, and the arrivals are `r/c`.
#[test]
fn rayleigh_speed_and_arrivals() {
    let gamma_r = gamma();
    let lamb = steel();
    let xi = (lamb.rayleigh_speed() / lamb.shear_speed()).powi(2);
    let residual = (2.0 - xi).powi(2) - 4.0 * (1.0 - xi / 3.0).sqrt() * (1.0 - xi).sqrt();
    assert!(residual.abs() < 1e-14, "{residual}");
    let ratio = lamb.rayleigh_speed() / lamb.shear_speed();
    assert!((ratio - 0.919_401_7).abs() < 1e-7, "{ratio}");
    assert!((lamb.pressure_speed() / lamb.shear_speed() - 3f64.sqrt()).abs() < 1e-15);
    assert!((lamb.shear_speed() - (80e9f64 / 7800.0).sqrt()).abs() < 1e-9);
    let a = lamb.arrivals(0.5).unwrap();
    assert!((a.s - 0.5 / lamb.shear_speed()).abs() < 1e-18);
    assert!((a.p * 3f64.sqrt() - a.s).abs() < 1e-18);
    assert!((a.rayleigh - gamma_r * a.s).abs() < 1e-13 * a.s);
    assert!((gamma_r - 1.087_663_873_580_6).abs() < 1e-13);
}

/// Nothing before the P arrival; both step responses start continuously from 0 at `τ_P`;
/// both are continuous at the S arrival (the two branches of each formula meet).
#[test]
fn step_responses_start_at_p_and_are_continuous_at_s() {
    let lamb = steel();
    let (r, arrival) = (0.3, lamb.arrivals(0.3).unwrap());
    for t in [-1.0, 0.0, 0.5 * arrival.p, arrival.p * (1.0 - 1e-12)] {
        assert_eq!(lamb.step_vertical(r, t).unwrap(), 0.0);
        assert_eq!(lamb.step_radial(r, t).unwrap(), 0.0);
    }
    let tau_p = 1.0 / 3f64.sqrt();
    for kernel in [vertical_kernel, radial_kernel] {
        assert!(kernel(tau_p * (1.0 + 1e-12)).abs() < 1e-6);
        let (below, above) = (kernel(1.0 - 1e-10), kernel(1.0 + 1e-10));
        assert!((below - above).abs() < 1e-6, "{below} {above}");
        assert!((kernel(1.0) - below).abs() < 1e-6);
    }
    // a push: the P wave moves the surface outward first, against the load vertically
    assert!(radial_kernel(0.7) > 0.0 && vertical_kernel(0.7) < 0.0);
}

/// Pekeris' closed form equals Kausel's partial fractions over the Rayleigh cubic's roots,
/// `w = (1−ν)/(2π) [½(1 − Σ A_i/√(τ²−x_i))]` (`x₃` term with `√(x₃−τ²)`), `A_i =
/// (x_i−½)²√|a²−x_i| / ∏(x_i−x_j)`: two derivations of the vertical step response.
#[test]
fn pekeris_vertical_matches_the_partial_fractions() {
    let gamma_r = gamma();
    let s3 = 3f64.sqrt();
    let x = [0.25, 0.25 * (3.0 - s3), 0.25 * (3.0 + s3)];
    let a2 = 1.0 / 3.0;
    // the roots solve the Rayleigh cubic
    for &xi in &x {
        assert!((4.0 * xi.powi(3) - 7.0 * xi * xi + 3.0 * xi - 0.375).abs() < 1e-14);
    }
    let coef = |i: usize| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        (x[i] - 0.5).powi(2) * (a2 - x[i]).abs().sqrt() / ((x[i] - x[j]) * (x[i] - x[k]))
    };
    let f = 0.75 / (2.0 * PI);
    for k in 1..200 {
        let tau = a2.sqrt() + (gamma_r - a2.sqrt()) * k as f64 / 200.0;
        let t2 = tau * tau;
        let kausel = if tau < 1.0 {
            0.5 * f
                * (1.0
                    - coef(0) / (t2 - x[0]).sqrt()
                    - coef(1) / (t2 - x[1]).sqrt()
                    - coef(2) / (x[2] - t2).sqrt())
        } else {
            f * (1.0 - coef(2) / (x[2] - t2).sqrt())
        };
        let pekeris = vertical_kernel(tau);
        assert!(
            (pekeris - kausel).abs() < 1e-13,
            "τ = {tau}: {pekeris} {kausel}"
        );
    }
}

/// The Rayleigh wave's two singular parts have the ratio of a Rayleigh wave's horizontal
/// to vertical surface amplitudes, `(1 + s² − 2qs)/(q(1 − s²))`, `q = √(1 − ξ/3)`,
/// `s = √(1 − ξ)` (0.6812 at `ν = 1/4`): the radial formula (Kausel) and the vertical one
/// (Pekeris) agree on the Rayleigh pole. The radial is finite before, the vertical after.
#[test]
fn rayleigh_singularities_have_the_rayleigh_ellipticity() {
    let gamma_r = gamma();
    let xi = 1.0 / (gamma_r * gamma_r);
    let (q, s) = ((1.0 - xi / 3.0).sqrt(), (1.0 - xi).sqrt());
    let ellipticity = (1.0 + s * s - 2.0 * q * s) / (q * (1.0 - s * s));
    assert!((ellipticity - 0.6812).abs() < 1e-4);
    let d = 1e-12;
    let vertical =
        vertical_kernel(gamma_r - d) * (gamma_r * gamma_r - (gamma_r - d).powi(2)).sqrt();
    let radial = radial_kernel(gamma_r + d) * ((gamma_r + d).powi(2) - gamma_r * gamma_r).sqrt();
    assert!(
        (radial / vertical - ellipticity).abs() < 1e-5,
        "{}",
        radial / vertical
    );
    assert!(radial_kernel(gamma_r - 1e-9).abs() < 1.0 && radial_kernel(gamma_r).is_finite());
    assert_eq!(vertical_kernel(gamma_r), 3.0 / (8.0 * PI));
}

/// After the Rayleigh arrival the step responses reach Boussinesq: `w = 3F/(8πμr)` at
/// once, `u_r → −F/(8πμr)` like `τ/√(τ²−γ²)`.
#[test]
fn step_responses_reach_boussinesq() {
    let lamb = steel();
    let r = 0.2;
    let t_r = lamb.arrivals(r).unwrap().rayleigh;
    let (w, u) = (
        lamb.static_vertical(r).unwrap(),
        lamb.static_radial(r).unwrap(),
    );
    assert!((w - 3e3 / (8.0 * PI * 80e9 * r)).abs() < 1e-12 * w);
    assert!((u + 1e3 / (8.0 * PI * 80e9 * r)).abs() < 1e-12 * w);
    assert_eq!(lamb.step_vertical(r, 1.01 * t_r).unwrap(), w);
    let late = lamb.step_radial(r, 1000.0 * t_r).unwrap();
    assert!((late / u - 1.0).abs() < 1e-6, "{late} {u}");
}

/// Duhamel under a smooth ramp: zero before `t_P`; once the ramp's end has passed with the
/// Rayleigh wave the vertical is Boussinesq's exactly and the radial within `O(τ⁻²)`;
/// linear in `F` and odd in its sign.
#[test]
fn smooth_ramp_reaches_the_static_solution() {
    let lamb = steel();
    let r = 0.1;
    let a = lamb.arrivals(r).unwrap();
    let ramp = LoadHistory::SmoothRamp { rise: 2.0 * a.s };
    assert_eq!(lamb.vertical(r, 0.999 * a.p, &ramp).unwrap(), 0.0);
    assert_eq!(lamb.radial(r, 0.999 * a.p, &ramp).unwrap(), 0.0);
    let (w, u) = (
        lamb.static_vertical(r).unwrap(),
        lamb.static_radial(r).unwrap(),
    );
    let t = 2.0 * a.s + 1.5 * a.rayleigh;
    let v = lamb.vertical(r, t, &ramp).unwrap();
    assert!((v / w - 1.0).abs() < 1e-9, "{v} {w}");
    let t = 2.0 * a.s + 300.0 * a.rayleigh;
    let h = lamb.radial(r, t, &ramp).unwrap();
    assert!((h / u - 1.0).abs() < 1e-5, "{h} {u}");
    let double = Lamb::new(lamb.shear_modulus, lamb.density, -2.0 * lamb.force).unwrap();
    for t in [0.8 * a.s, 1.1 * a.rayleigh, 2.5 * a.s] {
        let v = lamb.vertical(r, t, &ramp).unwrap();
        assert!((double.vertical(r, t, &ramp).unwrap() + 2.0 * v).abs() < 1e-15 * w);
        let h = lamb.radial(r, t, &ramp).unwrap();
        assert!((double.radial(r, t, &ramp).unwrap() + 2.0 * h).abs() < 1e-15 * w);
    }
}

/// A slow ramp: `w(t) = U∞ g(t) − g'(t) M + O(g'' t_R²)` with the lag moment
/// `M = ∫_0^{t_R} (U∞ − U(σ)) dσ` (expanding `g(t−σ)` in Duhamel's integral).
#[test]
fn slow_ramp_follows_the_static_solution_with_its_lag() {
    let gamma_r = gamma();
    let lamb = steel();
    let r = 0.1;
    let a = lamb.arrivals(r).unwrap();
    let rise = 2000.0 * a.rayleigh;
    let ramp = LoadHistory::SmoothRamp { rise };
    let w = lamb.static_vertical(r).unwrap();
    let speed = lamb.shear_speed();
    let mut lag = |tau: f64| w - lamb.step_vertical(r, tau * r / speed).unwrap();
    let moment = r / speed * adaptive_smoothed(&mut lag, 0.0, 1.0 / 3f64.sqrt(), 1e-20)
        + r / speed * adaptive_smoothed(&mut lag, 1.0 / 3f64.sqrt(), 1.0, 1e-20)
        + r / speed * adaptive_smoothed(&mut lag, 1.0, gamma_r, 1e-20);
    for t in [0.3 * rise, 0.5 * rise, 0.8 * rise] {
        let expected = w * ramp.factor(t) - ramp.rate(t) * moment;
        let v = lamb.vertical(r, t, &ramp).unwrap();
        assert!((v - expected).abs() < 1e-6 * w, "t = {t}: {v} {expected}");
        // the lag is resolved: dropping it misses by more than the tolerance
        assert!((v - w * ramp.factor(t)).abs() > 1e-4 * w);
    }
}

/// The square patch: statically `⟨1/ρ⟩ = (1/r)(1 + h²/(6r²) + O(h⁴/r⁴))`, so the patch
/// of side `a = 2h` at `r = 10a` is `+4.2e-4` above the point load; the radial differs at
/// `O((a/r)⁴)` only. Under a ramp over `2r/c_s` the dynamic difference stays below 1e-3 of
/// the peak.
#[test]
fn patch_average_differs_from_the_point_load_at_second_order() {
    let lamb = steel();
    let (r, half) = (0.2, 0.01);
    let a = lamb.arrivals(r + half * 2f64.sqrt()).unwrap();
    let ramp = LoadHistory::SmoothRamp {
        rise: 2.0 * r / lamb.shear_speed(),
    };
    let late = 2.0 * r / lamb.shear_speed() + 1.01 * a.rayleigh;
    let point = lamb.vertical(r, late, &ramp).unwrap();
    let patch = lamb.patch_vertical(r, late, &ramp, half).unwrap();
    let predicted = 1.0 + half * half / (6.0 * r * r);
    assert!(
        (patch / point - predicted).abs() < 1e-5,
        "{}",
        patch / point - 1.0
    );
    let static_r = lamb.static_radial(r).unwrap();
    // the largest difference over the history, relative to the point load's peak
    let dynamic = |half: f64| {
        let (mut peak, mut worst) = (0.0f64, 0.0f64);
        for k in 1..=40 {
            let t = late * k as f64 / 40.0;
            let point = lamb.vertical(r, t, &ramp).unwrap();
            let patch = lamb.patch_vertical(r, t, &ramp, half).unwrap();
            peak = peak.max(point.abs());
            worst = worst.max((patch - point).abs());
        }
        worst / peak
    };
    let (coarse, fine) = (dynamic(half), dynamic(0.5 * half));
    println!("dynamic patch difference: {coarse:e} at r = 10a, {fine:e} at r = 20a");
    assert!(coarse < 2e-3, "{coarse}");
    let order = (coarse / fine).log2();
    assert!((order - 2.0).abs() < 0.2, "order {order}");
    let far = late + 500.0 * a.rayleigh;
    let radial = lamb.patch_radial(r, far, &ramp, half).unwrap();
    assert!(
        (radial / static_r - 1.0).abs() < 2e-5,
        "{}",
        radial / static_r - 1.0
    );
}

/// Bad inputs are typed errors naming the parameter.
#[test]
fn bad_inputs_are_refused() {
    let material = LinearElastic::new(200e9, 0.3, 7800.0);
    assert_eq!(
        Lamb::from_material(&material, 1.0),
        Err(LambError::Poisson(0.3))
    );
    let lamb = steel();
    let ramp = LoadHistory::SmoothRamp { rise: 1e-5 };
    for (result, field) in [
        (lamb.step_vertical(0.0, 1e-5), "r"),
        (lamb.step_radial(f64::NAN, 1e-5), "r"),
        (lamb.vertical(0.1, f64::INFINITY, &ramp), "t"),
        (
            lamb.vertical(0.1, 1e-5, &LoadHistory::Ramp { rise: 0.0 }),
            "history duration",
        ),
        (lamb.patch_vertical(0.1, 1e-5, &ramp, 0.05), "half_side"),
        (Lamb::new(-1.0, 1.0, 1.0).map(|_| 0.0), "shear_modulus"),
    ] {
        match result {
            Err(LambError::Invalid { field: f, .. }) => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
    }
    let message = Lamb::new(1.0, 0.0, 1.0).unwrap_err().to_string();
    assert!(message.contains("density = 0"), "{message}");
}

/// The Duhamel integral against an independent route: integrating by parts once more,
/// `w(t) = (r/c_s)² ∫ V(τ) g''(t − τr/c_s) dτ` with the closed-form antiderivative
/// `V = ∫ U dτ` of Pekeris' step response (logarithms and arcsines, continuous through
/// the Rayleigh arrival), by a composite 6-point Gauss rule on 10⁵ panels: the two agree to
/// 1e-7 of the peak (the accuracy target is 1e-6).
#[test]
fn duhamel_matches_integration_by_parts_with_the_closed_form_antiderivative() {
    let lamb = steel();
    let gamma_r = gamma();
    let s3 = 3f64.sqrt();
    let tau_p = 1.0 / s3;
    let log_term = |tau: f64, c: f64| {
        ((tau + (tau * tau - c).sqrt()) / (tau_p + (tau_p * tau_p - c).sqrt())).ln()
    };
    let (rp, rm) = ((3.0 * s3 + 5.0).sqrt(), (3.0 * s3 - 5.0).sqrt());
    let first = |tau: f64| {
        (6.0 * (tau - tau_p) - s3 * log_term(tau, 0.25) + rm * log_term(tau, 0.25 * (3.0 - s3))
            - rp * ((tau / gamma_r).asin() - (tau_p / gamma_r).asin()))
            / (32.0 * PI)
    };
    let second = |tau: f64| {
        first(1.0)
            + (6.0 * (tau - 1.0) - rp * ((tau / gamma_r).asin() - (1.0 / gamma_r).asin()))
                / (16.0 * PI)
    };
    let antiderivative = |tau: f64| {
        if tau <= tau_p {
            0.0
        } else if tau < 1.0 {
            first(tau)
        } else if tau < gamma_r {
            second(tau)
        } else {
            second(gamma_r) + 3.0 / (8.0 * PI) * (tau - gamma_r)
        }
    };
    let r = 0.1;
    let rise = 1.5 * lamb.arrivals(r).unwrap().s;
    let ramp = LoadHistory::SmoothRamp { rise };
    let curvature = |t: f64| {
        if !(0.0..rise).contains(&t) {
            return 0.0;
        }
        let s = t / rise;
        60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (rise * rise)
    };
    let dt = r / lamb.shear_speed();
    let scale = lamb.force / (lamb.shear_modulus * r);
    let peak = lamb.static_vertical(r).unwrap();
    for t in [0.9, 1.2, 1.6, 2.0, 2.6] {
        let t = t * rise;
        let tau_t = t / dt;
        let mut breaks = vec![
            tau_p,
            1.0,
            gamma_r,
            tau_t,
            tau_t - rise / dt,
            tau_t - 0.5 * rise / dt,
        ];
        breaks.retain(|&b| (tau_p..=tau_t).contains(&b));
        breaks.sort_by(f64::total_cmp);
        let mut parts = 0.0;
        for w in breaks.windows(2) {
            let n = 20_000;
            let h = (w[1] - w[0]) / n as f64;
            for k in 0..n {
                let mid = w[0] + (k as f64 + 0.5) * h;
                for &(x, wx) in &super::lamb_quadrature::GAUSS6 {
                    let tau = mid + 0.5 * h * x;
                    parts += 0.5 * h * wx * antiderivative(tau) * curvature(t - tau * dt);
                }
            }
        }
        let parts = scale * dt * dt * parts;
        let duhamel = lamb.vertical(r, t, &ramp).unwrap();
        assert!(
            (duhamel - parts).abs() < 1e-7 * peak,
            "t = {t}: {duhamel} {parts}"
        );
    }
}

/// At low frequency the surface response is the static one plus, at order `ω`, a rigid
/// translation (the `O(ω)` field solves the static equations with free surface and no
/// source, and is bounded: a constant, vertical by symmetry). With
/// `H(ω) = ∫ U'(σ) e^{−iωσ} dσ = U∞ − iω ∫_0^∞ (U∞ − U) dσ + O(ω²)`, the radial step response
/// has `∫_0^∞ (U∞ − U_r) dτ = 0`; the pole's part gives `∫_γ^∞ (U∞ − pole) = −U∞ γ`, so
/// the elliptic part integrates to zero over `τ > τ_P`: a check of Kausel's elliptic
/// branches as a whole (dropping the elliptic part after `γ` misses by 1.8e-3).
#[test]
fn radial_step_response_has_no_low_frequency_radial_motion() {
    let tau_p = 1.0 / 3f64.sqrt();
    let gamma_r = gamma();
    let mut kernel = radial_elliptic;
    let positive = adaptive_smoothed(&mut |t: f64| kernel(t).abs(), tau_p, 1.0, 1e-15);
    let mut integral = adaptive_smoothed(&mut kernel, tau_p, 1.0, 1e-16)
        + adaptive_smoothed(&mut kernel, 1.0, gamma_r, 1e-16);
    let mut lower = gamma_r;
    for _ in 0..16 {
        integral += adaptive_smoothed(&mut kernel, lower, 2.0 * lower, 1e-16);
        lower *= 2.0;
    }
    // the tail ∝ τ⁻²
    integral += kernel(lower) * lower;
    println!("∫ elliptic part of U_r = {integral:e} (∫|U_r| over P..S = {positive:e})");
    assert!(integral.abs() < 1e-9 * positive, "{integral}");
    // the pole's part alone does not satisfy it
    let before = adaptive_smoothed(&mut kernel, tau_p, 1.0, 1e-16)
        + adaptive_smoothed(&mut kernel, 1.0, gamma_r, 1e-16);
    assert!(before.abs() > 0.3 * positive, "{before}");
}

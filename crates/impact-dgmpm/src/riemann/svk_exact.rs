//! Exact 1D Saint-Venant–Kirchhoff Riemann solver: rarefaction (Riemann invariant) and
//! shock (Rankine–Hugoniot) curves, Newton on the star stress (Toro 2009, ch. 4, for the
//! structure; the wave curves are those of the uniaxial `Π(F) = E/2 F (F² - 1)`).
use super::GhostCondition;
use impact_core::material::Svk;

/// Velocity behind a wave of the 1D system reaching the stress `pi` from the state
/// `(f, v)`: a left-going (1-) wave if `left` (the state on its left), else a
/// right-going (2-) wave. Rarefaction (the Riemann invariant `v ∓ φ(F)` holds) when
/// the stretch decreases across it, shock (Rankine–Hugoniot,
/// `[v]² = [Π][F]/ρ₀`) otherwise. `None` beyond the hyperbolicity limit.
pub fn wave_velocity_1d(m: &Svk, f: f64, v: f64, pi: f64, left: bool) -> Option<f64> {
    let f_star = m.stretch_for_1d(pi)?;
    let pi_side = m.piola_1d(f);
    let jump = if f_star < f {
        m.riemann_phi_1d(f_star) - m.riemann_phi_1d(f)
    } else {
        ((pi - pi_side) * (f_star - f) / m.linear.density)
            .max(0.0)
            .sqrt()
    };
    Some(if left { v + jump } else { v - jump })
}

/// Root of the increasing function `g` on `(lo, ∞)`: bracket by doubling from `guess`,
/// then Newton with slope `slope(π)` safeguarded by bisection. `None` when `g(lo) > 0`.
fn solve_increasing(
    g: impl Fn(f64) -> Option<f64>,
    slope: impl Fn(f64) -> f64,
    lo: f64,
    guess: f64,
    scale: f64,
) -> Option<f64> {
    let (mut a, mut b) = (lo, guess.max(lo + 1e-9 * scale));
    if g(a)? > 0.0 {
        return None;
    }
    let mut width = scale.max(1.0);
    let mut gb = g(b)?;
    let mut tries = 0;
    while gb < 0.0 {
        a = b;
        b += width;
        width *= 2.0;
        gb = g(b)?;
        tries += 1;
        if tries > 200 {
            return None;
        }
    }
    let mut x = guess.clamp(a, b);
    for _ in 0..200 {
        let gx = g(x)?;
        if gx == 0.0 {
            return Some(x);
        }
        if gx < 0.0 {
            a = x;
        } else {
            b = x;
        }
        let mut next = x - gx / slope(x);
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
        }
        if (next - x).abs() <= 1e-14 * (x.abs() + 1e-6 * scale)
            || b - a <= 1e-14 * (x.abs() + scale * 1e-6)
        {
            return Some(next);
        }
        x = next;
    }
    Some(x)
}

fn slope_1d(m: &Svk, pi: f64) -> f64 {
    let f = m.stretch_for_1d(pi).unwrap_or(1.0);
    1.0 / (m.linear.density * m.wave_speed_1d(f)).max(1e-300)
}

/// Exact 1D star state `(v*, Π*)` between `(F_L, v_L)` and `(F_R, v_R)`:
/// `v₁(Π*) = v₂(Π*)` with [`wave_velocity_1d`]. `None` if no admissible star state
/// exists (hyperbolicity lost).
pub fn exact_star_1d(m: &Svk, left: (f64, f64), right: (f64, f64)) -> Option<(f64, f64)> {
    let (_, pi_min) = m.hyperbolicity_limit_1d();
    let lo = pi_min * (1.0 - 1e-9);
    let (pl, pr) = (m.piola_1d(left.0), m.piola_1d(right.0));
    let (zl, zr) = (
        m.linear.density * m.wave_speed_1d(left.0),
        m.linear.density * m.wave_speed_1d(right.0),
    );
    let guess = (zr * pl + zl * pr + zl * zr * (right.1 - left.1)) / (zl + zr);
    let g = |pi: f64| {
        Some(
            wave_velocity_1d(m, left.0, left.1, pi, true)?
                - wave_velocity_1d(m, right.0, right.1, pi, false)?,
        )
    };
    let pi = solve_increasing(
        g,
        |p| 2.0 * slope_1d(m, p),
        lo,
        guess.max(lo),
        m.linear.elastic.young * 1e-3,
    )?;
    Some((wave_velocity_1d(m, left.0, left.1, pi, true)?, pi))
}

/// Exact 1D boundary problem: the interior state `(F, v)`, the outward normal sign
/// `outward` (±1) and the condition give `(v*, Π*)`: a traction `t_d` fixes
/// `Π* = t_d · outward` and `v*` follows from the interior's wave curve; a normal velocity
/// fixes `v* = v_n · outward` and `Π*` is solved on that curve (a velocity vector is its
/// normal component in 1D).
pub fn exact_boundary_1d(
    m: &Svk,
    interior: (f64, f64),
    outward: f64,
    condition: GhostCondition<1>,
) -> Option<(f64, f64)> {
    // the interior is on the left of a right boundary (1-wave), on the right of a left one
    let interior_left = outward > 0.0;
    if let Some((full, share)) = condition.split(&impact_core::Vector::<1>::new(outward)) {
        let covered = exact_boundary_1d(m, interior, outward, full)?;
        let free = exact_boundary_1d(m, interior, outward, GhostCondition::free())?;
        return Some((
            covered.0 * share + free.0 * (1.0 - share),
            covered.1 * share + free.1 * (1.0 - share),
        ));
    }
    match condition {
        // in 1D a prescribed velocity is a prescribed normal velocity
        GhostCondition::Velocity(v) => exact_boundary_1d(
            m,
            interior,
            outward,
            GhostCondition::NormalVelocity(v[0] * outward),
        ),
        GhostCondition::Traction(t) => {
            let pi = t[0] * outward;
            Some((
                wave_velocity_1d(m, interior.0, interior.1, pi, interior_left)?,
                pi,
            ))
        }
        GhostCondition::PartialVelocity { .. } => unreachable!("internal: split above"),
        GhostCondition::NormalVelocity(vn) => {
            let v = vn * outward;
            let (_, pi_min) = m.hyperbolicity_limit_1d();
            let sign = if interior_left { 1.0 } else { -1.0 };
            let g = |pi: f64| {
                Some(sign * (wave_velocity_1d(m, interior.0, interior.1, pi, interior_left)? - v))
            };
            let guess = m.piola_1d(interior.0);
            let pi = solve_increasing(
                g,
                |p| slope_1d(m, p),
                pi_min * (1.0 - 1e-9),
                guess,
                m.linear.elastic.young * 1e-3,
            )?;
            Some((v, pi))
        }
    }
}

#[cfg(test)]
mod svk_tests {
    use crate::riemann::svk::*;
    use crate::riemann::GhostCondition;
    use approx::assert_relative_eq;
    use impact_core::material::{LinearElastic, Svk};
    use impact_core::Vector;

    fn m() -> Svk {
        Svk::new(LinearElastic::new(2e11, 0.3, 7800.0))
    }

    #[test]
    fn equal_states_are_their_own_star_state() {
        let f = 0.995;
        let (v, pi) = exact_star_1d(&m(), (f, 3.0), (f, 3.0)).unwrap();
        assert_relative_eq!(v, 3.0, max_relative = 1e-10);
        assert_relative_eq!(pi, m().piola_1d(f), max_relative = 1e-10);
    }

    /// A pure fan: the left state is the star state of a compressive load reached through
    /// a rarefaction from rest; the solver returns it.
    #[test]
    fn pure_fan() {
        let f = m().stretch_for_1d(-8e8).unwrap();
        let v = -m().riemann_phi_1d(f);
        let (vs, pis) = exact_star_1d(&m(), (f, v), (1.0, 0.0)).unwrap();
        assert_relative_eq!(vs, v, max_relative = 1e-9);
        assert_relative_eq!(pis, -8e8, max_relative = 1e-9);
    }

    /// A pure shock: a tensile state behind a Rankine–Hugoniot shock into rest.
    #[test]
    fn pure_shock() {
        let f = m().stretch_for_1d(8e8).unwrap();
        let s = (m().piola_1d(f) / (7800.0 * (f - 1.0))).sqrt();
        let v = -s * (f - 1.0);
        let (vs, pis) = exact_star_1d(&m(), (f, v), (1.0, 0.0)).unwrap();
        assert_relative_eq!(vs, v, max_relative = 1e-9);
        assert_relative_eq!(pis, 8e8, max_relative = 1e-9);
    }

    /// Hand-worked colliding state: two halves at ±10 m/s meet; by symmetry v* = 0. The
    /// compression lowers the wave speed (Π'' > 0), so both waves are rarefactions (Lax):
    /// the invariant v - φ(F) across the 1-wave gives φ(F*) = -10 m/s.
    #[test]
    fn colliding_halves() {
        let (vs, pis) = exact_star_1d(&m(), (1.0, 10.0), (1.0, -10.0)).unwrap();
        assert!(vs.abs() < 1e-9);
        let f = m().stretch_for_1d(pis).unwrap();
        assert!(f < 1.0);
        assert_relative_eq!(m().riemann_phi_1d(f), -10.0, max_relative = 1e-9);
        // pulling apart instead gives two shocks: [v]² = [Π][F]/ρ₀
        let (vs, pis) = exact_star_1d(&m(), (1.0, -10.0), (1.0, 10.0)).unwrap();
        assert!(vs.abs() < 1e-9 && pis > 0.0);
        let f = m().stretch_for_1d(pis).unwrap();
        assert_relative_eq!(100.0, pis * (f - 1.0) / 7800.0, max_relative = 1e-9);
        let (_, pis) = exact_star_1d(&m(), (1.0, 10.0), (1.0, -10.0)).unwrap();
        // weak waves: close to the acoustic value Z v
        assert_relative_eq!(-pis, (7800.0 * 2e11f64).sqrt() * 10.0, max_relative = 0.01);
    }

    #[test]
    fn boundary_problems_enforce_their_condition() {
        let (v, pi) = exact_boundary_1d(
            &m(),
            (1.0, 0.0),
            -1.0,
            GhostCondition::Traction(Vector::<1>::new(8e8)),
        )
        .unwrap();
        assert_relative_eq!(pi, -8e8, max_relative = 1e-12);
        assert_relative_eq!(
            v,
            -m().riemann_phi_1d(m().stretch_for_1d(-8e8).unwrap()),
            max_relative = 1e-9
        );
        let (v, pi) =
            exact_boundary_1d(&m(), (1.0, 0.0), -1.0, GhostCondition::NormalVelocity(-5.0))
                .unwrap();
        assert_relative_eq!(v, 5.0, max_relative = 1e-12);
        assert!(pi < 0.0);
        // loads beyond the hyperbolicity limit have no star state
        let (_, pi_min) = m().hyperbolicity_limit_1d();
        assert!(exact_boundary_1d(
            &m(),
            (1.0, 0.0),
            -1.0,
            GhostCondition::Traction(Vector::<1>::new(-pi_min * 1.01))
        )
        .is_none());
    }
}

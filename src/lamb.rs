//! `impact bench lamb`: Lamb's problem (issue 24). Each method runs the scene (shipped
//! `lamb`: a pressure on a small square patch of the free surface of a half-space,
//! Poisson's ratio 1/4, a smooth load history) on a ladder of grids, records the
//! displacement at the scene's receivers (`[metrics] receivers`, on the loaded face) at
//! every step, and compares the vertical (along the load) and radial (away from it)
//! surface displacement traces with the exact ones ([`impact_core::exact::Lamb`]: Pekeris'
//! step response convolved with the history and averaged over the patch).
//!
//! **The load.** The loaded side must carry a pressure on a square box patch. Symmetry
//! sides through its low corner make it a quarter (or half) of a patch centred on the
//! symmetry lines (the shipped quarter model): the patch's centre is then on them and its
//! half-side the box's extent; the force is `p (2 h)²`.
//!
//! **The traces.** A receiver reads the sample (material point, FEM node) nearest to it;
//! the exact trace is taken at that sample's own distance from the load, so the lateral
//! offset of a cell-centred point is not an error, but its depth (half a cell below the
//! surface for DGMPM and MPM) is: an `O(h)` error that refinement removes. The displacement
//! is the time integral of the sample's velocity over the steps: DGMPM's and MPM's
//! velocities are at `t_n` (trapezoid rule); FEM's are at `t_{n−1/2}` (central differences),
//! whose sum `Σ v_{n−1/2} Δt` is its displacement exactly.
//!
//! **Metrics** per receiver: the L2 error of each trace over `[0, t_end]` relative to the
//! exact trace's L2 norm; the P arrival (first time the radial `u_r` reaches 20 % of the
//! exact trace's largest outward displacement: the P wave pushes the surface away from
//! the load before the Rayleigh wave pulls it back; [`p_level`])
//! and the Rayleigh arrival (the time of the peak of `|dw/dt|`, the Rayleigh pulse),
//! picked the same way on the exact and the numerical traces, their differences in cells
//! of the level's grid (`c Δt_pick / h` with the wave's speed). The S arrival is a kink of
//! the vertical trace that the smooth history hides; its exact time is listed.
use anyhow::{bail, Context, Result};
use impact_core::exact::Lamb;
use impact_core::method::{MethodKind, Samples};
use impact_core::{Boundary, PatchShape, Problem, Scene, Vector};

/// The load of a Lamb scene: where, how large, what history.
#[derive(Debug, Clone, Copy)]
pub struct LambLoad {
    /// The loaded side `(axis, side)`.
    pub face: (usize, usize),
    /// The patch's centre (on the face).
    pub centre: Vector<3>,
    /// Half-side of the (whole) square patch.
    pub half_side: f64,
    /// The exact solution for the whole patch's force.
    pub exact: Lamb,
    /// The load's history.
    pub history: impact_core::load::LoadHistory,
}

/// The Lamb load of `problem` (module doc), or why the scene is not Lamb's problem.
pub fn lamb_load(problem: &Problem<3>) -> Result<LambLoad> {
    let mut found = None;
    for axis in 0..3 {
        for side in 0..2 {
            match problem.boundaries[axis][side] {
                Boundary::Pressure(load) => {
                    if found.is_some() {
                        bail!("Lamb's problem has one loaded side; this scene has several");
                    }
                    found = Some((axis, side, load));
                }
                Boundary::Velocity { .. } => {
                    bail!("Lamb's problem is loaded by a pressure, not a prescribed velocity")
                }
                Boundary::Free | Boundary::Symmetry => {}
            }
        }
    }
    let Some((axis, side, load)) = found else {
        bail!("Lamb's problem needs a pressure on a patch of one side; this scene has none")
    };
    let Some(PatchShape::Box { lo, hi }) = load.patch.map(|p| p.shape) else {
        bail!("Lamb's problem needs the pressure on a square box patch (`from`, `to`)")
    };
    let grid = &problem.grid;
    let (low, high) = (grid.origin, grid.upper());
    let mut centre = Vector::<3>::zeros();
    centre[axis] = if side == 0 { low[axis] } else { high[axis] };
    let mut half = [0.0; 2];
    for (slot, k) in impact_core::Grid::<3>::tangent_axes(axis).enumerate() {
        let on_low_mirror = lo[slot] <= low[k] + 1e-12 * (high[k] - low[k]);
        if on_low_mirror && problem.boundaries[k][0] == Boundary::Symmetry {
            centre[k] = low[k];
            half[slot] = hi[slot] - low[k];
        } else {
            centre[k] = 0.5 * (lo[slot] + hi[slot]);
            half[slot] = 0.5 * (hi[slot] - lo[slot]);
        }
    }
    if (half[0] - half[1]).abs() > 1e-9 * half[0] {
        bail!(
            "Lamb's problem needs a square patch: half-sides {} and {} m",
            half[0],
            half[1]
        );
    }
    let force = load.value * 4.0 * half[0] * half[0];
    let exact = Lamb::from_material(&problem.material, force)
        .map_err(|e| anyhow::anyhow!("invalid value for `material.poisson`: {e}"))?;
    Ok(LambLoad {
        face: (axis, side),
        centre,
        half_side: half[0],
        exact,
        history: load.history,
    })
}

/// One receiver's traces of one run: times, vertical and radial displacement, and the
/// exact ones, at the sample's distance `r`.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    /// Distance of the receiving sample from the load (m).
    pub r: f64,
    /// Times (s).
    pub t: Vec<f64>,
    /// Vertical displacement (along the load), numerical.
    pub vertical: Vec<f64>,
    /// Radial displacement (away from the load), numerical.
    pub radial: Vec<f64>,
    /// Exact vertical displacement.
    pub vertical_exact: Vec<f64>,
    /// Exact radial displacement.
    pub radial_exact: Vec<f64>,
}

/// Run `config` on `problem` to its end time and record the traces at `receivers`.
pub fn traces(
    problem: &Problem<3>,
    config: impact_core::method::MethodConfig,
    load: &LambLoad,
    receivers: &[Vector<3>],
) -> Result<Vec<Trace>> {
    let mut method = crate::build(problem, config)?;
    let mut samples = Samples::<3>::default();
    method.sample_into(&mut samples);
    let (axis, side) = load.face;
    let mut inward = Vector::<3>::zeros();
    inward[axis] = if side == 0 { 1.0 } else { -1.0 };
    let picked: Vec<usize> = receivers
        .iter()
        .map(|x| {
            (0..samples.len())
                .min_by(|&i, &j| {
                    let (a, b) = (
                        (samples.reference[i] - x).norm(),
                        (samples.reference[j] - x).norm(),
                    );
                    a.total_cmp(&b)
                })
                .expect("internal: a body has samples")
        })
        .collect();
    let directions: Vec<(f64, Vector<3>)> = picked
        .iter()
        .map(|&i| {
            let mut d = samples.reference[i] - load.centre;
            d[axis] = 0.0;
            (d.norm(), d / d.norm())
        })
        .collect();
    let staggered = config.kind() == MethodKind::Fem;
    let dt = method.stable_dt();
    let steps = (problem.t_end / dt).ceil() as usize;
    let dt = problem.t_end / steps as f64;
    let mut out: Vec<Trace> = directions
        .iter()
        .map(|&(r, _)| Trace {
            r,
            t: vec![0.0],
            vertical: vec![0.0],
            radial: vec![0.0],
            ..Trace::default()
        })
        .collect();
    let mut displacement = vec![Vector::<3>::zeros(); picked.len()];
    let mut previous: Vec<Vector<3>> = picked.iter().map(|&i| samples.velocity[i]).collect();
    for n in 0..steps {
        let t = n as f64 * dt;
        method.step(t, dt);
        if n % 16 == 15 {
            method
                .check_finite()
                .map_err(|e| anyhow::anyhow!("{} at {:?} (step {n})", e.reason, e.place))?;
        }
        method.sample_into(&mut samples);
        for (k, &i) in picked.iter().enumerate() {
            let v = samples.velocity[i];
            displacement[k] += if staggered {
                v * dt
            } else {
                (previous[k] + v) * (0.5 * dt)
            };
            previous[k] = v;
            let trace = &mut out[k];
            trace.t.push(t + dt);
            trace.vertical.push(displacement[k].dot(&inward));
            trace.radial.push(displacement[k].dot(&directions[k].1));
        }
    }
    method
        .check_finite()
        .map_err(|e| anyhow::anyhow!("{} at {:?}", e.reason, e.place))?;
    for trace in &mut out {
        for &t in &trace.t {
            let h = &load.history;
            let e = &load.exact;
            trace
                .vertical_exact
                .push(e.patch_vertical(trace.r, t, h, load.half_side)?);
            trace
                .radial_exact
                .push(e.patch_radial(trace.r, t, h, load.half_side)?);
        }
    }
    Ok(out)
}

/// `sqrt(Σ (a − b)²) / sqrt(Σ b²)` over equally spaced samples.
pub fn relative_l2(a: &[f64], b: &[f64]) -> f64 {
    let error: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    (error / norm.max(f64::MIN_POSITIVE)).sqrt()
}

/// The P pick: the first time `w` reaches `level` (a signed level: the P wave moves the
/// surface away from the load, `u_r > 0`), linearly interpolated between samples.
pub fn onset(t: &[f64], w: &[f64], level: f64) -> Option<f64> {
    let reached = |v: f64| if level >= 0.0 { v >= level } else { v <= level };
    let k = w.iter().position(|&v| reached(v))?;
    if k == 0 {
        return Some(t[0]);
    }
    let (a, b) = (w[k - 1], w[k]);
    let s = if b != a {
        ((level - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    Some(t[k - 1] + s * (t[k] - t[k - 1]))
}

/// The P level of an exact radial trace: 20 % of its largest outward displacement (the P
/// phase, before the Rayleigh trough pulls the surface towards the load).
pub fn p_level(radial_exact: &[f64]) -> f64 {
    0.2 * radial_exact.iter().fold(0.0f64, |m, &v| m.max(v))
}

/// The Rayleigh pick: the time of the largest `|dw/dt|` (centred differences, refined by a
/// parabola through the three values around the peak).
pub fn steepest(t: &[f64], w: &[f64]) -> Option<f64> {
    if t.len() < 5 {
        return None;
    }
    let rate: Vec<f64> = (1..t.len() - 1)
        .map(|k| ((w[k + 1] - w[k - 1]) / (t[k + 1] - t[k - 1])).abs())
        .collect();
    let k = (1..rate.len() - 1).max_by(|&i, &j| rate[i].total_cmp(&rate[j]))?;
    let (a, b, c) = (rate[k - 1], rate[k], rate[k + 1]);
    let curvature = a - 2.0 * b + c;
    let shift = if curvature < 0.0 {
        (0.5 * (a - c) / curvature).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Some(t[k + 1] + shift * (t[k + 2] - t[k + 1]))
}

/// The scene's receivers as points (refused if there are none or one is off the loaded
/// face).
pub fn receivers(scene: &Scene, load: &LambLoad, problem: &Problem<3>) -> Result<Vec<Vector<3>>> {
    let points = scene.receivers();
    if points.is_empty() {
        bail!(
            "invalid value for `metrics.receivers`: none (allowed: points on the loaded face, \
             e.g. `receivers = [[0.4, 0.0, 1.2]]`)"
        );
    }
    let (axis, _) = load.face;
    let at = load.centre[axis];
    points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let x = Vector::<3>::new(p[0], p[1], p[2]);
            let h = problem.grid.spacing[axis];
            if (x[axis] - at).abs() > 1e-9 * h {
                bail!(
                    "invalid value for `metrics.receivers[{k}]`: {p:?} (allowed: a point on \
                     the loaded face {} = {at} m)",
                    ["x", "y", "z"][axis]
                );
            }
            let mut d = x - load.centre;
            d[axis] = 0.0;
            if d.norm() < 2.0 * load.half_side {
                bail!(
                    "invalid value for `metrics.receivers[{k}]`: {p:?} (allowed: a point at \
                     least one patch side, {} m, from the load's centre)",
                    2.0 * load.half_side
                );
            }
            Ok(x)
        })
        .collect::<Result<Vec<_>>>()
        .context("the receivers of Lamb's problem")
}

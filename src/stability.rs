//! Stability: empirical critical Courant numbers for every method and configuration, and a
//! von Neumann analysis of DGMPM computed by the program for any points-per-cell layout.
//!
//! - **Empirical**: a body with no load (free ends in 1D; symmetry edges in 2D, the mirror
//!   planes closest to the periodic grid of the von Neumann analysis) starts from a
//!   deterministic random
//!   velocity perturbation (uniform in ±1 m/s at every velocity carrier) and runs `steps`
//!   steps; it is unstable when the guard fires (energy above 10× the initial energy, or a
//!   non-finite state) or when the largest sampled velocity at the end exceeds 10× its
//!   initial value (the max norm: a growing local mode, e.g. at a corner, that the total
//!   energy would show only much later). The critical Courant number is found by bisection
//!   in [0.05, 1.5].
//! - **Von Neumann (DGMPM)**: the scheme is linear and translation invariant, so one step
//!   maps the unknowns of cell `j` (`σ` and `v` of each point) to those of cells `j + m` by
//!   matrices `B_m`. They are measured by stepping a unit perturbation of each unknown of
//!   the middle cell of a grid with free edges, far from them. The amplification matrix
//!   of a Fourier mode `q_j = q̂ e^{i j·θ}` is `G(θ) = Σ_m B_m e^{-i m·θ}`; its spectral
//!   radius is maximised over a grid of wave numbers, and the critical Courant number (the
//!   largest with `max ρ(G) ≤ 1 + 1e-9`) is found by bisection (17 halvings: to 1.1e-5).
//!   The unknowns are non-dimensional: stresses are divided by the impedance `Z = ρ c_p`,
//!   so every unknown is a velocity. In Pa and m/s the matrices mixed entries about 4e7
//!   apart, and their eigenvalues carried errors near 1e-6. That put the printed limits for
//!   3 and 4 points per cell (0.6431, 0.6325) and for RK2 (0.994, 0.988) below their values.
use crate::von_neumann::step_matrices;
pub use crate::von_neumann::{max_amplification, von_neumann_limit};
mod files;
pub use files::{chart, figure, write};
use impact_core::method::{Integrator, MethodConfig, MethodKind, PointUpdate, TransverseFlux};
use impact_core::{Method, Problem, Vector};
use serde::Serialize;

/// One configuration and its limits.
#[derive(Debug, Clone, Serialize)]
pub struct StabilityRow {
    /// Dimension.
    pub dim: usize,
    /// Method name.
    pub method: String,
    /// Points per cell.
    pub points_per_cell: usize,
    /// Integrator label.
    pub integrator: String,
    /// Transverse flux (2D DGMPM) or `-`.
    pub flux: String,
    /// DGMPM's point update (`nodal` or `increment`) or `-`.
    pub update: String,
    /// Where the points sit in a cell (`PointLayout::label`).
    pub layout: String,
    /// Empirical critical Courant number.
    pub empirical: f64,
    /// Von Neumann critical Courant number (DGMPM), if computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub von_neumann: Option<f64>,
    /// Largest Courant number with a monotone one-step operator (DGMPM, 1D; 0: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monotone: Option<f64>,
}

impl StabilityRow {
    /// The configuration in one line: `2D dgmpm 1ppc euler ctu nodal`.
    pub fn label(&self) -> String {
        format!(
            "{}D {} {}ppc {} {} {}",
            self.dim, self.method, self.points_per_cell, self.integrator, self.flux, self.update
        )
    }
}

/// Cells of a 2D sweep body (`x`, `y`): the plane wave's cut since issue 10.
pub const SWEEP_CELLS_2D: [usize; 2] = [16, 12];

/// Cells of a 3D sweep body: 12 on every axis (16×12×12 would cost a third more per run).
pub const SWEEP_CELLS_3D: [usize; 3] = [12, 12, 12];

/// The scene a sweep in dimension `dim` (1 or 2) runs on: the paper's bar, or the plane
/// wave cut to 16×12 cells (the 2D perturbed runs and von Neumann matrices stay small).
pub fn sweep_scene(dim: usize) -> impact_core::Scene {
    if dim == 1 {
        return impact_core::Scene::builtin("bar").expect("shipped scene");
    }
    let mut scene = impact_core::Scene::builtin("plate-wave").expect("shipped scene");
    scene.domain.cells = SWEEP_CELLS_2D.to_vec();
    scene
}

/// `scene` cut for a sweep (`impact stability --scene`): at most 150 cells in 1D; in 2D
/// and 3D exactly [`SWEEP_CELLS_2D`] or [`SWEEP_CELLS_3D`], each cell's size kept (the
/// lengths shrink or grow), at rest, every edge free (the sweep replaces the edges by its
/// unloaded body's anyway), without the scene's metrics (a measuring line, receivers or
/// region of the full body may lie outside the cut one, and a sweep measures none).
/// Material, model, point layout and method options stay the scene's.
///
/// A thin axis is widened, not kept: the perturbed runs see only the wave numbers
/// `kπ/N` the body holds, so a body a few cells across misses the unstable modes of the
/// other axes' wave numbers. `block-wave`'s 4 cells across gave an empirical limit of 1.0007
/// for RK2 donor-cell at 8 points per cell, where a 12³ body gives 0.9394 and the von
/// Neumann limit is 0.9115 (`smooth-block` at Courant 0.96 blows up at step 550).
pub fn cut_scene(scene: &impact_core::Scene) -> impact_core::Scene {
    let mut s = scene.clone();
    for l in 0..s.dim {
        let h = s.domain.length[l] / s.domain.cells[l] as f64;
        s.domain.cells[l] = match s.dim {
            1 => s.domain.cells[l].min(150),
            2 => SWEEP_CELLS_2D[l],
            _ => SWEEP_CELLS_3D[l],
        };
        s.domain.length[l] = h * s.domain.cells[l] as f64;
    }
    s.initial = None;
    s.boundary = impact_core::scene::BoundarySpec::default();
    s.metrics = None;
    s
}

/// The sweep's configurations of `base` that `problem` refuses ([`Problem::check_config`]),
/// each with its reason: [`sweep`] skips them.
pub fn refused<const D: usize>(problem: &Problem<D>, base: &impact_core::Scene) -> Vec<String> {
    configurations::<D>(base)
        .iter()
        // configurations the layout does not seed are left out of the sweep silently
        .filter(|c| problem.layout.fits(c.points_per_cell) || c.kind() == MethodKind::Fem)
        .filter_map(|c| {
            problem.check_config(c).err().map(|e| {
                let flux = match (c.dgmpm(), D) {
                    (Some(o), 2..) => format!(" {}", o.flux),
                    _ => String::new(),
                };
                format!(
                    "{}D {} {}ppc {}{flux}: {e}",
                    D,
                    c.kind(),
                    c.points_per_cell,
                    c.integrator_label()
                )
            })
        })
        .collect()
}

/// Deterministic uniform numbers in [-1, 1) (64-bit LCG).
pub(crate) fn noise(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// The unloaded body of `problem`: free ends in 1D, symmetry edges in 2D (the closest to
/// the periodic grid of the von Neumann analysis; [`free_edge_limit`] measures free edges).
pub(crate) fn unloaded<const D: usize>(problem: &Problem<D>) -> Problem<D> {
    let edge = if D == 1 {
        impact_core::Boundary::Free
    } else {
        impact_core::Boundary::Symmetry
    };
    let mut p = problem.clone();
    p.boundaries = [[edge; 2]; D];
    p
}

/// Empirical critical Courant number with every edge free (2D: shows the edge treatment).
pub fn free_edge_limit<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    steps: usize,
) -> f64 {
    let mut p = problem.clone();
    p.boundaries = [[impact_core::Boundary::Free; 2]; D];
    bisect(0.05, 1.5, 12, |c| {
        let mut cfg = config;
        cfg.courant = c;
        stays_bounded(&p, cfg, steps)
    })
}

/// Whether `config` stays bounded for `steps` steps from the perturbed state.
pub fn is_stable<const D: usize>(problem: &Problem<D>, config: MethodConfig, steps: usize) -> bool {
    stays_bounded(&unloaded(problem), config, steps)
}

fn stays_bounded<const D: usize>(body: &Problem<D>, config: MethodConfig, steps: usize) -> bool {
    let Ok(mut method) = crate::build(body, config) else {
        return false;
    };
    let mut seed = 12345u64;
    method.perturb_velocity(&mut |_, _| Vector::<D>::from_fn(|_, _| noise(&mut seed)));
    let mut samples = impact_core::method::Samples::<D>::default();
    let max_speed = |m: &dyn Method<D>, samples: &mut impact_core::method::Samples<D>| {
        m.sample_into(samples);
        samples
            .velocity
            .iter()
            .map(|v| v.norm())
            .fold(0.0, f64::max)
    };
    let initial_max = max_speed(method.as_ref(), &mut samples);
    let t_end = steps as f64 * method.stable_dt();
    let mut run = body.clone();
    run.output_times = vec![t_end];
    run.t_end = t_end;
    let result = impact_core::controller::run::<D, dyn Method<D>, std::convert::Infallible>(
        method.as_mut(),
        &run.output_times,
        crate::interrupt::guard(),
        |_, _, _, _| Ok(()),
        |_| {},
    );
    // a NaN maximum is not within the bound either
    result.is_ok() && max_speed(method.as_ref(), &mut samples) <= 10.0 * initial_max
}

/// Bisection for the largest stable value in `[lo, hi]` of a monotone criterion.
pub(crate) fn bisect(
    mut lo: f64,
    mut hi: f64,
    iterations: usize,
    stable: impl Fn(f64) -> bool,
) -> f64 {
    if stable(hi) {
        return hi;
    }
    if !stable(lo) {
        return lo;
    }
    for _ in 0..iterations {
        let mid = 0.5 * (lo + hi);
        if stable(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Empirical critical Courant number of `config` (see the module doc).
pub fn empirical_limit<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    steps: usize,
) -> f64 {
    bisect(0.05, 1.5, 12, |c| {
        let mut cfg = config;
        cfg.courant = c;
        is_stable(problem, cfg, steps)
    })
}

/// The configurations of the sweep for dimension `D`.
pub fn configurations<const D: usize>(base: &impact_core::Scene) -> Vec<MethodConfig> {
    let mut out = Vec::new();
    // 2 and 3 points per axis in 2D; 2 in 3D (27 points per cell would make the sweep's
    // perturbed runs 27× the cut body's cells)
    let layouts: &[usize] = match D {
        1 => &[1, 2, 3, 4],
        2 => &[1, 4, 9],
        _ => &[1, 8],
    };
    let fluxes: &[TransverseFlux] = if D == 1 {
        &[TransverseFlux::DonorCell]
    } else {
        &[TransverseFlux::DonorCell, TransverseFlux::Ctu]
    };
    for &ppc in layouts {
        for integrator in [Integrator::Euler, Integrator::Rk2] {
            for &flux in fluxes {
                let mut c = base.method_config(MethodKind::Dgmpm);
                c.points_per_cell = ppc;
                if let Some(o) = c.dgmpm_mut() {
                    (o.integrator, o.flux) = (integrator, flux);
                }
                out.push(c);
            }
        }
        // 1D: the increment point update too (the thesis tabulates both)
        if D == 1 && ppc > 1 {
            for integrator in [Integrator::Euler, Integrator::Rk2] {
                let mut c = base.method_config(MethodKind::Dgmpm);
                c.points_per_cell = ppc;
                if let Some(o) = c.dgmpm_mut() {
                    (o.integrator, o.update) = (integrator, PointUpdate::Increment);
                }
                out.push(c);
            }
        }
    }
    for ppc in [1, layouts[1]] {
        let mut c = base.method_config(MethodKind::Mpm);
        c.points_per_cell = ppc;
        out.push(c);
    }
    out.push(base.method_config(MethodKind::Fem));
    out
}

/// Run the sweep for `problem` (with the configurations of `base`).
pub fn sweep<const D: usize>(
    problem: &Problem<D>,
    base: &impact_core::Scene,
    steps: usize,
    mut progress: impl FnMut(&StabilityRow),
) -> Vec<StabilityRow> {
    let mut rows = Vec::new();
    let layout = problem.layout.label();
    for c in configurations::<D>(base) {
        if !problem.layout.fits(c.points_per_cell) && c.kind() != MethodKind::Fem {
            continue;
        }
        // an option the model refuses (listed by `refused`)
        if problem.check_config(&c).is_err() {
            continue;
        }
        let dgmpm = c.kind() == MethodKind::Dgmpm;
        let row = StabilityRow {
            dim: D,
            method: c.kind().name().into(),
            points_per_cell: if c.kind() == MethodKind::Fem {
                1
            } else {
                c.points_per_cell
            },
            integrator: c.integrator_label().into(),
            update: c.dgmpm().map_or("-".into(), |o| o.update.name().into()),
            layout: layout.clone(),
            flux: match (c.dgmpm(), D) {
                (Some(o), 2..) => o.flux.name().into(),
                _ => "-".into(),
            },
            empirical: empirical_limit(problem, c, steps),
            // 2D: one point per cell (4 and 9 points per cell make 20×20 and 45×45
            // amplification matrices per wave number, too slow for the sweep); 3D: also 8
            // points per cell (the octant of `crate::von_neumann`: 20 to 50 s each on 2
            // cores with Euler, 40 to 100 s with RK2, whose step reaches two cells)
            von_neumann: (dgmpm
                && (D == 1 || c.points_per_cell == 1 || (D == 3 && c.points_per_cell == 8)))
                .then(|| von_neumann_limit(problem, c, [256, 24, 16][D.min(3) - 1]))
                .filter(|v| v.is_finite()),
            monotone: monotonicity_limit(problem, c),
        };
        progress(&row);
        rows.push(row);
    }
    rows
}

/// Why a run of `config` on `problem` may have blown up: when its Courant number is above
/// the limit the stability test measures for the same configuration, material and cell
/// size (the unloaded body of [`empirical_limit`], cut to 40 cells in 1D and 16×12 in 2D,
/// 2000 or 500 steps), a sentence naming that limit; `None` when the Courant number is
/// within it (the cause lies elsewhere: the load, the model).
pub fn diagnose_blowup<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Option<String> {
    let mut body = problem.clone();
    let small = if D == 1 { [40, 1] } else { [16, 12] };
    for l in 0..D {
        body.grid.cells[l] = body.grid.cells[l].min(small[l.min(1)]);
    }
    let steps = if D == 1 { 2000 } else { 500 };
    let limit = empirical_limit(&body, config, steps);
    (config.courant > limit).then(|| {
        format!(
            "the Courant number {} is above {limit:.3}, the stability limit measured for this \
             configuration ({}, {} points per cell, {}; the test of `impact stability`: {steps} \
             steps of the unloaded body from a random perturbation): lower --courant",
            config.courant,
            config.kind(),
            config.points_per_cell,
            config.integrator_label(),
        )
    })
}

/// The largest row sum `max_α Σ_β |D_αβ|` of DGMPM's one-step operator on either
/// characteristic, `r = v − σ/Z` (right-going) and `l = v + σ/Z` (left-going) (1D): the
/// monotonicity (positivity) bound the DGMPM thesis uses. The scheme is linear and the
/// characteristics decouple, so `D` is the `r → r` (or `l → l`) block of the step matrices
/// `B_m`, read between every point `β` of the cells around and every point `α` of the
/// middle cell. A monotone scheme has `Σ_β |D_αβ| ≤ 1`. The two blocks differ where the
/// layout is not mirror symmetric (the left-going wave sees the layout `1 − ξ`: given
/// positions 0.3, 0.5 are monotone up to 0.7077 on `r` but 0.6900 on `l`; reading `r` alone
/// overstated the limit there, found by `tests/stability.rs`' independent analysis).
pub fn monotonicity_row_sum<const D: usize>(problem: &Problem<D>, config: MethodConfig) -> f64 {
    let (_, matrices) = step_matrices(problem, config, 2);
    let ppc = config.points_per_cell;
    // unknowns per point: (σ/Z, v); r = v − σ/Z has the unit input (−½, ½), l = v + σ/Z
    // the unit input (½, ½): `sign` −1 for r, +1 for l
    let mut worst: f64 = 0.0;
    for sign in [-1.0, 1.0] {
        for alpha in 0..ppc {
            let mut sum = 0.0;
            for b in &matrices {
                for beta in 0..ppc {
                    let (s_out, v_out) = (2 * alpha, 2 * alpha + 1);
                    let (s_in, v_in) = (2 * beta, 2 * beta + 1);
                    // B (½ sign e_s + ½ e_v), then v + sign s
                    let column = |row: usize| 0.5 * (b[(row, v_in)] + sign * b[(row, s_in)]);
                    sum += (column(v_out) + sign * column(s_out)).abs();
                }
            }
            worst = worst.max(sum);
        }
    }
    worst
}

/// The largest Courant number with a monotone one-step operator
/// ([`monotonicity_row_sum`] ≤ 1), by bisection in [0.05, 1.5] (17 halvings); 0 when the
/// operator is not monotone even at 0.05. DGMPM in 1D only (`None` otherwise).
pub fn monotonicity_limit<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Option<f64> {
    if D != 1 || config.dgmpm().is_none() {
        return None;
    }
    let monotone = |c: f64| {
        let mut cfg = config;
        cfg.courant = c;
        monotonicity_row_sum(problem, cfg) <= 1.0 + 1e-12
    };
    if !monotone(0.05) {
        return Some(0.0);
    }
    Some(bisect(0.05, 1.5, 17, monotone))
}

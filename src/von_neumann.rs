//! DGMPM's von Neumann analysis, computed by the program for any points-per-cell layout
//! (the module doc of [`crate::stability`] states the step matrices `B_m` and the
//! amplification matrix `G(θ) = Σ_m B_m e^{-i m·θ}`).
//!
//! **Which wave numbers.** `θ` runs over the grid `2π k/N`, `k = 0..N-1` per axis (`N` =
//! 256 in 1D, 24 in 2D, 16 in 3D; `θ = π` on every axis is on it). In 3D that is 4096
//! eigenvalue problems per Courant number, 72 × 72 at 8 points per cell: minutes. Two exact
//! reductions bring it to seconds:
//!
//! - **Mirror symmetry.** Where the scheme commutes with the reflection `x_l → −x_l` of
//!   axis `l` (an isotropic material, and points placed symmetrically in the cell, as the
//!   centred layout does), `B_{R m} = P B_m P` with `R` the reflection of the offsets and
//!   `P` the signed permutation that mirrors the points of a cell and flips the sign of
//!   `v_l` and of `σ_{lk}`, `k ≠ l`. Then `G(R θ) = P G(θ) P`: the same eigenvalues. The
//!   program does not assume it: it checks `B_{R m} = P B_m P` on the measured matrices
//!   (to 1e-12 of their largest entry) for each axis, and only then samples the octant
//!   `θ_l ∈ [0, π]`, `k = 0..N/2` (9³ = 729 wave numbers in 3D, 5.6× fewer). Reflecting
//!   the negative components of any `θ ∈ (−π, π]^D` lands on that octant's grid, so the
//!   maximum over the octant equals the maximum over the whole grid, not an estimate of
//!   it (the test `octant_equals_the_whole_grid` compares them). Without the symmetry (a
//!   shifted or given layout) the whole grid is sampled.
//! - **Parallel, and few whole samples.** The wave numbers are spread over rayon's pool;
//!   the bisection of the limit runs on a few candidate wave numbers and checks the whole
//!   sample only at the limit it finds ([`von_neumann_limit`]).
//!
//! Only in 3D: in 1D and 2D the grid is sampled whole, as before (the limits there stay
//! the ones every table states).
use impact_core::method::{Integrator, MethodConfig};
use impact_core::{Method, Problem};
use nalgebra::{Complex, DMatrix};
use rayon::prelude::*;

/// Unknowns of one point: `σ` (the symmetric part, one value per pair) and `v`.
fn unknowns(d: usize) -> usize {
    d * (d + 1) / 2 + d
}

/// The unknowns of point `i`, stresses divided by the impedance `z` (so that every unknown
/// is a velocity: the step matrices are then well scaled, module doc).
fn read_point<const D: usize>(
    p: &impact_core::points::MaterialPoints<D>,
    i: usize,
    z: f64,
    out: &mut Vec<f64>,
) {
    for r in 0..D {
        for c in r..D {
            out.push(p.stress[i][(r, c)] / z);
        }
    }
    out.extend(p.velocity[i].iter());
}

/// Set unknown `k` of point `i` to `value` in the scaled unknowns (a stress is `z · value`).
fn write_unknown<const D: usize>(
    p: &mut impact_core::points::MaterialPoints<D>,
    i: usize,
    k: usize,
    value: f64,
    z: f64,
) {
    let mut n = 0;
    for r in 0..D {
        for c in r..D {
            if n == k {
                p.stress[i][(r, c)] = z * value;
                p.stress[i][(c, r)] = z * value;
                return;
            }
            n += 1;
        }
    }
    p.velocity[i][k - n] = value;
}

/// The step matrices `B_m` of DGMPM for `config` on a grid of `2·reach + 1` cells per axis
/// around the middle cell, `m` in `[-reach, reach]^D`: returns `(offsets, matrices)`.
pub(crate) fn step_matrices<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    reach: usize,
) -> (Vec<[isize; D]>, Vec<DMatrix<f64>>) {
    let mut body = crate::stability::unloaded(problem);
    let n = 4 * reach + 3;
    for l in 0..D {
        body.grid.cells[l] = n;
    }
    let ppc = config.points_per_cell;
    let size = ppc * unknowns(D);
    let middle = [n / 2; D];
    let centre = body.grid.cell_index(middle);
    let offsets: Vec<[isize; D]> = (0..(2 * reach + 1).pow(D as u32))
        .map(|mut k| {
            let mut o = [0isize; D];
            for v in o.iter_mut() {
                *v = (k % (2 * reach + 1)) as isize - reach as isize;
                k /= 2 * reach + 1;
            }
            o
        })
        .collect();
    let mut matrices = vec![DMatrix::<f64>::zeros(size, size); offsets.len()];
    let template = impact_dgmpm::Dgmpm::new(&body, config).expect("internal: valid configuration");
    let dt = template.stable_dt();
    let per = unknowns(D);
    let z = body.material.density * body.material.p_wave_speed::<D>();
    // one step per unknown of the middle cell, spread over rayon's pool
    let columns: Vec<Vec<Vec<f64>>> = (0..size)
        .into_par_iter()
        .map(|col| {
            let mut m = template.clone();
            write_unknown(
                &mut m.state.points,
                centre * ppc + col / per,
                col % per,
                1.0,
                z,
            );
            m.step(0.0, dt);
            offsets
                .iter()
                .map(|offset| {
                    let mut idx = middle;
                    for l in 0..D {
                        idx[l] = (middle[l] as isize + offset[l]) as usize;
                    }
                    let c = body.grid.cell_index(idx);
                    let mut values = Vec::with_capacity(size);
                    for k in 0..ppc {
                        read_point(&m.state.points, c * ppc + k, z, &mut values);
                    }
                    values
                })
                .collect()
        })
        .collect();
    for (col, column) in columns.into_iter().enumerate() {
        for (o, values) in column.into_iter().enumerate() {
            for (row, v) in values.into_iter().enumerate() {
                matrices[o][(row, col)] = v;
            }
        }
    }
    (offsets, matrices)
}

/// The step matrices of a configuration and the wave numbers their amplification is
/// sampled on (module doc).
pub struct Amplification<const D: usize> {
    offsets: Vec<[isize; D]>,
    matrices: Vec<DMatrix<f64>>,
    /// Whether the mirror symmetry holds on every axis (then the octant is sampled).
    pub mirrored: bool,
}

impl<const D: usize> Amplification<D> {
    /// Measure the step matrices of `config` on `problem` and check their mirror symmetry.
    pub fn new(problem: &Problem<D>, config: MethodConfig) -> Self {
        // order 2 (limited wave corrections): the limited scheme is nonlinear, so the
        // analysis linearises it as its unlimited (Lax-Wendroff) scheme, a stencil of 2
        // cells per stage (Sweby's TVD limiters, `0 ≤ φ ≤ 2`, keep the limited scheme TVD
        // to Courant 1 at one point per cell, LeVeque 2002 §6.12)
        let mut config = config;
        let second = config.dgmpm().and_then(|o| o.wave_limiter()).is_some();
        if let Some(o) = config.dgmpm_mut().filter(|_| second) {
            o.limiter = Some(impact_core::method::WaveLimiter::None);
        }
        let rk2 = config.dgmpm().map(|o| o.integrator) == Some(Integrator::Rk2);
        // the cells one step can reach, with a margin of one in 1D and 2D (as measured
        // there since issue 20); in 3D the stencil's own reach, 1 per stage (a cell reads
        // its 3^D neighbourhood; 2 with order 2), which keeps the 3D grids small: the test
        // `reach_one_per_stage_holds_every_coupling_in_3d` checks the couplings one cell
        // further vanish
        let per_stage = if second { 2 } else { 1 };
        let reach = match (D, rk2, second) {
            (3, false, _) => per_stage,
            (3, true, _) => 2 * per_stage,
            (_, true, true) => 4,
            (_, true, false) => 3,
            (_, false, _) => 2,
        };
        Self::with_reach(problem, config, reach)
    }

    /// As [`Self::new`], with the step matrices measured for offsets up to `reach` cells.
    pub fn with_reach(problem: &Problem<D>, config: MethodConfig, reach: usize) -> Self {
        let (offsets, matrices) = step_matrices(problem, config, reach);
        let mirrored = D == 3 && mirror_symmetric(problem, config, &offsets, &matrices);
        Self {
            offsets,
            matrices,
            mirrored,
        }
    }

    /// The wave numbers sampled with `samples` per axis: the octant `k = 0..=N/2` where
    /// mirrored (and `N` even), else the whole grid `k = 0..N`.
    pub fn wave_numbers(&self, samples: usize) -> Vec<[f64; D]> {
        let per_axis = if self.mirrored && samples.is_multiple_of(2) {
            samples / 2 + 1
        } else {
            samples
        };
        (0..per_axis.pow(D as u32))
            .map(|k| {
                let mut theta = [0.0; D];
                let mut rest = k;
                for t in theta.iter_mut() {
                    *t = 2.0 * std::f64::consts::PI * (rest % per_axis) as f64 / samples as f64;
                    rest /= per_axis;
                }
                theta
            })
            .collect()
    }

    /// Every wave number of the grid, `k = 0..N` per axis (what the octant stands for).
    pub fn all_wave_numbers(samples: usize) -> Vec<[f64; D]> {
        let whole = Self {
            offsets: Vec::new(),
            matrices: Vec::new(),
            mirrored: false,
        };
        whole.wave_numbers(samples)
    }

    /// The eigenvalues of `G(θ)` (`None` if no Schur decomposition converges).
    pub fn spectrum(&self, theta: &[f64; D]) -> Option<Vec<Complex<f64>>> {
        let size = self.matrices[0].nrows();
        let mut g = DMatrix::<Complex<f64>>::zeros(size, size);
        for (offset, b) in self.offsets.iter().zip(&self.matrices) {
            let phase: f64 = (0..D).map(|l| -(offset[l] as f64) * theta[l]).sum();
            let e = Complex::new(phase.cos(), phase.sin());
            g.zip_apply(b, |gij, bij| *gij += e * bij);
        }
        eigenvalues(g)
    }

    /// The spectral radius of `G(θ)` (`None` if no Schur decomposition converges).
    pub fn radius(&self, theta: &[f64; D]) -> Option<f64> {
        let eig = self.spectrum(theta)?;
        Some(eig.iter().map(|z| z.norm()).fold(0.0, f64::max))
    }

    /// The largest spectral radius over `thetas` and where (`None` if an eigenvalue
    /// computation failed).
    pub fn max_radius(&self, thetas: &[[f64; D]]) -> Option<(f64, [f64; D])> {
        let radii: Option<Vec<f64>> = thetas.par_iter().map(|t| self.radius(t)).collect();
        let radii = radii?;
        let (k, rho) =
            radii.iter().enumerate().fold(
                (0, 0.0f64),
                |best, (k, &r)| if r > best.1 { (k, r) } else { best },
            );
        Some((rho, thetas.get(k).copied().unwrap_or([0.0; D])))
    }
}

/// Whether `B_{R m} = P B_m P` for the reflection of each axis (module doc), to 1e-12 of
/// the largest entry.
fn mirror_symmetric<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    offsets: &[[isize; D]],
    matrices: &[DMatrix<f64>],
) -> bool {
    let ppc = config.points_per_cell;
    let per = unknowns(D);
    // the points of one cell, in cell 0 of a one-cell grid of the same layout
    let mut body = problem.clone();
    body.grid.cells = [1; D];
    let Ok(template) = impact_dgmpm::Dgmpm::new(&body, config) else {
        return false;
    };
    let points = &template.state.points;
    let centre = body.grid.cell_centre(0);
    let scale = matrices
        .iter()
        .flat_map(|b| b.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let tol = 1e-12 * scale.max(1e-300);
    for l in 0..D {
        // the mirrored point of each point of the cell
        let mut mirror = vec![usize::MAX; ppc];
        for (k, slot) in mirror.iter_mut().enumerate() {
            let mut x = points.reference[k];
            x[l] = 2.0 * centre[l] - x[l];
            let h = body.grid.spacing.min();
            *slot = match (0..ppc).find(|&q| (points.reference[q] - x).amax() <= 1e-9 * h) {
                Some(q) => q,
                None => return false,
            };
        }
        // the sign of each unknown under the reflection: σ_rc flips with one index on l,
        // v_r flips for r = l
        let mut sign = Vec::with_capacity(per);
        for r in 0..D {
            for c in r..D {
                sign.push(if (r == l) != (c == l) { -1.0 } else { 1.0 });
            }
        }
        sign.extend((0..D).map(|r| if r == l { -1.0 } else { 1.0 }));
        let map = |i: usize| (mirror[i / per] * per + i % per, sign[i % per]);
        for (o, offset) in offsets.iter().enumerate() {
            let mut reflected = *offset;
            reflected[l] = -reflected[l];
            let Some(r) = offsets.iter().position(|x| *x == reflected) else {
                return false;
            };
            let (b, br) = (&matrices[o], &matrices[r]);
            for i in 0..b.nrows() {
                let (pi, si) = map(i);
                for j in 0..b.ncols() {
                    let (pj, sj) = map(j);
                    if (br[(pi, pj)] - si * sj * b[(i, j)]).abs() > tol {
                        return false;
                    }
                }
            }
        }
    }
    true
}

/// Largest spectral radius of `G(θ)` over the `samples^D` wave numbers of the grid (the
/// octant where the mirror symmetry holds, module doc; `None` if a complex Schur
/// decomposition does not converge within its iteration cap).
pub fn max_amplification<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    samples: usize,
) -> Option<f64> {
    let amplification = Amplification::new(problem, config);
    let thetas = amplification.wave_numbers(samples);
    amplification.max_radius(&thetas).map(|(rho, _)| rho)
}

/// The eigenvalues of `g` from its complex Schur form `T` (the diagonal of `T`). Where
/// nalgebra leaves a 2 × 2 block on the diagonal, its two eigenvalues are the roots of the
/// block's characteristic polynomial, `tr/2 ± sqrt(tr²/4 - det)`. Where the QR iteration
/// does not converge (measured: 3D donor-cell at its limit, θ = (0, 3π/2, 3π/2), a
/// defective matrix on which the shifts stall), the eigenvalues `μ - s` of the shifted
/// `g + s 1` (`s` = 0.25, 0.5 + 0.5i, 0.3i); `None` if none converges.
fn eigenvalues(g: DMatrix<Complex<f64>>) -> Option<Vec<Complex<f64>>> {
    let n = g.nrows();
    let shifts = [
        Complex::new(0.0, 0.0),
        Complex::new(0.25, 0.0),
        Complex::new(0.5, 0.5),
        Complex::new(0.0, 0.3),
    ];
    for shift in shifts {
        let shifted = if shift == Complex::new(0.0, 0.0) {
            g.clone()
        } else {
            &g + DMatrix::<Complex<f64>>::identity(n, n) * shift
        };
        let Some(schur) = nalgebra::linalg::Schur::try_new(shifted, 1e-14, 10_000) else {
            continue;
        };
        if let Some(e) = schur.eigenvalues() {
            return Some(e.iter().map(|z| z - shift).collect());
        }
        let (_, t) = schur.unpack();
        let mut out = Vec::with_capacity(n);
        let mut i = 0;
        while i < n {
            if i + 1 < n && t[(i + 1, i)].norm() > 0.0 {
                let (a, b, c, d) = (t[(i, i)], t[(i, i + 1)], t[(i + 1, i)], t[(i + 1, i + 1)]);
                let half = (a + d) * 0.5;
                let root = (half * half - (a * d - b * c)).sqrt();
                out.extend([half + root - shift, half - root - shift]);
                i += 2;
            } else {
                out.push(t[(i, i)] - shift);
                i += 1;
            }
        }
        return Some(out);
    }
    None
}

/// Von Neumann critical Courant number of DGMPM `config` (`NaN` if an eigenvalue
/// computation failed; 0 if unstable at every Courant number from 0.05): bisection to
/// 1.1e-5 (17 halvings of `[0.05, 1.5]`) on a few candidate wave numbers, then a check of
/// the whole sample at the limit found; a wave number unstable there joins the candidates
/// and the bisection runs again. The candidates start as the 8 worst at Courant 1.5. The
/// result is the limit over every sampled wave number, as a bisection over all of them
/// at each step would give, at the cost of a few whole samples instead of 18.
pub fn von_neumann_limit<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    samples: usize,
) -> f64 {
    let at = |c: f64| {
        let mut cfg = config;
        cfg.courant = c;
        Amplification::new(problem, cfg)
    };
    let top = at(1.5);
    let thetas = top.wave_numbers(samples);
    let radii: Option<Vec<f64>> = thetas.par_iter().map(|t| top.radius(t)).collect();
    let Some(radii) = radii else {
        return f64::NAN;
    };
    let mut order: Vec<usize> = (0..thetas.len()).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]));
    let mut candidates: Vec<[f64; D]> = order.iter().take(8).map(|&k| thetas[k]).collect();
    let failed = std::cell::Cell::new(false);
    for _ in 0..8 {
        let stable = |c: f64| {
            let a = at(c);
            candidates.iter().all(|t| match a.radius(t) {
                Some(rho) => rho <= 1.0 + 1e-9,
                None => {
                    failed.set(true);
                    false
                }
            })
        };
        // unstable even at the bracket's low end: 0 (e.g. Euler with the increment
        // update, whose excess amplification grows like C³ from 0)
        if !stable(0.05) {
            return if failed.get() { f64::NAN } else { 0.0 };
        }
        let limit = crate::stability::bisect(0.05, 1.5, 17, stable);
        if failed.get() {
            return f64::NAN;
        }
        if limit >= 1.5 {
            // the candidates are the worst at 1.5: every wave number is stable there
            return limit;
        }
        // the bisection's stable end, half its last bracket below the midpoint returned
        let stable_end = limit - 0.5 * 1.45 / f64::from(1u32 << 17);
        let check = at(stable_end);
        let radii: Option<Vec<f64>> = thetas.par_iter().map(|t| check.radius(t)).collect();
        let Some(radii) = radii else {
            return f64::NAN;
        };
        let unstable: Vec<[f64; D]> = (0..thetas.len())
            .filter(|&k| radii[k] > 1.0 + 1e-9 && !candidates.contains(&thetas[k]))
            .map(|k| thetas[k])
            .collect();
        if unstable.is_empty() {
            return limit;
        }
        candidates.extend(unstable);
    }
    // not settled in 8 rounds: the bisection on every wave number at each step
    let stable = |c: f64| {
        let a = at(c);
        match a.max_radius(&thetas) {
            Some((rho, _)) => rho <= 1.0 + 1e-9,
            None => {
                failed.set(true);
                false
            }
        }
    };
    let limit = if stable(0.05) {
        crate::stability::bisect(0.05, 1.5, 17, stable)
    } else {
        0.0
    };
    if failed.get() {
        f64::NAN
    } else {
        limit
    }
}

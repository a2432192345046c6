//! An independent von Neumann and monotonicity analysis of 1D DGMPM, written here from the
//! scheme's definition (paper §3-4) and sharing no code with `impact::stability` or
//! `impact::von_neumann` (which perturb the solver itself and measure its step matrices).
//!
//! Linear 1D elasticity splits into two characteristics `w± = v ∓ σ/Z` moving at `±c`;
//! the Godunov flux (paper §4) is upwind on each, and every phase of the scheme is linear
//! and the same for every component, so the scheme on the system is the scheme on the
//! scalar `u_t + c u_x = 0` for each characteristic (the left-going one sees the mirrored
//! layout `1 − ξ`). Units: `Δx = c = 1`, Courant `ν = Δt`. One cell holds the nodes `L`
//! (`S_L = 1 − ξ`) and `R` (`S_R = ξ`), discontinuous across faces, and `n` points at
//! `ξ_α` of equal volume `w = 1/n` (uniform density, so masses ∝ `w`):
//!
//! - points → nodes (paper eq. 17): `u_i = Σ_α S_iα w u_α / M_i`, `M_i = Σ_α S_iα w`
//!   (lumped mass, §3.2 remark): the 2 × n matrix `P`;
//! - nodal rates (paper eq. 16, `∂S_L/∂X = −1`, `∂S_R/∂X = 1`, the flux interpolated at
//!   the points, eq. 14-15; `U = Σ_α w u_h(ξ_α) = M_L u_L + M_R u_R`; upwind face flux:
//!   the left cell's `R` node): `M_L u̇_L = −U + e^{−iθ} u_R`, `M_R u̇_R = U − u_R`, i.e.
//!   `u̇ = (L₀ + e^{−iθ} L₁) u` on a Fourier mode `e^{ijθ}` over cells `j`;
//! - the nodal update, Euler `R = 1 + νL` or Heun (RK2) `R = 1 + νL + (νL)²/2`;
//! - nodes → points (eq. 14): `u_α = Σ_i S_iα u_i`, the n × 2 matrix `I`; the point takes
//!   the new nodal field (`nodal`) or adds the nodal increment (`increment`).
//!
//! One step on the points is `G = I R P` (nodal) or `G = 1 + I (R − 1) P` (increment).
//! `G` has rank 2 plus the identity at most, and the nonzero eigenvalues of `AB` are those
//! of `BA`, so its eigenvalues are those of the 2 × 2 `R (P I)` (or `1 +` those of
//! `(R − 1)(P I)`, plus eigenvalues 1), found by the quadratic formula: no iterative
//! eigen-solver. Extra zeros or ones never raise the spectral radius above 1, so they do
//! not move a limit.
use nalgebra::{Complex, DMatrix, Matrix2};

type C = Complex<f64>;

/// The scheme at one layout, integrator and point update.
pub struct Scheme {
    xi: Vec<f64>,
    rk2: bool,
    increment: bool,
}

impl Scheme {
    /// `xi`: the points' positions in the cell, in (0, 1).
    pub fn new(xi: Vec<f64>, rk2: bool, increment: bool) -> Self {
        Self { xi, rk2, increment }
    }

    /// The centred layout `ξ_α = (α + ½)/n`.
    pub fn centred(n: usize, rk2: bool, increment: bool) -> Self {
        Self::new(
            (0..n).map(|a| (a as f64 + 0.5) / n as f64).collect(),
            rk2,
            increment,
        )
    }

    fn mirrored(&self) -> Self {
        Self::new(
            self.xi.iter().rev().map(|x| 1.0 - x).collect(),
            self.rk2,
            self.increment,
        )
    }

    fn masses(&self) -> (f64, f64) {
        let w = 1.0 / self.xi.len() as f64;
        let ml: f64 = self.xi.iter().map(|x| w * (1.0 - x)).sum();
        let mr: f64 = self.xi.iter().map(|x| w * x).sum();
        (ml, mr)
    }

    /// `P` (2 × n) and `I` (n × 2).
    fn maps(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.xi.len();
        let w = 1.0 / n as f64;
        let (ml, mr) = self.masses();
        let p = DMatrix::from_fn(2, n, |i, a| {
            let s = if i == 0 { 1.0 - self.xi[a] } else { self.xi[a] };
            w * s / if i == 0 { ml } else { mr }
        });
        let interp = DMatrix::from_fn(
            n,
            2,
            |a, i| {
                if i == 0 {
                    1.0 - self.xi[a]
                } else {
                    self.xi[a]
                }
            },
        );
        (p, interp)
    }

    /// `(L₀, L₁)`: the nodal rates' coupling inside the cell and to the upwind cell.
    fn rates(&self) -> (Matrix2<f64>, Matrix2<f64>) {
        let (ml, mr) = self.masses();
        let l0 = Matrix2::new(-1.0, -mr / ml, ml / mr, (mr - 1.0) / mr);
        let l1 = Matrix2::new(0.0, 1.0 / ml, 0.0, 0.0);
        (l0, l1)
    }

    /// The spectral radius of one step at Courant `nu` and phase `theta`, for the
    /// right-going characteristic of this layout.
    fn radius_right(&self, nu: f64, theta: f64) -> f64 {
        let (p, interp) = self.maps();
        let pi = (&p * &interp).map(|x| C::new(x, 0.0));
        let pi = Matrix2::new(pi[(0, 0)], pi[(0, 1)], pi[(1, 0)], pi[(1, 1)]);
        let (l0, l1) = self.rates();
        let shift = C::new(0.0, -theta).exp();
        let l = l0.map(|x| C::new(nu * x, 0.0)) + l1.map(|x| C::new(nu * x, 0.0) * shift);
        let mut r = Matrix2::identity() + l;
        if self.rk2 {
            r += l * l * C::new(0.5, 0.0);
        }
        if self.increment {
            r -= Matrix2::identity();
        }
        let m = r * pi;
        let (tr, det) = (m[(0, 0)] + m[(1, 1)], m.determinant());
        let root = (tr * tr * 0.25 - det).sqrt();
        let offset = if self.increment { 1.0 } else { 0.0 };
        let radius = |lambda: C| (lambda + offset).norm();
        let mut rho = radius(tr * 0.5 + root).max(radius(tr * 0.5 - root));
        if self.increment && self.xi.len() > 2 {
            rho = rho.max(1.0);
        }
        rho
    }

    /// The largest spectral radius over `samples` phases in [0, 2π), both characteristics.
    pub fn max_radius(&self, nu: f64, samples: usize) -> f64 {
        let mirror = self.mirrored();
        (0..samples)
            .map(|k| {
                let theta = std::f64::consts::TAU * k as f64 / samples as f64;
                self.radius_right(nu, theta)
                    .max(mirror.radius_right(nu, theta))
            })
            .fold(0.0, f64::max)
    }

    /// The von Neumann limit: the first Courant number where the spectral radius exceeds
    /// `1 + 1e-9` (scanned in steps of 1/200 from 1/200 to 1.5, then bisected to 1e-9).
    pub fn von_neumann_limit(&self, samples: usize) -> f64 {
        first_failure(|nu| self.max_radius(nu, samples) <= 1.0 + 1e-9)
    }

    /// The largest row sum `Σ_β |D_αβ|` of the one-step operator on the points of a cell
    /// and of its upwind neighbour (`G = D₀ + e^{−iθ} D₁`), both characteristics.
    pub fn row_sum(&self, nu: f64) -> f64 {
        let right = |s: &Self| {
            let (p, interp) = s.maps();
            let (l0, l1) = s.rates();
            let to = |m: Matrix2<f64>| DMatrix::from_fn(2, 2, |i, j| m[(i, j)]);
            let n = s.xi.len();
            let identity = DMatrix::<f64>::identity(n, n);
            let d0 = if s.increment {
                &identity + &interp * to(l0 * nu) * &p
            } else {
                &interp * to(Matrix2::identity() + l0 * nu) * &p
            };
            let d1 = &interp * to(l1 * nu) * &p;
            (0..n)
                .map(|a| {
                    (0..n)
                        .map(|b| d0[(a, b)].abs() + d1[(a, b)].abs())
                        .sum::<f64>()
                })
                .fold(0.0, f64::max)
        };
        right(self).max(right(&self.mirrored()))
    }

    /// The monotonicity limit: the first Courant number with a row sum above `1 + 1e-12`
    /// (0 when the operator is not monotone at 1/200 already).
    pub fn monotonicity_limit(&self) -> f64 {
        first_failure(|nu| self.row_sum(nu) <= 1.0 + 1e-12)
    }
}

/// The first Courant number in (0, 1.5] where `ok` fails: a scan in steps of 1/200, then
/// bisection to 1e-9; 0 if it fails at 1/200, 1.5 if it never does.
fn first_failure(ok: impl Fn(f64) -> bool) -> f64 {
    let step = 1.0 / 200.0;
    if !ok(step) {
        return 0.0;
    }
    let mut lo = step;
    while ok(lo + step) {
        lo += step;
        if lo >= 1.5 {
            return 1.5;
        }
    }
    let mut hi = lo + step;
    while hi - lo > 1e-9 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

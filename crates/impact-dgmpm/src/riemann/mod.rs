//! Riemann solvers: pure functions with fixed signatures, each file tested alone against
//! hand-worked states (in the manner of clawpack's `riemann` package).
//!
//! - `linear`: the exact linear-elastic solver normal to a face, the Godunov flux and the
//!   fluctuations (paper §4, eqs. 18-21).
//! - [`axis`]: the same flux and the transverse solver written out for a grid-axis normal
//!   (the fused cell path's interior faces).
//! - `ghost`: ghost states and boundary half-problems (LeVeque 2002, §7.3), and the
//!   restriction of CTU corrections on boundary faces.
//! - `transverse`: the transverse solver of corner transport upwind (LeVeque 2002, §21.2).
//! - [`svk`]: Saint-Venant–Kirchhoff, approximate (acoustic, [`svk_approximate`]) and exact
//!   1D ([`svk_exact`]).
//!
//! A new solver goes in a file of its own here, with its formula and reference in its doc
//! and its tests at the end of the file; the flux phase ([`crate::fluxes`]) calls it.
//!
//! Notation (all files): `n` the unit normal pointing from the left state to the right
//! state, traction `t = σ n`, normal parts `t_n = n·t`, `v_n = n·v`, tangential parts
//! `t_t = t - t_n n`, `v_t = v - v_n n`.

pub mod axis;
pub mod elastoplastic;
mod ghost;
mod linear;
pub mod svk_approximate;
pub mod svk_exact;
mod transverse;

pub use ghost::{constrain_correction, ghost_full, ghost_state, GhostCondition};
pub use linear::{fluctuations, linear_elastic_star, normal_flux};
pub use transverse::{transverse_into_face, transverse_split};

/// Saint-Venant–Kirchhoff solvers (paper §4, §5.3) for the total Lagrangian system
/// `q = (F, ρ₀ v)`, `F_n(q) = -(v ⊗ n, Π(F) n)` (paper eq. 6).
pub mod svk {
    pub use super::svk_approximate::*;
    pub use super::svk_exact::*;
}

use impact_core::{Tensor, Vector};

/// Traction and velocity of one side of a face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceState<const D: usize> {
    /// Traction `σ n` on the face, with `n` from left to right.
    pub traction: Vector<D>,
    /// Velocity.
    pub velocity: Vector<D>,
}

/// Acoustic impedances of the two wave families.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedances {
    /// `Z_p = ρ c_p`.
    pub p: f64,
    /// `Z_s = ρ c_s` (0 in 1D: no shear wave).
    pub s: f64,
}

/// A vector of conserved quantities, or a flux or fluctuation in that space: `q = (σ, ρ v)`
/// in small strain (paper eq. 7), `q = (F, ρ₀ v)` under Saint-Venant–Kirchhoff (eq. 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conserved<const D: usize> {
    /// Tensor part (`σ` in small strain, `F` in large strain).
    pub tensor: Tensor<D>,
    /// Momentum part `ρ v`.
    pub momentum: Vector<D>,
}

impl<const D: usize> Conserved<D> {
    /// Zero.
    pub fn zeros() -> Self {
        Self {
            tensor: Tensor::<D>::zeros(),
            momentum: Vector::<D>::zeros(),
        }
    }
    /// `self + other * s`.
    #[inline]
    pub fn add_scaled(&self, other: &Self, s: f64) -> Self {
        Self {
            tensor: self.tensor + other.tensor * s,
            momentum: self.momentum + other.momentum * s,
        }
    }
}

/// A full state: the tensor field (`σ` in small strain, `F` in large strain) and velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullState<const D: usize> {
    /// `σ` (small strain) or `F` (Saint-Venant–Kirchhoff).
    pub tensor: Tensor<D>,
    /// Velocity `v`.
    pub velocity: Vector<D>,
}

impl<const D: usize> FullState<D> {
    /// Traction `σ n` and velocity on a face of normal `normal` (small strain).
    #[inline]
    pub fn on_face(&self, normal: &Vector<D>) -> FaceState<D> {
        FaceState {
            traction: self.tensor * normal,
            velocity: self.velocity,
        }
    }
}

/// Isotropic linear elasticity as the flux functions need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// `λ` (unused in 1D).
    pub lambda: f64,
    /// `μ` (in 1D the bar's `E/2`, so that `C(ε) = 2μ ε = E ε`).
    pub mu: f64,
    /// Density `ρ`.
    pub density: f64,
    /// Impedances.
    pub z: Impedances,
}

impl Elastic {
    /// `C : ε` (1D: `E ε`; 2D: `λ tr ε 1 + 2μ ε`).
    #[inline]
    pub fn stress<const D: usize>(&self, strain: &Tensor<D>) -> Tensor<D> {
        let mut s = strain * (2.0 * self.mu);
        if D > 1 {
            s += Tensor::<D>::identity() * (self.lambda * strain.trace());
        }
        s
    }
}

/// `sym(a ⊗ b)`.
#[inline]
pub(crate) fn sym<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> Tensor<D> {
    let outer = a * b.transpose();
    (outer + outer.transpose()) * 0.5
}

#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    pub fn steel() -> Elastic {
        let (e, nu, rho): (f64, f64, f64) = (2e11, 0.3, 7800.0);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        Elastic {
            lambda,
            mu,
            density: rho,
            z: Impedances {
                p: (rho * (lambda + 2.0 * mu)).sqrt(),
                s: (rho * mu).sqrt(),
            },
        }
    }

    pub fn sample() -> Conserved<2> {
        Conserved {
            tensor: Tensor::<2>::new(3.0e8, -1.0e8, -1.0e8, 2.0e8),
            momentum: Vector::<2>::new(4.0e4, -2.5e4),
        }
    }
}

//! Which computation a step runs ([`StepPath`]): the nodal phases, their one-point fast
//! path, their fused sweep, the cell path and its fused sweep.
use impact_core::method::Integrator;

/// Which computation a step runs. [`StepPath::fastest`] picks it; every path gives the
/// same result to round-off (tested).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepPath {
    /// Phases 1-5 on the DG nodes, with the general particles→nodes map.
    Nodal,
    /// Phases 1-5 on the DG nodes, one point per cell: particles→nodes copies the point's
    /// state (the mass-weighted map `Σ S m q / Σ S m` is the identity there) and only
    /// weighs the lumped masses.
    SinglePoint,
    /// Phases 2-4 of each stage in one sweep over the cell rows ([`crate::fused`]): linear
    /// elasticity (no elastoplastic Riemann solver), 1D or 2D ([`Fusable::All`]), any
    /// points per cell, Euler or RK2; no face or rate arrays. Phases 1 and 5 as [`StepPath::SinglePoint`] with one
    /// point per cell, as [`StepPath::Nodal`] otherwise. RK2 at one point per cell with
    /// every point strictly inside its cell: two cell sweeps, no nodal field (`fused/heun.rs`).
    FusedNodal,
    /// One point per cell strictly inside its cell, forward Euler: the step reduces exactly
    /// to the cell-centred Godunov update ([`crate::DgmpmSolver::cell_update`]); no nodal buffer.
    Cell,
    /// The cell path with its phases fused into one sweep ([`crate::fused`]): linear elasticity
    /// (no elastoplastic Riemann solver), 1D, 2D or 3D ([`Fusable::Cell`] or more); no
    /// face arrays.
    Fused,
}

/// Which fused sweeps a solver's model and dimension allow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fusable {
    /// None (large strain, the elastoplastic Riemann solver).
    No,
    /// The cell path's sweep only (linear elasticity in 3D).
    Cell,
    /// The cell path's and the nodal stages' (linear elasticity in 1D and 2D).
    All,
}

impl Fusable {
    /// The fused sweeps in `dim` dimensions for a model that is (`linear`) or is not
    /// small-strain linear elasticity with the linear Riemann solver.
    pub(crate) fn of(dim: usize, linear: bool) -> Self {
        match (linear, dim) {
            (false, _) => Fusable::No,
            (true, 1 | 2) => Fusable::All,
            (true, _) => Fusable::Cell,
        }
    }
}

impl StepPath {
    /// Whether `self` applies to `points_per_cell` points per cell with `integrator`;
    /// `inside` tells whether every shape function value at the points is positive (the
    /// cell path needs every lumped mass `S_a m > 0`: a point strictly inside its cell);
    /// `fusable`: which fused sweeps the model and the dimension allow.
    pub fn applies(
        self,
        points_per_cell: usize,
        integrator: Integrator,
        inside: bool,
        fusable: Fusable,
    ) -> bool {
        match self {
            StepPath::Nodal => true,
            StepPath::SinglePoint => points_per_cell == 1,
            StepPath::FusedNodal => fusable == Fusable::All,
            StepPath::Cell => points_per_cell == 1 && integrator == Integrator::Euler && inside,
            StepPath::Fused => {
                fusable != Fusable::No
                    && StepPath::Cell.applies(points_per_cell, integrator, inside, fusable)
            }
        }
    }

    /// The fastest path that applies.
    pub fn fastest(
        points_per_cell: usize,
        integrator: Integrator,
        inside: bool,
        fusable: Fusable,
    ) -> Self {
        [
            StepPath::Fused,
            StepPath::Cell,
            StepPath::FusedNodal,
            StepPath::SinglePoint,
            StepPath::Nodal,
        ]
        .into_iter()
        .find(|p| p.applies(points_per_cell, integrator, inside, fusable))
        .unwrap_or(StepPath::Nodal)
    }

    /// Whether the path stores nodal fields.
    pub fn nodal(self) -> bool {
        !matches!(self, StepPath::Cell | StepPath::Fused)
    }

    /// Whether the path runs a fused sweep (no face arrays).
    pub fn fused(self) -> bool {
        matches!(self, StepPath::Fused | StepPath::FusedNodal)
    }
}

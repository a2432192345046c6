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
    /// elasticity (no elastoplastic Riemann solver), 1D or 2D, any points per cell, Euler or
    /// RK2; no face or rate arrays. Phases 1 and 5 as [`StepPath::SinglePoint`] with one
    /// point per cell, as [`StepPath::Nodal`] otherwise.
    FusedNodal,
    /// One point per cell strictly inside its cell, forward Euler: the step reduces exactly
    /// to the cell-centred Godunov update ([`crate::DgmpmSolver::cell_update`]); no nodal buffer.
    Cell,
    /// The cell path with its phases fused into one sweep ([`crate::fused`]): linear elasticity
    /// (no elastoplastic Riemann solver), 1D or 2D; no face arrays.
    Fused,
}

impl StepPath {
    /// Whether `self` applies to `points_per_cell` points per cell with `integrator`;
    /// `inside` tells whether every shape function value at the points is positive (the
    /// cell path needs every lumped mass `S_a m > 0`: a point strictly inside its cell);
    /// `fusable`: linear elasticity without the elastoplastic Riemann solver, in 1D or 2D.
    pub fn applies(
        self,
        points_per_cell: usize,
        integrator: Integrator,
        inside: bool,
        fusable: bool,
    ) -> bool {
        match self {
            StepPath::Nodal => true,
            StepPath::SinglePoint => points_per_cell == 1,
            StepPath::FusedNodal => fusable,
            StepPath::Cell => points_per_cell == 1 && integrator == Integrator::Euler && inside,
            StepPath::Fused => {
                fusable && StepPath::Cell.applies(points_per_cell, integrator, inside, fusable)
            }
        }
    }

    /// The fastest path that applies.
    pub fn fastest(
        points_per_cell: usize,
        integrator: Integrator,
        inside: bool,
        fusable: bool,
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

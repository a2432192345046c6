//! Which computation a step runs ([`StepPath`]): the nodal phases, their one-point fast
//! path, the cell path and its fused sweep.
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
}

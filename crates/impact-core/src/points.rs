//! Material points as a struct of arrays.
use crate::{Grid, Tensor, Vector};

/// Material points (struct of arrays). `reference` is the position in the reference
/// configuration (the material coordinate `X`), `position` the current one.
#[derive(Debug, Clone, Default)]
pub struct MaterialPoints<const D: usize> {
    /// Reference position `X_α`.
    pub reference: Vec<Vector<D>>,
    /// Current position `x_α`.
    pub position: Vec<Vector<D>>,
    /// Mass `m_α`.
    pub mass: Vec<f64>,
    /// Current volume `V_α` (reference volume for the total Lagrangian DGMPM).
    pub volume: Vec<f64>,
    /// Velocity `v_α`.
    pub velocity: Vec<Vector<D>>,
    /// Cauchy stress `σ_α` (small strain).
    pub stress: Vec<Tensor<D>>,
    /// Half-size of the point's domain along each axis (for the exact cell averages).
    pub half_size: Vec<Vector<D>>,
    /// Deformation gradient `F` (large-strain models only; empty otherwise).
    pub deformation: Vec<Tensor<D>>,
}

impl<const D: usize> MaterialPoints<D> {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Allocate the deformation gradients (`F = 1`) for a large-strain model.
    pub fn with_deformation(mut self) -> Self {
        self.deformation = vec![Tensor::<D>::identity(); self.len()];
        self
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// `per_axis^D` points per cell of `grid` for every cell, at the centres of the
    /// sub-cells, each carrying the sub-cell's mass `ρ V_cell / per_axis^D`. Points are
    /// stored cell by cell: the points of cell `c` are `c*n .. (c+1)*n` with `n = per_axis^D`.
    pub fn regular(grid: &Grid<D>, per_axis: usize, density: f64) -> Self {
        let per_cell = per_axis.pow(D as u32);
        let n = grid.cell_count() * per_cell;
        let volume = grid.cell_volume() / per_cell as f64;
        let sub = grid.spacing / per_axis as f64;
        let mut points = Self {
            reference: Vec::with_capacity(n),
            position: Vec::with_capacity(n),
            mass: vec![density * volume; n],
            volume: vec![volume; n],
            velocity: vec![Vector::<D>::zeros(); n],
            stress: vec![Tensor::<D>::zeros(); n],
            half_size: vec![sub * 0.5; n],
            deformation: Vec::new(),
        };
        for c in 0..grid.cell_count() {
            let lower = grid.cell_lower(c);
            for k in 0..per_cell {
                let mut rest = k;
                let mut x = lower;
                for l in 0..D {
                    x[l] += ((rest % per_axis) as f64 + 0.5) * sub[l];
                    rest /= per_axis;
                }
                points.reference.push(x);
                points.position.push(x);
            }
        }
        points
    }
}

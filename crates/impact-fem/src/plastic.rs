//! J2 plasticity at the Gauss points (issue 12): each Gauss point keeps its stress, its
//! total strain at the last update and its plastic history (a [`MaterialPoints`] set used
//! for the arrays only). Each step, before the internal forces, the strain increment
//! `Δε = sym ∇u^{n+1} − ε^n` gives the elastic trial `σ^n + C : Δε` (plane strain: `σ_zz`
//! from `ε^p_zz`, `impact_core::plasticity::J2::out_of_plane`), which the radial return
//! corrects (`J2::correct_points`); the forces then read the stored stresses.
use crate::{FemSolver, CHUNK, MAX_NODES};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::plasticity::J2;
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

/// Gauss-point state of a J2 FEM run.
#[derive(Debug, Clone)]
pub struct GaussPlasticity<const D: usize> {
    /// The material.
    pub j2: J2,
    /// Stress and plastic history per Gauss point (element `c`, point `q` at `c·2^D + q`).
    pub points: MaterialPoints<D>,
    /// Total strain per Gauss point at the last update.
    pub strain: Vec<Tensor<D>>,
}

impl<const D: usize> GaussPlasticity<D> {
    /// Zero stress and history at `gauss_points` points.
    pub fn new(j2: J2, gauss_points: usize) -> Self {
        let points = MaterialPoints::<D> {
            mass: vec![0.0; gauss_points],
            stress: vec![Tensor::<D>::zeros(); gauss_points],
            ..Default::default()
        }
        .with_plasticity();
        Self {
            j2,
            points,
            strain: vec![Tensor::<D>::zeros(); gauss_points],
        }
    }
}

impl<const D: usize> FemSolver<D> {
    /// The elastic trial at every Gauss point from the new displacement, then the return
    /// map (module doc). Elements in parallel over disjoint chunks.
    pub(crate) fn update_gauss_stresses(&mut self, displacement: &[Vector<D>]) {
        let Some(mut plastic) = self.plastic.take() else {
            return;
        };
        let npc = Grid::<D>::NODES_PER_CELL;
        let this = &*self;
        let per_chunk = (CHUNK / npc).max(1) * npc;
        let parts = (
            chunks(&mut plastic.points.stress, per_chunk),
            chunks(&mut plastic.strain, per_chunk),
        );
        for_each_chunk(this.parallel, 1, parts, |r, (stress, strain)| {
            let first = r * per_chunk / npc;
            for (k, (sigma, eps)) in stress
                .chunks_mut(npc)
                .zip(strain.chunks_mut(npc))
                .enumerate()
            {
                let nodes: [usize; MAX_NODES] = this.element_nodes(first + k);
                for q in 0..npc {
                    let g = &this.gauss_gradient[q * npc..(q + 1) * npc];
                    let grad = Self::displacement_gradient(displacement, &nodes, g);
                    let total = (grad + grad.transpose()) * 0.5;
                    sigma[q] += this.material.stress(&(total - eps[q]));
                    eps[q] = total;
                }
            }
        });
        plastic
            .j2
            .correct_points(&mut plastic.points, self.parallel);
        self.plastic = Some(plastic);
    }
}

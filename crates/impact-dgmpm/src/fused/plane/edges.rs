//! The 2D sweeps' edge faces (module doc of [`super::super`], `fused/mod.rs`): the ghost
//! cells' y-fluctuations behind the x-edges down their columns, an x-edge face's final
//! flux, and a boundary face's CTU correction by the axis transverse solver.
use super::Sweep2d;
use crate::faces::Fields;
use crate::riemann::axis::axis_transverse_2d;
use crate::riemann::{constrain_correction, Conserved};
use crate::{unit, DgmpmSolver};
use impact_core::method::EdgeTreatment;
use impact_core::Vector;

impl DgmpmSolver<2> {
    /// Under CTU at order 1, the y-fluctuations of the ghost cells behind the low and high
    /// x-edges on cell row `j`, down their columns with the rows
    /// ([`Self::ghost_column_fluctuation`], `carry` per edge); otherwise `None`, and
    /// `face_correction` forms them per face.
    #[inline]
    pub(in crate::fused) fn x_edge_ghosts(
        &self,
        j: usize,
        fields: Fields<'_, 2>,
        ctu: bool,
        carry: &mut [Option<(usize, Conserved<2>)>; 2],
    ) -> [Option<Conserved<2>>; 2] {
        if !ctu || !self.wave_flux[1].is_empty() {
            return [None, None];
        }
        let last = self.grid.cells[0] - 1;
        let [low, high] = carry;
        [(0, low), (1, high)].map(|(side, carry)| {
            let cell = [side * last, j];
            Some(self.ghost_column_fluctuation((0, side, 1), cell, fields, carry))
        })
    }
}

impl DgmpmSolver<2> {
    /// The final flux of the x-edge face `idx` (`i = 0` or `nx`) from its Godunov flux,
    /// adding its force to `force`: under CTU (`w`, the y-fluctuations of the cells on
    /// either side, a ghost cell's `None` where the sweep did not form it) corrected by
    /// [`Self::edge_correction`], or by `face_correction` (which forms the ghost's).
    #[inline(always)]
    pub(in crate::fused) fn x_edge_flux(
        &self,
        idx: [usize; 2],
        godunov: Conserved<2>,
        w: Option<[Option<Conserved<2>>; 2]>,
        (fields, k): (Fields<'_, 2>, &Sweep2d),
        force: &mut Vector<2>,
    ) -> Conserved<2> {
        let flux = match w {
            Some([Some(low), Some(high)]) => {
                godunov.add_scaled(&self.edge_correction::<0>(idx, [low, high], k), 1.0)
            }
            Some(w) => {
                let correction = self.face_correction(0, idx, w, fields, k.scale[0]);
                godunov.add_scaled(&correction, 1.0)
            }
            None => godunov,
        };
        *force += self.boundary_face_force(0, idx, &flux);
        flux
    }

    /// The CTU correction of the boundary face `idx` normal to `e_K` from the fluctuations
    /// of the cells below and above it, a ghost cell's formed by the sweep
    /// ([`Self::x_edge_ghosts`], [`Self::ghost_row_fluctuations`]): `face_correction`'s
    /// with the axis transverse solver ([`axis_transverse_2d`]), restricted to what the
    /// edge's condition leaves free (`restricted` edges). The axis solver leaves out only
    /// products by a zero component of `n = e_K`, which add `±0` in
    /// `transverse_into_face`: the same values but for the sign of a zero (outputs
    /// compared bit for bit, `benchmarks/compare/dgmpm_edges.txt`).
    #[inline]
    pub(in crate::fused) fn edge_correction<const K: usize>(
        &self,
        idx: [usize; 2],
        [below, above]: [Conserved<2>; 2],
        k: &Sweep2d,
    ) -> Conserved<2> {
        let total = axis_transverse_2d::<K>(&below, &above, &k.constants);
        let correction = Conserved::zeros().add_scaled(&total, -k.scale[K]);
        let on_edge = idx[K] == 0 || idx[K] == self.grid.cells[K];
        if on_edge && self.options.edges == EdgeTreatment::Restricted {
            let side = usize::from(idx[K] != 0);
            let condition = self.edge_condition(K, side, &idx);
            return constrain_correction(&correction, &unit::<2>(K), condition);
        }
        correction
    }
}

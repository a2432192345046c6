//! Phase 2b (2D, CTU only): corner transport upwind corrections (LeVeque 2002, §21.2);
//! 3D in `ctu3.rs`.
use crate::faces::Fields;
use crate::riemann::{
    constrain_correction, fluctuations, linear_elastic_star, normal_flux, transverse_into_face,
    Conserved, FullState, GhostCondition,
};
use crate::{unit, DgmpmSolver, CHUNK};
use impact_core::method::EdgeTreatment;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::Grid;

mod ghost_row;

impl<const D: usize> DgmpmSolver<D> {
    /// Fluctuations `(A⁻Δq, A⁺Δq)` of the face between `left` and `right` (normal `e_l`;
    /// a missing side the ghost through the condition of the edge at the tangential
    /// position of the cell or face `at`, [`Self::edge_condition`]).
    #[inline]
    pub(crate) fn face_fluctuations(
        &self,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        at: &[usize; D],
    ) -> (Conserved<D>, Conserved<D>) {
        let e = unit::<D>(l);
        let (a, b) = self.face_pair_at(l, left, right, at);
        let (fa, fb) = (a.on_face(&e), b.on_face(&e));
        let star = linear_elastic_star(&fa, &fb, &e, self.elastic.z);
        fluctuations(&fa, &fb, &star, &e, &self.elastic)
    }

    /// Phase 2b (2D, CTU only): corner transport upwind (LeVeque 2002, §21.2). The
    /// fluctuation entering cell `C` through a face normal to `e_l` is split by the
    /// transverse solver (`riemann::transverse_split`, applied as
    /// [`transverse_into_face`]) along `e_k`, and its up- and down-going parts correct the
    /// fluxes of `C`'s faces normal to `e_k`:
    /// `F_k(C, high) -= Δt/(2Δx_l) B⁺A^±Δq`, `F_k(C, low) -= Δt/(2Δx_l) B⁻A^±Δq`.
    /// Cells outside an edge are ghost cells (mirror states through the edge's condition),
    /// so a plane wave along an edge stays plane.
    ///
    /// The fluctuations entering a cell through its two `l`-faces add up to
    /// `A⁺Δq_low + A⁻Δq_high = F*_high - F*_low + F(q_C,low) - F(q_C,high)` (with `q_C,side`
    /// the cell's state on that face), so they are formed from the stored Godunov fluxes;
    /// on the cell path the last two terms cancel.
    ///
    /// Every correction must read uncorrected fluxes, and the corrections of the faces
    /// normal to `e_k` read only the fluxes of the other axis `e_l`. So in 2D the last
    /// axis's corrections go to one scratch array (they read the first axis's fluxes), the
    /// first axis's are then added to its fluxes in place (they read the last axis's, still
    /// uncorrected), and last the scratch is added to the last axis's fluxes: one face
    /// array of scratch instead of a correction array per axis (48 B per cell less), and
    /// `face_flux` ends holding the final fluxes, bit for bit `F + correction`.
    /// In 3D: `transverse_corrections_3d` (file `ctu3.rs`) (transverse and transverse-transverse).
    pub fn transverse_corrections(&mut self, points: &MaterialPoints<D>, dt: f64) {
        if D == 3 {
            return self.transverse_corrections_3d(points, dt);
        }
        let last = D - 1;
        let order = std::iter::once((last, false)).chain((0..last).map(|k| (k, true)));
        for (k, in_place) in order {
            if !self.path.nodal() {
                self.transverse_corrections_axis::<true>(k, points, dt, in_place);
            } else {
                self.transverse_corrections_axis::<false>(k, points, dt, in_place);
            }
        }
        let mut scratch = std::mem::take(&mut self.correction_scratch);
        let mut fluxes = std::mem::take(&mut self.face_flux[last]);
        if scratch.len() == fluxes.len() {
            for_each_chunk(
                self.parallel,
                1,
                (chunks(&mut fluxes, CHUNK), chunks(&mut scratch, CHUNK)),
                |_, (f, c)| {
                    for (f, c) in f.iter_mut().zip(c.iter()) {
                        *f = f.add_scaled(c, 1.0);
                    }
                },
            );
        }
        self.face_flux[last] = fluxes;
        self.correction_scratch = scratch;
    }

    /// [`Self::transverse_corrections`] of the faces normal to `e_k`; `PER_CELL`: the
    /// cell path (compiled apart so that its kernel carries no nodal branch). 2D: `e_l` is
    /// the one transverse axis of `e_k`; 3D takes `ctu3.rs` (transverse-transverse terms,
    /// LeVeque 2002, §21.6; Clawpack's `rptt3`).
    /// `in_place`: add the corrections to the axis's fluxes; otherwise write them to the
    /// scratch array.
    fn transverse_corrections_axis<const PER_CELL: bool>(
        &mut self,
        k: usize,
        points: &MaterialPoints<D>,
        dt: f64,
        in_place: bool,
    ) {
        {
            let Some(l) = Grid::<D>::segment_axis(k) else {
                return;
            };
            let scale = dt / (2.0 * self.grid.spacing[l]);
            let mut corrections = match in_place {
                true => std::mem::take(&mut self.face_flux[k]),
                false => std::mem::take(&mut self.correction_scratch),
            };
            let this = &*self;
            let fields = this.fields(points);
            let l_fluxes = &this.face_flux[l];
            // order 2: the corrections F̃ of the l-faces (in `l_fluxes` once; Clawpack splits
            // the fluctuations with `cqxx = 2 F̃` added, so once more here)
            let l_waves = &this.wave_flux[l];
            // strides of the l-face array: a cell's low l-face is Σ_m c_m stride_m, its high
            // one `stride_l` further (index arithmetic only: writing a multi-index entry
            // picked at run time stalls store forwarding in this loop)
            let stride: [usize; D] = std::array::from_fn(|m| {
                (0..m)
                    .map(|p| this.grid.cells[p] + usize::from(p == l))
                    .product()
            });
            let kernel = |idx: [usize; D], out: &mut Conserved<D>| {
                let base: usize = Grid::<D>::tangent_axes(k).map(|m| idx[m] * stride[m]).sum();
                // the fluctuations of the cell below the face (side 0: their B⁺ part counts)
                // and above (side 1: B⁻); a ghost cell's are formed by `face_correction`
                let w_of = |side: usize| {
                    let j = idx[k] as isize - 1 + side as isize;
                    let inside = j >= 0 && (j as usize) < this.grid.cells[k];
                    inside.then(|| {
                        let lo = base + j as usize * stride[k];
                        let mut w = l_fluxes[lo + stride[l]].add_scaled(&l_fluxes[lo], -1.0);
                        if !l_waves.is_empty() {
                            w = w
                                .add_scaled(&l_waves[lo + stride[l]], 1.0)
                                .add_scaled(&l_waves[lo], -1.0);
                        }
                        if PER_CELL {
                            w
                        } else {
                            let mut cell = idx;
                            cell[k] = j as usize;
                            w.add_scaled(&this.side_flux_difference(fields, cell, l), 1.0)
                        }
                    })
                };
                let w_side = [w_of(0), w_of(1)];
                let correction = this.face_correction(k, idx, w_side, fields, scale);
                *out = match in_place {
                    true => out.add_scaled(&correction, 1.0),
                    false => correction,
                };
            };
            this.sum_over_faces(k, &mut corrections, |idx, out| {
                kernel(idx, out);
                0.0
            });
            match in_place {
                true => self.face_flux[k] = corrections,
                false => self.correction_scratch = corrections,
            }
        }
    }

    /// The CTU correction of the face of axis `k` with multi-index `idx`:
    /// `-scale (B⁺ w_below + B⁻ w_above)` ([`transverse_into_face`]), `scale = Δt/(2Δx_l)`,
    /// from the `l`-fluctuations `w` of the cells below and above the face along `e_k`
    /// (`None`: the ghost cell behind the edge, whose fluctuations are formed here); on an
    /// edge face restricted to what the edge's condition leaves free (Clawpack's
    /// ghost-cell-only treatment leaves it).
    #[inline(always)]
    pub(crate) fn face_correction(
        &self,
        k: usize,
        idx: [usize; D],
        w: [Option<Conserved<D>>; 2],
        fields: Fields<'_, D>,
        scale: f64,
    ) -> Conserved<D> {
        let Some(l) = Grid::<D>::segment_axis(k) else {
            return Conserved::zeros();
        };
        let n_k = unit::<D>(k);
        let ghost = |side: usize| {
            // ghost cell behind the edge of axis k on this side
            let j = idx[k] as isize - 1 + side as isize;
            let mut cell = idx;
            cell[k] = j.clamp(0, self.grid.cells[k] as isize - 1) as usize;
            let (m_in, p_in) = self.ghost_cell_fluctuations(k, side, l, cell, fields);
            let w = m_in.add_scaled(&p_in, 1.0);
            if self.wave_flux[l].is_empty() {
                return w;
            }
            // order 2 (Clawpack's `amdq += cqxx`, `apdq −= cqxx`, `cqxx = 2 F̃`): the ghost
            // row's corrections, dropped where the fluctuation is (a traction corner)
            let (low, high) = self.ghost_cell_corrections(k, side, l, cell, fields, 2.0 * scale);
            let [drop_low, drop_high] = self.dropped_corner_faces(k, side, l, cell);
            let w = if drop_low {
                w
            } else {
                w.add_scaled(&low, -2.0)
            };
            if drop_high {
                w
            } else {
                w.add_scaled(&high, 2.0)
            }
        };
        let w_side = [
            w[0].unwrap_or_else(|| ghost(0)),
            w[1].unwrap_or_else(|| ghost(1)),
        ];
        let total = transverse_into_face(&w_side[0], &w_side[1], &n_k, &self.elastic);
        let correction = Conserved::<D>::zeros().add_scaled(&total, -scale);
        let on_edge = idx[k] == 0 || idx[k] == self.grid.cells[k];
        if on_edge && self.options.edges == EdgeTreatment::Restricted {
            let side = usize::from(idx[k] != 0);
            let cond = self.edge_condition(k, side, &idx);
            return constrain_correction(&correction, &n_k, cond);
        }
        correction
    }

    /// Whether the ghost cell mirroring `cell` through the edge of axis `k` at `side` has
    /// its low and high `l`-face dropped (`ghost_cell_fluctuations`: under `restricted`
    /// edges, the face towards the diagonal ghost at a corner of two traction edges).
    pub(crate) fn dropped_corner_faces(
        &self,
        k: usize,
        side: usize,
        l: usize,
        cell: [usize; D],
    ) -> [bool; 2] {
        let traction = |axis: usize, axis_side: usize| {
            matches!(
                self.edge_condition(axis, axis_side, &cell),
                GhostCondition::Traction(_)
            )
        };
        let restricted = self.options.edges == EdgeTreatment::Restricted;
        let corner = |l_side: usize| restricted && traction(k, side) && traction(l, l_side);
        [
            cell[l] == 0 && corner(0),
            cell[l] + 1 == self.grid.cells[l] && corner(1),
        ]
    }

    /// `F(q_C,low) - F(q_C,high) = F(q_C,low - q_C,high)` (the flux is linear): the
    /// difference of the normal fluxes (`e_l`) of cell `C`'s states on its low and high
    /// `l`-faces (nodal path only; kept out of line so the cell path's kernel stays small).
    #[inline(never)]
    pub(crate) fn side_flux_difference(
        &self,
        fields: Fields<'_, D>,
        cell: [usize; D],
        l: usize,
    ) -> Conserved<D> {
        let e_l = unit::<D>(l);
        let c = self.grid.cell_index(cell);
        // the normal flux is linear in the state: one flux of the difference of the states
        let (low, high) = (fields.side(c, l, false), fields.side(c, l, true));
        let difference = FullState {
            tensor: low.tensor - high.tensor,
            velocity: low.velocity - high.velocity,
        };
        normal_flux(&difference.on_face(&e_l), &e_l, &self.elastic)
    }
}

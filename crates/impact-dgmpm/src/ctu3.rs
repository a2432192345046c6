//! Phase 2b in 3D (CTU only): corner transport upwind with the transverse and the
//! transverse-transverse corrections (Langseth & LeVeque 2000, "A wave propagation method
//! for three-dimensional hyperbolic conservation laws", J. Comput. Phys. 165; LeVeque 2002
//! §21.6; Clawpack's `flux3` with `rpt3`/`rptt3`, `method(3) = 11`).
//!
//! With `W_l(X) = A⁺Δq_low + A⁻Δq_high` the fluctuations entering cell `X` through its two
//! faces normal to `e_l` (as in 2D, [`crate::ctu`]), `B_k^±` the transverse solver along
//! `e_k` (`riemann::transverse_split`) and, for the face normal to `e_k` between the cells
//! `D` (below) and `U` (above) and the two other axes `l`, `m`, Clawpack's scatter
//! - transverse: `F_k(X, high) -= Δt/(2Δx_l) B_k⁺ W_l(X)`, `F_k(X, low) -= Δt/(2Δx_l) B_k⁻ W_l(X)`;
//! - transverse-transverse (the part of `W_l` that crossed an `m`-face of `X` on its way):
//!   `F_k(X, high) += s (B_k⁺C_m⁺ - B_k⁺C_m⁻) W_l(X)`, `F_k(X + e_m, high) -= s B_k⁺C_m⁺ W_l(X)`,
//!   `F_k(X - e_m, high) += s B_k⁺C_m⁻ W_l(X)` (and `low`, `B_k⁻`, likewise), with
//!   `s = Δt²/(6 Δx_l Δx_m)` and `C_m^±` the transverse solver along `e_m`;
//!
//! gathered on the face and using that every solver is linear, is one transverse solve
//! `F_k += B_k⁺ V_k(D) + B_k⁻ V_k(U)` (`riemann::transverse_into_face`, written out for
//! `n = e_k` in [`axis_transverse`]) of the per-cell source
//! `V_k(X) = -Σ_{l≠k} Δt/(2Δx_l) W_l(X)
//!     + s [C_m⁺(W_l(X) - W_l(X - e_m)) + C_m⁻(W_l(X + e_m) - W_l(X))]
//!     + s [C_l⁺(W_m(X) - W_m(X - e_l)) + C_l⁻(W_m(X + e_l) - W_m(X))]`.
//! Every `W_l` (ghost layers included) is formed from the uncorrected fluxes first (three
//! arrays, each `W` formed once: reading them in the sources costs a sixth of forming
//! them there); then per axis the sources `V_k` (one scratch array) and the corrections,
//! added in place.
//!
//! Edges: cells outside one edge are ghost cells, their fluctuations formed from the
//! mirror states through the edge's condition as in 2D (`ghost_cell_fluctuations`);
//! behind an edge of two axes (needed by the transverse-transverse terms only) the
//! ghost's fluctuations are the mirror of the single ghost's through a symmetry edge,
//! and otherwise the mean of the two single ghosts' (zero gradient along each edge in
//! turn, averaged so that neither axis is preferred: a centred square impact keeps its
//! y ↔ z symmetry, `tests/three_d.rs`). Under
//! `edges = "restricted"` the correction on an edge face is restricted to what the edge's
//! condition leaves free ([`constrain_correction`]), as in 2D.
//!
//! **Order 2** (`order = 2`, as Clawpack's `flux3` with `method = (2, 22)`, the
//! recommended second-order CTU, stable to Courant 1): with `F̃` the correction fluxes of
//! [`crate::wave_correction`] (added to the face fluxes before this phase, `cqxx = F̃` in
//! `flux3`) and `G_l(X) = F̃_l(X, high) − F̃_l(X, low)`, the transverse terms split
//! `A⁻ΔQ + 2cqxx` and `A⁺ΔQ − 2cqxx` (flux3's `gadd −= ½Δt/Δx B^±A^±ΔQ` and
//! `gadd ± Δt/Δx B^± cqxx`), and the transverse-transverse terms `A⁻ΔQ + 3cqxx` and
//! `A⁺ΔQ − 3cqxx` (flux3's `cpapdq2 = cpapdq − 3 cpcqxxp`, `cpamdq2 = cpamdq + 3 cpcqxxm`,
//! and the same for `bpapdq` before the H fluxes). Summed over a cell's two `l`-faces,
//! `V_k` takes `W_l + 2G_l` in its first terms and `W_l + 3G_l` in the `s` terms. The
//! arrays `W_l` hold `W_l + 3G_l` (the stored fluxes already carry `F̃` once, so `+ 2G_l`
//! inside; `+ 3G_l` on a ghost cell, whose fluctuations come from its states) and `G_l`
//! beside it; `V_k = V_k(W + 3G) + Δt/(2Δx_l) G_l + Δt/(2Δx_m) G_m`. A ghost cell's `G_l`
//! comes from its ghost row's waves ([`DgmpmSolver::ghost_cell_corrections`], the face
//! dropped at a restricted traction corner dropping its `F̃`, as in 2D), behind two edges
//! by the same mirror-or-mean rule as `W_l`. Order 2 never takes the fused sweep.
//!
//! The fused 3D sweep (`fused/block/ctu.rs`, the default at one point per cell with
//! Euler) forms the same values layer by layer through [`source_of`] and
//! `DgmpmSolver::ghost_fluctuation`, bit for bit these arrays' results.
use crate::faces::Fields;
use crate::riemann::axis::{axis_transverse, AxisConstants};
use crate::riemann::{constrain_correction, Conserved};
use crate::{unit, DgmpmSolver, CHUNK};
use impact_core::method::EdgeTreatment;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::problem::Boundary;

/// The mirror of `w` through a plane normal to `e_b`: `(M W M, M m)`, `M = 1 - 2 e_b ⊗ e_b`
/// (the fluctuations of the mirror cell behind a symmetry edge).
#[inline]
fn mirror<const D: usize>(w: &Conserved<D>, b: usize) -> Conserved<D> {
    let mut out = *w;
    for i in 0..D {
        if i != b {
            out.tensor[(i, b)] = -out.tensor[(i, b)];
            out.tensor[(b, i)] = -out.tensor[(b, i)];
        }
    }
    out.momentum[b] = -out.momentum[b];
    out
}

impl<const D: usize> DgmpmSolver<D> {
    /// Dimensions of the source array `V_k`: the cells plus a ghost layer at each end of
    /// axis `k`.
    pub(crate) fn source_dims(&self, k: usize) -> [usize; D] {
        std::array::from_fn(|j| self.grid.cells[j] + 2 * usize::from(j == k))
    }

    /// Dimensions of the fluctuation array `W_l`: the cells plus a ghost layer at each end
    /// of every other axis.
    fn fluctuation_dims(&self, l: usize) -> [usize; D] {
        std::array::from_fn(|j| self.grid.cells[j] + 2 * usize::from(j != l))
    }

    /// Phase 2b in 3D (module doc): the fluctuations `W_l` of every cell and ghost cell
    /// from the uncorrected fluxes (one array per axis), then per axis `k` the sources
    /// `V_k` (one scratch array) and `F_k += B_k⁺ V_k(D) + B_k⁻ V_k(U)` on every face
    /// normal to `e_k` (restricted on an edge face under `edges = "restricted"`).
    pub(crate) fn transverse_corrections_3d(&mut self, points: &MaterialPoints<D>, dt: f64) {
        let mut fluct = std::mem::replace(
            &mut self.transverse_sources,
            std::array::from_fn(|_| Vec::new()),
        );
        let order2 = !self.wave_flux[0].is_empty();
        for (l, w) in fluct.iter_mut().enumerate() {
            let dims = self.fluctuation_dims(l);
            let this = &*self;
            let fields = this.fields(points);
            if order2 {
                // order 2: `W_l + 3G_l` in the first half, `G_l` in the second (module doc)
                let dtdx = dt / this.grid.spacing[l];
                let half = w.len() / 2;
                let (tt, g) = w.split_at_mut(half);
                let parts = (chunks(tt, CHUNK), chunks(g, CHUNK));
                for_each_chunk(this.parallel, 1, parts, |r, (tt, g)| {
                    let mut idx = Self::multi_index(dims, r * CHUNK);
                    for (v, g) in tt.iter_mut().zip(g.iter_mut()) {
                        let pos = std::array::from_fn(|j| idx[j] as isize - isize::from(j != l));
                        (*v, *g) = this.corrected_fluctuation_at(l, pos, fields, dtdx);
                        Self::advance(&mut idx, &dims);
                    }
                });
                continue;
            }
            for_each_chunk(this.parallel, 1, chunks(w, CHUNK), |r, out| {
                let mut idx = Self::multi_index(dims, r * CHUNK);
                for v in out.iter_mut() {
                    let pos = std::array::from_fn(|j| idx[j] as isize - isize::from(j != l));
                    *v = this.fluctuation_at(l, pos, fields);
                    Self::advance(&mut idx, &dims);
                }
            });
        }
        let mut source = std::mem::take(&mut self.correction_scratch);
        let constants = AxisConstants::new(&self.elastic);
        for k in 0..D {
            let dims = self.source_dims(k);
            let len: usize = dims.iter().product();
            let this = &*self;
            let scales = SourceScales::new(&this.grid.spacing, k, dt);
            for_each_chunk(
                this.parallel,
                1,
                chunks(&mut source[..len], CHUNK),
                |r, out| {
                    let mut idx = Self::multi_index(dims, r * CHUNK);
                    for v in out.iter_mut() {
                        let mut pos = idx.map(|i| i as isize);
                        pos[k] -= 1;
                        *v = this.transverse_source(k, pos, &fluct, &scales, &constants);
                        Self::advance(&mut idx, &dims);
                    }
                },
            );
            let mut fluxes = std::mem::take(&mut self.face_flux[k]);
            let this = &*self;
            let source = &source[..len];
            let e_k = unit::<D>(k);
            // the source of the cell above a face is one k-stride further
            let stride_k: usize = dims[..k].iter().product();
            let restricted = this.options.edges == EdgeTreatment::Restricted;
            this.sum_over_faces(k, &mut fluxes, |idx, flux| {
                let mut below = 0;
                for j in (0..D).rev() {
                    below = below * dims[j] + idx[j];
                }
                let mut c =
                    axis_transverse(k, &source[below], &source[below + stride_k], &constants);
                let on_edge = idx[k] == 0 || idx[k] == this.grid.cells[k];
                if on_edge && restricted {
                    let side = usize::from(idx[k] != 0);
                    let cond = this.edge_condition(k, side, &idx);
                    c = constrain_correction(&c, &e_k, cond);
                }
                *flux = flux.add_scaled(&c, 1.0);
                0.0
            });
            self.face_flux[k] = fluxes;
        }
        self.correction_scratch = source;
        self.transverse_sources = fluct;
    }

    /// The source `V_k(X)` of the cell at `pos` (one layer outside the grid along `k` at
    /// most) from the fluctuation arrays `fluct`: module doc.
    fn transverse_source(
        &self,
        k: usize,
        pos: [isize; D],
        fluct: &[Vec<Conserved<D>>; D],
        scales: &SourceScales,
        constants: &AxisConstants,
    ) -> Conserved<D> {
        let mut others = (0..D).filter(|&j| j != k);
        let (l, m) = (others.next().unwrap_or(0), others.next().unwrap_or(0));
        let cells = self.grid.cells;
        // entry of W_a at `p` shifted by `d` along axis `b`
        let w = |a: usize, b: usize, d: isize| {
            let mut index = 0;
            for j in (0..D).rev() {
                let ghost = j != a;
                let coordinate = pos[j] + if j == b { d } else { 0 } + isize::from(ghost);
                index = index * (cells[j] + 2 * usize::from(ghost)) + coordinate as usize;
            }
            fluct[a][index]
        };
        // W_l and its neighbours along e_m, W_m and its neighbours along e_l
        let wl = [w(l, m, -1), w(l, m, 0), w(l, m, 1)];
        let wm = [w(m, l, -1), w(m, l, 0), w(m, l, 1)];
        let v = source_of(
            k,
            [&wl[0], &wl[1], &wl[2]],
            [&wm[0], &wm[1], &wm[2]],
            scales,
            constants,
        );
        if self.wave_flux[0].is_empty() {
            return v;
        }
        // order 2: the arrays hold `W + 3G` (the transverse-transverse terms'); the
        // face-sharing terms take `W + 2G`, so `G` once less (module doc)
        let g = |a: usize| {
            let half = fluct[a].len() / 2;
            let mut index = 0;
            for j in (0..D).rev() {
                let ghost = j != a;
                let coordinate = pos[j] + isize::from(ghost);
                index = index * (cells[j] + 2 * usize::from(ghost)) + coordinate as usize;
            }
            fluct[a][half + index]
        };
        v.add_scaled(&g(l), -scales.l).add_scaled(&g(m), -scales.m)
    }

    /// Order 2 (module doc): `(W_l + 3G_l, G_l)` of the cell at `pos`, `G_l = F̃_high −
    /// F̃_low` its `l`-faces' correction fluxes (`dtdx = Δt/Δx_l`): inside from the stored
    /// `F̃` (the stored fluxes, hence `fluctuation_at`, hold `W_l + G_l`), behind one edge
    /// from the ghost row's waves (`ghost_cell_corrections`, a face whose fluctuation is
    /// dropped at a traction corner dropping its `F̃` too, as in 2D), behind two edges the
    /// same rule as `W_l` (mirror or mean).
    fn corrected_fluctuation_at(
        &self,
        l: usize,
        pos: [isize; D],
        fields: Fields<'_, D>,
        dtdx: f64,
    ) -> (Conserved<D>, Conserved<D>) {
        let n = self.grid.cells;
        if (0..D).all(|a| pos[a] >= 0 && pos[a] < n[a] as isize) {
            let cell: [usize; D] = std::array::from_fn(|j| pos[j] as usize);
            let lo = Self::face_index(&self.grid, l, cell);
            let stride: usize = n[..l].iter().product();
            let f = &self.wave_flux[l];
            let g = f[lo + stride].add_scaled(&f[lo], -1.0);
            let w = self.fluctuation_at(l, pos, fields);
            return (w.add_scaled(&g, 2.0), g);
        }
        let g = self.two_edge_rule(pos, |a, side, cell| {
            let (low, high) = self.ghost_cell_corrections(a, side, l, cell, fields, dtdx);
            let [drop_low, drop_high] = self.dropped_corner_faces(a, side, l, cell);
            let g = Conserved::<D>::zeros();
            let g = if drop_low {
                g
            } else {
                g.add_scaled(&low, -1.0)
            };
            if drop_high {
                g
            } else {
                g.add_scaled(&high, 1.0)
            }
        });
        let w = self.ghost_fluctuation(l, pos, fields);
        (w.add_scaled(&g, 3.0), g)
    }

    /// `W_l` of the cell at `pos` (never outside along `l`): from the stored fluxes inside
    /// (the cell's side fluxes added on the nodal paths), from the ghost states behind one
    /// edge, and behind two edges the module doc's rule.
    fn fluctuation_at(&self, l: usize, pos: [isize; D], fields: Fields<'_, D>) -> Conserved<D> {
        let n = self.grid.cells;
        if (0..D).all(|a| pos[a] >= 0 && pos[a] < n[a] as isize) {
            let cell: [usize; D] = std::array::from_fn(|j| pos[j] as usize);
            let lo = Self::face_index(&self.grid, l, cell);
            let stride: usize = n[..l].iter().product();
            let f = &self.face_flux[l];
            let w = f[lo + stride].add_scaled(&f[lo], -1.0);
            return match self.path.nodal() {
                true => w.add_scaled(&self.side_flux_difference(fields, cell, l), 1.0),
                false => w,
            };
        }
        self.ghost_fluctuation(l, pos, fields)
    }

    /// `W_l` of the ghost cell at `pos` (outside the grid along one or two axes other than
    /// `l`): behind one edge from the mirror states (`ghost_cell_fluctuations`), behind two
    /// the module doc's rule. Shared with the fused 3D sweep.
    pub(crate) fn ghost_fluctuation(
        &self,
        l: usize,
        pos: [isize; D],
        fields: Fields<'_, D>,
    ) -> Conserved<D> {
        self.two_edge_rule(pos, |a, side, cell| {
            let (minus, plus) = self.ghost_cell_fluctuations(a, side, l, cell, fields);
            minus.add_scaled(&plus, 1.0)
        })
    }

    /// The value of the ghost cell at `pos` (outside the grid along one or two axes) from
    /// `single(a, side, cell)`, the value behind the one edge of axis `a` at `side` of the
    /// clamped `cell`: behind one edge that value, behind two the module doc's rule.
    fn two_edge_rule(
        &self,
        pos: [isize; D],
        single: impl Fn(usize, usize, [usize; D]) -> Conserved<D>,
    ) -> Conserved<D> {
        let n = self.grid.cells;
        let cell: [usize; D] = std::array::from_fn(|j| pos[j].clamp(0, n[j] as isize - 1) as usize);
        let side = |a: usize| usize::from(pos[a] >= 0);
        let mut outside = (0..D).filter(|&a| pos[a] < 0 || pos[a] >= n[a] as isize);
        let ghost = |a: usize| single(a, side(a), cell);
        match (outside.next(), outside.next()) {
            (None, _) => unreachable!("internal: a ghost cell lies outside the grid"),
            (Some(a), None) => ghost(a),
            (Some(a), Some(b)) => {
                let symmetric = |x: usize| self.boundaries[x][side(x)] == Boundary::Symmetry;
                if symmetric(b) {
                    mirror(&ghost(a), b)
                } else if symmetric(a) {
                    mirror(&ghost(b), a)
                } else {
                    // neither edge a mirror: the mean of the two single ghosts, so that
                    // no axis is preferred (a square impact keeps its y ↔ z symmetry)
                    Conserved::<D>::zeros()
                        .add_scaled(&ghost(a), 0.5)
                        .add_scaled(&ghost(b), 0.5)
                }
            }
        }
    }
}

/// The scales of the source `V_k`, `-Δt/(2Δx_l)`, `-Δt/(2Δx_m)` and
/// `s = Δt²/(6 Δx_l Δx_m)` (`l < m` the two other axes), formed once per axis and step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SourceScales {
    l: f64,
    m: f64,
    s: f64,
}

impl SourceScales {
    /// The scales of `V_k` on cells of sizes `h` with step `dt`.
    pub(crate) fn new<const D: usize>(h: &impact_core::Vector<D>, k: usize, dt: f64) -> Self {
        let mut others = (0..D).filter(|&j| j != k);
        let (l, m) = (others.next().unwrap_or(0), others.next().unwrap_or(0));
        Self {
            l: -dt / (2.0 * h[l]),
            m: -dt / (2.0 * h[m]),
            s: dt * dt / (6.0 * h[l] * h[m]),
        }
    }
}

/// The source `V_k(X)` (module doc) from `W_l` at `X - e_m`, `X`, `X + e_m` and `W_m` at
/// `X - e_l`, `X`, `X + e_l` (`l < m` the two axes other than `k`). The phase path and the
/// fused 3D sweep both call it, so they agree bit for bit.
#[inline(always)]
pub(crate) fn source_of<const D: usize>(
    k: usize,
    [wl_low, wl, wl_high]: [&Conserved<D>; 3],
    [wm_low, wm, wm_high]: [&Conserved<D>; 3],
    scales: &SourceScales,
    constants: &AxisConstants,
) -> Conserved<D> {
    let mut others = (0..D).filter(|&j| j != k);
    let (l, m) = (others.next().unwrap_or(0), others.next().unwrap_or(0));
    let tt_l = axis_transverse(
        m,
        &wl.add_scaled(wl_low, -1.0),
        &wl_high.add_scaled(wl, -1.0),
        constants,
    );
    let tt_m = axis_transverse(
        l,
        &wm.add_scaled(wm_low, -1.0),
        &wm_high.add_scaled(wm, -1.0),
        constants,
    );
    Conserved::<D>::zeros()
        .add_scaled(wl, scales.l)
        .add_scaled(wm, scales.m)
        .add_scaled(&tt_l, scales.s)
        .add_scaled(&tt_m, scales.s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_core::{Tensor, Vector};

    /// Mirroring twice is the identity, and through `e_b` flips exactly the `b`-shear
    /// components and the `b` momentum.
    #[test]
    fn mirror_flips_the_components_normal_to_the_plane() {
        let w = Conserved {
            tensor: Tensor::<3>::from_fn(|i, j| (1 + i + 3 * j) as f64),
            momentum: Vector::<3>::new(1.0, 2.0, 3.0),
        };
        let m = mirror(&w, 2);
        assert_eq!(mirror(&m, 2), w);
        assert_eq!(m.momentum, Vector::<3>::new(1.0, 2.0, -3.0));
        assert_eq!(m.tensor[(0, 2)], -w.tensor[(0, 2)]);
        assert_eq!(m.tensor[(2, 1)], -w.tensor[(2, 1)]);
        assert_eq!(m.tensor[(2, 2)], w.tensor[(2, 2)]);
        assert_eq!(m.tensor[(0, 1)], w.tensor[(0, 1)]);
    }
}

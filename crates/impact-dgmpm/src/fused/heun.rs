//! Heun's RK2 at one point per cell strictly inside its cell, linear elasticity, on the
//! fused sweeps: both stages as cell sweeps, no nodal rate and no nodal field (one source
//! for every dimension; the sweeps run in 1D and 2D, where the fused nodal path applies).
//!
//! **Stage 1.** Phase 1 gives every node of the cell the point's state, `q_i = q_p`, and
//! the lumped masses are `M_i = S_i m_p` (`S_i = S_i(X_p) > 0`). The stage's fluxes are
//! then the cell path's (Godunov and CTU on the cells' states), and the nodal rates (paper
//! eq. 14-16, `DgmpmSolver::rates_of_cell`) are
//! `q̇_i = (ρ/M_i) [C : sym(-V_p v_p ⊗ ∇S_i) + Σ_f s_f w_f F_f]`,
//! `v̇_i = (1/M_i) [-V_p σ_p ∇S_i + Σ_f s_f w_f F_f]` (momentum part of `F_f`),
//! the sums over the cell's faces `f = (m, s)` that hold node `i` (bit `m` of `i` is `s`),
//! `s_f = +1` on a low face and `-1` on a high one, `w_m = (V_cell/Δx_m) 2/2^D`. The
//! second stage reads only the averages of each side's `2^{D-1}` nodes (paper §4),
//! `q¹_{l,h} = q_p + Δt (2/2^D) Σ_{i ∈ (l,h)} q̇_i`. With the nodes' `G_i = -V_p ∇S_i`
//! and `κ_i = (2/2^D)/M_i`, `C : sym(·)` linear, each side `(l, h)` has fixed weights
//! (formed once, [`DgmpmSolver::form_heun_weights`]): `W = Σ_{i ∈ (l,h)} κ_i G_i` and,
//! per face `(m, t)` touching it (its own face `(l, h)` and both faces of each other
//! axis), `K_{m,t} = s_t w_m Σ_{i ∈ (l,h), i_m = t} κ_i` (`i_m` bit `m` of `i`). Its state
//! is then `σ¹ = σ_p + Δt ρ [C : sym(v_p ⊗ W) + Σ K_{m,t} F^σ_{m,t}]`,
//! `v¹ = v_p + Δt [σ_p W + Σ K_{m,t} F^p_{m,t}]`: no division, no nodal field, the point's
//! interpolation `Σ_i S_i q_p = q_p` not formed. Only what a face normal to `e_l` reads
//! is formed and stored, the traction `σ¹ e_l` and `v¹` ([`SideState`]). The traction's
//! volume part is linear in `v_p` with a matrix fixed per side, formed with the weights:
//! `(C : sym(v ⊗ W)) e_l = λ (v · W) e_l + μ (v W_l + W v_l) = M v`,
//! `M_jk = λ δ_jl W_k + μ (δ_jk W_l + W_j δ_kl)` ([`volume_matrix`]). The weights are
//! stored once (`W`, `K` per side) and scaled for the step's `Δt` into rows of
//! `Δt W_k`, `Δt ρ M`, `Δt ρ K` and `Δt K` (`DgmpmSolver::scale_heun_weights`, again only
//! when `Δt` changes: the last step of an output interval), so a side costs `2D - 1`
//! face products and `D` column products for each of its two parts and no scaling:
//! `σ¹ e_l = σ_p e_l + Σ (Δt ρ K) F^σ e_l + Σ_k (Δt ρ M)_{·k} v_{p,k}`,
//! `v¹ = v_p + Σ (Δt K) F^p + Σ_k σ_{p,·k} (Δt W_k)`.
//!
//! **Stage 2.** With `Σ_i S_i = 1`, `Σ_i ∇S_i = 0` and each face's flux reaching its
//! `2^{D-1}` nodes with weight `w_m`, `Σ_i S_i q̇_i` is the cell path's update
//! `-(ρV/m_p) Σ_l (F_l,high - F_l,low)/Δx_l` (momentum part without `ρ`) with the stage's
//! fluxes. Phases 3-5 of Heun's second stage, `q_p ← Σ_i S_i [½ q_p + ½ (q¹_i + Δt q̇¹_i)]`,
//! are therefore `q_p ← q_p + ½ Δq(F¹) + ½ Δq(F²)`, `Δq(F)` the cell path's increment
//! with fluxes `F`: stage 1 stores `q_p + ½ Δq(F¹)` (in the fused buffers' next state),
//! stage 2 solves its faces from the side states (Godunov, and under CTU the nodal
//! sweep's fluctuations with the side terms `F_l(q¹_{C,low} - q¹_{C,high})`) and adds
//! `½ Δq(F²)`, and moves the point, `x ← x + Δt v` with the new velocity (phase 5's
//! move, as `DgmpmSolver::move_points`); the next state is then swapped into the points.
//! The increment update
//! (`PointUpdate::Increment`) gives the same formula at one point per cell.
//!
//! **Wavefront (2D, `heun/wavefront.rs`).** Stage 2 of a cell row reads the side states
//! of that row and the rows next to it only, so each band of rows runs stage 1 one row
//! ahead of stage 2 (and on the rows next to the band, for their side states) and keeps the
//! side states in a ring of a few rows instead of a whole-grid array: the same values,
//! formed by the same operations, as two whole-grid sweeps. In 1D the stages are two
//! sweeps ([`DgmpmSolver::heun_step`]).
//!
//! The sums are associated differently from the phase-by-phase path
//! ([`crate::StepPath::SinglePoint`]): `Σ_i ∇S_i`, `Σ_i S_i - 1` and `Σ_i S_i q_p - q_p` are
//! zero only to round-off there, so the two agree to round-off (`tests/fused.rs`, 1e-13
//! of the peaks), not bit for bit.
use super::{Band, FusedBuffers, UpdateConstants, CHUNK};
use crate::faces::{Fields, SideState};
use crate::riemann::axis::AxisConstants;
use crate::riemann::{Conserved, FullState};
use crate::{DgmpmSolver, StepPath, MAX_NODES};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{CoreError, Grid, Tensor, Vector};
use std::collections::HashMap;

mod wavefront;
pub(crate) use wavefront::{ring_len, rings, BandTotals};

/// Weights per side of a cell as formed (and compared for the store-once blocks): `W`
/// (`D`), the own face's `K` and the two faces' `K` of each other axis (module doc).
const fn per_side(d: usize) -> usize {
    3 * d - 1
}

/// Rows of [`Lanes`] per side of a cell in [`DgmpmSolver::heun_scaled`], scaled for the
/// step's `Δt` (module doc): each `Δt W_k` in every lane (`D`), the columns of
/// `Δt ρ M` (`D`), then each of its `2D - 1` weights as `Δt ρ K` and as `Δt K` in every
/// lane, so that a product by one weight is a lane-wise product with a row loaded whole
/// (no broadcast in the sweep).
const fn lane_rows(d: usize) -> usize {
    6 * d - 2
}

/// `D` values kept as one aligned row (a SIMD register's worth in 2D): a side's `W` or
/// one weight repeated in every lane ([`lane_rows`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
pub(crate) struct Lanes<const D: usize>([f64; D]);

impl<const D: usize> Lanes<D> {
    /// The row as a vector.
    #[inline(always)]
    fn vector(&self) -> Vector<D> {
        Vector::<D>::from_fn(|k, _| self.0[k])
    }

    /// `w` in every lane.
    fn splat(w: f64) -> Self {
        Self([w; D])
    }
}

/// The step's constants of the Heun sweeps: the cell update's at `½Δt`, and `Δt` (the
/// side states' scalings are in the scaled weights).
struct HeunConstants<const D: usize> {
    half: UpdateConstants<D>,
    dt: f64,
}

/// The volume matrix `M` of a side normal to `e_l` with weight `W` (module doc):
/// `(C : sym(v ⊗ W)) e_l = λ (v · W) e_l + μ (v W_l + W v_l) = M v`, so
/// `M_jk = λ δ_jl W_k + μ (δ_jk W_l + W_j δ_kl)`.
fn volume_matrix<const D: usize>(w: &[f64], l: usize, lambda: f64, mu: f64) -> Tensor<D> {
    let delta = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
    Tensor::<D>::from_fn(|j, k| {
        lambda * delta(j, l) * w[k] + mu * (delta(j, k) * w[l] + w[j] * delta(k, l))
    })
}

/// What one band of a Heun stage writes: stage 1 its cells' side states (`2D` per cell)
/// and `q_p + ½ Δq(F¹)`; stage 2 adds `½ Δq(F²)` to the latter and moves the points.
enum HeunOut<'a, const D: usize> {
    First {
        sides: &'a mut [SideState<D>],
        next: (&'a mut [Tensor<D>], &'a mut [Vector<D>]),
    },
    Second {
        next: (&'a mut [Tensor<D>], &'a mut [Vector<D>]),
        position: &'a mut [Vector<D>],
    },
}

impl<const D: usize> DgmpmSolver<D> {
    /// Whether RK2 takes the Heun cell sweeps ([`self`](self) module doc): the fused nodal
    /// path at one point per cell, every point strictly inside its cell.
    pub(crate) fn heun_on_cells(&self) -> bool {
        self.path == StepPath::FusedNodal && self.fused_nodal_single() && self.inside
    }

    /// Form the sides' weights `W_(l,s) = Σ_i κ_i G_i` and `K_(l,s),(m,t) = s_t w_m Σ_i κ_i`
    /// (module doc: `G_i = -V_p ∇S_i`, `κ_i = (2/2^D)/M_i`, `κ_i = 0` at a node without
    /// mass, whose rates are zero) from the shape functions at the (fixed) points, their
    /// masses and volumes, and drop the shape functions, where [`Self::heun_on_cells`];
    /// each distinct cell's once (bit-equal blocks; a seeding's local coordinates round
    /// to a handful of values per axis, so a uniform grid has few) with a block index per
    /// cell, and no index where one block serves every cell. Elsewhere the weights are
    /// dropped.
    pub(crate) fn form_heun_weights(
        &mut self,
        points: &MaterialPoints<D>,
    ) -> Result<(), CoreError> {
        if !self.heun_on_cells() {
            self.heun_weights = Vec::new();
            self.heun_scaled = Vec::new();
            self.heun_layout = Vec::new();
            return Ok(());
        }
        if !self.heun_weights.is_empty() {
            return Ok(());
        }
        let n = Grid::<D>::NODES_PER_CELL;
        let k = 2.0 / n as f64;
        // the faces' node weights with their signs, `s_t w_m` (`+` low, `-` high)
        let face_weight = |m: usize, t: usize| {
            let w = self.grid.cell_volume() / self.grid.spacing[m] * k;
            if t == 0 {
                w
            } else {
                -w
            }
        };
        let stride = 2 * D * per_side(D);
        // each distinct cell's weights once (bit-equal blocks: a map from their bits to the
        // block), a block index per cell
        let mut weights = Vec::new();
        let mut layout = Vec::with_capacity(points.len());
        let mut index: HashMap<Vec<u64>, u32> = HashMap::new();
        let mut block = Vec::with_capacity(stride);
        let mut bits = Vec::with_capacity(stride);
        for c in 0..points.len() {
            block.clear();
            let (mass, volume) = (points.mass[c], points.volume[c]);
            let nodes: [(Vector<D>, f64); MAX_NODES] = std::array::from_fn(|a| {
                let Some(&shape) = self.shape[c * n..(c + 1) * n].get(a) else {
                    return (Vector::<D>::zeros(), 0.0);
                };
                let nodal_mass = shape * mass;
                let kappa = if nodal_mass > 0.0 {
                    k / nodal_mass
                } else {
                    0.0
                };
                (self.shape_gradient[c * n + a] * -volume, kappa)
            });
            let node = |a: usize| nodes[a];
            for (l, s) in (0..D).flat_map(|l| [(l, 0), (l, 1)]) {
                // the side's nodes: bit l of the node index is s
                let side = || (0..n).filter(move |a| (a >> l) & 1 == s);
                let w = side().fold(Vector::<D>::zeros(), |w, a| {
                    let (g, kappa) = node(a);
                    w + g * kappa
                });
                block.extend(w.iter());
                let kappas = |t: Option<(usize, usize)>| {
                    side()
                        .filter(|a| t.is_none_or(|(m, t)| (a >> m) & 1 == t))
                        .map(|a| node(a).1)
                        .sum::<f64>()
                };
                block.push(kappas(None) * face_weight(l, s));
                for m in (0..D).filter(|&m| m != l) {
                    for t in 0..2 {
                        block.push(kappas(Some((m, t))) * face_weight(m, t));
                    }
                }
            }
            bits.clear();
            bits.extend(block.iter().map(|w| w.to_bits()));
            let next = index.len();
            let l = match index.get(bits.as_slice()) {
                Some(&l) => l,
                None => {
                    let l = u32::try_from(next)
                        .map_err(|_| crate::unsupported("more than 2^32 distinct cells"))?;
                    index.insert(bits.clone(), l);
                    weights.extend_from_slice(&block);
                    l
                }
            };
            layout.push(l);
        }
        if index.len() == 1 {
            // one block serves every cell: no index
            layout = Vec::new();
        }
        weights.shrink_to_fit();
        layout.shrink_to_fit();
        // the scaled rows, formed at the first step (`scale_heun_weights`)
        let scaled = index.len() * 2 * D * lane_rows(D);
        self.heun_scaled = vec![Lanes([0.0; D]); scaled];
        self.heun_scaled_dt = f64::NAN;
        self.heun_weights = weights;
        self.heun_layout = layout;
        self.shape = Vec::new();
        self.shape_gradient = Vec::new();
        Ok(())
    }

    /// The scaled weights of cell `cell` (module doc), [`lane_rows`] per side.
    #[inline(always)]
    fn heun_weights_of(&self, cell: usize) -> &[Lanes<D>] {
        let stride = 2 * D * lane_rows(D);
        let start = match self.heun_layout.is_empty() {
            true => 0,
            false => self.heun_layout[cell] as usize * stride,
        };
        &self.heun_scaled[start..start + stride]
    }

    /// The rows of [`lane_rows`] for a step of `dt` from the stored weights `W`, `K` of each
    /// block (module doc), into the buffer formed with them; nothing when they already
    /// are `dt`'s (a run's steps share `Δt` but for the last of an output interval).
    fn scale_heun_weights(&mut self, dt: f64) {
        if dt.to_bits() == self.heun_scaled_dt.to_bits() {
            return;
        }
        let (lambda, mu) = self.heun_lame();
        let dt_rho = dt * self.material.density;
        let sides = self.heun_weights.chunks_exact(per_side(D));
        let rows = self.heun_scaled.chunks_exact_mut(lane_rows(D));
        for (side, (w, out)) in sides.zip(rows).enumerate() {
            let (w, k) = w.split_at(D);
            let (w_rows, rest) = out.split_at_mut(D);
            let (volume_rows, rest) = rest.split_at_mut(D);
            let (traction_rows, momentum_rows) = rest.split_at_mut(2 * D - 1);
            for (row, &w) in w_rows.iter_mut().zip(w) {
                *row = Lanes::splat(dt * w);
            }
            let volume = volume_matrix::<D>(w, side % (2 * D) / 2, lambda, mu) * dt_rho;
            for (c, row) in volume_rows.iter_mut().enumerate() {
                *row = Lanes(std::array::from_fn(|j| volume[(j, c)]));
            }
            for ((traction, momentum), &k) in traction_rows.iter_mut().zip(momentum_rows).zip(k) {
                *traction = Lanes::splat(dt_rho * k);
                *momentum = Lanes::splat(dt * k);
            }
        }
        self.heun_scaled_dt = dt;
    }

    /// The Lamé constants of `C : sym(·)`: `λ = 0`, `μ = E/2` in 1D (`C : ε = E ε`).
    fn heun_lame(&self) -> (f64, f64) {
        let lambda = if D == 1 { 0.0 } else { self.elastic.lambda };
        (lambda, self.elastic.mu)
    }

    /// The constants of a Heun step of `dt`.
    fn heun_constants(&self, dt: f64) -> HeunConstants<D> {
        HeunConstants {
            half: self.update_constants(0.5 * dt),
            dt,
        }
    }

    /// Heun's RK2 step on the cell sweeps (module doc): in 2D both stages in one
    /// wavefront ([`wavefront`]), in 1D one sweep per stage. Returns each stage's power
    /// and force of the boundary conditions.
    pub(crate) fn heun_step(
        &mut self,
        points: &mut MaterialPoints<D>,
        dt: f64,
    ) -> [(f64, Vector<D>); 2] {
        self.scale_heun_weights(dt);
        if D == 2 {
            self.by_dimension(
                points,
                |_, _| unreachable!("internal: D = 2"),
                |solver, points| {
                    solver.heun_wavefront_2d(points, dt);
                    (0.0, Vector::<2>::zeros())
                },
                |_, _| unreachable!("internal: D = 2"),
            );
            return [0, 1].map(|stage| self.fused.stage_totals(stage));
        }
        [true, false].map(|first| {
            self.by_dimension(
                points,
                |_, _| unreachable!("internal: the Heun sweeps are 1D and 2D (Fusable::All)"),
                |_, _| unreachable!("internal: the 2D Heun sweeps are the wavefront"),
                |solver, points| solver.heun_sweep_1d(points, dt, first),
            )
        })
    }

    /// Run `sweep(band index, band, face fields, inverse point masses, output)` on every band:
    /// stage 1 reads the points and writes the side states and the next state; stage 2
    /// reads the side states, updates the next state in place, moves the points and swaps
    /// the next state into them. Returns the bands' power and force.
    fn heun_bands(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        first: bool,
        sweep: impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, &[f64], HeunOut<'_, D>) + Sync,
    ) -> (f64, Vector<D>) {
        self.with_buffers(|this, buffers, _| {
            let FusedBuffers {
                bands,
                next_tensor,
                next_velocity,
                side_states,
                ..
            } = buffers;
            let (stress, velocity) = (&mut points.stress, &mut points.velocity);
            let (position, inverse_mass) = (&mut points.position, &this.inverse_mass[..]);
            {
                let next = (
                    chunks(next_tensor, cells_per_band),
                    chunks(next_velocity, cells_per_band),
                );
                let bands = chunks(bands, 1);
                if first {
                    let fields = Fields::per_cell(stress, velocity);
                    let sides = chunks(side_states, cells_per_band * 2 * D);
                    let parts = (bands, next, sides);
                    for_each_chunk(this.parallel, 1, parts, |b, (band, next, sides)| {
                        let out = HeunOut::First { sides, next };
                        sweep(this, b, &mut band[0], fields, inverse_mass, out);
                    });
                } else {
                    let fields = Fields::sides(side_states, 0);
                    let parts = (bands, next, chunks(position, cells_per_band));
                    for_each_chunk(this.parallel, 1, parts, |b, (band, next, position)| {
                        let out = HeunOut::Second { next, position };
                        sweep(this, b, &mut band[0], fields, inverse_mass, out);
                    });
                }
            }
            if !first {
                std::mem::swap(stress, next_tensor);
                std::mem::swap(velocity, next_velocity);
            }
        })
    }

    /// One cell of a Heun stage (entry `local` of its band, 1D) from its faces' final
    /// fluxes: [`Self::heun_first`] or [`Self::heun_second`].
    #[inline(always)]
    fn heun_cell<const FIRST: bool>(
        &self,
        u: &HeunConstants<D>,
        (cell, local): (usize, usize),
        faces: [[&Conserved<D>; 2]; D],
        (fields, inverse_mass): (Fields<'_, D>, f64),
        out: &mut HeunOut<'_, D>,
    ) {
        match out {
            HeunOut::First { sides, next } if FIRST => {
                let first_side = local * 2 * D;
                let sides = &mut sides[first_side..first_side + 2 * D];
                let next = Some((&mut next.0[local], &mut next.1[local]));
                self.heun_first(u, cell, faces, (fields, inverse_mass), sides, next);
            }
            HeunOut::Second { next, position } if !FIRST => {
                let next = (&mut next.0[local], &mut next.1[local]);
                Self::heun_second(u, faces, inverse_mass, next, &mut position[local]);
            }
            _ => unreachable!("internal: a Heun stage's output"),
        }
    }

    /// Stage 1 of cell `cell` from its faces' final fluxes `[low, high]` per axis (module
    /// doc): each side's traction and velocity into `sides` (`2D`),
    /// `σ¹ e_l = σ_p e_l + Σ (Δt ρ K) F^σ e_l + Σ_k (Δt ρ M)_{·k} v_{p,k}`,
    /// `v¹ = v_p + Σ (Δt K) F^p + Σ_k σ_{p,·k} (Δt W_k)` (its weights `W`, `K` and volume
    /// matrix `M = M(W)`, [`volume_matrix`], scaled for the step by
    /// [`Self::scale_heun_weights`]); writes `q_p + ½ Δq(F¹)` to
    /// `next` (where given),
    /// `Δq(F) = -Δt (ρV/m_p) Σ_l (F_l,high - F_l,low)/Δx_l`.
    #[inline(always)]
    fn heun_first(
        &self,
        u: &HeunConstants<D>,
        cell: usize,
        faces: [[&Conserved<D>; 2]; D],
        (fields, inverse_mass): (Fields<'_, D>, f64),
        sides: &mut [SideState<D>],
        next: Option<(&mut Tensor<D>, &mut Vector<D>)>,
    ) {
        let (dq, dv) = Self::flux_increment(&u.half, faces, inverse_mass);
        let FullState {
            tensor: q,
            velocity: v,
        } = fields.cell(cell);
        // (written before the side states: not held in registers across them)
        if let Some((next_q, next_v)) = next {
            *next_q = q + dq;
            *next_v = v + dv;
        }
        let w = self.heun_weights_of(cell);
        // `v_k` in every lane, for `Δt ρ M v = Σ_k (Δt ρ M)_{·k} v_k` on every side
        let v_lanes: [Vector<D>; D] = std::array::from_fn(|k| Vector::<D>::repeat(v[k]));
        for (side, out) in sides.iter_mut().enumerate() {
            let (l, s) = (side / 2, side % 2);
            let w = &w[side * lane_rows(D)..(side + 1) * lane_rows(D)];
            let (w_lanes, rest) = w.split_at(D);
            let (volume, rest) = rest.split_at(D);
            let (k_traction, k_momentum) = rest.split_at(2 * D - 1);
            let column = |f: &Conserved<D>| Vector::<D>::from_fn(|j, _| f.tensor[(j, l)]);
            // Σ K F (each K in every lane): the own face, then both faces of each other axis
            let own = faces[l][s];
            let mut traction = q.column(l) + column(own).component_mul(&k_traction[0].vector());
            let mut momentum = v + own.momentum.component_mul(&k_momentum[0].vector());
            let mut index = 1;
            for m in (0..D).filter(|&m| m != l) {
                for face in faces[m] {
                    traction += column(face).component_mul(&k_traction[index].vector());
                    momentum += face.momentum.component_mul(&k_momentum[index].vector());
                    index += 1;
                }
            }
            // Δt ρ (C : sym(v_p ⊗ W)) e_l = Δt ρ M v_p, and Δt σ_p W = Σ_k σ_{p,·k} Δt W_k
            for (column_k, v_k) in volume.iter().zip(&v_lanes) {
                traction += column_k.vector().component_mul(v_k);
            }
            for (k, w_k) in w_lanes.iter().enumerate() {
                momentum += q.column(k).component_mul(&w_k.vector());
            }
            *out = SideState {
                traction,
                velocity: momentum,
            };
        }
    }

    /// Stage 2 of a cell from its faces' final fluxes (module doc): `next += ½ Δq(F²)`
    /// and the move `x ← x + Δt v` with the new velocity.
    #[inline(always)]
    fn heun_second(
        u: &HeunConstants<D>,
        faces: [[&Conserved<D>; 2]; D],
        inverse_mass: f64,
        next: (&mut Tensor<D>, &mut Vector<D>),
        position: &mut Vector<D>,
    ) {
        let (dq, dv) = Self::flux_increment(&u.half, faces, inverse_mass);
        *next.0 += dq;
        *next.1 += dv;
        *position += *next.1 * u.dt;
    }
}

impl DgmpmSolver<1> {
    /// A Heun stage in 1D: [`Self::walk_1d`] on the cells' states (stage 1) or on the side
    /// states (stage 2) with [`Self::heun_cell`].
    fn heun_sweep_1d(
        &mut self,
        points: &mut MaterialPoints<1>,
        dt: f64,
        first: bool,
    ) -> (f64, Vector<1>) {
        let constants = AxisConstants::new(&self.elastic);
        let u = self.heun_constants(dt);
        self.heun_bands(
            points,
            CHUNK,
            first,
            |this, b, band, fields, inverse_mass, mut out| match first {
                true => this.walk_1d::<false>(b, band, fields, &constants, |c, l, faces| {
                    this.heun_cell::<true>(&u, (c, l), faces, (fields, inverse_mass[c]), &mut out)
                }),
                false => this.walk_1d::<true>(b, band, fields, &constants, |c, l, faces| {
                    this.heun_cell::<false>(&u, (c, l), faces, (fields, inverse_mass[c]), &mut out)
                }),
            },
        )
    }
}

#[cfg(test)]
mod tests;

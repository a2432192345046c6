//! Phase 2c (`order = 2`, 1D, 2D and 3D): the limited second-order wave corrections of the face
//! fluxes (LeVeque 2002, §6.8-6.15, and §15.4 for systems; Clawpack classic `step1`, and
//! `flux2` along each axis in 2D, with `order = 2`), added to the Godunov fluxes of phase 2
//! before the flux balance (and, with CTU, before the transverse corrections).
//!
//! Each face `i−½` has the Riemann problem of its two states (each side's face-node average,
//! paper §4: the corrections act on the cells' nodal face states, at any points per cell;
//! on the cell path, the points). The linear solver's star state `q*` splits the jump into
//! the left-going P wave `W¹ = q* − q_L` (speed `s¹ = −c_p`) and the right-going one
//! `W² = q_R − q*` (`s² = +c_p`), with `q = (σ, ρ v)`. They are used as f-waves
//! `Z^p = s^p W^p` (LeVeque 2002, §15.5): `Z¹ = F(q*) − F(q_L)`, `Z² = F(q_R) − F(q*)`, the
//! fluctuations, so the correction flux
//!
//! `F̃_{i−½} = ½ Σ_p |s^p| (1 − Δt|s^p|/Δx) φ(θ^p) W^p = ½ Σ_p sign(s^p) (1 − Δt|s^p|/Δx) φ(θ^p) Z^p`
//!
//! is Clawpack's to round-off (for one family `θ` is the same ratio of `W` or of `Z`;
//! [`crate::limiter`] gives `θ` and `φ`). It is added to the face's flux `F_{i−½}`, so the
//! cell update takes `−Δt (F̃_{i+½} − F̃_{i−½})/Δx` on top of the Godunov update: on the
//! cell path exactly Clawpack's `q_i −= Δt/Δx (A⁺ΔQ_{i−½} + A⁻ΔQ_{i+½}) + Δt/Δx (F̃_{i+½} −
//! F̃_{i−½})`; on the nodal paths the face flux reaches the face's nodes as before.
//!
//! **Ghost faces.** The limiter of a boundary face reads the wave of the face beyond it.
//! As Clawpack with two ghost cells, the ghost cells are mirror images through the edge's
//! condition ([`crate::riemann::ghost_full`], the rule of the boundary face): the first ghost
//! mirrors the first interior cell, the second mirrors the second (Clawpack's `wall`
//! pattern); so the face beyond the edge has as left state the mirror of the second cell's
//! face state towards the first, and as right state the mirror of the first cell's face
//! state towards the second (the mirror image of the first interior face). A one-cell grid
//! mirrors its one cell twice. A free end's corrections then carry no traction and a
//! velocity end's no velocity: the edge conditions hold exactly.
//!
//! **2D.** Along each axis `l`, row by row, the same with the linear solver's four waves
//! normal to `e_l` (`DgmpmSolver::linear_waves`: P and S on each side, through the states
//! between them), `Δx_l`, and the mirror ghosts of the row's two ends. With CTU
//! (`ctu.rs`), as Clawpack's `transverse_waves = 2`: the fluctuations the transverse solver
//! splits carry the corrections, `A⁻ΔQ + cqxx` and `A⁺ΔQ − cqxx` with `cqxx = 2F̃`
//! (`flux2`), so each cell's split sum gains `2(F̃_high − F̃_low)`: once through the
//! corrected face fluxes, once from the stored `F̃` (`wave_flux`); a ghost cell beyond an
//! edge takes the corrections of its ghost row (every state mirrored through that edge
//! first, `DgmpmSolver::padded_face_waves`). Donor-cell with the corrections is Clawpack's
//! `transverse_waves = 0`, which lacks the cross-derivative term: unstable with forward
//! Euler at every Courant number (von Neumann), stable with RK2.
//!
//! **3D.** The same row by row along each of the three axes; with CTU the transverse and
//! transverse-transverse split of `ctu3.rs` (Clawpack's `flux3`, `method = (2, 22)`).
//!
//! **Δt.** Euler uses the step's `Δt`. Each stage of Heun's RK2 is a forward Euler step of
//! the full `Δt` (`q¹ = q⁰ + Δt L(q⁰)`, `q² = q¹ + Δt L(q¹)`, averaged), so each stage's
//! corrections use `(1 − Δt|s|/Δx)` with that `Δt`: each stage is then the Lax-Wendroff-type
//! step it replaces (with RK2 the time accuracy is then both the stage's and the
//! Runge-Kutta's; the corrections are not re-derived for the method of lines).
//!
//! **The elastoplastic solver** (J2, `--riemann elastoplastic`, the rod in 1D and plane
//! strain in 2D): each side's normal jump to the star state is an elastic wave (`±c_0`) up
//! to the bound of the side's elastic range it crosses, then a plastic wave (`±c_t`), the
//! wave curves of `riemann::elastoplastic`; in 2D the linear solver's shear waves carry the
//! tangential part: six families, each limited against its own family
//! (`wave_correction/elastoplastic.rs`). A mirrored ghost side takes the mirrored range (a
//! traction mirror `σ ↦ k − σ` turns it over), so the ghost face's star state is the
//! boundary half problem's.
//!
//! **Saint-Venant–Kirchhoff** (approximate solver): in 1D its two acoustic waves, each
//! linearised about its side (`wave_correction/svk.rs`); in 2D and 3D (donor-cell) each
//! side's jump split into a P wave along the side's acoustic tensor's largest eigenvector
//! and one shear wave, in the linear solver's P and S slots (`wave_correction/svk_nd.rs`).
//!
//! Implemented for the linear-elastic solver (linear elasticity, and J2 with the elastic
//! solver and the return map after the step; 1D, 2D and 3D), the elastoplastic solver
//! (1D, and 2D with donor-cell: CTU is refused with it at any order) and the approximate
//! SVK solver (1D, 2D and 3D; donor-cell, CTU is refused with SVK at any order);
//! `Problem::check_config` refuses the others (SVK with the exact solver). The buffers
//! are allocated once (one row of waves, the longest axis's faces and two ghost faces;
//! with CTU the `F̃` of every face); the step allocates nothing.
mod elastoplastic;
mod svk;
mod svk_nd;

use crate::faces::Fields;
use crate::limiter::{limiter_phi, wave_ratio};
use crate::riemann::{
    ghost_full, linear_elastic_star, normal_flux, Conserved, FaceState, FullState, GhostCondition,
};
use crate::{unit, DgmpmSolver};
use elastoplastic::elastic_range;
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Vector};

/// Wave families of a face: left-going elastic (P), left-going plastic, left-going shear
/// (S), right-going shear, right-going plastic, right-going elastic. The linear solver has
/// no plastic waves, the rod (1D) no shear waves, the approximate SVK solver only the first
/// and the last: the others are zero (and skipped by the limiter, so the sum of the
/// corrections is the same, in the same order, as over the nonzero families alone).
pub(crate) const WAVES: usize = 6;

/// The last family (right-going elastic).
pub(crate) const LAST: usize = WAVES - 1;

/// The f-waves `Z^p` of one face and their speeds `s^p`, in family order (module doc).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceWaves<const D: usize> {
    pub wave: [Conserved<D>; WAVES],
    pub speed: [f64; WAVES],
}

impl<const D: usize> Default for FaceWaves<D> {
    fn default() -> Self {
        Self {
            wave: [Conserved::zeros(); WAVES],
            speed: [0.0; WAVES],
        }
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 2c: add the limited second-order corrections `F̃` (module doc) to the face
    /// fluxes of phase 2, row by row along each axis, for a stage of length `dt`; returns
    /// the change of the power the boundary conditions deliver (the loaded ends' flux
    /// changes). Nothing at order 1.
    pub fn wave_corrections(&mut self, points: &MaterialPoints<D>, dt: f64) -> f64 {
        let Some(limiter) = self.options.wave_limiter() else {
            return 0.0;
        };
        let mut waves = std::mem::take(&mut self.face_waves);
        let mut power = 0.0;
        let grid = self.grid.clone();
        for l in 0..D {
            let n = grid.cells[l];
            let rows: usize = Grid::<D>::tangent_axes(l).map(|k| grid.cells[k]).product();
            let dtdx = dt / grid.spacing[l];
            let mut fluxes = std::mem::take(&mut self.face_flux[l]);
            for row in 0..rows {
                // the row's multi-index on the other axes
                let mut idx = [0usize; D];
                let mut rest = row;
                for k in Grid::<D>::tangent_axes(l) {
                    idx[k] = rest % grid.cells[k];
                    rest /= grid.cells[k];
                }
                let waves = &mut waves[..n + 3];
                self.row_waves_into(l, idx, points, waves);
                for f in 0..=n {
                    // the face's waves at f + 1 in the padded row (a ghost face at each end)
                    let correction =
                        correction_of(&waves[f + 1], &waves[f], &waves[f + 2], limiter, dtdx);
                    idx[l] = f;
                    let face = Self::face_index(&grid, l, idx);
                    if let Some(store) = self.wave_flux[l].get_mut(face) {
                        *store = correction;
                    }
                    let flux = &mut fluxes[face];
                    if f == 0 || f == n {
                        power -= self.end_power(l, idx, flux);
                        *flux = flux.add_scaled(&correction, 1.0);
                        power += self.end_power(l, idx, flux);
                    } else {
                        *flux = flux.add_scaled(&correction, 1.0);
                    }
                }
            }
            self.face_flux[l] = fluxes;
        }
        self.face_waves = waves;
        power
    }

    /// The power the condition of the end face of axis `l` at `idx` delivers with face flux
    /// `flux`, `sign |Γ_f| t·v`, the traction `t = −F_momentum` and the velocity from
    /// `F_tensor = −C : sym(v ⊗ e_l)`: `v_l = −F_ll/(λ + 2μ)` (1D: `/E`), `v_k = −F_kl/μ`
    /// (0 on a free end, as `boundary_power`).
    fn end_power(&self, l: usize, idx: [usize; D], flux: &Conserved<D>) -> f64 {
        let side = usize::from(idx[l] != 0);
        let s = self.edge_coordinate(l, &idx);
        if !self.owns_edge_face(&idx) || self.ghost_condition(l, side, s) == GhostCondition::free()
        {
            return 0.0;
        }
        let sign = if side == 0 { -1.0 } else { 1.0 };
        let area = self.grid.cell_volume() / self.grid.spacing[l];
        if let crate::Physics::Svk { .. } = self.physics {
            // `F_n = −(v ⊗ n, Π n)`: the velocity is `−F_tensor e_l`
            let velocity = -(flux.tensor * unit::<D>(l));
            return -sign * area * flux.momentum.dot(&velocity);
        }
        let m = &self.elastic;
        let normal_modulus = 2.0 * m.mu + if D > 1 { m.lambda } else { 0.0 };
        let velocity = Vector::<D>::from_fn(|k, _| match k == l {
            true => -flux.tensor[(l, l)] / normal_modulus,
            false => -flux.tensor[(k, l)] / m.mu,
        });
        -sign * area * flux.momentum.dot(&velocity)
    }

    /// The f-waves of every face of the row of axis `l` through `idx` (its other entries)
    /// and of the ghost face beyond each end (module doc), into `waves` (`cells_l + 3`, the
    /// ghost faces first and last).
    fn row_waves_into(
        &self,
        l: usize,
        idx: [usize; D],
        points: &MaterialPoints<D>,
        waves: &mut [FaceWaves<D>],
    ) {
        let fields = self.fields(points);
        for (j, slot) in waves.iter_mut().enumerate() {
            *slot = self.padded_face_waves(l, idx, j, fields, Some(points), None);
        }
    }

    /// The f-waves of padded face `j` (face `j − 1`, between cells `j − 2` and `j − 1`; the
    /// ghost faces `0` and `cells_l + 2`) of the row of axis `l` through `idx`; with
    /// `transverse = (k, side)`, of the ghost row beyond the edge of axis `k` at `side`
    /// (every state mirrored first through that edge's condition, at its cell's position
    /// along it: the ghost cells of Clawpack's `bc2`, corners included). `points` gives the
    /// plastic states of the rod's elastoplastic solver (1D).
    pub(crate) fn padded_face_waves(
        &self,
        l: usize,
        mut idx: [usize; D],
        j: usize,
        fields: Fields<'_, D>,
        points: Option<&MaterialPoints<D>>,
        transverse: Option<(usize, usize)>,
    ) -> FaceWaves<D> {
        if let crate::Physics::Svk { svk, .. } = self.physics {
            return match D {
                1 => self.svk_padded_waves(&svk, j, fields),
                _ => self.svk_padded_waves_nd(&svk, l, idx, j, fields),
            };
        }
        let n = self.grid.cells[l];
        let e = unit::<D>(l);
        // the ends' conditions at the row's tangential coordinates
        let conditions = [0, 1].map(|end| {
            idx[l] = end * n;
            self.ghost_condition(l, end, self.edge_coordinate(l, &idx))
        });
        // cell i's state on its high or low face (first mirrored through the transverse
        // edge, if any), mirrored through end `mirror` if given, with its elastic range
        // under the rod's elastoplastic solver (`None` otherwise)
        let side = |i: usize, high: bool, mirror: Option<usize>| -> Side<D> {
            let mut at = idx;
            at[l] = i;
            let c = self.grid.cell_index(at);
            let mut state = fields.side(c, l, high);
            if let Some((k, k_side)) = transverse {
                let outward = unit::<D>(k) * if k_side == 0 { -1.0 } else { 1.0 };
                let cond = self.ghost_condition(k, k_side, self.edge_coordinate(k, &at));
                state = ghost_full(&state, &outward, cond);
            }
            let range = match (self.rod_solver, points) {
                (Some((j2, _)), Some(points)) => Some(elastic_range(&j2, l, c, &state, points)),
                _ => None,
            };
            let Some(end) = mirror else {
                return (state, range);
            };
            let outward = if end == 0 { -e } else { e };
            let ghost = ghost_full(&state, &outward, conditions[end]);
            // a traction mirror maps σ to k − σ (the range turns over); the velocity
            // mirrors keep σ (and the range)
            // (a partly covered face keeps the linear solver, as its Godunov flux does)
            let range = range.and_then(|(lower, upper)| match conditions[end] {
                GhostCondition::Traction(_) => {
                    let k = ghost.tensor[(l, l)] + state.tensor[(l, l)];
                    Some((k - upper, k - lower))
                }
                GhostCondition::PartialVelocity { .. } => None,
                _ => Some((lower, upper)),
            });
            (ghost, range)
        };
        let second = |i: usize| if n > 1 { i } else { 0 };
        let (left, right) = match j {
            0 => (side(second(1), false, Some(0)), side(0, true, Some(0))),
            j if j == n + 2 => (
                side(n - 1, false, Some(1)),
                side(n - 1 - second(1), true, Some(1)),
            ),
            1 => (side(0, false, Some(0)), side(0, false, None)),
            j if j == n + 1 => (side(n - 1, true, None), side(n - 1, true, Some(1))),
            j => (side(j - 2, true, None), side(j - 1, false, None)),
        };
        match (left.1, right.1) {
            (Some(lr), Some(rr)) => self.elastoplastic_waves(l, (&left.0, lr), (&right.0, rr)),
            _ => self.linear_waves(l, &left.0, &right.0),
        }
    }

    /// CTU with order 2 (2D): the correction fluxes `F̃` of the low and high `l`-faces of
    /// the ghost cell that mirrors `cell` through the edge of axis `k` at `side`, from the
    /// ghost row's waves (`padded_face_waves` with the transverse mirror); `dtdx = Δt/Δx_l`.
    pub(crate) fn ghost_cell_corrections(
        &self,
        k: usize,
        side: usize,
        l: usize,
        cell: [usize; D],
        fields: Fields<'_, D>,
        dtdx: f64,
    ) -> (Conserved<D>, Conserved<D>) {
        let Some(limiter) = self.options.wave_limiter() else {
            return (Conserved::zeros(), Conserved::zeros());
        };
        // the ghost cell's faces are padded cell[l] + 1 (low) and + 2 (high); their
        // upwind neighbours one further each way
        let j = cell[l];
        let waves: [FaceWaves<D>; 4] = std::array::from_fn(|m| {
            self.padded_face_waves(l, cell, j + m, fields, None, Some((k, side)))
        });
        let at = |p: usize| correction_of(&waves[p], &waves[p - 1], &waves[p + 1], limiter, dtdx);
        (at(1), at(2))
    }

    /// The f-waves of the linear-elastic Riemann problem `(left, right)` normal to `e_l`,
    /// through the states between the waves: on the left `m_L` (the star state's normal
    /// traction and velocity, the left state's tangential ones), on the right `m_R`:
    /// `Z¹ = F(m_L) − F(q_L)` at `−c_p`, `Z² = F(q*) − F(m_L)` at `−c_s`,
    /// `Z³ = F(m_R) − F(q*)` at `+c_s`, `Z⁴ = F(q_R) − F(m_R)` at `+c_p` (1D: `Z²`, `Z³`
    /// vanish, no shear wave).
    #[inline]
    fn linear_waves(&self, l: usize, left: &FullState<D>, right: &FullState<D>) -> FaceWaves<D> {
        let e = unit::<D>(l);
        let (a, b) = (left.on_face(&e), right.on_face(&e));
        let star = linear_elastic_star(&a, &b, &e, self.elastic.z);
        // normal parts of the star state, tangential parts of `outer`
        let between = |outer: &FaceState<D>| FaceState {
            traction: e * star.traction.dot(&e) + (outer.traction - e * outer.traction.dot(&e)),
            velocity: e * star.velocity.dot(&e) + (outer.velocity - e * outer.velocity.dot(&e)),
        };
        let flux = |q: &FaceState<D>| normal_flux(q, &e, &self.elastic);
        let (fl, fml, fs, fmr, fr) = (
            flux(&a),
            flux(&between(&a)),
            flux(&star),
            flux(&between(&b)),
            flux(&b),
        );
        let (cp, cs) = (
            self.elastic.z.p / self.elastic.density,
            self.elastic.z.s / self.elastic.density,
        );
        // the P and S families of `WAVES` (no plastic waves)
        FaceWaves {
            wave: [
                fml.add_scaled(&fl, -1.0),
                Conserved::zeros(),
                fs.add_scaled(&fml, -1.0),
                fmr.add_scaled(&fs, -1.0),
                Conserved::zeros(),
                fr.add_scaled(&fmr, -1.0),
            ],
            speed: [-cp, 0.0, -cs, cs, 0.0, cp],
        }
    }
}

/// The correction flux `F̃ = ½ Σ_p sign(s^p) (1 − dtdx |s^p|) φ(θ^p) Z^p` of the face
/// with waves `here` (module doc), `before` and `after` its neighbours along the axis (the
/// upwind one of each family gives `θ`).
#[inline]
fn correction_of<const D: usize>(
    here: &FaceWaves<D>,
    before: &FaceWaves<D>,
    after: &FaceWaves<D>,
    limiter: impact_core::method::WaveLimiter,
    dtdx: f64,
) -> Conserved<D> {
    let mut correction = Conserved::<D>::zeros();
    for p in 0..WAVES {
        let s = here.speed[p];
        let upwind = if s > 0.0 { before } else { after };
        let Some(theta) = wave_ratio(&upwind.wave[p], &here.wave[p]) else {
            continue;
        };
        let weight = 0.5 * s.signum() * (1.0 - dtdx * s.abs()) * limiter_phi(limiter, theta);
        correction = correction.add_scaled(&here.wave[p], weight);
    }
    correction
}

/// A face side: its state and, under the elastoplastic solver, its elastic range.
type Side<const D: usize> = (FullState<D>, Option<(f64, f64)>);

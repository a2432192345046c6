//! The fused cell path ([`StepPath::Fused`]): one point per cell, forward Euler, linear
//! elasticity, 1D, 2D or 3D. The phases of the cell path ([`crate::cell_path`]) in one sweep:
//!
//! 1. phase 2, the Godunov flux `F_{e_l}(q*)` of each face (paper §4, eqs. 18-21);
//! 2. phase 2b (2D, CTU), the transverse corrections
//!    `F_k -= Δt/(2Δx_l) (B⁺ w_below + B⁻ w_above)` (LeVeque 2002, §21.2), `w` the flux
//!    difference `F_l,high - F_l,low` of the cells on either side;
//! 3. the boundary force and power of the loaded faces;
//! 4. the cell update `q ← q - Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l` and the point's
//!    move `x ← x + Δt v`.
//!
//! The 2D sweep walks the cell rows `j` upwards and keeps only rolling rows of faces: the
//! Godunov x-fluxes of cell rows `j` and `j+1`, the Godunov and the final y-fluxes of face
//! rows `j` and `j+1` (the low and high faces of row `j`). Each face is solved once, the
//! face arrays of the phase-by-phase path (144 B per cell) are not allocated, and the step
//! reads each point's state once and writes it once (the cell path moves 776-920 B per
//! cell and step, this one about 130). Interior faces call the axis solvers
//! ([`crate::riemann::axis`]); boundary faces and the ghost cells' fluctuations call the
//! same functions as the phase path (`DgmpmSolver::linear_face_flux`,
//! `DgmpmSolver::ghost_cell_fluctuations`' pieces), each ghost face solved once: along a
//! y-edge a row at a time (`ghost_row_fluctuations`), behind an x-edge down the column
//! with the rows (`ghost_column_fluctuation`, a carry per edge in the band). The CTU
//! correction of a boundary face is then the axis transverse solver's, restricted by the
//! edge's condition (`edge_correction`: the general `face_correction`'s values, which
//! differ only by products with a zero component of the normal); at order 2 (wave
//! corrections of the ghost rows) `face_correction` forms it. The new states go to a
//! second buffer, swapped with the points' at the end, so every face reads the old states
//! (48 B per cell).
//!
//! Parallel: bands of `BAND_ROWS` (32) cell rows (1D: chunks of cells), each band with its
//! own rolling rows; a band recomputes the Godunov fluxes of the row below it (one row in
//! `BAND_ROWS` computed twice). The bands are fixed by the grid, so results do not depend
//! on the thread count. Tested equal to the phase-by-phase cell path to 1e-13.
//!
//! The nodal paths' stages run the same 2D sweep with face states from the DG nodes and
//! the nodal rates in place of the cell update ([`StepPath::FusedNodal`], `nodal.rs`).
//!
//! In 3D (`block.rs`, CTU in `block/ctu.rs`) the sweep walks z-layers in slabs with
//! rolling planes of faces, fluctuations `W` and sources `V` (the transverse-transverse
//! terms of `ctu3.rs`); tested bit for bit equal to the cell path.
//!
//! Files: this one (buffers, dispatch, the cell update), `plane.rs` (the 2D sweep and its
//! face rows, for both), `bar.rs` (the 1D sweep), `block.rs` (the 3D sweep, donor-cell)
//! and `block/ctu.rs` (its CTU), `nodal.rs` (the nodal stage: its dispatch, buffers, cell
//! update and 1D sweep; 1D and 2D only) and `heun.rs` (RK2 at one point per cell strictly
//! inside its cell: both stages as cell sweeps, no nodal field).
use crate::faces::{Fields, SideState};
use crate::riemann::Conserved;
use crate::{DgmpmSolver, StepPath, CHUNK};
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};
use std::any::Any;

mod bar;
mod block;
mod heun;
pub(crate) use heun::Lanes;
mod nodal;
mod plane;

/// Cell rows per band of the 2D sweep (the unit of parallel work).
pub(crate) const BAND_ROWS: usize = 32;

/// The rolling face rows of one band (2D) and the boundary power and force of its faces.
#[derive(Debug, Clone)]
pub(crate) struct Band<const D: usize> {
    /// Godunov fluxes of the x-faces of cell rows `j` and `j+1` (`nx + 1` each).
    x_godunov: [Vec<Conserved<D>>; 2],
    /// Godunov fluxes of the y-faces of face rows `j` and `j+1` (`nx` each).
    y_godunov: [Vec<Conserved<D>>; 2],
    /// Final (CTU-corrected) fluxes of face rows `j` and `j+1`.
    y_final: [Vec<Conserved<D>>; 2],
    /// Under CTU (empty otherwise): the x-fluctuations of the cells of rows `j` and `j+1`
    /// (`nx` each), `w_x = F_x,high - F_x,low`, on nodal states
    /// `+ F_x(q_C,low - q_C,high)`, formed once per row by `x_godunov_row` for the final
    /// fluxes of the face rows below and above the row.
    x_fluctuation: [Vec<Conserved<D>>; 2],
    /// Nodal sweep with CTU: the y-fluctuations `w_y` of row `j`'s cells (`nx`).
    w_y: Vec<Conserved<D>>,
    /// Under CTU at order 1: per x-edge (low, high), the `A⁺Δq` of the ghost face above
    /// the last row swept, with the row it serves
    /// (`DgmpmSolver::ghost_column_fluctuation`); cleared at a band's start.
    edge_carry: [Option<(usize, Conserved<D>)>; 2],
    /// Power of the boundary conditions on the band's faces.
    power: f64,
    /// Force on the body through the band's loaded boundary faces.
    force: Vector<D>,
}

impl<const D: usize> Default for Band<D> {
    fn default() -> Self {
        Self {
            x_godunov: Default::default(),
            y_godunov: Default::default(),
            y_final: Default::default(),
            x_fluctuation: Default::default(),
            w_y: Vec::new(),
            edge_carry: [None, None],
            power: 0.0,
            force: Vector::<D>::zeros(),
        }
    }
}

/// What the fused buffers hold: next-state entries per cell (1 on the cell path, `2^D`
/// between RK2's nodal stages, 0 where the only stage writes the points), whether the
/// bands keep the nodal side terms (nodal sweep with CTU) and whether the cells' side
/// states are kept (the Heun cell sweeps).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Layout {
    next_per_cell: usize,
    sides: bool,
    /// The cell path with CTU (2D: the bands keep the rows' x-fluctuations; 3D: the slabs
    /// keep the transverse planes).
    ctu: bool,
    /// The Heun cell sweeps' `2D` side states per cell (`heun.rs`).
    side_states: bool,
}

impl Layout {
    /// The cell path's: one next state per cell (point), with or without CTU.
    pub(crate) fn cell(ctu: bool) -> Self {
        Self {
            next_per_cell: 1,
            sides: false,
            ctu,
            side_states: false,
        }
    }

    /// The nodal sweep's, with `next_per_cell` next nodal states per cell.
    pub(crate) fn nodal(next_per_cell: usize, ctu: bool) -> Self {
        Self {
            next_per_cell,
            sides: ctu,
            ctu: false,
            side_states: false,
        }
    }

    /// The Heun cell sweeps' (`heun.rs`): the nodal sweep's with one next state per cell
    /// and the cells' side states.
    pub(crate) fn heun(ctu: bool) -> Self {
        Self {
            side_states: true,
            ..Self::nodal(1, ctu)
        }
    }
}

/// The buffers of the fused sweeps: one [`Band`] per band and the next state.
#[derive(Debug, Clone, Default)]
pub(crate) struct FusedBuffers<const D: usize> {
    bands: Vec<Band<D>>,
    /// 3D: one slab of layers each, with its rolling planes (`block.rs`).
    slabs: Vec<block::Slab>,
    next_tensor: Vec<Tensor<D>>,
    next_velocity: Vec<Vector<D>>,
    /// The Heun cell sweeps' side states, `2D` per cell (`layout.side_states`; empty
    /// otherwise): in 2D a ring of a few rows per thread (`heun/wavefront.rs`).
    side_states: Vec<SideState<D>>,
    /// The Heun wavefront's power and force per band and stage (2D; empty otherwise).
    heun_totals: Vec<heun::BandTotals>,
    layout: Option<Layout>,
}

impl<const D: usize> FusedBuffers<D> {
    /// The layout allocated (`None` before allocation).
    pub(crate) fn layout(&self) -> Option<Layout> {
        self.layout
    }

    /// Buffers for `grid`'s cells: in 2D bands of [`BAND_ROWS`] rows, each with its face
    /// rows (and the side terms' rows, `layout.sides`); in 1D one (empty) band per chunk of
    /// [`CHUNK`] cells; the next state as `layout` says.
    pub(crate) fn new(cells: [usize; D], layout: Layout) -> Self {
        let count: usize = cells.iter().product();
        let bands = match D {
            2 => {
                let nx = cells[0];
                let sides = if layout.sides { nx } else { 0 };
                let fluctuations = if layout.sides || layout.ctu { nx } else { 0 };
                let band = Band {
                    x_fluctuation: [
                        vec![Conserved::zeros(); fluctuations],
                        vec![Conserved::zeros(); fluctuations],
                    ],
                    w_y: vec![Conserved::zeros(); sides],
                    x_godunov: [
                        vec![Conserved::zeros(); nx + 1],
                        vec![Conserved::zeros(); nx + 1],
                    ],
                    y_godunov: [vec![Conserved::zeros(); nx], vec![Conserved::zeros(); nx]],
                    y_final: [vec![Conserved::zeros(); nx], vec![Conserved::zeros(); nx]],
                    ..Band::default()
                };
                let bands = cells[1].div_ceil(BAND_ROWS);
                // (the Heun wavefront: two per ring, one per stage, `heun/wavefront.rs`)
                let count = match layout.side_states {
                    true => 2 * heun::rings(bands),
                    false => bands,
                };
                vec![band; count]
            }
            1 => vec![Band::default(); count.div_ceil(CHUNK)],
            _ => Vec::new(),
        };
        let slabs = match D {
            3 => block::Slab::for_grid([cells[0], cells[1], cells[2]], layout.ctu),
            _ => Vec::new(),
        };
        let next = count * layout.next_per_cell;
        let side_states = match (layout.side_states, D) {
            // a ring of rows per thread (`heun/wavefront.rs`)
            (true, 2) => heun::rings(cells[1].div_ceil(BAND_ROWS)) * heun::ring_len(cells[0]),
            (true, _) => count * 2 * D,
            (false, _) => 0,
        };
        Self {
            bands,
            slabs,
            next_tensor: vec![Tensor::<D>::zeros(); next],
            next_velocity: vec![Vector::<D>::zeros(); next],
            side_states: vec![SideState::zeros(); side_states],
            heun_totals: match (layout.side_states, D) {
                (true, 2) => vec![(0.0, Vector::<2>::zeros()); 2 * cells[1].div_ceil(BAND_ROWS)],
                _ => Vec::new(),
            },
            layout: Some(layout),
        }
    }
}

/// The points' next state of one band or chunk, and their positions (moved in place).
struct Next<'a, const D: usize> {
    tensor: &'a mut [Tensor<D>],
    velocity: &'a mut [Vector<D>],
    position: &'a mut [Vector<D>],
}

impl<const D: usize> DgmpmSolver<D> {
    /// One step of the fused path: the module doc's phases 1-4 in one sweep. Returns the
    /// power and the force of the boundary conditions.
    pub(crate) fn fused_step(
        &mut self,
        points: &mut MaterialPoints<D>,
        dt: f64,
    ) -> (f64, Vector<D>) {
        debug_assert_eq!(self.path, StepPath::Fused);
        self.by_dimension(
            points,
            |solver, points| solver.sweep_3d(points, dt),
            |solver, points| solver.sweep_2d(points, dt),
            |solver, points| solver.sweep_1d(points, dt),
        )
    }

    /// `three`, `two` or `one` on the solver and the points at their concrete dimension
    /// (the sweeps are written per dimension; `Any` downcasts, no unsafe code), the force
    /// returned at `D`.
    fn by_dimension(
        &mut self,
        points: &mut MaterialPoints<D>,
        three: impl FnOnce(&mut DgmpmSolver<3>, &mut MaterialPoints<3>) -> (f64, Vector<3>),
        two: impl FnOnce(&mut DgmpmSolver<2>, &mut MaterialPoints<2>) -> (f64, Vector<2>),
        one: impl FnOnce(&mut DgmpmSolver<1>, &mut MaterialPoints<1>) -> (f64, Vector<1>),
    ) -> (f64, Vector<D>) {
        let solver: &mut dyn Any = self;
        let points: &mut dyn Any = points;
        let same = "internal: same D";
        let mut force = [0.0; 3];
        let power = if let Some(solver) = solver.downcast_mut::<DgmpmSolver<3>>() {
            let (power, f) = three(solver, points.downcast_mut().expect(same));
            force = [f[0], f[1], f[2]];
            power
        } else if let Some(solver) = solver.downcast_mut::<DgmpmSolver<2>>() {
            let (power, f) = two(solver, points.downcast_mut().expect(same));
            force[..2].copy_from_slice(&[f[0], f[1]]);
            power
        } else if let Some(solver) = solver.downcast_mut::<DgmpmSolver<1>>() {
            let (power, f) = one(solver, points.downcast_mut().expect(same));
            force[0] = f[0];
            power
        } else {
            unreachable!("internal: the fused sweeps are refused beyond 3D")
        };
        (power, Vector::<D>::from_fn(|k, _| force[k]))
    }

    /// Run `sweep` on every band with the points' old state and the band's part of the
    /// next state, swap the next state in and add up the bands' power and force.
    fn sweep_bands(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        sweep: impl Fn(&Self, usize, &mut Band<D>, Fields<'_, D>, &[f64], Next<'_, D>) + Sync,
    ) -> (f64, Vector<D>) {
        self.sweep_parts(points, cells_per_band, |b| &mut b.bands, sweep)
    }

    /// [`Self::sweep_bands`] over the parts `parts` picks from the buffers (the bands, or
    /// in 3D the slabs).
    fn sweep_parts<P: Send>(
        &mut self,
        points: &mut MaterialPoints<D>,
        cells_per_band: usize,
        parts_of: fn(&mut FusedBuffers<D>) -> &mut Vec<P>,
        sweep: impl Fn(&Self, usize, &mut P, Fields<'_, D>, &[f64], Next<'_, D>) + Sync,
    ) -> (f64, Vector<D>) {
        let mut buffers = std::mem::take(&mut self.fused);
        let mut bands = std::mem::take(parts_of(&mut buffers));
        {
            let this = &*self;
            let MaterialPoints {
                stress,
                velocity,
                position,
                ..
            } = &mut *points;
            let fields = Fields::per_cell(stress, velocity);
            let inverse_mass = &this.inverse_mass[..];
            let parts = (
                chunks(&mut bands, 1),
                chunks(&mut buffers.next_tensor, cells_per_band),
                (
                    chunks(&mut buffers.next_velocity, cells_per_band),
                    chunks(position, cells_per_band),
                ),
            );
            for_each_chunk(this.parallel, 1, parts, |b, (band, tensor, (v, x))| {
                let next = Next {
                    tensor,
                    velocity: v,
                    position: x,
                };
                sweep(this, b, &mut band[0], fields, inverse_mass, next);
            });
        }
        *parts_of(&mut buffers) = bands;
        std::mem::swap(&mut points.stress, &mut buffers.next_tensor);
        std::mem::swap(&mut points.velocity, &mut buffers.next_velocity);
        let totals = buffers.totals();
        self.fused = buffers;
        totals
    }

    /// Phase 4 for one cell: `q ← q - Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l` (momentum
    /// part: `v ← v - Δt (V/m) Σ_l …`) from its faces' final fluxes `[low, high]` per axis, and the
    /// move `x ← x + Δt v`; the same arithmetic as [`Self::cell_update`], with the
    /// step's constants `u` formed once.
    #[inline(always)]
    fn update_cell(
        u: &UpdateConstants<D>,
        faces: [[&Conserved<D>; 2]; D],
        (q, v, inverse_mass): (&Tensor<D>, &Vector<D>, f64),
        next: (&mut Tensor<D>, &mut Vector<D>, &mut Vector<D>),
    ) {
        let (dq, dv) = Self::flux_increment(u, faces, inverse_mass);
        *next.0 = q + dq;
        *next.1 = v + dv;
        *next.2 += *next.1 * u.dt;
    }

    /// The cell update's increment `-Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l` (momentum
    /// part `-Δt (V/m) Σ_l …`) of a cell whose point has mass `m` (`inverse_mass` `1/m`,
    /// formed once: [`DgmpmSolver::inverse_mass`]) from its faces' final fluxes
    /// `[low, high]` per axis, `Δt` being `u`'s.
    #[inline(always)]
    fn flux_increment(
        u: &UpdateConstants<D>,
        faces: [[&Conserved<D>; 2]; D],
        inverse_mass: f64,
    ) -> (Tensor<D>, Vector<D>) {
        let mut dq = Tensor::<D>::zeros();
        let mut dm = Vector::<D>::zeros();
        // (`+= (low - high)`, not `-= (high - low)`: the same values but for the sign of a
        // zero, without a negation)
        for (l, [low, high]) in faces.iter().enumerate() {
            dq += (low.tensor - high.tensor) * u.inv_spacing[l];
            dm += (low.momentum - high.momentum) * u.inv_spacing[l];
        }
        (
            dq * (u.tensor_scale * inverse_mass),
            dm * (u.velocity_scale * inverse_mass),
        )
    }

    /// The constants of [`Self::update_cell`] for a step of `dt`.
    fn update_constants(&self, dt: f64) -> UpdateConstants<D> {
        let (density, volume) = (self.material.density, self.grid.cell_volume());
        UpdateConstants {
            inv_spacing: std::array::from_fn(|l| 1.0 / self.grid.spacing[l]),
            tensor_scale: dt * density * volume,
            velocity_scale: dt * volume,
            dt,
        }
    }
}

/// The constants of the cell update: `1/Δx_l`, `Δt ρ V`, `Δt V` and `Δt`.
struct UpdateConstants<const D: usize> {
    inv_spacing: [f64; D],
    tensor_scale: f64,
    velocity_scale: f64,
    dt: f64,
}

impl<const D: usize> DgmpmSolver<D> {
    /// `run(solver, fused buffers, nodal fields)` with both taken out of the solver (the
    /// nodal and Heun sweeps read the solver while they write them) and put back after;
    /// returns the bands' power and force, added up.
    fn with_buffers(
        &mut self,
        run: impl FnOnce(&Self, &mut FusedBuffers<D>, &mut crate::NodalFields<D>),
    ) -> (f64, Vector<D>) {
        let mut buffers = std::mem::take(&mut self.fused);
        let mut nodes = std::mem::take(&mut self.nodes);
        run(self, &mut buffers, &mut nodes);
        self.nodes = nodes;
        let totals = buffers.totals();
        self.fused = buffers;
        totals
    }
}

impl<const D: usize> DgmpmSolver<D> {
    /// The Godunov flux of a boundary face ([`Self::linear_face_flux`]), its power and
    /// force added to `band`'s (kept out of the sweeps' inner loops).
    #[inline(never)]
    fn boundary_flux(
        &self,
        l: usize,
        idx: [usize; D],
        fields: Fields<'_, D>,
        band: &mut Band<D>,
    ) -> Conserved<D> {
        let (flux, power) = self.linear_face_flux(l, idx, fields);
        band.power += power;
        band.force += self.boundary_face_force(l, idx, &flux);
        flux
    }
}

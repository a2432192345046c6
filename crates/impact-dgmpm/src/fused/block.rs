//! The fused cell path in 3D (linear elasticity, one point per cell, forward Euler): the
//! phases of the cell path (`interface_fluxes`, `ctu3.rs`'s transverse corrections,
//! `boundary_force`, `cell_update`) in one sweep over the z-layers of cells, with rolling
//! planes of faces instead of the face and fluctuation arrays. Bit for bit the cell path:
//! the same functions, or the same operations in the same order, on every value (the
//! axis fluxes leave out only products by the zero and unit components of the normal,
//! which change no value); `tests/fused_3d.rs` compares the bits of every component.
//!
//! Phases, for each layer `z` of a slab (CTU, LeVeque 2002 §21.6; Langseth & LeVeque
//! 2000; Clawpack's `flux3`, `method(3) = 11`, with `rpt3`/`rptt3`):
//! 1. the Godunov fluxes `F_l(q*)` (paper §4, eqs. 18-21) of the x- and y-faces of layer
//!    `z + 1` and of the z-faces between layers `z` and `z + 1`;
//! 2. the fluctuations `W_l(X) = F_l,high - F_l,low` of layer `z + 1` (x, y) and of layer
//!    `z` (z), with a ring of ghost cells (`DgmpmSolver::ghost_fluctuation`: mirror states
//!    behind one edge; behind two, the mirror through a symmetry edge or the mean of the two
//!    single ghosts); a whole ghost layer below the block and above it;
//! 3. the sources `V_z` of layer `z + 1`, `V_x`, `V_y` of layer `z` row by row
//!    (`ctu3::source_of`:
//!    `V_k = -Σ_{l≠k} Δt/(2Δx_l) W_l + Δt²/(6Δx_lΔx_m) [C_m^± ΔW_l + C_l^± ΔW_m]`);
//! 4. the final fluxes `F_k += B_k⁺ V_k(below) + B_k⁻ V_k(above)`
//!    (`riemann::axis::axis_transverse`, restricted on an edge face under
//!    `edges = "restricted"`, [`crate::riemann::constrain_correction`]);
//! 5. the boundary force and power, and the cell update
//!    `q ← q - Δt (ρV/m) Σ_l (F_l,high - F_l,low)/Δx_l`, `x ← x + Δt v`.
//!
//! Donor-cell keeps phase 1 and 5 only: a rolling x-face along the row, a row of y-faces,
//! a plane of z-faces.
//!
//! Memory (`nx × ny` planes of 96 B entries): per slab, CTU keeps the Godunov x-, y- and
//! z-faces of two layers, `W_x`, `W_y` of three layers and `W_z` of one (with a ghost
//! ring), `V_z` and the final z-faces of two: 17 planes, plus one row of `V_x` and two of
//! `V_y` (phases 3-5 of a layer run row by row, the final x- and y-faces formed in place);
//! donor-cell keeps one plane of z-faces and one row of y-faces. The slabs are
//! `max(8, ⌈nz/4⌉)` layers thick (at most four: the unit of parallel work, each with its
//! own planes; a slab recomputes the Godunov x- and y-faces of the layer below it), so at
//! 128³ the planes cost about 51 B per cell and at 512³ 13. The new states go to a second
//! buffer (96 B per cell), swapped with the points'. Results do not depend on the slabs
//! (each value is formed by the same operations), only the sums of the boundary power and
//! force are added in another order.
use super::{FusedBuffers, Next};
use crate::ctu3::SourceScales;
use crate::faces::Fields;
use crate::riemann::axis::AxisConstants;
use crate::riemann::{Conserved, Elastic, FullState};
use crate::DgmpmSolver;
use impact_core::method::{EdgeTreatment, TransverseFlux};
use impact_core::points::MaterialPoints;
use impact_core::{Tensor, Vector};

mod ctu;

type C3 = Conserved<3>;

/// Fewest layers per slab, and most slabs.
const MIN_SLAB_LAYERS: usize = 8;
const MAX_SLABS: usize = 4;

/// Layers per slab for `nz` layers.
fn slab_layers(nz: usize) -> usize {
    MIN_SLAB_LAYERS.max(nz.div_ceil(MAX_SLABS))
}

/// The rolling planes of one slab and the boundary power and force of its faces. Slot 0
/// holds layer (face) `z`, slot 1 `z + 1`; `wx`, `wy` hold layers `z - 1`, `z`, `z + 1`;
/// `vx` one cell row's `V_x`, `vy` two rows' `V_y`.
#[derive(Debug, Clone)]
pub(crate) struct Slab {
    gx: [Vec<C3>; 2],
    gy: [Vec<C3>; 2],
    gz: [Vec<C3>; 2],
    wx: [Vec<C3>; 3],
    wy: [Vec<C3>; 3],
    wz: Vec<C3>,
    vx: Vec<C3>,
    vy: [Vec<C3>; 2],
    vz: [Vec<C3>; 2],
    fz: [Vec<C3>; 2],
    pub(super) power: f64,
    pub(super) force: Vector<3>,
}

impl Slab {
    /// The slabs of a grid of `cells`: CTU's planes, or donor-cell's (a plane of z-faces
    /// and a row of y-faces).
    pub(super) fn for_grid(cells: [usize; 3], ctu: bool) -> Vec<Self> {
        let [nx, ny, nz] = cells;
        let plane = |len: usize, keep: bool| vec![Conserved::zeros(); if keep { len } else { 0 }];
        let ring = (nx + 2) * (ny + 2);
        let slab = Slab {
            gx: [plane((nx + 1) * ny, ctu), plane((nx + 1) * ny, ctu)],
            // donor-cell: one row of y-faces
            gy: [
                plane(if ctu { nx * (ny + 1) } else { nx }, true),
                plane(nx * (ny + 1), ctu),
            ],
            gz: [plane(nx * ny, true), plane(nx * ny, ctu)],
            wx: std::array::from_fn(|_| plane(ring, ctu)),
            wy: std::array::from_fn(|_| plane(ring, ctu)),
            wz: plane(ring, ctu),
            vx: plane(nx + 2, ctu),
            vy: [plane(nx, ctu), plane(nx, ctu)],
            vz: [plane(nx * ny, ctu), plane(nx * ny, ctu)],
            fz: [plane(nx * ny, ctu), plane(nx * ny, ctu)],
            power: 0.0,
            force: Vector::<3>::zeros(),
        };
        vec![slab; nz.div_ceil(slab_layers(nz))]
    }
}

/// The constants of the axis fluxes, formed as `riemann::linear` forms them.
#[derive(Debug, Clone, Copy)]
struct Flux3 {
    lambda: f64,
    /// `-λ` and `-2μ`: the negated stress parts as products, `-(c x) = (-c) x` exactly
    /// (as `crate::riemann::axis::AxisConstants`).
    neg_lambda: f64,
    neg_two_mu: f64,
    half_zp: f64,
    half_over_zp: f64,
    half_zs: f64,
    half_over_zs: f64,
    shear: bool,
}

impl Flux3 {
    fn new(m: &Elastic) -> Self {
        Self {
            lambda: m.lambda,
            neg_lambda: -m.lambda,
            neg_two_mu: -(2.0 * m.mu),
            half_zp: 0.5 * m.z.p,
            half_over_zp: 0.5 / m.z.p,
            half_zs: 0.5 * m.z.s,
            half_over_zs: 0.5 / m.z.s,
            shear: m.z.s > 0.0,
        }
    }
}

/// Godunov flux through an interior face normal to `e_L` (3D):
/// `normal_flux(linear_elastic_star(…))` for `n = e_L` with the products by the zero and
/// unit components of `n` left out, every other operation as there (the same values):
/// `t_L* = ½(t_Ll + t_Lr) + ½Z_p(v_Lr - v_Ll)`, `v_L* = ½(v_Ll + v_Lr) + (t_Lr - t_Ll)/(2Z_p)`,
/// the same per tangent `o` with `Z_s`; `F = -(C : sym(v* ⊗ e_L), t*)`.
#[inline(always)]
fn axis_flux_3d<const L: usize>(left: &FullState<3>, right: &FullState<3>, k: &Flux3) -> C3 {
    let (tl, tr) = (left.tensor[(L, L)], right.tensor[(L, L)]);
    let (vl, vr) = (left.velocity[L], right.velocity[L]);
    let t_n = 0.5 * (tl + tr) + k.half_zp * (vr - vl);
    let v_n = 0.5 * (vl + vr) + (tr - tl) * k.half_over_zp;
    let mut tensor = Tensor::<3>::zeros();
    let mut momentum = Vector::<3>::zeros();
    tensor[(L, L)] = v_n * k.neg_two_mu - k.lambda * v_n;
    momentum[L] = -t_n;
    for o in [(L + 1) % 3, (L + 2) % 3] {
        let (t, v) = match k.shear {
            true => (
                (left.tensor[(o, L)] + right.tensor[(o, L)]) * 0.5
                    + (right.velocity[o] - left.velocity[o]) * k.half_zs,
                (left.velocity[o] + right.velocity[o]) * 0.5
                    + (right.tensor[(o, L)] - left.tensor[(o, L)]) * k.half_over_zs,
            ),
            false => (0.0, 0.0),
        };
        let shear = (v * 0.5) * k.neg_two_mu;
        tensor[(o, o)] = k.neg_lambda * v_n;
        tensor[(o, L)] = shear;
        tensor[(L, o)] = shear;
        momentum[o] = -t;
    }
    Conserved { tensor, momentum }
}

/// The constants of one 3D sweep.
struct Sweep3d {
    flux: Flux3,
    constants: AxisConstants,
    scales: [SourceScales; 3],
    restricted: bool,
}

/// Index of `(i, j)` in a plane with a ghost ring (`i ∈ [-1, nx]`, `j ∈ [-1, ny]`).
#[inline(always)]
fn ring(nx: usize, i: isize, j: isize) -> usize {
    ((j + 1) * (nx as isize + 2) + i + 1) as usize
}

impl DgmpmSolver<3> {
    /// The 3D sweep (module doc) of every slab, donor-cell or CTU.
    pub(super) fn sweep_3d(&mut self, points: &mut MaterialPoints<3>, dt: f64) -> (f64, Vector<3>) {
        let [nx, ny, nz] = self.grid.cells;
        let k = Sweep3d {
            flux: Flux3::new(&self.elastic),
            constants: AxisConstants::new(&self.elastic),
            scales: std::array::from_fn(|a| SourceScales::new(&self.grid.spacing, a, dt)),
            restricted: self.options.edges == EdgeTreatment::Restricted,
        };
        let ctu = self.options.flux == TransverseFlux::Ctu;
        let u = self.update_constants(dt);
        let layers = slab_layers(nz);
        let slabs: fn(&mut FusedBuffers<3>) -> &mut Vec<Slab> = |b| &mut b.slabs;
        self.sweep_parts(
            points,
            layers * nx * ny,
            slabs,
            |this, b, slab, fields, inverse_mass, next| {
                let Next {
                    tensor,
                    velocity,
                    position,
                } = next;
                slab.power = 0.0;
                slab.force = Vector::<3>::zeros();
                let z0 = b * layers;
                let mut update = |cell: usize, faces: [[&C3; 2]; 3]| {
                    let state = fields.cell(cell);
                    let old = (&state.tensor, &state.velocity, inverse_mass[cell]);
                    let local = cell - z0 * nx * ny;
                    let out = (
                        &mut tensor[local],
                        &mut velocity[local],
                        &mut position[local],
                    );
                    Self::update_cell(&u, faces, old, out);
                };
                let range = z0..(z0 + layers).min(nz);
                match ctu {
                    true => this.slab_ctu(range, slab, fields, &k, &mut update),
                    false => this.slab_dcu(range, slab, fields, &k.flux, &mut update),
                }
            },
        )
    }

    /// The Godunov flux of a boundary face and its power.
    #[inline(never)]
    fn boundary_godunov(&self, l: usize, idx: [usize; 3], fields: Fields<'_, 3>) -> (C3, f64) {
        self.linear_face_flux(l, idx, fields)
    }

    /// Donor-cell on the layers `range`: per cell its high x-, y- and z-faces and the update.
    fn slab_dcu(
        &self,
        range: std::ops::Range<usize>,
        slab: &mut Slab,
        fields: Fields<'_, 3>,
        k: &Flux3,
        update: &mut impl FnMut(usize, [[&C3; 2]; 3]),
    ) {
        let [nx, ny, nz] = self.grid.cells;
        let plane = nx * ny;
        let z0 = range.start;
        let [zf, yrow] = [&mut slab.gz[0], &mut slab.gy[0]];
        // the low z-faces of the first layer
        for j in 0..ny {
            for i in 0..nx {
                let c = z0 * plane + j * nx + i;
                zf[j * nx + i] = match z0 {
                    0 => {
                        let (flux, power) = self.boundary_godunov(2, [i, j, 0], fields);
                        slab.power += power;
                        slab.force += self.boundary_face_force(2, [i, j, 0], &flux);
                        flux
                    }
                    _ => axis_flux_3d::<2>(&fields.cell(c - plane), &fields.cell(c), k),
                };
            }
        }
        let boundary = |l: usize, idx: [usize; 3], slab_power: &mut f64, force: &mut Vector<3>| {
            let (flux, power) = self.boundary_godunov(l, idx, fields);
            *slab_power += power;
            *force += self.boundary_face_force(l, idx, &flux);
            flux
        };
        let (mut power, mut force) = (0.0, Vector::<3>::zeros());
        for z in range {
            for j in 0..ny {
                let row = z * plane + j * nx;
                let mut x_low = boundary(0, [0, j, z], &mut power, &mut force);
                for i in 0..nx {
                    let c = row + i;
                    let state = fields.cell(c);
                    let x_high = match i + 1 < nx {
                        true => axis_flux_3d::<0>(&state, &fields.cell(c + 1), k),
                        false => boundary(0, [nx, j, z], &mut power, &mut force),
                    };
                    if j == 0 {
                        yrow[i] = boundary(1, [i, 0, z], &mut power, &mut force);
                    }
                    let y_high = match j + 1 < ny {
                        true => axis_flux_3d::<1>(&state, &fields.cell(c + nx), k),
                        false => boundary(1, [i, ny, z], &mut power, &mut force),
                    };
                    let z_high = match z + 1 < nz {
                        true => axis_flux_3d::<2>(&state, &fields.cell(c + plane), k),
                        false => boundary(2, [i, j, nz], &mut power, &mut force),
                    };
                    let zf = &mut zf[j * nx + i];
                    update(c, [[&x_low, &x_high], [&yrow[i], &y_high], [zf, &z_high]]);
                    (x_low, yrow[i], *zf) = (x_high, y_high, z_high);
                }
            }
        }
        slab.power += power;
        slab.force += force;
    }
}

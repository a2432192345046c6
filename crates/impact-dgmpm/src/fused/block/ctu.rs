//! CTU in the 3D sweep (module doc of [`super`]): per slab, the prologue (the layer below
//! the slab, or the ghost layer below the block), then per layer the Godunov faces of the
//! next layer, the fluctuations `W`, the sources `V` and the final fluxes, and the cell
//! updates. Each value is formed as `ctu3.rs` forms it (`ghost_fluctuation`, `source_of`,
//! `axis_transverse` and `constrain_correction`, in the same order).
use super::{axis_flux_3d, ring, Flux3, Slab, Sweep3d, C3};
use crate::ctu3::source_of;
use crate::faces::Fields;
use crate::riemann::axis::axis_transverse;
use crate::riemann::constrain_correction;
use crate::{unit, DgmpmSolver};

impl DgmpmSolver<3> {
    /// CTU on the layers `range` of a slab.
    pub(super) fn slab_ctu(
        &self,
        range: std::ops::Range<usize>,
        slab: &mut Slab,
        fields: Fields<'_, 3>,
        k: &Sweep3d,
        update: &mut impl FnMut(usize, [[&C3; 2]; 3]),
    ) {
        let [nx, ny, nz] = self.grid.cells;
        let plane = nx * ny;
        let (z0, z1) = (range.start, range.end);
        let f = &k.flux;
        let Slab {
            gx,
            gy,
            gz,
            wx,
            wy,
            wz,
            vx,
            vy,
            vz,
            fz,
            power,
            force,
        } = slab;
        // prologue: W_x, W_y of the layer below (ghosts below the block), V_z there and in
        // the first layer, the first layer's Godunov faces and its final low z-faces
        if z0 == 0 {
            self.w_layer(0, -1, None, fields, &mut wx[0]);
            self.w_layer(1, -1, None, fields, &mut wy[0]);
        } else {
            self.godunov_x(z0 - 1, fields, f, &mut gx[1]);
            self.godunov_y(z0 - 1, fields, f, &mut gy[1]);
            self.w_layer(0, z0 as isize - 1, Some(&gx[1]), fields, &mut wx[0]);
            self.w_layer(1, z0 as isize - 1, Some(&gy[1]), fields, &mut wy[0]);
        }
        *power += self.godunov_x(z0, fields, f, &mut gx[0]);
        *power += self.godunov_y(z0, fields, f, &mut gy[0]);
        self.w_layer(0, z0 as isize, Some(&gx[0]), fields, &mut wx[1]);
        self.w_layer(1, z0 as isize, Some(&gy[0]), fields, &mut wy[1]);
        self.v_z_layer(&wx[0], &wy[0], k, &mut vz[0]);
        self.v_z_layer(&wx[1], &wy[1], k, &mut vz[1]);
        *power += self.godunov_z(z0, fields, f, &mut gz[0]);
        self.final_z(z0, &gz[0], [&vz[0], &vz[1]], k, &mut fz[0], force);
        vz.swap(0, 1);
        for z in z0..z1 {
            let next = z + 1;
            if next < nz {
                let p = self.godunov_x(next, fields, f, &mut gx[1])
                    + self.godunov_y(next, fields, f, &mut gy[1]);
                if next < z1 {
                    *power += p;
                }
                self.w_layer(0, next as isize, Some(&gx[1]), fields, &mut wx[2]);
                self.w_layer(1, next as isize, Some(&gy[1]), fields, &mut wy[2]);
            } else {
                self.w_layer(0, nz as isize, None, fields, &mut wx[2]);
                self.w_layer(1, nz as isize, None, fields, &mut wy[2]);
            }
            let p = self.godunov_z(next, fields, f, &mut gz[1]);
            *power += p;
            self.w_z_layer(z, [&gz[0], &gz[1]], fields, wz);
            self.v_z_layer(&wx[2], &wy[2], k, &mut vz[1]);
            // per row j: V_y of row j + 1 and the final y-faces between rows j and j + 1,
            // V_x of row j and its final x-faces, the final high z-faces of row j, and the
            // updates of row j (the V rows roll; the faces are finalised in place)
            let [vy_low, vy_high] = vy;
            self.v_y_row(-1, wx, wz, k, vy_low);
            self.v_y_row(0, wx, wz, k, vy_high);
            self.final_y_row(
                z,
                0,
                &mut gy[0][..nx],
                [&vy_low[..], &vy_high[..]],
                k,
                force,
            );
            std::mem::swap(vy_low, vy_high);
            for j in 0..ny {
                self.v_y_row(j as isize + 1, wx, wz, k, vy_high);
                let row = &mut gy[0][(j + 1) * nx..(j + 2) * nx];
                self.final_y_row(z, j + 1, row, [&vy_low[..], &vy_high[..]], k, force);
                std::mem::swap(vy_low, vy_high);
                self.v_x_row(j, wy, wz, k, vx);
                let row = &mut gx[0][j * (nx + 1)..(j + 1) * (nx + 1)];
                for i in 0..=nx {
                    let edge = i == 0 || i == nx;
                    let idx = [i, j, z];
                    row[i] = self.corrected(0, idx, &row[i], [&vx[i], &vx[i + 1]], k, edge);
                    if edge {
                        *force += self.boundary_face_force(0, idx, &row[i]);
                    }
                }
                let (top, edge) = (j * nx..(j + 1) * nx, next == nz);
                for (i, out) in fz[1][top.clone()].iter_mut().enumerate() {
                    let (y, idx) = (j * nx + i, [i, j, next]);
                    *out = self.corrected(2, idx, &gz[1][y], [&vz[0][y], &vz[1][y]], k, edge);
                    if edge {
                        *force += self.boundary_face_force(2, idx, out);
                    }
                }
                for i in 0..nx {
                    let (x, y) = (j * (nx + 1) + i, j * nx + i);
                    let faces = [
                        [&gx[0][x], &gx[0][x + 1]],
                        [&gy[0][y], &gy[0][y + nx]],
                        [&fz[0][y], &fz[1][y]],
                    ];
                    update(z * plane + y, faces);
                }
            }
            gx.swap(0, 1);
            gy.swap(0, 1);
            gz.swap(0, 1);
            vz.swap(0, 1);
            fz.swap(0, 1);
            wx.rotate_left(1);
            wy.rotate_left(1);
        }
    }

    /// `F_k = G + c`, `c = B_k⁺ V(below) + B_k⁻ V(above)`, restricted on an `edge` face
    /// (as `ctu3.rs` corrects a face of axis `k` at `idx`).
    #[inline(always)]
    fn corrected(
        &self,
        axis: usize,
        idx: [usize; 3],
        godunov: &C3,
        [below, above]: [&C3; 2],
        k: &Sweep3d,
        edge: bool,
    ) -> C3 {
        let mut c = axis_transverse(axis, below, above, &k.constants);
        if edge && k.restricted {
            let side = usize::from(idx[axis] != 0);
            let cond = self.edge_condition(axis, side, &idx);
            c = constrain_correction(&c, &unit::<3>(axis), cond);
        }
        godunov.add_scaled(&c, 1.0)
    }

    /// The final z-faces `f` (`nx × ny`) from their Godunov fluxes and the sources `V_z`
    /// of the layers below and above; the force of a boundary face added to `force`.
    fn final_z(
        &self,
        f: usize,
        godunov: &[C3],
        [below, above]: [&[C3]; 2],
        k: &Sweep3d,
        out: &mut [C3],
        force: &mut impact_core::Vector<3>,
    ) {
        let [nx, ny, nz] = self.grid.cells;
        let edge = f == 0 || f == nz;
        for j in 0..ny {
            for i in 0..nx {
                let (y, idx) = (j * nx + i, [i, j, f]);
                out[y] = self.corrected(2, idx, &godunov[y], [&below[y], &above[y]], k, edge);
                if edge {
                    *force += self.boundary_face_force(2, idx, &out[y]);
                }
            }
        }
    }

    /// Godunov fluxes of the x-faces of layer `z` (`(nx + 1) × ny`); the boundary faces'
    /// power.
    fn godunov_x(&self, z: usize, fields: Fields<'_, 3>, f: &Flux3, out: &mut [C3]) -> f64 {
        let [nx, ny, _] = self.grid.cells;
        let mut power = 0.0;
        for j in 0..ny {
            let row = (z * ny + j) * nx;
            let o = &mut out[j * (nx + 1)..(j + 1) * (nx + 1)];
            for i in 1..nx {
                o[i] = axis_flux_3d::<0>(&fields.cell(row + i - 1), &fields.cell(row + i), f);
            }
            for i in [0, nx] {
                let p;
                (o[i], p) = self.boundary_godunov(0, [i, j, z], fields);
                power += p;
            }
        }
        power
    }

    /// Godunov fluxes of the y-faces of layer `z` (`nx × (ny + 1)`); the boundary faces'
    /// power.
    fn godunov_y(&self, z: usize, fields: Fields<'_, 3>, f: &Flux3, out: &mut [C3]) -> f64 {
        let [nx, ny, _] = self.grid.cells;
        let mut power = 0.0;
        for j in 0..=ny {
            let o = &mut out[j * nx..(j + 1) * nx];
            if j == 0 || j == ny {
                for (i, o) in o.iter_mut().enumerate() {
                    let p;
                    (*o, p) = self.boundary_godunov(1, [i, j, z], fields);
                    power += p;
                }
                continue;
            }
            let above = (z * ny + j) * nx;
            for (i, o) in o.iter_mut().enumerate() {
                *o = axis_flux_3d::<1>(&fields.cell(above + i - nx), &fields.cell(above + i), f);
            }
        }
        power
    }

    /// Godunov fluxes of the z-faces `f` (between layers `f - 1` and `f`, `nx × ny`); the
    /// boundary faces' power.
    fn godunov_z(&self, f: usize, fields: Fields<'_, 3>, k: &Flux3, out: &mut [C3]) -> f64 {
        let [nx, ny, nz] = self.grid.cells;
        let plane = nx * ny;
        let mut power = 0.0;
        for j in 0..ny {
            for i in 0..nx {
                let y = j * nx + i;
                out[y] = match f == 0 || f == nz {
                    true => {
                        let p;
                        let flux;
                        (flux, p) = self.boundary_godunov(2, [i, j, f], fields);
                        power += p;
                        flux
                    }
                    false => {
                        let c = f * plane + y;
                        axis_flux_3d::<2>(&fields.cell(c - plane), &fields.cell(c), k)
                    }
                };
            }
        }
        power
    }

    /// `W_l` (`l` = 0 or 1) of layer `z` into a ring plane: from the layer's Godunov faces
    /// `g` inside (`None`: a ghost layer, `z = -1` or `nz`), ghosts on the ring across the
    /// other in-plane axis.
    fn w_layer(&self, l: usize, z: isize, g: Option<&[C3]>, fields: Fields<'_, 3>, out: &mut [C3]) {
        let [nx, ny, _] = self.grid.cells;
        let (nxi, nyi) = (nx as isize, ny as isize);
        let ghost = |i: isize, j: isize| self.ghost_fluctuation(l, [i, j, z], fields);
        // the ring across the other axis: j = -1, ny (l = x) or i = -1, nx (l = y)
        let (along, across) = match l {
            0 => (0..nxi, [-1, nyi]),
            _ => (0..nyi, [-1, nxi]),
        };
        let at = |a: isize, b: isize| match l {
            0 => (a, b),
            _ => (b, a),
        };
        for b in across {
            for a in along.clone() {
                let (i, j) = at(a, b);
                out[ring(nx, i, j)] = ghost(i, j);
            }
        }
        for j in 0..nyi {
            for i in 0..nxi {
                out[ring(nx, i, j)] = match g {
                    None => ghost(i, j),
                    Some(g) => {
                        let (iu, ju) = (i as usize, j as usize);
                        let (lo, hi) = match l {
                            0 => (ju * (nx + 1) + iu, ju * (nx + 1) + iu + 1),
                            _ => (ju * nx + iu, (ju + 1) * nx + iu),
                        };
                        g[hi].add_scaled(&g[lo], -1.0)
                    }
                };
            }
        }
    }

    /// `W_z` of layer `z` into a ring plane: `gz[1] - gz[0]` inside, ghosts on the ring
    /// (the corners behind two edges).
    fn w_z_layer(&self, z: usize, gz: [&[C3]; 2], fields: Fields<'_, 3>, out: &mut [C3]) {
        let [nx, ny, _] = self.grid.cells;
        let (nxi, nyi) = (nx as isize, ny as isize);
        let ghost = |i: isize, j: isize| self.ghost_fluctuation(2, [i, j, z as isize], fields);
        for j in -1..=nyi {
            for i in [-1, nxi] {
                out[ring(nx, i, j)] = ghost(i, j);
            }
        }
        for j in [-1, nyi] {
            for i in 0..nxi {
                out[ring(nx, i, j)] = ghost(i, j);
            }
        }
        for j in 0..ny {
            for i in 0..nx {
                let y = j * nx + i;
                out[ring(nx, i as isize, j as isize)] = gz[1][y].add_scaled(&gz[0][y], -1.0);
            }
        }
    }

    /// `V_z` of one layer (`nx × ny`) from its `W_x`, `W_y` (ring planes).
    fn v_z_layer(&self, wx: &[C3], wy: &[C3], k: &Sweep3d, out: &mut [C3]) {
        let [nx, ny, _] = self.grid.cells;
        for j in 0..ny as isize {
            for i in 0..nx as isize {
                let r = |a: isize, b: isize| ring(nx, i + a, j + b);
                let wl = [&wx[r(0, -1)], &wx[r(0, 0)], &wx[r(0, 1)]];
                let wm = [&wy[r(-1, 0)], &wy[r(0, 0)], &wy[r(1, 0)]];
                out[(j * nx as isize + i) as usize] =
                    source_of(2, wl, wm, &k.scales[2], &k.constants);
            }
        }
    }

    /// The final y-faces of face row `j` of layer `z` in place (`row`, `nx`), from the
    /// `V_y` of the cell rows below and above it; a boundary face's force added.
    fn final_y_row(
        &self,
        z: usize,
        j: usize,
        row: &mut [C3],
        [below, above]: [&[C3]; 2],
        k: &Sweep3d,
        force: &mut impact_core::Vector<3>,
    ) {
        let edge = j == 0 || j == self.grid.cells[1];
        for (i, g) in row.iter_mut().enumerate() {
            let idx = [i, j, z];
            *g = self.corrected(1, idx, g, [&below[i], &above[i]], k, edge);
            if edge {
                *force += self.boundary_face_force(1, idx, g);
            }
        }
    }

    /// `V_x` of cell row `j` (`nx + 2`, a ghost cell at each end) from `W_y` of the layers
    /// below, at and above it and `W_z` of the layer.
    fn v_x_row(&self, j: usize, wy: &[Vec<C3>; 3], wz: &[C3], k: &Sweep3d, out: &mut [C3]) {
        let nx = self.grid.cells[0];
        let j = j as isize;
        for (slot, i) in (-1..=nx as isize).enumerate() {
            let r = ring(nx, i, j);
            let wl = [&wy[0][r], &wy[1][r], &wy[2][r]];
            let wm = [&wz[ring(nx, i, j - 1)], &wz[r], &wz[ring(nx, i, j + 1)]];
            out[slot] = source_of(0, wl, wm, &k.scales[0], &k.constants);
        }
    }

    /// `V_y` of cell row `j` (`-1 ≤ j ≤ ny`; `nx`) from `W_x` of the layers below, at and
    /// above it and `W_z` of the layer.
    fn v_y_row(&self, j: isize, wx: &[Vec<C3>; 3], wz: &[C3], k: &Sweep3d, out: &mut [C3]) {
        let nx = self.grid.cells[0];
        for (i, out) in out.iter_mut().enumerate() {
            let i = i as isize;
            let r = ring(nx, i, j);
            let wl = [&wx[0][r], &wx[1][r], &wx[2][r]];
            let wm = [&wz[ring(nx, i - 1, j)], &wz[r], &wz[ring(nx, i + 1, j)]];
            *out = source_of(1, wl, wm, &k.scales[1], &k.constants);
        }
    }
}

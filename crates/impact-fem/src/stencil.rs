//! The internal force of linear elasticity as a fixed node stencil (issue 14).
//!
//! On the regular mesh every element has the same stiffness
//! `K_e[a][b] = Σ_g w_g V_e B_a(ξ_g)ᵀ C B_b(ξ_g)` (`D×D` blocks, local nodes `a`, `b`), so
//! `f_int = K u` is, at every node, a sum over its `3^D` neighbours `n + o`,
//! `o ∈ {-1, 0, 1}^D`, of one `D×D` block times `u_{n+o}`:
//! `S_t[o] = Σ_{elements e ∋ n, n+o} K_e[a(n, e)][b(n+o, e)]` (Hughes 1987, §1.13: the
//! assembled stiffness of a uniform mesh is a difference stencil). The block depends only
//! on the node's type `t`: per axis low edge, interior or high edge (`3^D` types; an edge
//! node misses the elements outside). Each node gathers its own force: no scatter, no
//! colouring, disjoint writes in parallel. On a rank's box of the mesh (`slab.rs`) the
//! types are read off the stored box; they are the whole mesh's on every owned node, since
//! a cut face's nodes are halo nodes, whose accelerations come from their owners.
//!
//! `K_e` is built by applying the solver's own Gauss-point force to unit displacements
//! ([`crate::FemSolver::element_stiffness`]), so the stencil and the Gauss path share the
//! material law; they agree to round-off (tested to 1e-13 relative on every node). It
//! applies to linear elasticity only: Saint-Venant–Kirchhoff is nonlinear and J2 reads its
//! Gauss-point history, so both keep the Gauss path.
//!
//! Two sums are arranged for speed, with the same operator: in 2D the interior nodes
//! take the two blocks of each pair of opposite neighbours `±o` as one (they are equal:
//! [`Stencil::new`]), `S[0] u_n + Σ_{4 pairs} S[o] (u_{n+o} + u_{n-o})`, five block
//! products per node instead of nine (in 3D, 14 instead of 27: 13 pairs); in 1D, where a
//! layer is one node, the passes walk slabs of [`SLAB_1D`] nodes whose interior is one loop
//! over three fixed coefficients.
//!
//! The stencil runs layer by layer (node layers along the last axis): a layer's
//! acceleration reads the displacement of the layer below, its own and the one above
//! ([`Stencil::slab_into`]). That lets the step fuse its two phases
//! ([`Stencil::step_into`]): the central-difference update `v += Δt_avg a`, `u += Δt v`
//! (`FemSolver::nodal_update`) runs one layer ahead of `a = -(K u)/m`, so each node's
//! `u`, `v`, `a` pass through memory once per step instead of twice. In parallel the
//! layers are cut into bands; a band needs the updated displacement of the layer on each
//! side of it, which its neighbours update in the same pass, so those two layers are
//! formed first into a halo buffer, from the same values with the same operations (bit
//! for bit what the neighbour stores). The separate phases stay the reference the fused
//! step is tested against (`tests/fused_step.rs`).
use crate::central::advance_node;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::{Grid, Tensor, Vector};

/// The node stencil of a regular mesh (module doc).
#[derive(Debug, Clone)]
pub struct Stencil<const D: usize> {
    /// Nodes per axis.
    counts: [usize; D],
    /// Per node type, its nonzero blocks: the layer they read (0 the layer below, 1 the
    /// node's own, 2 the layer above), the node offset within that layer, the block.
    blocks: Vec<Vec<(usize, isize, Tensor<D>)>>,
    /// 2D: the interior type's blocks as plain `2×2` arrays: the centre's, then those of
    /// the four pairs of opposite neighbours `±o`, `(S[o] + S[-o])/2` ([`Stencil::new`]).
    interior_2d: [[f64; 4]; 5],
    /// 3D: the interior type's centre block, then the 13 pairs `±o` (the offset `o` of
    /// index `k < 13` in `{-1, 0, 1}³`, first axis fastest, paired with `26 − k`), as plain
    /// `3×3` arrays (row-major), `(S[o] + S[-o])/2` ([`Stencil::new`]).
    interior_3d: Box<[[f64; 9]; 14]>,
}

/// Nodes per slab of the 1D passes ([`Stencil::slab_layers`]).
const SLAB_1D: usize = 512;

/// `3^D`.
const fn types(d: usize) -> usize {
    3usize.pow(d as u32)
}

/// Where index `i` of `n` lies along an axis: 0 low edge, 1 interior, 2 high edge.
#[inline]
fn kind(i: usize, n: usize) -> usize {
    if i == 0 {
        0
    } else if i + 1 == n {
        2
    } else {
        1
    }
}

impl<const D: usize> Stencil<D> {
    /// The stencil of `grid` from the element stiffness `element[a * 2^D + b]` (the force
    /// on local node `a` per unit displacement of local node `b`, a `D×D` block).
    pub fn new(grid: &Grid<D>, element: &[Tensor<D>]) -> Self {
        let counts = grid.vertex_counts();
        let npc = Grid::<D>::NODES_PER_CELL;
        // node-index stride along each axis
        let stride: [isize; D] =
            std::array::from_fn(|l| counts[..l].iter().product::<usize>() as isize);
        let mut blocks: Vec<Vec<(usize, isize, Tensor<D>)>> = Vec::with_capacity(types(D));
        for t in 0..types(D) {
            // per axis: 0 low edge, 1 interior, 2 high edge
            let kind: [usize; D] = std::array::from_fn(|l| t / types(l) % 3);
            let mut sum = vec![Tensor::<D>::zeros(); types(D)];
            let mut used = vec![false; types(D)];
            // elements around the node: lower corner at node + e, e ∈ {-1, 0}^D
            for e in 0..(1usize << D) {
                let below: [bool; D] = std::array::from_fn(|l| (e >> l) & 1 == 1);
                // a low-edge node has no element below it, a high-edge node none above
                let exists = (0..D).all(|l| !matches!((below[l], kind[l]), (true, 0) | (false, 2)));
                if !exists {
                    continue;
                }
                // the node is local node a of the element: bit l set where it is the upper
                // node (the element lies below it)
                let a: usize = (0..D).map(|l| usize::from(below[l]) << l).sum();
                for b in 0..npc {
                    // offset of local node b from the node, per axis in {-1, 0, 1}
                    let o: usize = (0..D)
                        .map(|l| {
                            let step = ((b >> l) & 1) as isize - isize::from(below[l]);
                            (step + 1) as usize * types(l)
                        })
                        .sum();
                    sum[o] += element[a * npc + b];
                    used[o] = true;
                }
            }
            // ordered by offset, the last axis slowest (as the interior rows read them)
            let list = (0..types(D))
                .filter(|&o| used[o])
                .map(|o| {
                    let within: isize = (0..D - 1)
                        .map(|l| ((o / types(l) % 3) as isize - 1) * stride[l])
                        .sum();
                    (o / types(D - 1), within, sum[o])
                })
                .collect();
            blocks.push(list);
        }
        // 2D interior: opposite neighbours `±o` share one block. `S[-o] = S[o]ᵀ` (K is
        // symmetric), and with an isotropic material each interior block is itself
        // symmetric, so `S[-o] = S[o]` in exact arithmetic; the element integration leaves
        // them 1e-17 apart, and their mean is taken. Nine products per node become five.
        let mut interior_2d = [[0.0; 4]; 5];
        if D == 2 {
            let mut nine = [[0.0; 4]; 9];
            for &(layer, within, block) in &blocks[types(D) / 2] {
                let k = layer * 3 + (within + 1) as usize;
                nine[k] = [block[(0, 0)], block[(0, 1)], block[(1, 0)], block[(1, 1)]];
            }
            interior_2d[0] = nine[4];
            for pair in 0..4 {
                let (low, high) = (nine[pair], nine[8 - pair]);
                interior_2d[pair + 1] = std::array::from_fn(|e| 0.5 * (low[e] + high[e]));
            }
        }
        // 3D interior: the same pairing, 27 products per node become 14
        let mut interior_3d = Box::new([[0.0; 9]; 14]);
        if D == 3 {
            let list = &blocks[types(D) / 2];
            debug_assert_eq!(list.len(), 27);
            let plain =
                |k: usize| -> [f64; 9] { std::array::from_fn(|e| list[k].2[(e / 3, e % 3)]) };
            interior_3d[0] = plain(13);
            for k in 0..13 {
                let (low, high) = (plain(k), plain(26 - k));
                interior_3d[k + 1] = std::array::from_fn(|e| 0.5 * (low[e] + high[e]));
            }
        }
        Self {
            counts,
            blocks,
            interior_2d,
            interior_3d,
        }
    }

    /// Nodes per layer (along the last axis).
    pub fn layer_nodes(&self) -> usize {
        self.counts[..D - 1].iter().product()
    }

    /// Node layers along the last axis.
    pub fn layers(&self) -> usize {
        self.counts[D - 1]
    }

    /// `out = -(K u) · (1/m)` on the nodes of layer `layer` (module doc), from `around`:
    /// the displacement of the layer below, of the layer, of the layer above (the first or
    /// the last empty at the mesh's edges). In 2D and 3D the interior nodes of an interior
    /// layer take [`interior_row_2d`] or [`interior_row_3d`] (the pairs of blocks, no
    /// per-node type); edge nodes the general sum over the node type's blocks.
    fn layer_into(
        &self,
        layer: usize,
        around: [&[Vector<D>]; 3],
        inv_mass: &[f64],
        out: &mut [Vector<D>],
    ) {
        let counts = self.counts;
        let layer_kind = kind(layer, counts[D - 1]) * types(D - 1);
        let general = |j: usize, within: [usize; D], out: &mut [Vector<D>]| {
            let t: usize = layer_kind
                + (0..D - 1)
                    .map(|l| kind(within[l], counts[l]) * types(l))
                    .sum::<usize>();
            let mut sum = Vector::<D>::zeros();
            for &(l, offset, ref block) in &self.blocks[t] {
                sum += block * around[l][(j as isize + offset) as usize];
            }
            out[j] = -sum * inv_mass[j];
        };
        if D == 2 && layer_kind == types(D - 1) && counts[0] > 2 {
            let n = counts[0];
            let mut within = [0; D];
            general(0, within, out);
            let rows = around.map(|u| &u[..n]);
            interior_row_2d(
                &self.interior_2d,
                rows,
                &inv_mass[1..n - 1],
                &mut out[1..n - 1],
            );
            within[0] = n - 1;
            general(n - 1, within, out);
            return;
        }
        if D == 3 && layer_kind == types(D - 1) && counts[0] > 2 && counts[1] > 2 {
            let (nx, ny) = (counts[0], counts[1]);
            for r in 0..ny {
                let mut within = [0; D];
                within[1] = r;
                let row = r * nx..(r + 1) * nx;
                if r == 0 || r + 1 == ny {
                    for i in 0..nx {
                        within[0] = i;
                        general(row.start + i, within, out);
                    }
                    continue;
                }
                general(row.start, within, out);
                interior_row_3d(&self.interior_3d, around, nx, (r, inv_mass), out);
                within[0] = nx - 1;
                general(row.end - 1, within, out);
            }
            return;
        }
        let mut within = [0; D];
        for j in 0..out.len() {
            general(j, within, out);
            // next node in storage order
            within[0] += 1;
            for l in 0..D.saturating_sub(2) {
                if within[l] == counts[l] {
                    within[l] = 0;
                    within[l + 1] += 1;
                }
            }
        }
    }

    /// Layers per slab, the unit the passes walk: one layer in 2D and 3D; in 1D, where a
    /// layer is one node, [`SLAB_1D`] nodes (a run the interior loop takes at once).
    pub fn slab_layers(&self) -> usize {
        if D == 1 {
            SLAB_1D
        } else {
            1
        }
    }

    /// `out = -(K u) · (1/m)` on a slab of layers from layer `first` on (`out.len()` nodes,
    /// one layer unless 1D), from `around`: the displacement of the layer below the slab,
    /// of the slab, of the layer above it (the first or the last empty at the mesh's
    /// edges).
    pub fn slab_into(
        &self,
        first: usize,
        around: [&[Vector<D>]; 3],
        inv_mass: &[f64],
        out: &mut [Vector<D>],
    ) {
        if D > 1 {
            return self.layer_into(first, around, inv_mass, out);
        }
        // 1D: node j of the slab reads nodes j - 1, j, j + 1, below and above the slab at
        // its ends
        let count = out.len();
        let node = |j: isize| -> &Vector<D> {
            match j {
                -1 => &around[0][0],
                j if j as usize == count => &around[2][0],
                j => &around[1][j as usize],
            }
        };
        let general = |j: usize, out: &mut [Vector<D>]| {
            let mut sum = Vector::<D>::zeros();
            for &(l, _, ref block) in &self.blocks[kind(first + j, self.layers())] {
                sum += block * node(j as isize + l as isize - 1);
            }
            out[j] = -sum * inv_mass[j];
        };
        general(0, out);
        if count > 2 {
            // interior nodes: the interior type's three blocks, summed in the same order
            let k: [f64; 3] = std::array::from_fn(|l| self.blocks[1][l].2[(0, 0)]);
            let u = around[1];
            for j in 1..count - 1 {
                let sum = k[0] * u[j - 1][0] + k[1] * u[j][0] + k[2] * u[j + 1][0];
                out[j][0] = -sum * inv_mass[j];
            }
        }
        if count > 1 {
            general(count - 1, out);
        }
    }

    /// `acceleration = -(K u) · (1/m)` (module doc; the caller adds `f_ext/m` at the
    /// loaded nodes), in chunks of whole slabs of at least `chunk` nodes, in parallel when
    /// `parallel`. The force `K u` is formed node by node and not stored.
    pub fn accelerations_into(
        &self,
        displacement: &[Vector<D>],
        (inv_mass, acceleration): (&[f64], &mut [Vector<D>]),
        chunk: usize,
        parallel: bool,
    ) {
        let (n, layers, slab) = (self.layer_nodes(), self.layers(), self.slab_layers());
        let per = chunk.div_ceil(n * slab).max(1) * slab;
        for_each_chunk(parallel, 1, chunks(acceleration, per * n), |r, acc| {
            for (k, out) in acc.chunks_mut(slab * n).enumerate() {
                let first = r * per + k * slab;
                let end = first + out.len() / n;
                let of = |l: usize| &displacement[l * n..(l + 1) * n];
                let below = if first > 0 { of(first - 1) } else { &[] };
                let above = if end < layers { of(end) } else { &[] };
                let around = [below, &displacement[first * n..end * n], above];
                self.slab_into(first, around, &inv_mass[first * n..end * n], out);
            }
        });
    }

    /// One central-difference step of the nodes and the next acceleration in one pass
    /// (module doc): per slab `v += Δt_avg a`, `u += Δt v` (the prescribed components,
    /// already set, have `a = 0`), one slab ahead of `a = -(K u) · (1/m)`. Bands of
    /// `band_layers` layers run in parallel when `parallel`; `halo` holds two layers per
    /// band. Bit for bit the result of `FemSolver::nodal_update` then
    /// [`Self::accelerations_into`].
    pub fn step_into(
        &self,
        (displacement, velocity, acceleration): (
            &mut [Vector<D>],
            &mut [Vector<D>],
            &mut [Vector<D>],
        ),
        inv_mass: &[f64],
        (dt, dt_avg): (f64, f64),
        (halo, band_layers): (&mut [Vector<D>], usize),
        parallel: bool,
    ) {
        let (n, layers, slab) = (self.layer_nodes(), self.layers(), self.slab_layers());
        // the updated displacement of the layers next to each band, from the old state
        {
            let (u, v, a) = (&*displacement, &*velocity, &*acceleration);
            let advanced_into = |layer: usize, out: &mut [Vector<D>]| {
                let nodes = layer * n..(layer + 1) * n;
                let old = u[nodes.clone()]
                    .iter()
                    .zip(&v[nodes.clone()])
                    .zip(&a[nodes]);
                for (o, ((u, v), a)) in out.iter_mut().zip(old) {
                    // the neighbour's update of this node, not stored
                    let (mut u, mut v) = (*u, *v);
                    advance_node(&mut u, &mut v, a, (dt, dt_avg));
                    *o = u;
                }
            };
            for_each_chunk(parallel, 1, chunks(halo, 2 * n), |b, h| {
                let (below, above) = h.split_at_mut(n);
                let (first, end) = (b * band_layers, ((b + 1) * band_layers).min(layers));
                if first > 0 {
                    advanced_into(first - 1, below);
                }
                if end < layers {
                    advanced_into(end, above);
                }
            });
        }
        let size = band_layers * n;
        let halo = &*halo;
        let parts = (
            (chunks(displacement, size), chunks(velocity, size)),
            chunks(acceleration, size),
        );
        for_each_chunk(parallel, 1, parts, |b, ((u, v), a)| {
            let count = u.len() / n;
            // the nodes of slab k of the band
            let nodes = |k: usize| k * slab * n..((k + 1) * slab).min(count) * n;
            // slab k: v += Δt_avg a, u += Δt v
            let advance = |k: usize, u: &mut [Vector<D>], v: &mut [Vector<D>], a: &[Vector<D>]| {
                let new = u[nodes(k)].iter_mut().zip(&mut v[nodes(k)]);
                for ((u, v), a) in new.zip(&a[nodes(k)]) {
                    advance_node(u, v, a, (dt, dt_avg));
                }
            };
            let (halo_below, halo_above) = halo[2 * b * n..2 * (b + 1) * n].split_at(n);
            let slabs = count.div_ceil(slab);
            let first = b * band_layers;
            advance(0, u, v, a);
            for k in 0..slabs {
                if k + 1 < slabs {
                    advance(k + 1, u, v, a);
                }
                let own = nodes(k);
                let (start, end) = (first + own.start / n, first + own.end / n);
                let below = match (k, start) {
                    (_, 0) => &[][..],
                    (0, _) => halo_below,
                    _ => &u[own.start - n..own.start],
                };
                let above = if k + 1 < slabs {
                    &u[own.end..own.end + n]
                } else if end < layers {
                    halo_above
                } else {
                    &[]
                };
                let around = [below, &u[own.clone()], above];
                let inv = &inv_mass[start * n..end * n];
                self.slab_into(start, around, inv, &mut a[own]);
            }
        });
    }

    /// Layers per band of [`Self::step_into`] on `threads` threads: about four bands per
    /// thread (load balance), at least 8 layers each (the halo's two extra layers per band
    /// stay a small part of the pass); all layers in one band where not `parallel`.
    pub fn band_layers(&self, threads: usize, parallel: bool) -> usize {
        if parallel {
            self.layers().div_ceil(4 * threads.max(1)).max(8)
        } else {
            self.layers()
        }
    }
}

/// The interior stencil of a 2D mesh on the nodes `out` of one row, from the rows of
/// displacement below, of and above them (`rows`, each starting at the node left of the
/// first one of `out`, `out.len() + 2` long): `f_n = Σ_o S[o] u_{n+o}`, summed as
/// `S[0] u_n + Σ_{4 pairs ±o} S[o] (u_{n+o} + u_{n-o})` with the blocks `pairs` (centre,
/// then the pairs south-west/north-east, south/north, south-east/north-west,
/// west/east; see [`Stencil::new`]); `out_n = -f_n · inv_mass_n`.
fn interior_row_2d<const D: usize>(
    pairs: &[[f64; 4]; 5],
    [below, middle, above]: [&[Vector<D>]; 3],
    inv_mass: &[f64],
    out: &mut [Vector<D>],
) {
    for (i, f) in out.iter_mut().enumerate() {
        let sums = [
            middle[i + 1],
            below[i] + above[i + 2],
            below[i + 1] + above[i + 1],
            below[i + 2] + above[i],
            middle[i] + middle[i + 2],
        ];
        let (mut x, mut y) = (0.0, 0.0);
        for (b, u) in pairs.iter().zip(&sums) {
            x += b[0] * u[0] + b[1] * u[1];
            y += b[2] * u[0] + b[3] * u[1];
        }
        f[0] = -x * inv_mass[i];
        f[1] = -y * inv_mass[i];
    }
}

/// The interior stencil of a 3D mesh on the interior nodes `1..nx-1` of row `r` (along y)
/// of a layer (along z), from the layers of displacement below, of and above it
/// (`around`, `nx` nodes per row): `f_n = S[0] u_n + Σ_{13 pairs ±o} S[o] (u_{n+o} + u_{n-o})`
/// with the blocks `pairs` ([`Stencil::new`]); `out_n = -f_n · inv_mass_n` (module doc).
fn interior_row_3d<const D: usize>(
    pairs: &[[f64; 9]; 14],
    around: [&[Vector<D>]; 3],
    nx: usize,
    (r, inv_mass): (usize, &[f64]),
    out: &mut [Vector<D>],
) {
    // per pair k: the layer and the in-layer offset of n + o and of n - o
    let step = |k: usize| -> (usize, isize) {
        let (sx, sy, sz) = (k % 3, (k / 3) % 3, k / 9);
        (sz, (sx as isize - 1) + (sy as isize - 1) * nx as isize)
    };
    let plus: [(usize, isize); 13] = std::array::from_fn(step);
    for i in 1..nx - 1 {
        let j = r * nx + i;
        let u = &around[1][j];
        let b = &pairs[0];
        let mut f = [
            b[0] * u[0] + b[1] * u[1] + b[2] * u[2],
            b[3] * u[0] + b[4] * u[1] + b[5] * u[2],
            b[6] * u[0] + b[7] * u[1] + b[8] * u[2],
        ];
        for (k, &(layer, offset)) in plus.iter().enumerate() {
            let a = &around[layer][(j as isize + offset) as usize];
            let c = &around[2 - layer][(j as isize - offset) as usize];
            let s = [a[0] + c[0], a[1] + c[1], a[2] + c[2]];
            let b = &pairs[k + 1];
            f[0] += b[0] * s[0] + b[1] * s[1] + b[2] * s[2];
            f[1] += b[3] * s[0] + b[4] * s[1] + b[5] * s[2];
            f[2] += b[6] * s[0] + b[7] * s[1] + b[8] * s[2];
        }
        for (m, fm) in f.iter().enumerate() {
            out[j][m] = -fm * inv_mass[j];
        }
    }
}

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
//! colouring, disjoint writes in parallel.
//!
//! `K_e` is built by applying the solver's own Gauss-point force to unit displacements
//! ([`crate::FemSolver::element_stiffness`]), so the stencil and the Gauss path share the
//! material law; they agree to round-off (tested to 1e-13 relative on every node). It
//! applies to linear elasticity only: Saint-Venant–Kirchhoff is nonlinear and J2 reads its
//! Gauss-point history, so both keep the Gauss path.
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::{Grid, Tensor, Vector};

/// The node stencil of a regular mesh (module doc).
#[derive(Debug, Clone)]
pub struct Stencil<const D: usize> {
    /// Nodes per axis.
    counts: [usize; D],
    /// Per node type, its nonzero blocks with their node-index offsets.
    blocks: Vec<Vec<(isize, Tensor<D>)>>,
}

/// `3^D`.
const fn types(d: usize) -> usize {
    3usize.pow(d as u32)
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
        let mut blocks = Vec::with_capacity(types(D));
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
            let list = (0..types(D))
                .filter(|&o| used[o])
                .map(|o| {
                    let offset: isize = (0..D)
                        .map(|l| ((o / types(l) % 3) as isize - 1) * stride[l])
                        .sum();
                    (offset, sum[o])
                })
                .collect();
            blocks.push(list);
        }
        Self { counts, blocks }
    }

    /// `acceleration = -(K u) · (1/m)` (module doc; the caller adds `f_ext/m` at the
    /// loaded nodes), in chunks of `chunk` nodes, in parallel when `parallel`. The force
    /// `K u` is formed node by node and not stored. In 2D the interior nodes of a chunk's
    /// interior rows take [`interior_row_2d`], the same sum with its nine blocks fixed (no
    /// per-node type, no bounds checks).
    pub fn accelerations_into(
        &self,
        displacement: &[Vector<D>],
        (inv_mass, acceleration): (&[f64], &mut [Vector<D>]),
        chunk: usize,
        parallel: bool,
    ) {
        let counts = self.counts;
        for_each_chunk(parallel, 1, chunks(acceleration, chunk), |r, acc| {
            let start = r * chunk;
            let mut idx: [usize; D] =
                std::array::from_fn(|l| start / counts[..l].iter().product::<usize>() % counts[l]);
            let mut j = 0;
            while j < acc.len() {
                let node = start + j;
                // a run of interior nodes of an interior row (2D): the fixed nine blocks
                if D == 2 && idx[0] == 1 && counts[0] > 2 && idx[1] > 0 && idx[1] + 1 < counts[1] {
                    let run = (counts[0] - 2).min(acc.len() - j);
                    let out = &mut acc[j..j + run];
                    let inv = &inv_mass[node..node + run];
                    interior_row_2d(
                        &self.blocks[types(D) / 2],
                        counts[0],
                        displacement,
                        node,
                        out,
                        inv,
                    );
                    j += run;
                    idx[0] += run;
                    continue;
                }
                let t: usize = (0..D)
                    .map(|l| {
                        let kind = if idx[l] == 0 {
                            0
                        } else if idx[l] + 1 == counts[l] {
                            2
                        } else {
                            1
                        };
                        kind * types(l)
                    })
                    .sum();
                let mut sum = Vector::<D>::zeros();
                for (offset, block) in &self.blocks[t] {
                    sum += block * displacement[(node as isize + offset) as usize];
                }
                acc[j] = -sum * inv_mass[node];
                // next node in storage order
                idx[0] += 1;
                for l in 0..D - 1 {
                    if idx[l] == counts[l] {
                        idx[l] = 0;
                        idx[l + 1] += 1;
                    }
                }
                j += 1;
            }
        });
    }
}

/// The interior stencil of a 2D mesh on `out.len()` consecutive interior nodes of one row,
/// the first being `first`: `f_n = Σ_o S[o] u_{n+o}` over the nine blocks `blocks` (the
/// interior type's, all present), rows `row` nodes long; `out_n = -f_n · inv_mass_n`.
fn interior_row_2d<const D: usize>(
    blocks: &[(isize, Tensor<D>)],
    row: usize,
    displacement: &[Vector<D>],
    first: usize,
    out: &mut [Vector<D>],
    inv_mass: &[f64],
) {
    debug_assert_eq!(blocks.len(), 9);
    // the blocks as plain 2×2 arrays, ordered by offset (dy, dx) = (-1..=1, -1..=1)
    let mut k = [[0.0; 4]; 9];
    for (offset, block) in blocks {
        let o = offset + row as isize + 1;
        let (dy, dx) = (o.div_euclid(row as isize), o.rem_euclid(row as isize));
        k[(dy * 3 + dx) as usize] = [block[(0, 0)], block[(0, 1)], block[(1, 0)], block[(1, 1)]];
    }
    // the three rows around the run, from the node left of its first one
    let below = &displacement[first - row - 1..first - row + out.len() + 1];
    let middle = &displacement[first - 1..first + out.len() + 1];
    let above = &displacement[first + row - 1..first + row + out.len() + 1];
    for (i, f) in out.iter_mut().enumerate() {
        let (mut x, mut y) = (0.0, 0.0);
        for (r, rows) in [below, middle, above].iter().enumerate() {
            for dx in 0..3 {
                let u = rows[i + dx];
                let b = &k[r * 3 + dx];
                x += b[0] * u[0] + b[1] * u[1];
                y += b[2] * u[0] + b[3] * u[1];
            }
        }
        f[0] = -x * inv_mass[i];
        f[1] = -y * inv_mass[i];
    }
}

//! Particle↔node mapping: phase 1 (particles→nodes, paper eq. 17) and phase 5
//! (nodes→particles), with the point-side updates that follow them (`Π(F)` at the points
//! under Saint-Venant–Kirchhoff, positions for output).
//!
//! The sums of phase 5 (`point_from_nodes`) and of phase 1 with the cells' fixed weights
//! (`weighted_cell`) start from `-0.0`, not `+0.0`: `-0 + x = x` for every `x`, so LLVM
//! drops the first addition (an `addpd` of zero per component and node: 4 ppc Euler on
//! the plate, 451.8 → 443.0 instructions per point), while `+0 + x` must stay (it turns
//! `x = -0` into `+0`). A sum
//! from `+0` equals the first term plus the rest, except when every term is `-0`: the sum
//! is then `-0` where it was `+0`, equal under `==` and in every physical quantity.
use crate::{DgmpmSolver, Physics, StepPath, CHUNK, MAX_NODES};
use impact_core::method::PointUpdate;
use impact_core::parallel::{chunks, for_each_chunk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

/// Cells per rayon leaf of the per-cell loops.
const CELL_GRAIN: usize = 512;

/// Phase 5 at one point with shape values `s` on its cell's nodes: the interpolated new
/// nodal field `Σ_i S_i (q_i, v_i)` ([`PointUpdate::Nodal`]), or with the nodes' start-of-step
/// fields `start` its increment `Σ_i S_i (q_i - q_i^n, v_i - v_i^n)` ([`PointUpdate::Increment`]).
#[inline(always)]
pub(crate) fn point_from_nodes<const D: usize>(
    s: &[f64],
    (nq, nv): (&[Tensor<D>], &[Vector<D>]),
    start: Option<(&[Tensor<D>], &[Vector<D>])>,
) -> (Tensor<D>, Vector<D>) {
    // the sums start from -0, the identity of `+` (`-0 + x = x` for every `x`, where
    // `+0 + (-0) = +0`), so the compiler drops the first addition (module doc)
    let mut q = Tensor::<D>::from_element(-0.0);
    let mut v = Vector::<D>::from_element(-0.0);
    match start {
        Some((q0, v0)) => {
            for a in 0..s.len() {
                q += (nq[a] - q0[a]) * s[a];
                v += (nv[a] - v0[a]) * s[a];
            }
        }
        None => {
            for a in 0..s.len() {
                q += nq[a] * s[a];
                v += nv[a] * s[a];
            }
        }
    }
    (q, v)
}

/// Phase 5 in the sweep for one cell's points ([`point_from_nodes`] at each, with their
/// shape values `shapes`, `2^D` per point, the cell's new nodal fields `new` and, for the
/// increment update, the nodes' start-of-step fields `start`), then each point's move
/// `x ← x + Δt v` with its new velocity (`DgmpmSolver::move_points`' arithmetic).
/// `N > 0`: the cell has exactly `N` points, a constant trip count, so the loop is
/// unrolled without index checks (a loop of unknown length over slices cut to it is
/// vectorised two points at a time by LLVM, whose per-cell set-up costs more than it
/// saves at 4 points; measured); `N = 0`: `tensor.len()` points, indexed.
#[inline(always)]
#[allow(clippy::type_complexity)]
pub(crate) fn points_of_cell<const D: usize, const N: usize>(
    shapes: &[f64],
    new: (&[Tensor<D>], &[Vector<D>]),
    start: Option<(&[Tensor<D>], &[Vector<D>])>,
    (tensor, velocity, position): (&mut [Tensor<D>], &mut [Vector<D>], &mut [Vector<D>]),
    dt: f64,
) {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let (tensor, velocity, position, shapes) = match N {
        0 => (tensor, velocity, position, shapes),
        _ => (
            &mut tensor[..N],
            &mut velocity[..N],
            &mut position[..N],
            &shapes[..N * nodes_per_cell],
        ),
    };
    let count = if N > 0 { N } else { tensor.len() };
    match start {
        None => {
            for k in 0..count {
                let s = &shapes[k * nodes_per_cell..(k + 1) * nodes_per_cell];
                let (pq, pv) = point_from_nodes(s, new, None);
                tensor[k] = pq;
                velocity[k] = pv;
                position[k] += pv * dt;
            }
        }
        Some(_) => {
            for k in 0..count {
                let s = &shapes[k * nodes_per_cell..(k + 1) * nodes_per_cell];
                let (dq, dv) = point_from_nodes(s, new, start);
                tensor[k] += dq;
                velocity[k] += dv;
                position[k] += velocity[k] * dt;
            }
        }
    }
}

/// One cell's phase-1 sums over its points `α` (weights `s`, `2^D` per point, states `q`,
/// `v`, masses `m`): `(Σ_α S_iα m_α, Σ_α S_iα m_α q_α, Σ_α S_iα m_α v_α)` per local node
/// `i`, each sum in point order from zero. The point loop is outside the node loop, so
/// each point is read once.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn cell_sums<const D: usize>(
    s: &[f64],
    q: &[Tensor<D>],
    v: &[Vector<D>],
    m: &[f64],
) -> (
    [f64; MAX_NODES],
    [Tensor<D>; MAX_NODES],
    [Vector<D>; MAX_NODES],
) {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let mut mass = [0.0; MAX_NODES];
    let mut tensor = [Tensor::<D>::zeros(); MAX_NODES];
    let mut velocity = [Vector::<D>::zeros(); MAX_NODES];
    for (((s, q), v), m) in s.chunks_exact(nodes_per_cell).zip(q).zip(v).zip(m) {
        for a in 0..nodes_per_cell {
            let w = s[a] * m;
            mass[a] += w;
            tensor[a] += q * w;
            velocity[a] += v * w;
        }
    }
    (mass, tensor, velocity)
}

/// One cell's phase 1 with its mapping weights `w` (`W_αi`, `2^D` per point, point after
/// point): `q_i = Σ_α W_αi q_α`, `v_i = Σ_α W_αi v_α` into the cell's nodes, each sum in
/// point order from zero. The point loop is outside the node loop, so each point is read
/// once; the node loop has the constant length `2^D`. `N > 0`: the cell has exactly `N`
/// points, a constant trip count (the loop unrolled, as in [`points_of_cell`]); `N = 0`:
/// `q.len()` points.
#[inline(always)]
fn weighted_cell<const D: usize, const N: usize>(
    w: &[f64],
    (q, v): (&[Tensor<D>], &[Vector<D>]),
    (tensor, velocity): (&mut [Tensor<D>], &mut [Vector<D>]),
) {
    let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
    let (w, q, v) = match N {
        0 => (w, q, v),
        _ => (&w[..N * nodes_per_cell], &q[..N], &v[..N]),
    };
    // from -0, the identity of `+`: the first addition is dropped (module doc)
    let mut tensor_sum = [Tensor::<D>::from_element(-0.0); MAX_NODES];
    let mut velocity_sum = [Vector::<D>::from_element(-0.0); MAX_NODES];
    for ((w, q), v) in w.chunks_exact(nodes_per_cell).zip(q).zip(v) {
        for a in 0..nodes_per_cell {
            tensor_sum[a] += q * w[a];
            velocity_sum[a] += v * w[a];
        }
    }
    tensor.copy_from_slice(&tensor_sum[..nodes_per_cell]);
    velocity.copy_from_slice(&velocity_sum[..nodes_per_cell]);
}

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 1: lumped nodal mass `M_i = Σ_α S_iα m_α` and mass-weighted nodal fields
    /// `M_i q_i = Σ_α S_iα m_α q_α` (paper eq. 17), `q` being `σ` (small strain) or `F`
    /// (Saint-Venant–Kirchhoff). On [`StepPath::SinglePoint`] (and [`StepPath::FusedNodal`]
    /// with one point per cell) the map is the identity
    /// (`q_i = q_p`) and only the masses are weighed. With several points per cell and the
    /// cells' mapping weights `W_αi = S_iα m_α / M_i` and the masses `M_i`
    /// (`layouts::cell_mapping_weights`, formed once in the cell layouts: the points never
    /// move in the grid of this total Lagrangian scheme) each node's field is the small
    /// dense product
    /// `q_i = Σ_α W_αi q_α` (`weighted_cell`): no mass sums and no division per step, and
    /// equal to the per-node formula to round-off (the division by `M_i` is taken before
    /// the sum; tested). Without them (one point per cell on [`StepPath::Nodal`]) the
    /// cell's points are walked once, each added to its cell's node sums (`cell_sums`),
    /// each node's sum in point order: the per-node formula bit for bit (tested).
    pub fn particles_to_nodes(&mut self, points: &MaterialPoints<D>) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let points_per_cell = self.points_per_cell;
        let layouts = &self.layouts;
        let source = self.point_tensor(points);
        let single = self.path == StepPath::SinglePoint
            || (self.path == StepPath::FusedNodal && points_per_cell == 1);
        let nodes = &mut self.nodes;
        // chunks of CELL_GRAIN cells, walked cell by cell
        let per_chunk = CELL_GRAIN * nodes_per_cell;
        if !single && layouts.has_mapping() {
            // the fixed weights: q_i = Σ_α W_αi q_α (the masses are in the layouts)
            let parts = (
                chunks(&mut nodes.tensor, per_chunk),
                chunks(&mut nodes.velocity, per_chunk),
            );
            for_each_chunk(self.parallel, 1, parts, |r, (tensor, vel)| {
                let first = r * CELL_GRAIN;
                let cells = tensor.len() / nodes_per_cell;
                let points_range = first * points_per_cell..(first + cells) * points_per_cell;
                let q = source[points_range.clone()].chunks_exact(points_per_cell);
                let v = points.velocity[points_range].chunks_exact(points_per_cell);
                let cells_out = tensor.chunks_exact_mut(nodes_per_cell);
                let cells_out = cells_out.zip(vel.chunks_exact_mut(nodes_per_cell));
                let cells_in = layouts
                    .layouts_of(first..first + cells)
                    .iter()
                    .zip(q.zip(v));
                let cells = cells_in.zip(cells_out);
                match points_per_cell {
                    4 => cells.for_each(|((&l, (q, v)), (tensor, vel))| {
                        let w = layouts.mapping_weights_of(l as usize);
                        weighted_cell::<D, 4>(w, (q, v), (tensor, vel));
                    }),
                    _ => cells.for_each(|((&l, (q, v)), (tensor, vel))| {
                        let w = layouts.mapping_weights_of(l as usize);
                        weighted_cell::<D, 0>(w, (q, v), (tensor, vel));
                    }),
                }
            });
            return;
        }
        let parts = (
            chunks(&mut nodes.mass, per_chunk),
            chunks(&mut nodes.tensor, per_chunk),
            chunks(&mut nodes.velocity, per_chunk),
        );
        for_each_chunk(self.parallel, 1, parts, |r, (mass, tensor, vel)| {
            let first = r * CELL_GRAIN;
            let cells = mass.len() / nodes_per_cell;
            if single {
                let cell_points = first..first + cells;
                let (q, v, m) = (
                    &source[cell_points.clone()],
                    &points.velocity[cell_points.clone()],
                    &points.mass[cell_points],
                );
                for j in 0..cells {
                    let shape = layouts.shape(first + j);
                    let nodes = j * nodes_per_cell..(j + 1) * nodes_per_cell;
                    for (a, i) in nodes.enumerate() {
                        mass[i] = shape[a] * m[j];
                        tensor[i] = q[j];
                        vel[i] = v[j];
                    }
                }
                return;
            }
            let points_range = first * points_per_cell..(first + cells) * points_per_cell;
            let (q, v, m) = (
                &source[points_range.clone()],
                &points.velocity[points_range.clone()],
                &points.mass[points_range],
            );
            // point by point: each point's state, mass and weights are read once and added
            // to its cell's node sums, each node's in point order (the order of the
            // per-node formula, so the sums are the same bit for bit; tested)
            for j in 0..cells {
                let cell = j * points_per_cell..(j + 1) * points_per_cell;
                let (q, v, m) = (&q[cell.clone()], &v[cell.clone()], &m[cell]);
                let sums = cell_sums::<D>(layouts.shape(first + j), q, v, m);
                let out = j * nodes_per_cell..(j + 1) * nodes_per_cell;
                let nodes = mass[out.clone()]
                    .iter_mut()
                    .zip(&mut tensor[out.clone()])
                    .zip(&mut vel[out]);
                for (a, ((mass, tensor), vel)) in nodes.enumerate() {
                    let (m, q, v) = (sums.0[a], sums.1[a], sums.2[a]);
                    *mass = m;
                    if m > 0.0 {
                        *tensor = q / m;
                        *vel = v / m;
                    } else {
                        *tensor = Tensor::<D>::zeros();
                        *vel = Vector::<D>::zeros();
                    }
                }
            }
        });
    }

    /// Phase 5: points take the new nodal field, `q_α = Σ_i S_iα q_i^{n+1}`
    /// ([`PointUpdate::Nodal`]), or add its increment,
    /// `q_α += Σ_i S_iα (q_i^{n+1} - q_i^n)` ([`PointUpdate::Increment`]).
    pub fn nodes_to_particles(&self, points: &mut MaterialPoints<D>) {
        let nodes_per_cell = Grid::<D>::NODES_PER_CELL;
        let points_per_cell = self.points_per_cell;
        let layouts = &self.layouts;
        let nodes = &self.nodes;
        let increment = self.options.update == PointUpdate::Increment;
        let (target, velocity) = self.point_fields_mut(points);
        // chunks of CELL_GRAIN cells, walked point by point
        let per_chunk = CELL_GRAIN * points_per_cell;
        let parts = (chunks(target, per_chunk), chunks(velocity, per_chunk));
        for_each_chunk(self.parallel, 1, parts, |r, (pq, pv)| {
            let first = r * per_chunk;
            for k in 0..pq.len() {
                let p = first + k;
                let c = p / points_per_cell;
                let own = p - c * points_per_cell;
                let s = &layouts.shape(c)[own * nodes_per_cell..(own + 1) * nodes_per_cell];
                let cell_nodes = c * nodes_per_cell..(c + 1) * nodes_per_cell;
                let new = (
                    &nodes.tensor[cell_nodes.clone()],
                    &nodes.velocity[cell_nodes.clone()],
                );
                let start = increment.then(|| {
                    (
                        &nodes.start_tensor[cell_nodes.clone()],
                        &nodes.start_velocity[cell_nodes],
                    )
                });
                let (q, v) = point_from_nodes(s, new, start);
                if increment {
                    pq[k] += q;
                    pv[k] += v;
                } else {
                    pq[k] = q;
                    pv[k] = v;
                }
            }
        });
        self.piola_at_points(points);
    }

    /// Saint-Venant–Kirchhoff: the points' first Piola–Kirchhoff stress is `Π(F)` of their
    /// new deformation gradient (paper eq. 22).
    pub(crate) fn piola_at_points(&self, points: &mut MaterialPoints<D>) {
        let Physics::Svk { svk, .. } = self.physics else {
            return;
        };
        let deformation = &points.deformation;
        for_each_chunk(
            self.parallel,
            1,
            chunks(&mut points.stress, CHUNK),
            |r, piola| {
                for (j, s) in piola.iter_mut().enumerate() {
                    *s = svk.piola(&deformation[r * CHUNK + j]);
                }
            },
        );
    }

    /// Points move with the velocity solution (output only: the grid is the reference).
    pub(crate) fn move_points(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let velocity = &points.velocity;
        for_each_chunk(
            self.parallel,
            1,
            chunks(&mut points.position, CHUNK),
            |r, x| {
                for (j, x) in x.iter_mut().enumerate() {
                    *x += velocity[r * CHUNK + j] * dt;
                }
            },
        );
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod weights_tests;

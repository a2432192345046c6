//! Phases 3-5 of the transfers: grid→particles (the velocity and position update, fused
//! with the stress update under USL), the MUSL remap and the stress update (module doc of
//! `transfer.rs`).
use super::*;

impl<const D: usize> MpmSolver<D> {
    /// Phase 3: the velocity update of the transfer (`PointVelocity`; APIC:
    /// `crate::affine`), FLIP's `v_p += Σ_i N_ip Δv_i` by default, and the position
    /// update `x_p += Δt Σ_i N_ip v_i` (`Δv_i = f_i (Δt (1/m_i))` and `v_i = p_i (1/m_i)`
    /// from the grid update, 0 on empty nodes; `Δt` the grid update's).
    pub fn grid_to_particles(
        &self,
        points: &mut MaterialPoints<D>,
        affine: &mut [Tensor<D>],
        dt: f64,
    ) {
        match PointVelocity::of(&self.options) {
            None => self.gather_affine::<false>(points, affine, dt),
            Some(update) => {
                let gather = match self.stencil.width {
                    2 => Self::gather::<false, 2, 0>,
                    3 => Self::gather::<false, 3, 0>,
                    _ => Self::gather::<false, 4, 0>,
                };
                gather(self, points, update, dt)
            }
        }
    }

    /// Phases 3 and 5 of USL in one gather of each point's nodes (small strain): the FLIP
    /// update of phase 3, and `σ_p += Δt C : sym(∇v)`, `∇v = Σ_i (p_i/m_i) ⊗ ∇N_ip`, of
    /// phase 5 (`V_p *= 1 + Δt tr ∇v` in the updated Lagrangian frame; J2: the return map
    /// after). Phase 5 reads only the grid-updated nodes, which phase 3 leaves alone, so
    /// the order is USL's; tested against the separate phases to 1e-13.
    pub fn grid_to_particles_and_stress(
        &self,
        points: &mut MaterialPoints<D>,
        affine: &mut [Tensor<D>],
        dt: f64,
    ) {
        match PointVelocity::of(&self.options) {
            None => self.gather_affine::<true>(points, affine, dt),
            Some(update) => {
                // the rows unrolled where the node count is fixed: hats (4 or 8 nodes); the
                // other stencils loop over their rows (2D quadratic B-splines, 9 nodes: the
                // loop is 5 instructions a point fewer than the rows unrolled at 8243458,
                // 519.9 against 524.9 a point-update on plate-wave 200 at 4 ppc; the two
                // have swapped before with unrelated changes, the 9 nodes' values spilling)
                let fused = match (self.stencil.width, self.stencil.nodes) {
                    (2, 4) => Self::gather::<true, 2, 4>,
                    (2, 8) => Self::gather::<true, 2, 8>,
                    (2, _) => Self::gather::<true, 2, 0>,
                    (3, _) => Self::gather::<true, 3, 0>,
                    _ => Self::gather::<true, 4, 0>,
                };
                fused(self, points, update, dt)
            }
        }
        if let Model::J2(j2) = self.model {
            j2.correct_points(points, self.parallel);
        }
    }

    /// The gather of phase 3 and, with `STRESS`, phase 5 (small strain), for the transfers
    /// without an affine part, for a stencil of rows of `W` nodes (its `width`) and `N`
    /// nodes (0: the count read at run time; fixed, the loop over the rows unrolls): each
    /// row of `W` consecutive nodes is sliced once from the nodal arrays (one bounds check
    /// per row, not per node; `gather_points`), and its nodes are read in the stencil's
    /// order, so the sums take the same operations in the same order as node by node.
    pub(crate) fn gather<const STRESS: bool, const W: usize, const N: usize>(
        &self,
        points: &mut MaterialPoints<D>,
        update: PointVelocity,
        dt: f64,
    ) {
        assert_eq!(self.stencil.width, W, "the gather's rows are the stencil's");
        let stride = self.weight_stride;
        assert!(
            stride == 0 || stride == self.stencil.nodes,
            "a point's row of weights is its stencil's"
        );
        let nodes = &self.nodes;
        assert_eq!(
            nodes.increment_dt.to_bits(),
            dt.to_bits(),
            "the nodal increments are the grid update's, of this step"
        );
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        let parts = (
            (
                chunks(&mut points.velocity, CHUNK),
                chunks(&mut points.position, CHUNK),
            ),
            (
                chunks(&mut points.stress, CHUNK),
                chunks(&mut points.volume, CHUNK),
            ),
        );
        for_each_chunk(
            self.parallel,
            1,
            parts,
            |r, ((velocity, position), (stress, volume))| {
                let npc = self.stencil.nodes;
                let input = GatherInput {
                    velocity: &nodes.velocity,
                    increment: &nodes.increment,
                    rows: &self.stencil.row_offsets,
                    material: self.material,
                    update,
                    moving,
                    dt,
                };
                let first_point = r * CHUNK;
                let count = velocity.len();
                let bases = &self.point_base[first_point..first_point + count];
                let points = (velocity, position, stress, volume);
                // the points' weights: one shared row, a row of the table of distinct rows
                // through each point's index, or a row of `npc` per point (read in step
                // with the points: no index, no bounds check per point)
                if stride == 0 {
                    let row = (&self.shape[..npc], &self.shape_gradient[..npc]);
                    gather_points::<STRESS, W, N, D>(input, points, bases, std::iter::repeat(row));
                } else if !self.point_row.is_empty() {
                    let rows = &self.point_row[first_point..first_point + count];
                    let table = table_rows(&self.shape, &self.shape_gradient, npc, rows);
                    gather_points::<STRESS, W, N, D>(input, points, bases, table);
                } else {
                    let range = first_point * npc..(first_point + count) * npc;
                    let shapes = self.shape[range.clone()].chunks_exact(npc);
                    let gradients = self.shape_gradient[range].chunks_exact(npc);
                    gather_points::<STRESS, W, N, D>(input, points, bases, shapes.zip(gradients));
                }
            },
        );
    }

    /// Phase 4 (MUSL): nodal momentum mapped again from the updated point velocities (with
    /// the shape functions of the start of the step) with the mass, the padding's sums
    /// folded onto the interior as in phase 2 (`grid_update.rs`), then the prescribed nodal
    /// velocities.
    /// APIC (`affine` not empty) maps `v_p + C_p (x_i − x_p)` as phase 1 does.
    pub fn remap_momentum(
        &mut self,
        points: &MaterialPoints<D>,
        affine: &[Tensor<D>],
        window: (f64, f64),
    ) {
        // the mass again too (the same sums as phase 1): the fold reads the padding's own
        let fill = Fill {
            mass: true,
            momentum: true,
            force: false,
        };
        self.scatter(fill, |weights, p, sums| {
            add_mass_and_momentum(weights, p, sums, points, affine);
        });
        self.fold_padding(window, false);
        self.constrain_momentum(window);
    }

    /// Velocity gradient `∇v = Σ_i v_i ⊗ ∇N_ip` at point `p` (`∇_X` in the total
    /// Lagrangian frame), `v_i = p_i/m_i`.
    pub(crate) fn velocity_gradient(&self, p: usize) -> Tensor<D> {
        let npc = self.stencil.nodes;
        let mut l = Tensor::<D>::zeros();
        for a in 0..npc {
            let i = self.point_base[p] + self.stencil.offsets[a];
            let m = self.nodes.mass[i];
            if self.empty.holds(i, m) {
                let g = self.shape_gradient[self.weight_row_start(p) + a];
                l += (self.nodes.momentum[i] / m) * g.transpose();
            }
        }
        l
    }

    /// Phase 5: `σ_p += Δt C : sym(∇v)` (and `V_p *= 1 + Δt tr ∇v` in the updated
    /// Lagrangian frame), or `F_p += Δt ∇_X v`, `Π_p = Π(F_p)` (Saint-Venant–Kirchhoff).
    pub fn update_stress(&self, points: &mut MaterialPoints<D>, dt: f64) {
        let moving = self.options.frame == MpmFrame::UpdatedLagrangian;
        if moving && !points.domain.is_empty() {
            // CPDI: the domain follows the motion, R ← (I + Δt ∇v) R (`crate::cpdi`)
            for_each_chunk(
                self.parallel,
                1,
                chunks(&mut points.domain, CHUNK),
                |r, domain| {
                    for (j, rp) in domain.iter_mut().enumerate() {
                        let l = self.velocity_gradient(r * CHUNK + j);
                        *rp += l * *rp * dt;
                    }
                },
            );
        }
        let parts = (
            chunks(&mut points.stress, CHUNK),
            chunks(&mut points.volume, CHUNK),
        );
        match self.model {
            Model::LinearElastic | Model::J2(_) => {
                for_each_chunk(self.parallel, 1, parts, |r, (stress, volume)| {
                    for (j, (s, vol)) in stress.iter_mut().zip(volume.iter_mut()).enumerate() {
                        let l = self.velocity_gradient(r * CHUNK + j);
                        *s += self.material.stress(&((l + l.transpose()) * 0.5)) * dt;
                        if moving {
                            *vol *= 1.0 + dt * l.trace();
                        }
                    }
                });
                // J2: the elastic update is the trial; the return map corrects it
                if let Model::J2(j2) = self.model {
                    j2.correct_points(points, self.parallel);
                }
            }
            Model::Svk(svk) => {
                // the total Lagrangian frame only (checked at construction)
                let both = (
                    chunks(&mut points.deformation, CHUNK),
                    chunks(&mut points.stress, CHUNK),
                );
                for_each_chunk(self.parallel, 1, both, |r, (deformation, piola)| {
                    for (j, (f, s)) in deformation.iter_mut().zip(piola.iter_mut()).enumerate() {
                        *f += self.velocity_gradient(r * CHUNK + j) * dt;
                        *s = svk.piola(f);
                    }
                });
            }
        }
    }
}

/// What the fused gather reads besides the points (`MpmSolver::gather`): the nodal `v_i`
/// and `Δv_i` (`NodeSums::increment`), the stencil's rows (`Stencil::row_offsets`), and
/// the step's constants. Passed by value: in registers or the kernel's own stack, not loads
/// through a closure's environment at every point.
#[derive(Clone, Copy)]
struct GatherInput<'a, const D: usize> {
    velocity: &'a [Vector<D>],
    increment: &'a [Vector<D>],
    rows: &'a [u32],
    material: LinearElastic,
    update: PointVelocity,
    moving: bool,
    dt: f64,
}

/// The points of one chunk of `MpmSolver::gather` (its doc: phase 3, and phase 5 with
/// `STRESS`; `W` nodes a row, `N` nodes or 0: read at run time), `points` their velocities, positions, stresses and volumes, `bases` their
/// stencils' base nodes and `weights` their rows of shape values and gradients, in step:
/// a generic function per kind of `weights` (one shared row, a row per point), so that the
/// loop and the per-point work compile into one function.
fn gather_points<'w, const STRESS: bool, const W: usize, const N: usize, const D: usize>(
    input: GatherInput<'_, D>,
    points: (
        &mut [Vector<D>],
        &mut [Vector<D>],
        &mut [Tensor<D>],
        &mut [f64],
    ),
    bases: &[usize],
    weights: impl Iterator<Item = (&'w [f64], &'w [Vector<D>])>,
) {
    let GatherInput {
        velocity: node_velocity,
        increment,
        rows,
        material,
        update,
        moving,
        dt,
    } = input;
    // sliced to one length here: a row checked against `v_i` is proved for `Δv_i`
    let increment = &increment[..node_velocity.len()];
    // the stencil's node count: `N` where fixed (the loop over the rows then has a constant
    // trip count and unrolls), else read here, once per chunk
    let nodes = if N == 0 { rows.len() * W } else { N };
    let rows = &rows[..nodes / W];
    let (velocity, position, stress, volume) = points;
    let points = (velocity.iter_mut().zip(position.iter_mut()))
        .zip(stress.iter_mut().zip(volume.iter_mut()))
        .zip(bases);
    for ((((vp, xp), (sp, vol)), &base), (shape, gradient)) in points.zip(weights) {
        let shape = shape[..nodes].as_chunks::<W>().0;
        let gradient = gradient[..nodes].as_chunks::<W>().0;
        // the nodes from the base node on (one check a point; the two of one length)
        let (node_velocity, increment) = (&node_velocity[base..], &increment[base..]);
        let row_of = |((&o, shape), gradient): ((&u32, &'w [f64; W]), &'w [Vector<D>; W])| {
            let first = o as usize;
            let nodes = (
                node_row::<Vector<D>, W>(node_velocity, first),
                node_row::<Vector<D>, W>(increment, first),
            );
            (nodes, (shape, gradient))
        };
        let mut rows = rows.iter().zip(shape).zip(gradient).map(row_of);
        // the sums from -0, the identity of `+` (`-0 + x = x`; `+0 + x` turns `x = -0` into
        // `+0`, so the compiler must keep it), or from the first node's terms, the same:
        // with the rows counted at run time, so that no sums are set before the loop nor a
        // stencil without a row tested (B-splines 4 ppc: 10 instructions a point fewer;
        // with a fixed count, the hats, 5 more)
        let mut sums = match N {
            0 => {
                let ((velocity, increment), (shape, gradient)) =
                    rows.next().expect("a stencil has a row");
                let mut sums = (
                    increment[0] * shape[0],
                    velocity[0] * shape[0],
                    velocity[0] * gradient[0].transpose(),
                );
                add_nodes::<STRESS, W, D>(&mut sums, 1, (velocity, increment), (shape, gradient));
                sums
            }
            _ => (
                Vector::<D>::from_element(-0.0),
                Vector::<D>::from_element(-0.0),
                Tensor::<D>::from_element(-0.0),
            ),
        };
        for (nodes, weights) in rows {
            add_nodes::<STRESS, W, D>(&mut sums, 0, nodes, weights);
        }
        let (dv, v, l) = sums;
        match update {
            PointVelocity::Flip => *vp += dv,
            PointVelocity::Pic => *vp = v,
            PointVelocity::Blend(alpha) => *vp = (*vp + dv) * alpha + v * (1.0 - alpha),
        }
        *xp += v * dt;
        if STRESS {
            *sp += material.stress(&((l + l.transpose()) * 0.5)) * dt;
            if moving {
                *vol *= 1.0 + dt * l.trace();
            }
        }
    }
}

/// The terms of the nodes `from..W` of one row of a stencil added to the gather's sums
/// `(Δv, v, L)`: `Σ S_i Δv_i`, `Σ S_i v_i` and, with `STRESS`, `Σ v_i ⊗ ∇S_i`, node by node.
#[inline(always)]
fn add_nodes<const STRESS: bool, const W: usize, const D: usize>(
    (dv, v, l): &mut (Vector<D>, Vector<D>, Tensor<D>),
    from: usize,
    (node_velocity, increment): (&[Vector<D>; W], &[Vector<D>; W]),
    (shape, gradient): (&[f64; W], &[Vector<D>; W]),
) {
    for c in from..W {
        let s = shape[c];
        let node_velocity = node_velocity[c];
        *dv += increment[c] * s;
        *v += node_velocity * s;
        if STRESS {
            *l += node_velocity * gradient[c].transpose();
        }
    }
}

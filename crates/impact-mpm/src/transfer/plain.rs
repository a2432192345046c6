//! Phase 1's default scatter (no APIC, with the internal force; `transfer.rs`'s module doc
//! for the colouring): a run of points read in step with its arrays and weights.
use super::*;

impl<const D: usize> MpmSolver<D> {
    /// Phase 1's sums without APIC, with the internal force (the default), for a stencil of
    /// rows of `W` nodes (its `width`) and `N` nodes (0: any): mass `m_i = Σ_p N_ip m_p`,
    /// momentum `p_i = Σ_p N_ip m_p v_p`, force `f_i = -Σ_p (V_p σ_p) ∇N_ip`. A run of
    /// points in their own order (the total Lagrangian frame; [`Run`]) is read in step
    /// with its arrays and rows of weights (no index, no bounds check per point), another
    /// one through the layer order; both through [`scatter_points`].
    /// In the total Lagrangian frame the mass sums are formed by the first scatter after
    /// the weights were evaluated and kept (`NodeSums::point_mass`: the same weights, masses
    /// and order of additions every step give the same sums, bit for bit); the later
    /// scatters copy them (the momentum and force still added, with the same operations).
    pub(super) fn scatter_plain<const W: usize, const N: usize>(
        &mut self,
        points: &MaterialPoints<D>,
    ) {
        let nodes = &mut self.nodes;
        let kept = !nodes.point_mass.is_empty();
        if kept && nodes.point_mass_ready {
            self.scatter_plain_sums::<W, N, false>(points);
            self.nodes.mass.copy_from_slice(&self.nodes.point_mass);
        } else {
            self.scatter_plain_sums::<W, N, true>(points);
            if kept {
                let nodes = &mut self.nodes;
                nodes.point_mass.copy_from_slice(&nodes.mass);
                nodes.point_mass_ready = true;
            }
        }
    }

    /// [`Self::scatter_plain`]'s sums, the mass's with `MASS` (else `mass` is left as it is).
    fn scatter_plain_sums<const W: usize, const N: usize, const MASS: bool>(
        &mut self,
        points: &MaterialPoints<D>,
    ) {
        assert_eq!(
            self.stencil.width, W,
            "the scatter's rows are the stencil's"
        );
        let stride = self.weight_stride;
        assert!(
            stride == 0 || stride == self.stencil.nodes,
            "a point's row of weights is its stencil's"
        );
        let fill = Fill {
            mass: MASS,
            momentum: true,
            force: true,
        };
        self.scatter_runs(fill, |weights, run, sums| {
            let npc = weights.offsets.len();
            let rows = weights.row_offsets;
            // the node count where fixed (`N`), else the stencil's
            let nodes = if N == 0 { npc } else { N };
            if !run.order.is_empty() {
                // the point arrays sliced to one length (a point checked against the mass
                // is proved for the others), the weights to one too; copied into the
                // iterator (`move`), not read through the closure's captures per point
                let count = points.mass.len();
                let (mass, velocity) = (&points.mass[..], &points.velocity[..count]);
                let (stress, volume) = (&points.stress[..count], &points.volume[..count]);
                let bases = &weights.bases[..count];
                let shape = weights.shape;
                let gradient = &weights.gradient[..shape.len()];
                let order = &run.order[run.points];
                let points = PointArrays {
                    mass,
                    velocity,
                    stress,
                    volume,
                    bases,
                };
                let table = (shape, gradient, nodes);
                // the point's first weight: the kind of storage is chosen here, once per run
                // (no branch on it per point; `weights::row_start`)
                return if weights.point_row.is_empty() {
                    let stride = weights.stride;
                    let data = through_order(order, points, table, move |p| p * stride);
                    scatter_points::<W, N, MASS, D>(sums, rows, data)
                } else {
                    let point_row = &weights.point_row[..count];
                    let first = move |p: usize| point_row[p] as usize * nodes;
                    let data = through_order(order, points, table, first);
                    scatter_points::<W, N, MASS, D>(sums, rows, data)
                };
            }
            let range = run.points;
            let (mass, velocity) = (&points.mass[range.clone()], &points.velocity[range.clone()]);
            let (stress, volume) = (&points.stress[range.clone()], &points.volume[range.clone()]);
            let bases = &weights.bases[range.clone()];
            let data = (mass.iter().zip(velocity))
                .zip(stress.iter().zip(volume))
                .zip(bases)
                .map(|(((&m, &v), (s, &vol)), &b)| (m, v, s * vol, b));
            if weights.stride == 0 {
                let row = (&weights.shape[..npc], &weights.gradient[..npc]);
                scatter_points::<W, N, MASS, D>(sums, rows, data.zip(std::iter::repeat(row)));
            } else if !weights.point_row.is_empty() {
                let point_row = &weights.point_row[range];
                // `nodes`: a constant where `N` fixes it (one bounds check a row)
                let table = table_rows(weights.shape, weights.gradient, nodes, point_row);
                scatter_points::<W, N, MASS, D>(sums, rows, data.zip(table));
            } else {
                let range = range.start * npc..range.end * npc;
                let shapes = weights.shape[range.clone()].chunks_exact(npc);
                let gradients = weights.gradient[range].chunks_exact(npc);
                scatter_points::<W, N, MASS, D>(sums, rows, data.zip(shapes.zip(gradients)));
            }
        });
    }
}

/// The arrays of the points a scatter reads through the layer order, sliced to one
/// length (a point checked against the mass is proved for the others).
#[derive(Clone, Copy)]
struct PointArrays<'a, const D: usize> {
    mass: &'a [f64],
    velocity: &'a [Vector<D>],
    stress: &'a [Tensor<D>],
    volume: &'a [f64],
    bases: &'a [usize],
}

/// A point as [`scatter_points`] takes it: its mass, velocity, `V_p σ_p` and base node,
/// and its row of shape values and gradients.
type ScatterPoint<'a, const D: usize> = (
    (f64, Vector<D>, Tensor<D>, usize),
    (&'a [f64], &'a [Vector<D>]),
);

/// The points `order` names, each as [`scatter_points`] takes it: its mass, velocity,
/// `V_p σ_p` (formed once per point), base node, and its row of weights, entries
/// `first_of(p) .. first_of(p) + nodes` of the `table`'s shape values and gradients.
#[inline(always)]
fn through_order<'a, const D: usize>(
    order: &'a [usize],
    points: PointArrays<'a, D>,
    (shape, gradient, nodes): (&'a [f64], &'a [Vector<D>], usize),
    first_of: impl Fn(usize) -> usize + 'a,
) -> impl Iterator<Item = ScatterPoint<'a, D>> + 'a {
    order.iter().map(move |&p| {
        let first = first_of(p);
        let row = first..first + nodes;
        let point = (
            points.mass[p],
            points.velocity[p],
            points.stress[p] * points.volume[p],
            points.bases[p],
        );
        (point, (&shape[row.clone()], &gradient[row]))
    })
}

/// Phase 1's sums ([`MpmSolver::scatter_plain`]; the mass's with `MASS`) of `points`: per
/// point its mass `m_p`,
/// velocity `v_p`, `V_p σ_p` and base node, and its row of shape values and gradients, on
/// a stencil of `rows` of `W` consecutive nodes (`Stencil::row_offsets`) and `N` nodes (0:
/// read here). Each row of the nodal sums is sliced once (one bounds check per row, not per
/// node) and its nodes added in the stencil's order (each node's sums take the same
/// operations in the same order as node by node). A generic function per kind of
/// `points`: the loop and the per-point work compile into one function, inlined into the
/// caller (which knows the lengths of the arrays the points index: one check per point).
#[inline(always)]
fn scatter_points<'w, const W: usize, const N: usize, const MASS: bool, const D: usize>(
    sums: &mut Band<'_, D>,
    rows: &[u32],
    points: impl Iterator<
        Item = (
            (f64, Vector<D>, Tensor<D>, usize),
            (&'w [f64], &'w [Vector<D>]),
        ),
    >,
) {
    // `N` where fixed (the loop over the rows then has a constant trip count and unrolls)
    let nodes = if N == 0 { rows.len() * W } else { N };
    let rows = &rows[..nodes / W];
    let offset = sums.offset;
    // the three sums sliced to one length: a row checked against the mass is proved for
    // the momentum and force
    let len = sums.mass.len();
    let (nodal_mass, momentum, force) = (
        &mut *sums.mass,
        &mut sums.momentum[..len],
        &mut sums.force[..len],
    );
    for ((mass, velocity, stress, base), (shape, gradient)) in points {
        let shape = shape[..nodes].as_chunks::<W>().0;
        let gradient = gradient[..nodes].as_chunks::<W>().0;
        // the band's nodes from the base node on (one check a point; the three of one
        // length)
        let base = base - offset;
        let (nodal_mass, momentum, force) = (
            &mut nodal_mass[base..],
            &mut momentum[base..],
            &mut force[base..],
        );
        for ((&o, shape), gradient) in rows.iter().zip(shape).zip(gradient) {
            let first = o as usize;
            let nodal_mass = node_row_mut::<f64, W>(nodal_mass, first);
            let momentum = node_row_mut::<Vector<D>, W>(momentum, first);
            let force = node_row_mut::<Vector<D>, W>(force, first);
            for c in 0..W {
                let w = shape[c] * mass;
                if MASS {
                    nodal_mass[c] += w;
                }
                momentum[c] += velocity * w;
                force[c] -= stress * gradient[c];
            }
        }
    }
}

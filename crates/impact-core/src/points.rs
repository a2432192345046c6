//! Material points as a struct of arrays.
use crate::method::Samples;
use crate::{Grid, Tensor, Vector};

/// Where the points of a cell sit, in the cell's local coordinates `[0, 1)^D`
/// (`impact stability` compares them; the DGMPM thesis tabulates the natural layout).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum PointLayout {
    /// At the centres of the `n^D` sub-cells: `(k + ½)/n` along each axis.
    #[default]
    Centred,
    /// Every point moved by `shift` sub-cell widths along each axis:
    /// `(k + ½ + shift)/n`, `|shift| < ½`.
    Shifted(f64),
    /// Given local positions, one per point of the cell (the first `D` coordinates used).
    Given(Vec<Vec<f64>>),
}

impl PointLayout {
    /// Whether the layout can seed `points_per_cell` points (a given layout: exactly its
    /// count).
    pub fn fits(&self, points_per_cell: usize) -> bool {
        match self {
            PointLayout::Given(list) => list.len() == points_per_cell,
            _ => true,
        }
    }

    /// A short label: `centred`, `shifted 0.25`, `given 0.2 0.7`.
    pub fn label(&self) -> String {
        match self {
            PointLayout::Centred => "centred".into(),
            PointLayout::Shifted(s) => format!("shifted {s}"),
            PointLayout::Given(list) => {
                let parts: Vec<String> = list
                    .iter()
                    .map(|p| {
                        p.iter()
                            .map(|u| u.to_string())
                            .collect::<Vec<_>>()
                            .join(":")
                    })
                    .collect();
                format!("given {}", parts.join(" "))
            }
        }
    }
    /// The local positions of the `per_axis^D` points of a cell (first axis fastest).
    pub fn local_positions<const D: usize>(&self, per_axis: usize) -> Vec<Vector<D>> {
        if let PointLayout::Given(list) = self {
            return list
                .iter()
                .map(|p| Vector::<D>::from_fn(|k, _| p[k]))
                .collect();
        }
        let shift = match self {
            PointLayout::Shifted(s) => *s,
            _ => 0.0,
        };
        (0..per_axis.pow(D as u32))
            .map(|k| {
                let mut rest = k;
                Vector::<D>::from_fn(|_, _| {
                    let j = rest % per_axis;
                    rest /= per_axis;
                    (j as f64 + 0.5 + shift) / per_axis as f64
                })
            })
            .collect()
    }
}

/// Material points (struct of arrays). `reference` is the position in the reference
/// configuration (the material coordinate `X`), `position` the current one.
#[derive(Debug, Clone, Default)]
pub struct MaterialPoints<const D: usize> {
    /// Reference position `X_α`.
    pub reference: Vec<Vector<D>>,
    /// Current position `x_α`.
    pub position: Vec<Vector<D>>,
    /// Mass `m_α`.
    pub mass: Vec<f64>,
    /// Current volume `V_α` (reference volume for the total Lagrangian DGMPM).
    pub volume: Vec<f64>,
    /// Velocity `v_α`.
    pub velocity: Vec<Vector<D>>,
    /// Stress: Cauchy `σ_α` in small strain, first Piola–Kirchhoff `Π_α` under
    /// Saint-Venant–Kirchhoff (total Lagrangian).
    pub stress: Vec<Tensor<D>>,
    /// Half-size of the point's domain along each axis (for the exact cell averages);
    /// empty when every point has `uniform_half_size` ([`Self::compact_half_sizes`]).
    pub half_size: Vec<Vector<D>>,
    /// The half-size every point shares, when `half_size` is compacted away.
    pub uniform_half_size: Option<Vector<D>>,
    /// Deformation gradient `F` (large-strain models only; empty otherwise).
    pub deformation: Vec<Tensor<D>>,
    /// Edge half-vectors of the point's domain as columns (CPDI only; empty otherwise).
    pub domain: Vec<Tensor<D>>,
    /// Accumulated plastic strain `ε̄` (J2 only; empty otherwise).
    pub equivalent_plastic_strain: Vec<f64>,
    /// Out-of-plane plastic strain `ε^p_zz` (J2: read in plane strain; empty otherwise).
    pub plastic_strain_zz: Vec<f64>,
    /// Plastic work per unit volume `∫ σ : dε_p` (J2 only; empty otherwise).
    pub plastic_work: Vec<f64>,
}

impl<const D: usize> MaterialPoints<D> {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Allocate the plastic history (J2): `ε̄`, `ε^p_zz` (read in plane strain only; kept
    /// in 1D too so one loop serves both) and the plastic work, all 0.
    pub fn with_plasticity(mut self) -> Self {
        let n = self.len();
        self.equivalent_plastic_strain = vec![0.0; n];
        self.plastic_strain_zz = vec![0.0; n];
        self.plastic_work = vec![0.0; n];
        self
    }

    /// Allocate the domains (`R = diag(half-size)`) for CPDI.
    pub fn with_domains(mut self) -> Self {
        self.domain = self
            .half_size
            .iter()
            .map(Tensor::<D>::from_diagonal)
            .collect();
        self
    }

    /// The points `range` (every per-point array cut to it; empty arrays stay empty): a
    /// rank's stored points.
    pub fn select(&self, range: std::ops::Range<usize>) -> Self {
        fn cut<T: Clone>(v: &[T], r: &std::ops::Range<usize>) -> Vec<T> {
            if v.is_empty() {
                Vec::new()
            } else {
                v[r.clone()].to_vec()
            }
        }
        Self {
            reference: cut(&self.reference, &range),
            position: cut(&self.position, &range),
            mass: cut(&self.mass, &range),
            volume: cut(&self.volume, &range),
            velocity: cut(&self.velocity, &range),
            stress: cut(&self.stress, &range),
            half_size: cut(&self.half_size, &range),
            uniform_half_size: self.uniform_half_size,
            deformation: cut(&self.deformation, &range),
            domain: cut(&self.domain, &range),
            equivalent_plastic_strain: cut(&self.equivalent_plastic_strain, &range),
            plastic_strain_zz: cut(&self.plastic_strain_zz, &range),
            plastic_work: cut(&self.plastic_work, &range),
        }
    }

    /// Drop the per-point half-sizes when all are equal (a method that never reads them per
    /// point, DGMPM: 16 B per point in 2D), keeping the shared value for the sampling.
    pub fn compact_half_sizes(&mut self) {
        if let Some(&first) = self.half_size.first() {
            if self.half_size.iter().all(|h| *h == first) {
                self.uniform_half_size = Some(first);
                self.half_size = Vec::new();
            }
        }
    }

    /// Allocate the deformation gradients (`F = 1`) for a large-strain model.
    pub fn with_deformation(mut self) -> Self {
        self.deformation = vec![Tensor::<D>::identity(); self.len()];
        self
    }

    /// Set each point's velocity and stress to the initial state at its reference position.
    pub fn apply_initial(&mut self, initial: &crate::initial::InitialState) {
        if initial.is_rest() {
            return;
        }
        for p in 0..self.len() {
            let x = self.reference[p];
            self.velocity[p] = initial.velocity(&x);
            self.stress[p] = initial.stress(&x);
        }
    }

    /// Copy the fields of the points `range` into `out` (the sampling of the point methods:
    /// every point on one rank, a slab's own points on several).
    pub fn sample_range_into(&self, range: std::ops::Range<usize>, out: &mut Samples<D>) {
        self.sample_runs_into(std::iter::once(range), out);
    }

    /// Copy the fields of the points `runs` into `out`, run after run (a box's own points
    /// are a run per row of its own cells).
    pub fn sample_runs_into(
        &self,
        runs: impl Iterator<Item = std::ops::Range<usize>>,
        out: &mut Samples<D>,
    ) {
        out.clear();
        for range in runs {
            out.reference
                .extend_from_slice(&self.reference[range.clone()]);
            out.position
                .extend_from_slice(&self.position[range.clone()]);
            match self.uniform_half_size {
                Some(h) => out.half_size.resize(out.half_size.len() + range.len(), h),
                None => out
                    .half_size
                    .extend_from_slice(&self.half_size[range.clone()]),
            }
            out.stress.extend_from_slice(&self.stress[range.clone()]);
            out.velocity
                .extend_from_slice(&self.velocity[range.clone()]);
            if !self.equivalent_plastic_strain.is_empty() {
                out.plastic_strain
                    .extend_from_slice(&self.equivalent_plastic_strain[range.clone()]);
            }
        }
    }

    /// Momentum `Σ m_α v_α` over the points `range`, in order.
    pub fn momentum_in(&self, range: std::ops::Range<usize>) -> Vector<D> {
        self.velocity[range.clone()]
            .iter()
            .zip(&self.mass[range])
            .fold(Vector::<D>::zeros(), |sum, (v, m)| sum + v * *m)
    }

    /// Kinetic plus strain energy over the points `range`, `Σ ½ m_α |v_α|² + V_α ψ_α`, with
    /// the strain energy density `ψ_α = energy_density(α)` (the point's index).
    /// The sum is taken a run of points at a time over the run's slices
    /// ([`crate::parallel::sum_over_runs`]), the terms in order.
    pub fn energy_in(
        &self,
        range: std::ops::Range<usize>,
        energy_density: impl Fn(usize) -> f64 + Sync,
    ) -> f64 {
        crate::parallel::sum_over_runs(range.len(), |run| {
            let first = range.start + run.start;
            let run = first..range.start + run.end;
            let (mass, velocity) = (&self.mass[run.clone()], &self.velocity[run.clone()]);
            let points = mass.iter().zip(velocity).zip(&self.volume[run]);
            let mut sum = -0.0;
            for (k, ((m, v), volume)) in points.enumerate() {
                sum += 0.5 * m * v.norm_squared() + volume * energy_density(first + k);
            }
            sum
        })
    }

    /// Whether point `i`'s stress and velocity (and, `with_position`, its position) are
    /// all finite: the sum of `x·0` over their components is 0 (`finite_zeros`).
    #[inline]
    pub fn values_finite(&self, i: usize, with_position: bool) -> bool {
        let position = with_position.then(|| &self.position[i]);
        finite_zeros(&self.stress[i], &self.velocity[i], position) == 0.0
    }

    /// The first of the points `range` (its offset in the range) that
    /// [`Self::values_finite`] fails, a run of points at a time over the run's slices
    /// ([`crate::parallel::first_failing_by_runs`]).
    pub fn first_non_finite(
        &self,
        range: std::ops::Range<usize>,
        with_position: bool,
    ) -> Option<usize> {
        let all_finite = |run: std::ops::Range<usize>| {
            let run = range.start + run.start..range.start + run.end;
            let (stress, velocity) = (&self.stress[run.clone()], &self.velocity[run.clone()]);
            let values = stress.iter().zip(velocity);
            let sum = match with_position {
                true => values
                    .zip(&self.position[run])
                    .fold(0.0, |sum, ((s, v), x)| sum + finite_zeros(s, v, Some(x))),
                false => values.fold(0.0, |sum, (s, v)| sum + finite_zeros(s, v, None)),
            };
            sum == 0.0
        };
        crate::parallel::first_failing_by_runs(range.len(), all_finite, |j| {
            self.values_finite(range.start + j, with_position)
        })
    }

    /// The peaks of `|σ|` and `|v|` over the points (component-wise maxima).
    pub fn peaks(&self) -> (f64, f64) {
        let stress = self.stress.iter().map(|s| s.amax()).fold(0.0, f64::max);
        let velocity = self.velocity.iter().map(|v| v.amax()).fold(0.0, f64::max);
        (stress, velocity)
    }

    /// The largest difference between the state of these points and `other`'s (the same
    /// points, e.g. two step paths of one method): stress and velocity relative to
    /// `other`'s peaks ([`Self::peaks`]), positions in m, volumes relative.
    pub fn difference(&self, other: &Self) -> f64 {
        let (scale_s, scale_v) = other.peaks();
        let mut worst: f64 = 0.0;
        for i in 0..self.len().min(other.len()) {
            worst = worst.max((self.stress[i] - other.stress[i]).amax() / scale_s);
            worst = worst.max((self.velocity[i] - other.velocity[i]).amax() / scale_v);
            worst = worst.max((self.position[i] - other.position[i]).amax());
            worst = worst.max((self.volume[i] - other.volume[i]).abs() / other.volume[i]);
        }
        worst
    }

    /// The point of largest `|v|` among `points` (a range, or the runs of a rank's own
    /// points in order; the last of equals), if any.
    pub fn hottest_in(&self, points: impl IntoIterator<Item = usize>) -> Option<usize> {
        points
            .into_iter()
            .max_by(|&a, &b| self.velocity[a].norm().total_cmp(&self.velocity[b].norm()))
    }

    /// Add `kick(α, X_α)` to every point's velocity.
    pub fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>) {
        for (i, (v, x)) in self.velocity.iter_mut().zip(&self.reference).enumerate() {
            *v += kick(i, x);
        }
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// `per_axis^D` points per cell of `grid` for every cell, at the centres of the
    /// sub-cells, each carrying the sub-cell's mass `ρ V_cell / per_axis^D`. Points are
    /// stored cell by cell: the points of cell `c` are `c*n .. (c+1)*n` with `n = per_axis^D`.
    pub fn regular(grid: &Grid<D>, per_axis: usize, density: f64) -> Self {
        Self::seeded(grid, per_axis, density, &PointLayout::Centred)
    }

    /// As [`Self::regular`] with the points of each cell placed by `layout` (equal masses
    /// and volumes; `half_size` stays half the sub-cell).
    pub fn seeded(grid: &Grid<D>, per_axis: usize, density: f64, layout: &PointLayout) -> Self {
        let whole: [std::ops::Range<usize>; D] = std::array::from_fn(|k| 0..grid.cells[k]);
        Self::seeded_box(grid, per_axis, density, layout, &whole)
    }

    /// [`Self::seeded`] for the box of cells `cells` (a range per axis) only (one rank's
    /// stored box, issue 27): the points of those cells of the whole `grid`, cell by cell in
    /// the box's lexicographic order (axis 0 fastest, the whole grid's relative order),
    /// placed from the whole grid's origin and global cell indices, so each point has the
    /// same bits as in the whole body's seeding (and the memory is the box's only).
    pub fn seeded_box(
        grid: &Grid<D>,
        per_axis: usize,
        density: f64,
        layout: &PointLayout,
        cells: &[std::ops::Range<usize>; D],
    ) -> Self {
        let per_cell = per_axis.pow(D as u32);
        let local = layout.local_positions::<D>(per_axis);
        let box_cells: usize = cells.iter().map(|r| r.len()).product();
        let n = box_cells * per_cell;
        let volume = grid.cell_volume() / per_cell as f64;
        let sub = grid.spacing / per_axis as f64;
        let mut points = Self {
            reference: Vec::with_capacity(n),
            position: Vec::with_capacity(n),
            mass: vec![density * volume; n],
            volume: vec![volume; n],
            velocity: vec![Vector::<D>::zeros(); n],
            stress: vec![Tensor::<D>::zeros(); n],
            half_size: vec![sub * 0.5; n],
            uniform_half_size: None,
            deformation: Vec::new(),
            domain: Vec::new(),
            equivalent_plastic_strain: Vec::new(),
            plastic_strain_zz: Vec::new(),
            plastic_work: Vec::new(),
        };
        for k in 0..box_cells {
            let mut rest = k;
            let idx: [usize; D] = std::array::from_fn(|l| {
                let i = cells[l].start + rest % cells[l].len();
                rest /= cells[l].len();
                i
            });
            let lower = grid.cell_lower(grid.cell_index(idx));
            for u in &local {
                let x = lower + grid.spacing.component_mul(u);
                points.reference.push(x);
                points.position.push(x);
            }
        }
        points
    }
}

/// `Σ x·0` over the components of a stress, a velocity and (if given) a position, without a
/// branch per component: `x·0` is `±0` for a finite `x` and NaN for `±∞` or NaN, so the sum
/// is 0 exactly when all are finite.
#[inline(always)]
fn finite_zeros<const D: usize>(
    stress: &Tensor<D>,
    velocity: &Vector<D>,
    position: Option<&Vector<D>>,
) -> f64 {
    let sum = (stress * 0.0).sum() + (velocity * 0.0).sum();
    match position {
        Some(x) => sum + (x * 0.0).sum(),
        None => sum,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `first_non_finite` finds a planted NaN, +∞ or −∞ in the stress, the velocity or
    /// (with positions) the position at its own offset, around the 4,096-point runs' ends
    /// and in a sub-range; a position is ignored without positions; finite values pass.
    /// `energy_in` (a run at a time) equals `sum_over` of the same terms, bit for bit.
    #[test]
    fn runs_find_the_first_non_finite_point_and_add_the_energy() {
        let grid = crate::Grid::<2> {
            origin: Vector::<2>::zeros(),
            spacing: Vector::<2>::new(1.0, 1.0),
            cells: [100, 90],
        };
        let mut points = MaterialPoints::<2>::regular(&grid, 1, 3.0);
        let n = points.len();
        for (i, (s, v)) in points
            .stress
            .iter_mut()
            .zip(&mut points.velocity)
            .enumerate()
        {
            *s = Tensor::<2>::from_fn(|r, c| ((i * 3 + r + 2 * c) as f64 * 0.7).sin() * 1e8);
            *v = Vector::<2>::from_fn(|r, _| ((i * 5 + r) as f64 * 0.3).cos());
        }
        let density = |i: usize| points.stress[i].norm_squared() * 1e-12;
        let plain = crate::parallel::sum_over(n, |i| {
            0.5 * points.mass[i] * points.velocity[i].norm_squared() + points.volume[i] * density(i)
        });
        assert_eq!(points.energy_in(0..n, density).to_bits(), plain.to_bits());
        assert_eq!(points.first_non_finite(0..n, true), None);
        for at in [0, 4095, 4096, 8191, n - 1] {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for field in 0..3 {
                    let mut p = points.clone();
                    match field {
                        0 => p.stress[at][(1, 0)] = bad,
                        1 => p.velocity[at][1] = bad,
                        _ => p.position[at][0] = bad,
                    }
                    assert_eq!(p.first_non_finite(0..n, true), Some(at), "{field} {bad}");
                    let without = if field == 2 { None } else { Some(at) };
                    assert_eq!(p.first_non_finite(0..n, false), without, "{field} {bad}");
                    let from = at.saturating_sub(10);
                    assert_eq!(p.first_non_finite(from..n, true), Some(at - from));
                }
            }
        }
    }
}

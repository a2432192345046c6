//! Phase 2: the Godunov flux on every face (linear elastic or Saint-Venant–Kirchhoff
//! Riemann solvers, ghost states on the boundary) and the force the loaded boundary
//! faces exert on the body.
use crate::faces::Fields;
use crate::riemann::{
    self, linear_elastic_star, normal_flux, Conserved, FullState, GhostCondition,
};
use crate::{unit, DgmpmSolver, Physics};
use impact_core::material::Svk;
use impact_core::method::RiemannSolver;
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Vector};

impl<const D: usize> DgmpmSolver<D> {
    /// Phase 2: the Godunov flux `F_{e_l}(q*)` on every face (exact Riemann solver, ghost
    /// states on the boundary); returns the power delivered by the boundary conditions,
    /// `Σ_boundary |Γ_f| (σ* n_out)·v*`.
    pub fn interface_fluxes(&mut self, points: &MaterialPoints<D>) -> f64 {
        let mut power = 0.0;
        for l in 0..D {
            let mut fluxes = std::mem::take(&mut self.face_flux[l]);
            let this = &*self;
            let fields = this.fields(points);
            power += this.sum_over_faces(l, &mut fluxes, |idx, flux| {
                let power;
                (*flux, power) = this.face_flux_at(l, idx, fields, points);
                power
            });
            self.face_flux[l] = fluxes;
        }
        power
    }

    /// The Godunov flux `F_{e_l}(q*)` of the face of axis `l` with multi-index `idx`, and
    /// the power its boundary condition delivers (0 inside).
    #[inline(always)]
    pub(crate) fn face_flux_at(
        &self,
        l: usize,
        idx: [usize; D],
        fields: Fields<'_, D>,
        points: &MaterialPoints<D>,
    ) -> (Conserved<D>, f64) {
        if self.physics == Physics::Linear && self.rod_solver.is_none() {
            return self.linear_face_flux(l, idx, fields);
        }
        let e = unit::<D>(l);
        let (lc, rc, s) = self.face_cells(l, idx);
        let left = lc.map(|c| fields.side(c, l, true));
        let right = rc.map(|c| fields.side(c, l, false));
        let (flux, star) = match self.physics {
            Physics::Linear => {
                let star = self.elastoplastic_star(points, l, (lc, rc), left, right, s);
                (normal_flux(&star, &e, &self.elastic), star)
            }
            Physics::Svk { svk, riemann } => {
                let star = self.svk_star(&svk, riemann, l, left, right, s);
                // F_n(q*) = -(v* ⊗ n, Π* n)
                let flux = Conserved {
                    tensor: -(star.velocity * e.transpose()),
                    momentum: -star.traction,
                };
                (flux, star)
            }
        };
        (flux, self.boundary_power(l, (lc, rc), &idx, &star))
    }

    /// [`Self::face_flux_at`] with the linear-elastic solver: the star state of the face's
    /// two states (a ghost state behind a boundary face) and its flux `F_{e_l}(q*)`.
    #[inline(always)]
    pub(crate) fn linear_face_flux(
        &self,
        l: usize,
        idx: [usize; D],
        fields: Fields<'_, D>,
    ) -> (Conserved<D>, f64) {
        let e = unit::<D>(l);
        let (lc, rc, _) = self.face_cells(l, idx);
        let left = lc.map(|c| fields.side(c, l, true));
        let right = rc.map(|c| fields.side(c, l, false));
        let (a, b) = self.face_pair_at(l, left, right, &idx);
        let star = linear_elastic_star(&a.on_face(&e), &b.on_face(&e), &e, self.elastic.z);
        let flux = normal_flux(&star, &e, &self.elastic);
        (flux, self.boundary_power(l, (lc, rc), &idx, &star))
    }

    /// Power a boundary face's condition delivers, `|Γ_f| (σ* n_out)·v*` (0 inside): the
    /// traction on the body is `σ* n_out`, `n_out = -e_l` at the low boundary. A
    /// traction-free face (multi-index `idx`; its edge's condition from the table,
    /// [`Self::edge_condition`]) delivers none: its star traction
    /// is zero up to round-off, which would otherwise add a round-off work (1e-20 J) that a
    /// relative energy error divides by.
    #[inline(always)]
    fn boundary_power(
        &self,
        l: usize,
        cells: (Option<usize>, Option<usize>),
        idx: &[usize; D],
        star: &riemann::FaceState<D>,
    ) -> f64 {
        let area = self.grid.cell_volume() / self.grid.spacing[l];
        let (side, cell) = match cells {
            (None, Some(c)) => (0, c),
            (Some(c), None) => (1, c),
            _ => return 0.0,
        };
        // a halo cell's edge faces are its owner's (a rank's box, `GridPlace`)
        if !self.owns_edge_face(&self.grid.cell_multi_index(cell)) {
            return 0.0;
        }
        if self.edge_condition(l, side, idx) == GhostCondition::free() {
            return 0.0;
        }
        let sign = if side == 0 { -1.0 } else { 1.0 };
        sign * area * star.traction.dot(&star.velocity)
    }

    /// Star state of a face with the elastoplastic solver ([`riemann::elastoplastic`]),
    /// in the `+e_l` orientation. The normal part follows each side's wave curve: elastic
    /// up to the yield surface, plastic beyond (the rod's `[−Y, Y]` in 1D; in plane strain
    /// the range of `σ_nn` along the uniaxial-strain path from the side's 3D state, with the
    /// plastic modulus `M_p`: exact for a plane wave, an approximation where shear is
    /// present). The tangential part is the linear solver's (elastic shear waves). Each
    /// side's plastic state is its cell's one point. A boundary face solves the normal half
    /// problem of its condition; a face partly covered by an impactor keeps the linear
    /// star.
    fn elastoplastic_star(
        &self,
        points: &MaterialPoints<D>,
        l: usize,
        cells: (Option<usize>, Option<usize>),
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: [f64; 2],
    ) -> riemann::FaceState<D> {
        use riemann::elastoplastic::{
            elastoplastic_boundary_1d, elastoplastic_star_1d, uniaxial_strain_bounds, PlasticSide,
            RodBoundary,
        };
        let (j2, z) = self.rod_solver.expect("internal: checked by the caller");
        let side = |c: usize, state: FullState<D>| {
            let y = j2.current_yield(&impact_core::plasticity::PlasticState {
                equivalent_plastic_strain: points.equivalent_plastic_strain[c],
            });
            let (stress, velocity) = (state.tensor[(l, l)], state.velocity[l]);
            if D == 1 {
                return PlasticSide::rod(stress, velocity, y);
            }
            let full = j2.stress3(&state.tensor, points.plastic_strain_zz[c]);
            let n = nalgebra::Vector3::from_fn(|k, _| if k == l { 1.0 } else { 0.0 });
            let lame = (j2.elastic.lame.lambda, j2.elastic.lame.mu);
            let (lower, upper) = uniaxial_strain_bounds(&full, &n, y, lame);
            PlasticSide {
                stress,
                velocity,
                lower,
                upper,
            }
        };
        let normal = match (cells.0.zip(left), cells.1.zip(right)) {
            (Some((a, la)), Some((b, rb))) => {
                Some(elastoplastic_star_1d(&side(a, la), &side(b, rb), z))
            }
            (inner, outer) => {
                let (c, state, face_side) = match (inner, outer) {
                    (Some((a, la)), None) => (a, la, 1),
                    (None, Some((b, rb))) => (b, rb, 0),
                    _ => unreachable!("internal: a face has at least one cell"),
                };
                let outward = if face_side == 0 { -1.0 } else { 1.0 };
                let condition = match self.ghost_condition(l, face_side, s) {
                    GhostCondition::Traction(t) => Some(RodBoundary::Traction(t[l])),
                    GhostCondition::NormalVelocity(v) => Some(RodBoundary::Velocity(v)),
                    GhostCondition::Velocity(v) => Some(RodBoundary::Velocity(v[l] * outward)),
                    GhostCondition::PartialVelocity { .. } => None,
                };
                condition.map(|cond| elastoplastic_boundary_1d(&side(c, state), outward, cond, z))
            }
        };
        // the rod has no tangential part: the linear star is needed only in 2D (its shear
        // part) or where the normal half problem is not solved (a partly covered face)
        let mut star = match normal {
            Some(_) if D == 1 => riemann::FaceState {
                traction: Vector::<D>::zeros(),
                velocity: Vector::<D>::zeros(),
            },
            _ => {
                let e = unit::<D>(l);
                let (a, b) = self.face_pair(l, left, right, s);
                linear_elastic_star(&a.on_face(&e), &b.on_face(&e), &e, self.elastic.z)
            }
        };
        if let Some((sigma, v)) = normal {
            star.traction[l] = sigma;
            star.velocity[l] = v;
        }
        star
    }

    /// Star state of a face for Saint-Venant–Kirchhoff (`FullState::tensor` holds `F`),
    /// in the `+e_l` orientation. Boundary faces solve the half problem: exactly in 1D
    /// ([`riemann::svk::exact_boundary_1d`]); with the acoustic solver from the interior's
    /// wave relation ([`riemann::svk::acoustic_boundary`]). A face with no admissible
    /// state (hyperbolicity lost) gets a NaN state, which the guard reports.
    pub(crate) fn svk_star(
        &self,
        svk: &Svk,
        riemann: RiemannSolver,
        l: usize,
        left: Option<FullState<D>>,
        right: Option<FullState<D>>,
        s: [f64; 2],
    ) -> riemann::FaceState<D> {
        let e = unit::<D>(l);
        let nan = riemann::FaceState {
            traction: Vector::<D>::from_element(f64::NAN),
            velocity: Vector::<D>::from_element(f64::NAN),
        };
        let one_d = |(v, pi): (f64, f64)| riemann::FaceState {
            traction: e * pi,
            velocity: e * v,
        };
        match (riemann, left, right) {
            (RiemannSolver::Exact, Some(a), Some(b)) if D == 1 => riemann::svk::exact_star_1d(
                svk,
                (a.tensor[(0, 0)], a.velocity[0]),
                (b.tensor[(0, 0)], b.velocity[0]),
            )
            .map_or(nan, one_d),
            (RiemannSolver::Exact, a, b) if D == 1 => {
                let (inner, side) = match (a, b) {
                    (Some(a), None) => (a, 1),
                    (None, Some(b)) => (b, 0),
                    _ => unreachable!("internal: a face has at least one cell"),
                };
                let outward = if side == 0 { -1.0 } else { 1.0 };
                let cond = match self.ghost_condition(l, side, s) {
                    GhostCondition::Traction(t) => GhostCondition::Traction(Vector::<1>::new(t[0])),
                    GhostCondition::NormalVelocity(v) => GhostCondition::NormalVelocity(v),
                    // in 1D the velocity is the normal velocity (outward component)
                    GhostCondition::Velocity(v) => GhostCondition::NormalVelocity(v[0] * outward),
                    GhostCondition::PartialVelocity {
                        velocity,
                        bonded,
                        share,
                    } => GhostCondition::PartialVelocity {
                        velocity: Vector::<1>::new(velocity[0]),
                        bonded,
                        share,
                    },
                };
                riemann::svk::exact_boundary_1d(
                    svk,
                    (inner.tensor[(0, 0)], inner.velocity[0]),
                    outward,
                    cond,
                )
                .map_or(nan, one_d)
            }
            (_, Some(a), Some(b)) => riemann::svk::acoustic_star(
                svk,
                (&a.tensor, &a.velocity),
                (&b.tensor, &b.velocity),
                &e,
            )
            .unwrap_or(nan),
            (_, a, b) => {
                let (inner, side) = match (a, b) {
                    (Some(a), None) => (a, 1),
                    (None, Some(b)) => (b, 0),
                    _ => unreachable!("internal: a face has at least one cell"),
                };
                let sign = if side == 0 { -1.0 } else { 1.0 };
                let outward = e * sign;
                // solve along the outward normal with the interior on the left
                let interior = riemann::FaceState {
                    traction: svk.piola(&inner.tensor) * outward,
                    velocity: inner.velocity,
                };
                let z = riemann::svk::impedance(svk, &inner.tensor, &outward);
                riemann::svk::acoustic_boundary(
                    &z,
                    &interior,
                    &outward,
                    self.ghost_condition(l, side, s),
                )
                .map(|st| riemann::FaceState {
                    traction: st.traction * sign,
                    velocity: st.velocity,
                })
                .unwrap_or(nan)
            }
        }
    }

    /// The flux of face `f` of axis `l` as the update uses it: Godunov plus, under CTU,
    /// the transverse correction (added in place by phase 2b).
    #[inline]
    fn final_flux(&self, l: usize, f: usize) -> Conserved<D> {
        self.face_flux[l][f]
    }

    /// Force on the body through the loaded boundary faces (those whose condition is not
    /// traction-free), `Σ -sign |Γ_f| F_{e_l}` (the momentum part of the final face fluxes,
    /// CTU corrections included). Free faces are left out, so momentum equals this impulse
    /// only if they carry no traction.
    pub fn boundary_force(&self) -> Vector<D> {
        let grid = &self.grid;
        let mut force = Vector::<D>::zeros();
        for l in 0..D {
            let layer: usize = Grid::<D>::tangent_axes(l).map(|k| grid.cells[k]).product();
            for t in 0..layer {
                let mut idx = [0usize; D];
                let mut rest = t;
                for k in Grid::<D>::tangent_axes(l) {
                    idx[k] = rest % grid.cells[k];
                    rest /= grid.cells[k];
                }
                for side in 0..2 {
                    idx[l] = side * grid.cells[l];
                    let f = Self::face_index(grid, l, idx);
                    force += self.boundary_face_force(l, idx, &self.final_flux(l, f));
                }
            }
        }
        force
    }

    /// Force on the body through the boundary face of axis `l` at `idx` whose final flux
    /// is `flux`: `-sign |Γ_f| F_{e_l}` (momentum part), zero on a traction-free face.
    #[inline]
    pub(crate) fn boundary_face_force(
        &self,
        l: usize,
        idx: [usize; D],
        flux: &Conserved<D>,
    ) -> Vector<D> {
        let side = usize::from(idx[l] != 0);
        if !self.owns_edge_face(&idx) {
            return Vector::<D>::zeros();
        }
        if self.edge_condition(l, side, &idx) == GhostCondition::free() {
            return Vector::<D>::zeros();
        }
        let sign = if side == 0 { -1.0 } else { 1.0 };
        let area = self.grid.cell_volume() / self.grid.spacing[l];
        -flux.momentum * (sign * area)
    }

    /// Whether the boundary face at `idx` (of any axis) counts on this grid: a box's halo
    /// cells' edge faces are their owner's (`GridPlace`); always on one rank.
    #[inline]
    pub(crate) fn owns_edge_face(&self, idx: &[usize; D]) -> bool {
        self.place.owns(idx, &self.grid.cells)
    }
}

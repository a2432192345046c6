//! The [`Method`] trait shared by DGMPM, MPM and FEM, and the sampled fields they return.
use crate::comm::{Comm, SerialComm};
pub use crate::options::{
    DgmpmOptions, EdgeKind, EdgeTreatment, FemOptions, Integrator, LayoutKind, LoadDirection,
    LoadShape, MaterialModel, MethodConfig, MethodKind, MethodOptions, MpmFrame, MpmOptions,
    MpmShape, MpmTransfer, PointUpdate, RiemannSolver, SchemeOrder, SegmentCover, StressUpdate,
    TransverseFlux, WaveLimiter,
};
pub use crate::problem::Model;
use crate::{Tensor, Vector};
use thiserror::Error;

/// Fields sampled where a method stores them (material points for DGMPM and MPM,
/// element centres for FEM), at their reference (material) positions.
#[derive(Debug, Clone, Default)]
pub struct Samples<const D: usize> {
    /// Reference position `X` of each sample.
    pub reference: Vec<Vector<D>>,
    /// Current position `x` of each sample.
    pub position: Vec<Vector<D>>,
    /// Half-size of the region each sample stands for (in the reference configuration).
    pub half_size: Vec<Vector<D>>,
    /// Stress: Cauchy `σ` in small strain, first Piola–Kirchhoff `Π` in large strain.
    pub stress: Vec<Tensor<D>>,
    /// Velocity.
    pub velocity: Vec<Vector<D>>,
    /// Accumulated plastic strain `ε̄` (J2 only; empty otherwise).
    pub plastic_strain: Vec<f64>,
    /// Out-of-plane stress `σ_zz` where the model sets it apart from the elastic
    /// plane-strain relation (J2 in 2D; empty otherwise).
    pub stress_zz: Vec<f64>,
}

impl<const D: usize> Samples<D> {
    /// Empty all arrays, keeping their capacity.
    pub fn clear(&mut self) {
        self.reference.clear();
        self.position.clear();
        self.half_size.clear();
        self.stress.clear();
        self.velocity.clear();
        self.plastic_strain.clear();
        self.stress_zz.clear();
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.stress.len()
    }
    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.stress.is_empty()
    }
}

fn show_place(place: &[f64]) -> String {
    let parts: Vec<String> = place.iter().map(|x| format!("{x:.6}")).collect();
    format!("({})", parts.join(", "))
}

/// A run stopped by the stability guard: which method, when and where.
#[derive(Debug, Clone, PartialEq, Error)]
#[error(
    "{method} blew up at step {step}, t = {time:.6e} s, near x = {} m: {reason}",
    show_place(place)
)]
pub struct Blowup {
    /// Method name.
    pub method: String,
    /// Step at which the guard fired.
    pub step: usize,
    /// Time at which the guard fired (s).
    pub time: f64,
    /// Reference position of the offending value.
    pub place: Vec<f64>,
    /// What was seen.
    pub reason: String,
}

/// Where a method's state first fails a check.
#[derive(Debug, Clone, PartialEq)]
pub struct BadState<const D: usize> {
    /// Reference position of the offending point, node or element.
    pub place: Vector<D>,
    /// What is wrong.
    pub reason: String,
}

/// One numerical method on one problem. `step` advances the method's own state; the
/// controller ([`crate::controller`]) owns the loop, the schedule and the guard.
pub trait Method<const D: usize>: Send {
    /// The configuration this run was built with.
    fn config(&self) -> &MethodConfig;
    /// Largest stable time step for the configured Courant number:
    /// `Δt = courant · Δx_min / c_p`.
    fn stable_dt(&self) -> f64;
    /// Advance from `t` to `t + dt`. Must not allocate.
    fn step(&mut self, t: f64, dt: f64);
    /// Sample stress and velocity where the method stores them.
    fn sample_into(&self, out: &mut Samples<D>);
    /// Kinetic plus strain energy of the discrete state, plus the plastic work `∫ q dε̄`
    /// under J2 (J).
    fn energy(&self) -> f64;
    /// Work done by the loads since `t = 0` (J), as the method delivered it.
    fn external_work(&self) -> f64;
    /// Kinetic plus strain energy of the discrete state at `t = 0` (J), as built: the
    /// energy the state should hold is this plus [`Self::external_work`].
    fn initial_energy(&self) -> f64;
    /// Total momentum of the discrete state.
    fn momentum(&self) -> Vector<D>;
    /// Impulse delivered since `t = 0` by the loads and the prescribed velocities
    /// (reactions included), as the method delivered it.
    fn external_impulse(&self) -> Vector<D>;
    /// First non-finite value of the state, if any.
    fn check_finite(&self) -> Result<(), BadState<D>>;
    /// Reference position of the largest velocity (where a blow-up is growing).
    fn hottest_place(&self) -> Vector<D>;
    /// Number of cells (or elements) of the discretisation.
    fn cells(&self) -> usize;
    /// Number of degrees of freedom updated per step (for throughput figures).
    fn updates_per_step(&self) -> usize;
    /// Add `kick(i, X_i)` to the velocity of every velocity carrier `i` (points, or FEM nodes)
    /// at reference position `X_i`: the perturbed start of the stability sweeps.
    fn perturb_velocity(&mut self, kick: &mut dyn FnMut(usize, &Vector<D>) -> Vector<D>);
    /// This rank's own samples, in global order: what the whole-body checks reduce over
    /// ([`Self::comm`]) and what this rank writes as its piece of an output frame. The
    /// default (one rank) is every sample, as [`Self::sample_into`]; a method split over
    /// ranks gives the samples of what it owns (a DGMPM slab: its owned layers' points), so
    /// that the rank's memory and messages do not grow with the whole body. Concatenated
    /// in rank order, the ranks' owned samples are [`Self::sample_into`]'s.
    fn owned_samples_into(&self, out: &mut Samples<D>) {
        self.sample_into(out);
    }
    /// The global index of each of [`Self::owned_samples_into`]'s samples (in the order
    /// [`Self::sample_into`] gives the whole body's), or empty where the ranks' owned
    /// samples concatenated in rank order are already the global order (one rank, slabs):
    /// what puts a subset of the owned samples gathered from every rank (the measuring
    /// line's, [`crate::comm_line`]) in the global order.
    fn owned_sample_order(&self) -> &[usize] {
        &[]
    }
    /// The ranks this method is split over, for the reductions of
    /// [`Self::owned_samples_into`]'s values: one rank ([`SerialComm`]) by default.
    fn comm(&self) -> &dyn Comm {
        &SerialComm
    }
    /// Bytes this rank sends to the other ranks per step (the halo exchange): 0 on one
    /// rank (the default).
    fn bytes_exchanged_per_step(&self) -> usize {
        0
    }
    /// Nodal velocities and displacements of this rank's piece of a conforming mesh on the
    /// body's grid, for the methods that have one (FEM); `None` for the point methods. The
    /// piece is the nodes of the rank's owned elements: per axis the node layers `[a, b]`
    /// of its owned element layers `[a, b)` (the nodes it shares with the neighbour above
    /// included), in the global lexicographic order within that box (axis 0 fastest):
    /// every node of the mesh on one rank. Called at outputs only; no communication.
    fn piece_nodal_fields(&self) -> Option<(Vec<Vector<D>>, Vec<Vector<D>>)> {
        None
    }
}

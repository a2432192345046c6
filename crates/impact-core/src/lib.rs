//! Shared core of `impact`: grid, material points (struct of arrays), materials, scenes,
//! boundary conditions and loads, exact solutions, metrics, the [`Method`] trait and the
//! time loop ([`controller`]).
//!
//! The spatial dimension is a const generic `D` (1 or 2); tensors are full `D×D`
//! nalgebra matrices. In 1D the body is a bar of unit cross-section in uniaxial stress
//! (modulus `E`); in 2D it is in plane strain (moduli `λ`, `μ`).
//!
//! Sign conventions: tension positive; a `pressure` load is positive in compression.
//!
//! Layout: `grid` (cells, vertices, shape functions: a new MPM shape function goes beside
//! `Grid::shape`), `points`, `material` (a new material: stateless, parameters apart, with
//! its `Model` variant in `problem`), `scene/` (parsing; `validate.rs`, `boundary.rs`: every
//! range), `options` (one enum per option), `exact/`, `reference`, `metrics`, `method` (the
//! trait), `controller` (time loop, guard, stop flag), `parallel` (the chunk helper).

// Index loops over tensor axes and local nodes read best as written in the formulas.
#![allow(clippy::needless_range_loop)]

pub mod comm;
pub mod comm_box;
pub mod comm_gather;
pub mod comm_halo;
pub mod comm_line;
pub mod comm_method;
pub mod comm_migrate;
mod comm_thread;
pub mod config_check;
pub mod controller;
pub mod converged;
pub mod distinct;
pub mod error;
pub mod exact;
pub mod grid;
pub mod initial;
pub mod interior;
pub mod line;
pub mod load;
pub mod material;
pub mod method;
pub mod metrics;
pub mod options;
pub mod parallel;
pub mod patch;
pub mod plasticity;
pub mod points;
pub mod problem;
pub mod reference;
pub mod scene;
pub mod scheme_order;
pub mod slab_method;
pub mod time_metrics;

pub use error::{CoreError, SceneError};
pub use grid::Grid;
pub use load::LoadHistory;
pub use material::{Lame, LinearElastic, YoungPoisson};
pub use method::{Blowup, Method, MethodKind, Samples};
pub use patch::{Patch, PatchShape};
pub use problem::{Boundary, Constraint, Load, Problem, StressMeasure};
pub use scene::Scene;

/// Vector of dimension `D`.
pub type Vector<const D: usize> = nalgebra::SVector<f64, D>;
/// Full `D×D` tensor.
pub type Tensor<const D: usize> = nalgebra::SMatrix<f64, D, D>;

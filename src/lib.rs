//! `impact`: DGMPM, MPM and explicit FEM on the same stress-wave problems.
//!
//! This library holds what the CLI and the cross-method tests share: a validated
//! [`study::Study`] (scene + command-line overrides), building a method from its
//! configuration ([`build`]), running methods with metrics and outputs ([`run`]), the
//! `check` gate and its pass/fail rule ([`check`]), the references ([`reference`](mod@reference)),
//! stability sweeps and work-precision ladders. The binary (`src/main.rs`,
//! `src/cli/`) only parses arguments and prints.
pub mod check;
pub mod check_report;
pub mod convergence;
pub mod fields;
pub mod figures;
pub mod flags;
pub mod guard;
pub mod interrupt;
pub mod ladder;
pub mod lamb;
pub mod lamb_study;
pub mod memory;
#[cfg(feature = "mpi")]
mod mpi_comm;
pub mod output;
pub mod output_bench;
pub mod plane;
pub mod plots;
pub mod progress_feed;
pub mod provenance;
pub mod ranks;
pub mod reference;
pub mod reference_cache;
pub mod reference_setup;
pub mod run;
pub mod stability;
pub mod stability_run;
pub mod study;
pub mod von_neumann;
pub mod work_precision;

pub use reference::{reference_for, REFERENCE_REFINEMENT};
pub use study::{Overrides, Study};

use impact_core::method::{MethodConfig, MethodKind};
use impact_core::{CoreError, Method, Problem};

/// Build a method for `problem` from its configuration.
pub fn build<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Result<Box<dyn Method<D>>, CoreError> {
    Ok(match config.kind() {
        MethodKind::Dgmpm => Box::new(impact_dgmpm::Dgmpm::new(problem, config)?),
        MethodKind::Mpm => Box::new(impact_mpm::Mpm::new(problem, config)?),
        MethodKind::Fem => Box::new(impact_fem::Fem::new(problem, config)?),
    })
}

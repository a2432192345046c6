//! The ranks of a run (issue 27): which [`Comm`] this process uses. One rank
//! ([`SerialComm`]) unless the binary was built with the `mpi` feature and started by an
//! MPI launcher (`mpirun`, `srun`), which [`init`] detects from the launcher's environment.
//!
//! Every rank runs the same command on the same code path; rank 0 prints and writes the
//! output folder, the others run silently into a private scratch folder that is removed at
//! the end (so every rank makes the same collective calls in the same order). Only
//! [`crate::run::run_method`]'s runs and `bench convergence`'s levels
//! ([`crate::convergence`]) are decomposed ([`build_ranked`]): DGMPM, MPM and FEM
//! in slabs along the last axis or in boxes of the rank grid `--ranks-grid`
//! ([`set_rank_grid`]; [`impact_dgmpm::slab`], [`impact_mpm::slab`], [`impact_fem::slab`];
//! MPM's updated frame with points migrating between the boxes, [`impact_mpm::migrate`],
//! CPDI included).
//! The converged references are shared by the ranks ([`crate::reference`]): rank 0 alone
//! reads the cache and tells the others hit or miss; a hit is sent from rank 0 to every
//! rank, a miss is run decomposed like these runs ([`build_ranked_on`]) and rank 0 writes
//! the cache entry.
use impact_core::comm::{Comm, CommError, RankGrid, SerialComm};
use impact_core::method::{MethodConfig, MethodKind, MpmFrame};
use impact_core::{CoreError, Method, Problem};
use std::sync::{Arc, OnceLock};

static COMM: OnceLock<Arc<dyn Comm>> = OnceLock::new();
static RANK_GRID: OnceLock<RankGrid> = OnceLock::new();

/// Use `grid` (`--ranks-grid`) to split this process's runs (first call only).
pub fn set_rank_grid(grid: RankGrid) {
    let _ = RANK_GRID.set(grid);
}

/// The rank grid of this process's runs (automatic unless `--ranks-grid` was given).
pub fn rank_grid() -> RankGrid {
    RANK_GRID.get().cloned().unwrap_or_default()
}

/// This process's communicator (one rank unless [`init`] found an MPI launcher).
pub fn comm() -> Arc<dyn Comm> {
    COMM.get_or_init(|| Arc::new(SerialComm)).clone()
}

/// Whether this process prints and writes (rank 0, or the only rank).
pub fn is_root() -> bool {
    COMM.get().is_none_or(|c| c.is_root())
}

/// Number of ranks.
pub fn size() -> usize {
    COMM.get().map_or(1, |c| c.size())
}

/// Use `comm` for this process (first call only; later calls are ignored).
pub fn set(comm: Arc<dyn Comm>) {
    let _ = COMM.set(comm);
}

/// What must live until the end of `main`: MPI's universe (finalised when dropped).
pub type Guard = Option<Box<dyn std::any::Any>>;

/// Start MPI when built with the `mpi` feature and launched by `mpirun`/`srun`
/// (`OMPI_COMM_WORLD_SIZE`, `PMI_SIZE` or `PMIX_RANK` set); otherwise one rank.
pub fn init() -> Result<Guard, CommError> {
    #[cfg(feature = "mpi")]
    {
        let launched = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
            .iter()
            .any(|v| std::env::var_os(v).is_some());
        if launched {
            let (comm, universe) = crate::mpi_comm::MpiComm::start()?;
            set(Arc::new(comm));
            return Ok(Some(universe));
        }
    }
    Ok(None)
}

/// Refuse the rank grid (`--ranks-grid`) of a `dim`-dimensional run before any run
/// starts: one that does not fit the rank count or the dimension. Every method runs on
/// boxes (DGMPM, MPM in both frames, FEM).
pub fn check_rank_grid(dim: usize) -> Result<(), CommError> {
    rank_grid().parts(dim, size())?;
    Ok(())
}

/// Build `config` on `problem` for this process's rank: the whole problem on one rank,
/// this rank's DGMPM, MPM or FEM slab on several.
pub fn build_ranked<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
) -> Result<Box<dyn Method<D>>, CoreError> {
    build_ranked_on(problem, config, comm(), &rank_grid())
}

/// [`build_ranked`] on the ranks of `comm` split as `grid` (the in-process ranks of the
/// tests, [`impact_core::comm::ThreadComm`]).
pub fn build_ranked_on<const D: usize>(
    problem: &Problem<D>,
    config: MethodConfig,
    comm: Arc<dyn Comm>,
    grid: &RankGrid,
) -> Result<Box<dyn Method<D>>, CoreError> {
    // (a rank grid that does not fit is refused on one rank too)
    grid.parts(D, comm.size()).map_err(CoreError::from)?;
    if comm.size() == 1 {
        return crate::build(problem, config);
    }
    match config.kind() {
        MethodKind::Dgmpm => Ok(Box::new(impact_dgmpm::slab::SlabDgmpm::<D>::on_grid(
            problem, config, comm, grid,
        )?)),
        MethodKind::Mpm if config.mpm().map(|o| o.frame) == Some(MpmFrame::UpdatedLagrangian) => {
            // points migrate between the boxes (`impact_mpm::migrate`)
            Ok(Box::new(impact_mpm::migrate::MigratingMpm::<D>::on_grid(
                problem, config, comm, grid,
            )?))
        }
        MethodKind::Mpm => Ok(Box::new(impact_mpm::slab::SlabMpm::<D>::on_grid(
            problem, config, comm, grid,
        )?)),
        MethodKind::Fem => Ok(Box::new(impact_fem::slab::SlabFem::<D>::on_grid(
            problem, config, comm, grid,
        )?)),
    }
}

/// The decomposition of a run of `config` on `problem`, for summary.json (`None` on one
/// rank).
pub fn decomposition<const D: usize>(
    problem: &Problem<D>,
    config: &MethodConfig,
) -> Option<String> {
    let ranks = size();
    if ranks == 1 {
        return None;
    }
    match (config.kind(), config.dgmpm(), config.mpm()) {
        (MethodKind::Fem, _, _) => Some(impact_fem::slab::describe(
            &problem.grid,
            ranks,
            &rank_grid(),
        )),
        (_, Some(o), _) => Some(impact_dgmpm::slab::describe(
            &problem.grid,
            o,
            ranks,
            &rank_grid(),
        )),
        (_, _, Some(o)) => Some(impact_mpm::slab::describe(
            &problem.grid,
            o,
            ranks,
            &rank_grid(),
        )),
        _ => None,
    }
}

/// The private folder of a rank other than 0 (its output folder, staging folder and lock
/// inside; removed at the end, [`scratch_output`]).
pub fn scratch_folder() -> std::path::PathBuf {
    std::env::temp_dir().join(format!(
        "impact-rank{}-{}",
        comm().rank(),
        std::process::id()
    ))
}

/// The folder a rank other than 0 writes into instead of `out`.
pub fn scratch_output() -> std::path::PathBuf {
    scratch_folder().join("out")
}

/// `eprintln!` on rank 0 only: on several ranks every rank runs the same command and would
/// print the same progress line, so rank 0 speaks for all.
#[macro_export]
macro_rules! root_eprintln {
    ($($arg:tt)*) => {
        if $crate::ranks::is_root() {
            eprintln!($($arg)*);
        }
    };
}

//! The integration tests in one binary: each file under this folder is a module here and
//! reads as it would alone (`cargo test --test integration <file>::`); one binary compiles and
//! links the solvers once, where a binary per file did it once per file (CI's build time).
//! Files that need a process of their own are targets of their own (Cargo.toml `[[test]]`):
//! `alloc` (its counting allocator), `fronts`, `reference` and `reference_ranks` (each sets
//! `IMPACT_CACHE_DIR` for its process). A new file is a `mod` line here (autotests are off:
//! a file listed nowhere would not run; `docs::every_test_file_is_a_module_or_a_target`
//! fails then).
mod common;

mod bad_input;
mod bar_ends;
mod bar_paper;
mod cli;
mod convergence;
mod docs;
mod faults;
mod fem_grid_pieces;
mod guard;
mod lamb;
mod loads;
mod oblique;
mod outputs;
mod plasticity;
mod plate;
mod provenance;
mod scene_fuzz;
mod schedule;
mod smooth;
mod stability;
mod svk;
mod threads;
mod three_d;
mod work_precision;

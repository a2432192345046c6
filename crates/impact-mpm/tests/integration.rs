//! The integration tests in one binary: each file under this folder is a module here and
//! reads as it would alone (`cargo test --test integration <file>::`); one binary compiles and
//! links the solvers once, where a binary per file did it once per file (CI's build time).
//! A new file is a `mod` line here (autotests are off: a file listed nowhere would not run;
//! the root's `docs::every_test_file_is_a_module_or_a_target` fails then).
mod decomposed;

mod boxes;
mod finite;
mod fused_gather;
mod migrate;
mod reductions;
mod slab;
mod standing_3d;
mod transfers;
mod weight_table;

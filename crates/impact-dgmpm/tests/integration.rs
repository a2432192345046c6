//! The integration tests in one binary: each file under this folder is a module here and
//! reads as it would alone (`cargo test --test integration <file>::`); one binary compiles and
//! links the solvers once, where a binary per file did it once per file (CI's build time).
//! A new file is a `mod` line here (autotests are off: a file listed nowhere would not run;
//! the root's `docs::every_test_file_is_a_module_or_a_target` fails then).
mod decomposed;

mod bar_exact;
mod boxes;
mod fused;
mod fused_3d;
mod line_metrics;
mod order2;
mod order2_3d;
mod order2_plastic;
mod order2_svk;
mod order2_svk_2d;
mod reductions;
mod slab;
mod three_d;

//! The integration tests in one binary: each file under this folder is a module here and
//! reads as it would alone (`cargo test --test integration <file>::`); one binary compiles and
//! links the solvers once, where a binary per file did it once per file (CI's build time).
//! Files that need a process of their own are targets of their own (Cargo.toml `[[test]]`).
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

//! A deterministic mutation fuzzer for rayforge's readers that runs on stable Rust.
//!
//! cargo-fuzz needs a nightly compiler; this does the same job without one, more slowly: seed
//! files (the repository's scenes and models, copies of community scenes, generated images)
//! are mutated by a seeded generator (byte flips, insertions, deletions, splices between files,
//! numbers replaced by NaN, infinities and extremes, deep nesting) and fed to each reader under
//! `catch_unwind`. `cargo test -p rayforge-fuzz` runs a few thousand inputs per target; the
//! `rayforge-fuzz` binary runs for as long as it is told (see `docs/reliability.md`).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod corpus;
pub mod mutate;
pub mod rng;
pub mod runner;
pub mod targets;

pub use runner::{fuzz, fuzz_from, minimize, run_one, Crash, Options, Report};
pub use targets::Target;

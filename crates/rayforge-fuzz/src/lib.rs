//! rayforge's fuzz targets and their seeds; the engine is [bolero](https://docs.rs/bolero).
//!
//! Each target ([`targets`]) is a plain function of the input's bytes: a reader of outside
//! input (scenes, OBJ models, glTF models, images, part files, the live page's messages),
//! followed by a tiny render of what it produced, so that values the readers let through are
//! also fed to the renderer. A target must never panic, hang or exhaust memory, whatever the
//! bytes; a refusal must say something. `tests/fuzz.rs` makes each target a `cargo test` that
//! replays its seeds ([`corpus`]), and a `cargo bolero test` target that fuzzes it for as long
//! as it is told (see `docs/reliability.md`).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod corpus;
pub mod targets;

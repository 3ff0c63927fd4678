//! WGSL composition: the project's one mechanism for sharing shader code.
//!
//! WGSL has no `#include`, so dermis runs a small line-based preprocessor over the files in
//! `shaders/` (embedded at compile time, so no file is read at run time; the shared modules
//! are listed in `sources.rs`, each shading model's comes with its descriptor):
//!
//! * `#import name` inlines module `name` once per composed shader: `shaders/name.wgsl`, or a
//!   module generated from a Rust declaration — `consts`, the constants shared with Rust
//!   (`consts.rs`), and one per struct the GPU reads, named after it (`#import FrameUniform`:
//!   `structs.rs` writes it from the `gpu_struct!` / `model_uniform!` declaration); a name can
//!   be an *alias* bound by the caller (the character shader imports `shading_model`, bound
//!   to `ward`, `dipole`, `oss`, … per pipeline);
//! * `#ifdef FLAG` / `#ifndef FLAG` / `#else` / `#endif` keep or drop lines by the caller's
//!   flags (effect variants), nesting allowed.
//!
//! Everything else is passed through unchanged, so composed output is plain WGSL that any
//! compiler (naga, tint) accepts. Selecting a shading model selects a file, not a branch.

mod compose;
pub mod consts;
mod sources;
pub mod structs;
pub mod uniforms;

pub use compose::{compose, compose_from, ComposeError, ShaderDefs};
pub use sources::{module_source, modules, SHARED};

//! The skin shading models of Lee, Kim & Chin (2014), one Rust module per WGSL file of the
//! same name in `shaders/`: each holds the model's parameters, the CPU-side precompute of
//! everything that does not vary per pixel, and an f64 reference of the per-pixel maths.
//!
//! [`ShadingModel`] is the one registry of model names, used by the CLI, the UI, the renderer
//! and every JSON output; its table ([`Descriptor`], `registry.rs`) holds one row per model.
//! Adding a model is one Rust file here, one WGSL file of the same name in `shaders/` and one
//! row in that table.

pub mod bake;
pub mod burley;
pub mod dipole;
pub mod edge_spread;
pub mod fresnel;
pub mod material;
pub mod oss;
pub mod pixel;
pub mod prediction;
pub mod preintegrated;
mod registry;
pub mod subsurface;
pub mod tabulated;
pub mod transport;
mod uniform;
pub mod units;
pub mod ward;

pub use material::Material;
pub use registry::{Descriptor, Effects, ShadingModel};
pub use uniform::{Field, Layout, ModelParams, Uniform, MODEL_PARAM_ROWS};

//! dermis-measure: everything that measures the engine rather than runs it. Used by the
//! desktop CLI's measurement commands (`sss`, `profile`, `reference`, `lut`, `bench shading`)
//! and by the tests; the APK does not link it (`cargo tree -p dermis-android`).
//!
//! - [`mc`]: the Monte Carlo photon transport (semi-infinite media, slabs, spheres, shadow
//!   edges) every accuracy number is measured against;
//! - [`ground_truth`]: the path-traced data set (`tools/reference/`) the models are scored on,
//!   and the error metric;
//! - [`scenes`]: those scenes rendered **through the real renderer** and read back in the
//!   Monte Carlo's units;
//! - [`conformance`]: the GPU conformance suite: the renderer's WGSL run in a compute shader
//!   against each model's f64 reference, and the tolerances;
//! - [`bake`] and [`lut`]: the offline Monte Carlo bakes of the spatial models' tables and the
//!   pre-integration LUTs the core ships (`assets/sss/`).

pub mod albedo;
pub mod bake;
pub mod conformance;
pub mod face;
pub mod grid;
pub mod ground_truth;
pub mod lut;
pub mod mc;
pub mod scenes;
pub mod texturing;

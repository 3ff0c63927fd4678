//! The scanned head against an outside path tracer (Mitsuba 3, `tools/mitsuba/`): the scene
//! exported as the path tracer reads it, the cached references, and the image-space score.
//!
//! - [`export`]: a welded PLY in metres, JSON with the camera, light and the material's
//!   coefficients.
//! - [`cache`]: the cached references, checked against the scene files they were made from.
//! - [`score`]: mean |ln(model/reference)| over the skin pixels above the reference's noise.

pub mod cache;
pub mod export;
pub mod score;

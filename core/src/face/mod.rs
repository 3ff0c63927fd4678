//! A real face: the scanned LeePerrySmith head (CC BY 3.0, [`head::ATTRIBUTION`]) in the
//! engine, its scene exported for an outside path tracer (Mitsuba 3, `tools/mitsuba/`), and
//! the image-space score of a shading model against that reference.
//!
//! - [`head`]: the head loaded into metres with its albedo, the camera and the three lights
//!   of the face scenes, and a renderer that draws it (PNG or linear radiance).
//! - [`export`]: the scene as the path tracer reads it (a welded PLY in metres, JSON with the
//!   camera, light and the material's coefficients).
//! - [`pfm`]: linear float images (Portable Float Map).
//! - [`score`]: mean |ln(model/reference)| over the skin pixels above the reference's noise.

pub mod cache;
pub mod export;
pub mod head;
pub mod pfm;
pub mod score;

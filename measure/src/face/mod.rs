//! The scanned head's ground truth and its score: the project's own Monte Carlo on the closed
//! head mesh, cached, and the image-space score of a rendered face against it; the scene
//! exported for an outside path tracer (Mitsuba 3, `tools/mitsuba/`) to cross-check it.
//!
//! - [`export`]: the welded, closed head (PLY in metres) and JSON with the camera, lights and
//!   the material's coefficients.
//! - [`truth`]: the truth under any point light: linear radiance and its standard error in the
//!   face scenes' camera.
//! - [`truth_cache`]: the cached truths (`tools/reference/face/`), checked against the scene.
//! - [`score`]: mean |ln(model/truth)| over the head's blocks where the truth is precise.
//! - [`render`]: the head drawn through the engine's renderer (linear radiance or an image).
//! - [`regions`]: where the error sits (eye sockets, nose, lips, ear, neck), per channel.

pub mod export;
pub mod regions;
pub mod render;
pub mod score;
pub mod truth;
pub mod truth_cache;

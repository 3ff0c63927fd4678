//! A real face: the scanned LeePerrySmith head (CC BY 3.0, [`head::ATTRIBUTION`]) in the
//! engine. Its export for an outside path tracer and the image-space score against that
//! reference are measurement: `dermis_measure::face`.
//!
//! - [`head`]: the head loaded into metres with its albedo, the camera and the three lights
//!   of the face scenes, and a renderer that draws it (PNG or linear radiance).
//! - [`pfm`]: linear float images (Portable Float Map).

pub mod head;
pub mod pfm;

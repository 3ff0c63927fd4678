//! Animation: sampling glTF channels (STEP / LINEAR / CUBICSPLINE), poses, crossfades and the
//! joint palette (jointWorld · inverseBind) that the vertex shader skins with.
//!
//! Nothing here allocates after [`Pose::new`] except [`skin_positions`] (a CPU reference path
//! that returns a new vector).

mod palette;
mod pose;
mod sample;

pub use palette::{first_skinned_mesh, joint_palette, skin_positions};
pub use pose::Pose;
pub use sample::{sample_quat, sample_vec3};

//! Animation: sampling glTF channels (STEP / LINEAR / CUBICSPLINE), poses, crossfades and the
//! joint palette (jointWorld · inverseBind) that the vertex shader skins with.
//!
//! Nothing here allocates after [`Pose::new`] except [`skin_positions`] (a CPU reference path
//! that returns a new vector) and the load-time helpers: the clips by name ([`find_clips`])
//! and a character's bounds and fit to a height ([`bind_pose_bounds`], [`fit_to_height`]).

mod clips;
mod fit;
mod palette;
mod pose;
mod reach;
mod sample;

pub use clips::{clip_by_role, find_clips, Clips, Role as ClipRole};
pub use fit::{bind_pose_bounds, fit_to_height, Fit};
pub use palette::{first_skinned_mesh, joint_palette, skin_positions};
pub use pose::Pose;
pub use reach::JointBoxes;
pub use sample::{sample_quat, sample_vec3};

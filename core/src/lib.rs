//! dermis-core: the platform-free engine core.
//!
//! Data flows one way: `asset` (glTF → [`asset::Model`]) → `anim` (clips → pose → joint
//! palette) → `render` (GPU resources, one frame) with `shading` supplying each skin model's
//! constants and `shader` composing the WGSL. Nothing here depends on a window system or on
//! Android; the desktop app and the Android app are thin shells around it.

pub mod anim;
pub mod app;
pub mod asset;
pub mod camera;
pub mod face;
pub mod game;
pub mod governor;
pub mod heap;
pub mod lifecycle;
pub mod pool;
pub mod render;
pub mod scene;
pub mod shader;
pub mod shading;
pub mod soak;
pub mod still;
pub mod ui;

//! dermis-engine: the platform-free engine.
//!
//! Data flows one way: `asset` (glTF → [`asset::Model`]) → `anim` (clips → pose → joint
//! palette) → `scene` (the plain data one frame is made of) → `render` (GPU resources, one
//! frame: prepare → encode) with `shading` supplying each skin model's constants and `shader`
//! composing the WGSL. Nothing here depends on the game (`dermis-game`), a window system or
//! Android: the compiler holds that, since this crate cannot name them.

pub mod anim;
pub mod asset;
pub mod camera;
pub mod heap;
pub mod pool;
pub mod render;
pub mod scene;
pub mod shader;
pub mod shading;
pub mod still;
pub mod ui;

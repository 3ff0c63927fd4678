//! glTF 2.0 loading into the engine's own, validated data model.
//!
//! [`load_gltf`] / [`load_gltf_slice`] parse the JSON with the `gltf` crate but load buffers
//! and images themselves, so that every declared size, range and count is checked (with
//! checked arithmetic, against [`limits`]) before anything is allocated. Every failure is an
//! [`AssetError`] naming the file; no input can make the loader panic.
//!
//! Policies worth knowing:
//! - Absent normals are generated *smooth* (area-weighted), keeping the vertex count, so
//!   skinning data and CPU skinning stay index-compatible with the file.
//! - Absent tangents are generated from per-triangle UV gradients (see `tangents`).
//! - Every vertex of a primitive with `WEIGHTS_0` must have a positive weight sum (zero-sum
//!   weights are an error, whatever the node); weights are normalised to sum 1.
//! - A node with a skin needs `JOINTS_0`/`WEIGHTS_0` on every primitive of its mesh, and each
//!   joint index (even with zero weight) must be below the skin's joint count.
//! - Non-triangle primitives (points, lines, strips, fans) are skipped with a warning.
//! - Materials are read whole ([`Material`]: metallic-roughness PBR, normal, occlusion,
//!   emissive, alpha mode, double-sidedness and the volume, volume-scatter, diffuse-transmission,
//!   IOR and emissive-strength extensions), each texture decoded once per role it is used in
//!   (colour: sRGB, data: linear), pixels as the file has them — or, where `cargo xtask
//!   assets` encoded it beside the model (`<file>.textures/`, see [`compressed`]), its GPU
//!   block encodings, which the renderer uploads as they are where the device samples them.
//!   A bad material value, a missing or undecodable texture gets a warning
//!   ([`Model::warnings`]) and a fallback, never an error. Which materials are skin is
//!   [`skin::classify`]'s decision.

mod accessor;
mod animation;
pub mod bounce;
pub mod compressed;
pub mod curvature;
mod error;
mod glb;
pub mod head;
mod images;
pub mod limits;
mod load;
mod material;
mod materials;
mod model;
mod nodes;
pub mod shapes;
pub mod skin;
pub mod tangents;
pub mod thickness;
mod uri;
mod vertices;

pub use compressed::{BlockFormat, BlockImage, Family, TextureRole};
pub use error::AssetError;
pub use load::{dir_reader, load_gltf, load_gltf_slice};
pub use material::*;
pub use materials::MATERIAL_EXTENSIONS;
pub use model::*;

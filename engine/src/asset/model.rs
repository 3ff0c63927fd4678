//! The engine's in-memory model: what the loader produces and the renderer and animation read.
//! Every index in here has been range-checked by the loader.

use glam::{Mat4, Quat, Vec3};

use super::Material;

/// One vertex as uploaded to the GPU (108 bytes, `#[repr(C)]`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// xyz tangent, w = handedness (±1). Generated when the file has none.
    pub tangent: [f32; 4],
    pub uv: [f32; 2],
    /// Indices into the skin's joint list (0 for rigid meshes).
    pub joints: [u16; 4],
    /// Normalised to sum 1 (`[1,0,0,0]` for rigid meshes).
    pub weights: [f32; 4],
    /// Local material thickness in metres (glTF attribute `_THICKNESS`): translucency's path,
    /// the OSS depth. Where a mesh has none, ray cast at load ([`super::thickness`]).
    pub thickness: f32,
    /// Curvature of the surface here (1/m; positive where convex) as `[a, κ₂]`: the normal
    /// curvature along a unit tangent t is κ₂ + (a·t)²; computed at load from the mesh
    /// ([`super::curvature`]).
    pub curvature: [f32; 4],
    /// The light the model returns to this vertex from its own surface, as (s, F): under a
    /// distant light along l of irradiance E, A·E·max(F/4 + s·l/2, 0) arrives here from the
    /// rest of a model of diffuse reflectance A ([`super::bounce`]; computed at load).
    pub bounce: [f32; 4],
}

/// Thickness where a mesh neither gives one nor has another side to cast to (metres).
pub const DEFAULT_THICKNESS_M: f32 = 0.004;

/// The most joints one skin may have: the palette is a 16 KiB uniform buffer (GLES-safe).
pub const MAX_JOINTS: usize = 256;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }
}

impl Transform {
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

#[derive(Clone, Debug)]
pub struct Node {
    pub name: Option<String>,
    pub parent: Option<usize>,
    pub children: Vec<usize>,
    /// Rest (bind-file) local transform; animation overrides it per channel.
    pub local: Transform,
    pub mesh: Option<usize>,
    pub skin: Option<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

#[derive(Clone, Debug)]
pub struct Primitive {
    pub vertices: Vec<Vertex>,
    /// Triangle list (u32; generated 0..n when the file has no indices).
    pub indices: Vec<u32>,
    pub material: Option<usize>,
    /// Bounds of the bind-pose positions.
    pub bounds: Aabb,
}

#[derive(Clone, Debug)]
pub struct Mesh {
    pub name: Option<String>,
    pub primitives: Vec<Primitive>,
}

#[derive(Clone, Debug)]
pub struct Skin {
    pub name: Option<String>,
    /// Node index of each joint.
    pub joints: Vec<usize>,
    /// One per joint (identity when the file has none).
    pub inverse_bind: Vec<Mat4>,
}

/// An image a material samples, as the file has it: decoded RGBA8, or its GPU block
/// encodings (see [`Texels`]). `srgb` when a material uses it as colour (base colour,
/// emissive, multi-scatter colour, …; see [`Material`](super::Material)), linear when as data
/// (normal, metallic-roughness, occlusion, …).
#[derive(Clone, Debug)]
pub struct TextureImage {
    pub width: u32,
    pub height: u32,
    pub texels: Texels,
    pub srgb: bool,
    /// The glTF image it was read from (its index in the file); `None` for an image that is
    /// not a glTF file's (the scanned head's maps, a test's).
    pub image: Option<usize>,
}

/// What a [`TextureImage`] holds.
#[derive(Clone, Debug)]
pub enum Texels {
    /// Decoded RGBA8, level 0, row-major (the renderer builds the mip chain).
    Rgba8(Vec<u8>),
    /// The image in GPU block formats (KTX2), each with its mip chain, in preference order:
    /// the renderer uploads the first its device samples, else decodes one to RGBA8.
    Blocks(Vec<std::sync::Arc<super::BlockImage>>),
}

impl TextureImage {
    /// A decoded RGBA8 image.
    pub fn rgba(width: u32, height: u32, rgba8: Vec<u8>, srgb: bool) -> Self {
        Self {
            width,
            height,
            texels: Texels::Rgba8(rgba8),
            srgb,
            image: None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
}

/// One animated property of one node. `values` holds `times.len()` elements of 3 (T, S) or
/// 4 (R, xyzw) floats; for cubic spline, 3 elements per key: in-tangent, value, out-tangent.
#[derive(Clone, Debug)]
pub struct Channel {
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    pub values: Vec<f32>,
}

#[derive(Clone, Debug)]
pub struct AnimationClip {
    pub name: Option<String>,
    /// Last key time over all channels (seconds).
    pub duration: f32,
    pub channels: Vec<Channel>,
}

/// A loaded glTF file.
#[derive(Clone, Debug)]
pub struct Model {
    /// The file name, used in every error message about this model.
    pub source: String,
    pub nodes: Vec<Node>,
    /// Root nodes of the default scene.
    pub roots: Vec<usize>,
    pub meshes: Vec<Mesh>,
    pub skins: Vec<Skin>,
    pub materials: Vec<Material>,
    pub textures: Vec<TextureImage>,
    pub animations: Vec<AnimationClip>,
    /// What the loader recovered from in the materials and textures (a bad value, a missing
    /// or undecodable texture…), one line each naming the file; each was also logged.
    pub warnings: Vec<String>,
}

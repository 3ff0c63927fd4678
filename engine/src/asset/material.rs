//! A glTF 2.0 material as its author made it: metallic-roughness PBR and the extensions that
//! declare a scattering volume (the loader's `materials` module fills it; `skin` decides
//! which materials are skin).
//!
//! Every texture field is an index into [`Model::textures`](super::Model::textures), sampled
//! with `TEXCOORD_0` (a reference to `TEXCOORD_1` is dropped with a warning: the engine's
//! vertices carry one UV set). Colour textures (base colour, emissive, multi-scatter colour,
//! diffuse-transmission colour) are decoded as sRGB, data textures (metallic-roughness,
//! normal, occlusion, thickness, diffuse transmission) as linear
//! ([`TextureImage::srgb`](super::TextureImage::srgb)); an image used in both roles is
//! decoded once per role. Pixels are kept as the file has them (alpha included: it means
//! what [`AlphaMode`] says).

/// How the base colour's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: fully opaque.
    Opaque,
    /// Opaque where alpha ≥ `cutoff`, absent elsewhere.
    Mask { cutoff: f32 },
    /// Alpha blended.
    Blend,
}

/// `KHR_materials_volume`: the surface bounds a homogeneous volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// Thickness of the volume under the surface, mesh units (0: thin-walled).
    pub thickness_factor: f32,
    /// × factor, G channel (linear).
    pub thickness_texture: Option<usize>,
    /// Mean distance light travels before interacting [m]; `f32::INFINITY`: no attenuation.
    pub attenuation_distance: f32,
    /// The colour white light turns into after `attenuation_distance`.
    pub attenuation_color: [f32; 3],
}

impl Default for Volume {
    fn default() -> Self {
        Self {
            thickness_factor: 0.0,
            thickness_texture: None,
            attenuation_distance: f32::INFINITY,
            attenuation_color: [1.0; 3],
        }
    }
}

/// `KHR_materials_volume_scatter` (Khronos draft): scattering inside the volume. Its
/// optics: `asset::skin::skin_optics`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeScatter {
    /// The multi-scatter albedo A (`multiscatterColor`; also read from the draft's
    /// `multiscatterColorFactor` and its earlier `scatterAlbedo`). Default black, as the
    /// draft says (a texture without a factor is black: the loader warns).
    pub multiscatter_color: [f32; 3],
    /// × factor, RGB (sRGB): A per texel.
    pub multiscatter_texture: Option<usize>,
    /// Henyey–Greenstein g (`scatterAnisotropy`), in (−1, 1).
    pub anisotropy: f32,
}

impl Default for VolumeScatter {
    fn default() -> Self {
        Self {
            multiscatter_color: [0.0; 3],
            multiscatter_texture: None,
            anisotropy: 0.0,
        }
    }
}

/// `KHR_materials_diffuse_transmission`: light crossing the surface diffusely.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// Fraction of the diffuse light transmitted (default 0).
    pub factor: f32,
    /// × factor, A channel (linear).
    pub texture: Option<usize>,
    /// Colour of the transmitted light (default white).
    pub color_factor: [f32; 3],
    /// × colour factor, RGB (sRGB).
    pub color_texture: Option<usize>,
}

impl Default for DiffuseTransmission {
    fn default() -> Self {
        Self {
            factor: 0.0,
            texture: None,
            color_factor: [1.0; 3],
            color_texture: None,
        }
    }
}

/// A material: glTF's defaults where the file says nothing ([`Material::default`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: Option<String>,
    /// Linear RGBA (default white).
    pub base_color_factor: [f32; 4],
    /// × factor (sRGB RGB, linear alpha).
    pub base_color_texture: Option<usize>,
    /// Default 1.
    pub metallic_factor: f32,
    /// Default 1.
    pub roughness_factor: f32,
    /// × factors: B = metalness, G = roughness (linear).
    pub metallic_roughness_texture: Option<usize>,
    /// A tangent-space normal map (linear RGB: xyz = 2·rgb − 1 in the vertex's tangent,
    /// bitangent and normal, +y toward decreasing v, the OpenGL convention).
    pub normal_texture: Option<usize>,
    /// Scales the map's x and y (default 1).
    pub normal_scale: f32,
    /// Ambient occlusion in R (linear).
    pub occlusion_texture: Option<usize>,
    /// 1 + strength · (occlusion − 1) (default 1).
    pub occlusion_strength: f32,
    /// Linear RGB (default black).
    pub emissive_factor: [f32; 3],
    /// `KHR_materials_emissive_strength` (default 1): multiplies the emission.
    pub emissive_strength: f32,
    /// × factor (sRGB).
    pub emissive_texture: Option<usize>,
    pub alpha_mode: AlphaMode,
    /// Both faces drawn, the back face with the normal flipped (default false).
    pub double_sided: bool,
    /// `KHR_materials_ior` (default 1.5).
    pub ior: f32,
    pub volume: Option<Volume>,
    pub volume_scatter: Option<VolumeScatter>,
    pub diffuse_transmission: Option<DiffuseTransmission>,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: None,
            base_color_factor: [1.0; 4],
            base_color_texture: None,
            metallic_factor: 1.0,
            roughness_factor: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive_factor: [0.0; 3],
            emissive_strength: 1.0,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            ior: DEFAULT_IOR,
            volume: None,
            volume_scatter: None,
            diffuse_transmission: None,
        }
    }
}

/// glTF's index of refraction where `KHR_materials_ior` is absent.
pub const DEFAULT_IOR: f32 = 1.5;

/// A skin material's albedo: linear RGB factor × the texture (sRGB RGB) when there is one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedo {
    pub factor: [f32; 3],
    pub texture: Option<usize>,
}

impl Material {
    /// The albedo of this material as skin: the multi-scatter colour (factor × texture) when
    /// `KHR_materials_volume_scatter` gives one, else the base colour (factor × texture).
    pub fn skin_albedo(&self) -> Albedo {
        match &self.volume_scatter {
            Some(s) => Albedo {
                factor: s.multiscatter_color,
                texture: s.multiscatter_texture,
            },
            None => Albedo {
                factor: [
                    self.base_color_factor[0],
                    self.base_color_factor[1],
                    self.base_color_factor[2],
                ],
                texture: self.base_color_texture,
            },
        }
    }

    /// How messages name material `index`: `material 1 "Skin"` (or `material 1`).
    pub fn label(&self, index: usize) -> String {
        match &self.name {
            Some(n) => format!("material {index} {n:?}"),
            None => format!("material {index}"),
        }
    }
}

//! The uniforms of the shared modules and of the renderer's passes, declared once, here:
//! below the renderer, so the composer serves their WGSL (`shader::structs`) to every shader
//! that imports them — the character's for each model, the tools' and the tests' as much as
//! the renderer's. What fills each lives with the code that writes it
//! (`render/frame_uniform.rs`, `render/material_gpu.rs`, the passes). A pass with a uniform
//! of its own declares it here and lists it in [`DECLARED`].

use crate::gpu_struct;
use crate::shading::{Layout, Uniform};

gpu_struct! {
/// What every pass reads at `@group(0) @binding(0)` (`common.wgsl`): the camera, the key
/// light, how the output is written, the shadow map and the penumbra map. Flags are `u32` 0/1.
pub struct FrameUniform {
    pub view_proj: glam::Mat4,
    pub camera_pos: [f32; 3],
    /// Multiplies radiance before tone mapping.
    pub exposure: f32,
    /// The point light's position (m).
    pub light_pos: [f32; 3],
    /// Its radiant intensity (W/sr).
    pub light_intensity: f32,
    /// Its colour (linear).
    pub light_color: [f32; 3],
    /// 1: the target is not sRGB, the shader encodes by hand.
    pub srgb_encode: u32,
    /// Ambient radiance (linear).
    pub ambient: [f32; 3],
    /// 1: write raw radiance (float targets): no exposure, no tone mapping.
    pub raw_output: u32,
    /// World → the shadow map's clip space (`render/shadow_view.rs`).
    pub shadow_view_proj: glam::Mat4,
    /// 1: a shadow map was drawn this frame (0: nothing casts, every point is lit).
    pub shadow_drawn: u32,
    /// How far receivers move their test point off the surface (m, half a texel).
    pub shadow_normal_offset: f32,
    /// The depth bias, in the map's depth units.
    pub shadow_bias: f32,
    /// One texel of the map, in uv.
    pub shadow_texel: f32,
    /// 1: the penumbra map (`render/passes/penumbra.rs`) was drawn this frame.
    pub penumbra_drawn: u32,
    /// The penumbra map's grid size (texels per side).
    pub penumbra_grid: f32,
    /// The shadow map's width at the casters (m).
    pub shadow_width: f32,
    /// The depth step that makes a shadow edge, in the map's depth units.
    pub edge_gap: f32,
}
}

gpu_struct! {
/// A glTF material's constants (`material.wgsl`): a skinned subject binds them at group 3,
/// props at group 1.
pub struct MaterialUniform {
    /// Linear RGBA: the base colour factor; for skin, the albedo's factor (rgb).
    pub base_color: [f32; 4],
    /// Linear emission (factor × strength).
    pub emissive: [f32; 3],
    pub metallic: f32,
    pub roughness: f32,
    /// Scales the normal map's x and y.
    pub normal_scale: f32,
    /// 1 + strength · (occlusion − 1).
    pub occlusion_strength: f32,
    /// Alpha below which a MASK material is absent (0: not masked).
    pub alpha_cutoff: f32,
    /// 1: the albedo is the skin's pigment per texel; 0: the medium's own (no pigment).
    pub pigmented: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}
}

gpu_struct! {
/// The key light's shadow-map pass (`shadow_caster.wgsl`).
pub struct CasterUniform {
    /// World → the shadow map's clip space.
    pub view_proj: glam::Mat4,
}
}

/// Shadow-map texels per penumbra grid texel, per side: the penumbra map's grid is the
/// shadow map's size over this (`render/light_maps.rs`), and its seed pass reads blocks of
/// this size (`penumbra.wgsl`, through `consts`).
pub const PENUMBRA_BLOCK: u32 = 8;

gpu_struct! {
/// One penumbra pass's constants (`penumbra.wgsl`: the seed pass and each jump pass).
pub struct PenumbraUniform {
    /// This pass's step (grid texels; 0: the seed pass).
    pub step: f32,
    /// The grid's size (texels per side).
    pub grid: f32,
    /// The depth step that makes an edge (the map's depth units).
    pub edge_gap: f32,
    pub _pad0: f32,
}
}

gpu_struct! {
/// The UI pass's constants (`ui.wgsl`).
pub struct UiUniform {
    /// x, y: the surface's size in pixels; z: 1 when the target format is sRGB; w: unused.
    pub screen: [f32; 4],
}
}

/// Every struct declared here, for the composer (`shader::structs::table`).
pub const DECLARED: [Layout; 5] = [
    FrameUniform::LAYOUT,
    MaterialUniform::LAYOUT,
    CasterUniform::LAYOUT,
    PenumbraUniform::LAYOUT,
    UiUniform::LAYOUT,
];

//! The per-frame uniform every pass binds at `@group(0) @binding(0)` (`FrameUniform` in
//! `shaders/common.wgsl`, member for member: `engine/tests/engine/uniform_layout.rs`).

use super::shadow_view::ShadowView;
use crate::scene::FrameView;

/// How the frame's fragments leave the shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputMode {
    /// Multiplies radiance before tone mapping.
    pub exposure: f32,
    /// The target is not an sRGB format: the shader encodes by hand.
    pub srgb_encode: bool,
    /// Write raw radiance (float targets, numerical checks): no exposure, no tone mapping.
    pub raw: bool,
}

impl OutputMode {
    /// The mode a target of `format` needs, with `exposure`.
    pub fn for_format(format: wgpu::TextureFormat, exposure: f32) -> Self {
        let raw = matches!(
            format,
            wgpu::TextureFormat::Rgba16Float | wgpu::TextureFormat::Rgba32Float
        );
        Self {
            exposure,
            srgb_encode: !raw && !format.is_srgb(),
            raw,
        }
    }
}

fn flag(on: bool) -> u32 {
    u32::from(on)
}

crate::shading::uniform::gpu_struct! {
/// What every pass reads at `@group(0) @binding(0)`: the camera, the key light, how the output
/// is written, the shadow map and the penumbra map. Flags are `u32` 0/1.
pub struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
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
    /// World → the shadow map's clip space.
    pub shadow_view_proj: [[f32; 4]; 4],
    /// 1: a shadow map was drawn this frame (0: nothing casts, every point is lit).
    pub shadow_drawn: u32,
    /// How far receivers move their test point off the surface (m).
    pub shadow_normal_offset: f32,
    /// The depth bias, in the map's depth units.
    pub shadow_bias: f32,
    /// One texel of the map, in uv.
    pub shadow_texel: f32,
    /// 1: the penumbra map was drawn this frame.
    pub penumbra_drawn: u32,
    /// The penumbra map's grid size (texels per side).
    pub penumbra_grid: f32,
    /// The shadow map's width at the casters (m).
    pub shadow_width: f32,
    /// The depth step that makes a shadow edge, in the map's depth units.
    pub edge_gap: f32,
}
}

impl FrameUniform {
    /// The frame's uniform for `view`, written as `output` says, with the shadow map of
    /// `shadow` (the penumbra members are the penumbra pass's: off until it sets them).
    pub fn new(view: &FrameView, output: OutputMode, shadow: &ShadowView) -> Self {
        let light = &view.light;
        Self {
            view_proj: view.view_proj.to_cols_array_2d(),
            camera_pos: view.camera_pos.to_array(),
            exposure: output.exposure,
            light_pos: light.position.to_array(),
            light_intensity: light.intensity,
            light_color: light.color.to_array(),
            srgb_encode: flag(output.srgb_encode),
            ambient: light.ambient.to_array(),
            raw_output: flag(output.raw),
            shadow_view_proj: shadow.view_proj.to_cols_array_2d(),
            shadow_drawn: flag(shadow.drawn),
            shadow_normal_offset: shadow.normal_offset_m(),
            shadow_bias: shadow.bias,
            shadow_texel: 1.0 / shadow.size as f32,
            penumbra_drawn: 0,
            penumbra_grid: 0.0,
            shadow_width: shadow.width_m(),
            edge_gap: 0.0,
        }
    }
}

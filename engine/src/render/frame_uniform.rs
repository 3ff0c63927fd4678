//! The per-frame uniform every pass binds at `@group(0) @binding(0)`, filled from the frame:
//! [`FrameUniform`] is declared in `shader/uniforms.rs` (the composer generates its WGSL).

use super::shadow_view::ShadowView;
use crate::scene::FrameView;
pub use crate::shader::uniforms::FrameUniform;

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

impl FrameUniform {
    /// The frame's uniform for `view`, written as `output` says, with the shadow map of
    /// `shadow` (the penumbra members are the penumbra pass's: off until it sets them).
    pub fn new(view: &FrameView, output: OutputMode, shadow: &ShadowView) -> Self {
        let light = &view.light;
        Self {
            view_proj: view.view_proj,
            camera_pos: view.camera_pos.to_array(),
            exposure: output.exposure,
            light_pos: light.position.to_array(),
            light_intensity: light.intensity,
            light_color: light.color.to_array(),
            srgb_encode: flag(output.srgb_encode),
            ambient: light.ambient.to_array(),
            raw_output: flag(output.raw),
            shadow_view_proj: shadow.view_proj,
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

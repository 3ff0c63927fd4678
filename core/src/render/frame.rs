//! The per-frame uniform (`Frame` in `shaders/common.wgsl`).

use glam::{Mat4, Vec3};

use super::shadow_map::ShadowView;

/// Where the key light stands relative to the character's feet: above, in front of and to the
/// right of it (the stage, `rig`, places it; declared here so the frame does not import it).
pub const KEY_LIGHT_OFFSET: Vec3 = Vec3::new(1.5, 3.0, 2.5);

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    /// Radiant intensity (irradiance at 1 m, normal incidence).
    pub intensity: f32,
    pub color: Vec3,
    pub ambient: Vec3,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            // The key light of a character standing at the origin.
            position: KEY_LIGHT_OFFSET,
            intensity: 30.0,
            color: Vec3::new(1.0, 0.97, 0.92),
            ambient: Vec3::new(0.10, 0.11, 0.13),
        }
    }
}

crate::shading::uniform::gpu_struct! {
/// What every pass reads at `@group(0) @binding(0)`: `FrameUniform` in `common.wgsl`, member
/// for member (`core/tests/uniform_layout.rs`).
pub struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub light_pos: [f32; 4],
    pub light_color: [f32; 4],
    pub ambient: [f32; 4],
    /// x: exposure, y: manual sRGB encode flag, z: raw radiance output flag.
    pub output: [f32; 4],
    /// World → the shadow map's clip space.
    pub shadow_view_proj: [[f32; 4]; 4],
    /// x: shadow map drawn (1) or not (0); y: normal offset (m); z: depth bias; w: texel (uv).
    pub shadow: [f32; 4],
    /// x: penumbra map drawn; y: its grid size; z: the shadow map's width (m); w: edge gap.
    pub penumbra: [f32; 4],
}
}

impl FrameUniform {
    /// The frame's uniform: the camera, the light, the output (exposure, manual sRGB encode,
    /// raw radiance) and the shadow map with its penumbra grid (0: none).
    pub fn new(
        view_proj: Mat4,
        camera_pos: Vec3,
        light: &Light,
        (exposure, manual_srgb, raw): (f32, bool, bool),
        (shadow, penumbra_grid): (&ShadowView, u32),
    ) -> Self {
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            camera_pos: camera_pos.extend(1.0).to_array(),
            light_pos: light.position.extend(light.intensity).to_array(),
            light_color: light.color.extend(1.0).to_array(),
            ambient: light.ambient.extend(0.0).to_array(),
            output: [
                exposure,
                f32::from(u8::from(manual_srgb)),
                f32::from(u8::from(raw)),
                0.0,
            ],
            shadow_view_proj: shadow.view_proj.to_cols_array_2d(),
            shadow: shadow.params(),
            penumbra: shadow.penumbra_params(penumbra_grid),
        }
    }
}

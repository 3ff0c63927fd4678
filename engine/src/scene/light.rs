//! The scene's light: a point key light with its colour and the ambient around it.

use glam::Vec3;

use super::stage::KEY_LIGHT_OFFSET;

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

//! The face scenes: the camera that looks at the scanned head ([`crate::asset::head`]) and
//! its three named point lights, in metres in the head's own frame. The path-traced face truth
//! (`dermis_measure::face`) and the renderer's face shots share them.

use glam::Vec3;

/// The face scenes' camera: a three-quarter view from the front-right, so the right ear is
/// seen beside the face (metres, the head's own frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view (degrees).
    pub fov_y_deg: f32,
}

/// The middle of the head (between the ears, at the eyes' height).
pub const HEAD_CENTRE: Vec3 = Vec3::new(0.0, 0.048, 0.012);

pub fn camera() -> Camera {
    let dir = Vec3::new(0.45, 0.08, 0.89).normalize();
    Camera {
        eye: HEAD_CENTRE + dir * 0.75,
        target: HEAD_CENTRE,
        fov_y_deg: 24.0,
    }
}

/// Radiant intensity of the face scenes' point light [W/sr].
pub const LIGHT_INTENSITY: f32 = 1.0;
/// Distance of the face scenes' light from the head's centre [m].
pub const LIGHT_DISTANCE_M: f32 = 0.8;

/// The three lights of the face scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceLight {
    /// From the front, above and left of the camera.
    Front,
    /// From the right, level with the nose: the terminator runs along it.
    Side,
    /// From behind the head, right and a little above: through the right ear.
    Back,
}

impl FaceLight {
    pub const ALL: [FaceLight; 3] = [FaceLight::Front, FaceLight::Side, FaceLight::Back];

    pub fn name(self) -> &'static str {
        match self {
            FaceLight::Front => "front",
            FaceLight::Side => "side",
            FaceLight::Back => "back",
        }
    }

    /// Looks a light up by name.
    pub fn parse(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown face light `{s}` (known: front, side, back)"))
    }

    /// The light's position [m].
    pub fn position(self) -> Vec3 {
        let dir = match self {
            FaceLight::Front => Vec3::new(-0.2, 0.3, 1.0),
            FaceLight::Side => Vec3::new(1.0, 0.05, 0.1),
            FaceLight::Back => Vec3::new(0.35, 0.15, -1.0),
        };
        HEAD_CENTRE + dir.normalize() * LIGHT_DISTANCE_M
    }
}

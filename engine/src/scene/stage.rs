//! The stage every shell and command shares — one of each: the exposure before tone mapping,
//! the key light's place relative to the character, and the character's bound (the height
//! every character is normalised to, and the box, capsule, sphere and chest derived from it
//! that the governor, the culling and the cameras use).

use glam::Vec3;

use super::light::Light;
use crate::camera::Capsule;

/// Exposure before tone mapping (the game, the demo, stills).
pub const EXPOSURE: f32 = 1.6;

/// Where the key light stands relative to the character's feet: above, in front of and to the
/// right of it.
pub const KEY_LIGHT_OFFSET: Vec3 = Vec3::new(1.5, 3.0, 2.5);

/// The key light for a character standing at `feet`.
pub fn key_light(feet: Vec3) -> Light {
    Light {
        position: feet + KEY_LIGHT_OFFSET,
        ..Light::default()
    }
}

/// A character's bound, feet at the origin of its transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CharacterBound {
    /// Standing height (m): stills and the demo normalise any character to it.
    pub height: f32,
    /// Radius of the standing body around its vertical axis (m).
    pub radius: f32,
    /// What poses add around the standing body (arms, hair, a jump's tuck), m.
    pub margin: f32,
    /// Height of the chest (m), where the light's reach is measured.
    pub chest: f32,
}

/// The one character bound.
pub const CHARACTER: CharacterBound = CharacterBound {
    height: 1.75,
    radius: 0.35,
    margin: 0.1,
    chest: 1.3,
};

impl CharacterBound {
    /// The axis-aligned box that holds any pose of a character standing at `feet`.
    pub fn box_at(&self, feet: Vec3) -> (Vec3, Vec3) {
        let r = self.radius + self.margin;
        (
            feet + Vec3::new(-r, 0.0, -r),
            feet + Vec3::new(r, self.height + self.margin, r),
        )
    }

    /// The sphere around [`Self::box_at`]: (centre, radius).
    pub fn sphere_at(&self, feet: Vec3) -> (Vec3, f32) {
        let (lo, hi) = self.box_at(feet);
        ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
    }

    /// The capsule a camera keeps out of, for the character at `feet` drawn at `scale` × this
    /// bound (a character normalised to [`Self::height`]: 1).
    pub fn capsule_at(&self, feet: Vec3, scale: f32) -> Capsule {
        Capsule {
            base: feet,
            height: (self.height + self.margin) * scale,
            radius: (self.radius + self.margin) * scale,
        }
    }

    /// The chest of a character standing at `feet`.
    pub fn chest_at(&self, feet: Vec3) -> Vec3 {
        feet + Vec3::Y * self.chest
    }

    /// The scale that brings a character `raw_height` tall to [`Self::height`].
    pub fn normalising_scale(&self, raw_height: f32) -> f32 {
        self.height / raw_height.max(1e-6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_holds_the_standing_character() {
        let (lo, hi) = CHARACTER.box_at(Vec3::ZERO);
        assert_eq!(
            (lo, hi),
            (Vec3::new(-0.45, 0.0, -0.45), Vec3::new(0.45, 1.85, 0.45))
        );
        let (c, r) = CHARACTER.sphere_at(Vec3::ZERO);
        assert!(c.distance(lo) <= r + 1e-6 && c.distance(hi) <= r + 1e-6);
        assert!(CHARACTER
            .capsule_at(Vec3::ZERO, 1.0)
            .contains(Vec3::Y * 1.7));
        assert_eq!(key_light(Vec3::X).position, Vec3::X + KEY_LIGHT_OFFSET);
    }
}

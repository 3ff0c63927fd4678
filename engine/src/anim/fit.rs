//! A character's size as its file poses it, and the transform that makes any character the
//! runner's height: an exporter's 100× armature (4.6 m) and a 30 cm figure run the same lanes.

use glam::{Mat4, Vec3};

use super::{skin_positions, Pose};
use crate::asset::{Aabb, Model};

/// World-space bounds of every mesh of `model` in its rest (bind-file) pose: skinned meshes as
/// their joints place them, rigid ones by their node's world transform. `None` when there is
/// no finite vertex.
pub fn bind_pose_bounds(model: &Model) -> Option<Aabb> {
    let pose = Pose::new(model);
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let mut seen = vec![false; model.meshes.len()];
    for node in &model.nodes {
        let Some(mesh) = node.mesh else {
            continue;
        };
        match seen.get_mut(mesh) {
            Some(s) if !*s => *s = true,
            _ => continue,
        }
        for p in skin_positions(model, mesh, &pose)
            .into_iter()
            .filter(|p| p.is_finite())
        {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo.x <= hi.x).then_some(Aabb { min: lo, max: hi })
}

/// A uniform scale about the origin, then a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub scale: f32,
    pub translation: Vec3,
}

impl Fit {
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_translation(self.translation) * Mat4::from_scale(Vec3::splat(self.scale))
    }

    /// Where a point of the file lands.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        p * self.scale + self.translation
    }
}

/// The transform that makes a character with bounds `b` `height` tall (its y extent), its
/// feet on y = 0 and its bounds centred on x = z = 0. `None` for a flat or non-finite box or a
/// height that is not positive.
pub fn fit_to_height(b: Aabb, height: f32) -> Option<Fit> {
    let size = b.max - b.min;
    if !(size.is_finite() && size.y > 0.0 && height > 0.0 && height.is_finite()) {
        return None;
    }
    let scale = height / size.y;
    let centre = (b.min + b.max) * 0.5;
    Some(Fit {
        scale,
        translation: Vec3::new(-centre.x * scale, -b.min.y * scale, -centre.z * scale),
    })
}

//! Where a skin's vertices can be once posed: per joint, the box (in bind space) of every
//! vertex that joint moves with any weight. A posed vertex is a weighted mean of its joints'
//! palette matrices applied to it, so it lies in the box around the union of those joints'
//! boxes carried by their palette matrices ([`JointBoxes::posed`]): a bound of the posed
//! mesh, not an estimate, from 8 corners per joint (no vertex is touched per frame).

use glam::{Mat4, Vec3};

use crate::asset::Model;

/// Per joint of one skin, the bind-space box of the vertices it moves (`None`: none).
#[derive(Clone, Debug, Default)]
pub struct JointBoxes {
    boxes: Vec<Option<(Vec3, Vec3)>>,
}

impl JointBoxes {
    /// An empty set for a skin of `joints` joints.
    pub fn new(joints: usize) -> Self {
        Self {
            boxes: vec![None; joints],
        }
    }

    /// Adds the vertices of `mesh` (skinned with this skin) of `model`.
    pub fn add_mesh(&mut self, model: &Model, mesh: usize) {
        let Some(m) = model.meshes.get(mesh) else {
            return;
        };
        for v in m.primitives.iter().flat_map(|p| &p.vertices) {
            let p = Vec3::from(v.position);
            if !p.is_finite() {
                continue;
            }
            for (&j, &w) in v.joints.iter().zip(&v.weights) {
                if let Some(slot) = self.boxes.get_mut(j as usize).filter(|_| w > 0.0) {
                    let (lo, hi) = slot.unwrap_or((p, p));
                    *slot = Some((lo.min(p), hi.max(p)));
                }
            }
        }
    }

    /// The world box of the mesh posed by `palette` (one matrix per joint, the vertex
    /// shader's); `None` where no joint moves a vertex.
    pub fn posed(&self, palette: &[Mat4]) -> Option<(Vec3, Vec3)> {
        let mut out: Option<(Vec3, Vec3)> = None;
        for (b, m) in self.boxes.iter().zip(palette) {
            let Some((lo, hi)) = *b else { continue };
            for k in 0..8 {
                let c = Vec3::select(glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0), hi, lo);
                let p = m.transform_point3(c);
                if !p.is_finite() {
                    continue;
                }
                let (l, h) = out.unwrap_or((p, p));
                out = Some((l.min(p), h.max(p)));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn the_posed_box_holds_every_blended_vertex() {
        // Two joints' boxes, the second rotated and moved; a vertex half on each lies inside.
        let mut jb = JointBoxes::new(2);
        jb.boxes[0] = Some((Vec3::ZERO, Vec3::ONE));
        jb.boxes[1] = Some((Vec3::new(0.5, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0)));
        let a = Mat4::IDENTITY;
        let b =
            Mat4::from_rotation_translation(Quat::from_rotation_z(1.2), Vec3::new(3.0, 0.5, 0.0));
        let (lo, hi) = jb.posed(&[a, b]).unwrap();
        for v in [
            Vec3::new(0.7, 0.9, 0.5),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::splat(0.5),
        ] {
            let p = 0.5 * (a.transform_point3(v) + b.transform_point3(v));
            assert!(
                p.cmpge(lo - 1e-5).all() && p.cmple(hi + 1e-5).all(),
                "{p} ∉ {lo}..{hi}"
            );
        }
        assert!(JointBoxes::new(3).posed(&[a; 3]).is_none());
    }
}

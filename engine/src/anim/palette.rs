//! Joint palettes and CPU skinning (the reference the GPU path and tests compare against).
//!
//! Per the glTF spec the skinned mesh node's own transform does not apply:
//! `world = Σ wᵢ · (jointWorld[jᵢ] · inverseBind[jᵢ]) · v`.

use glam::{Mat4, Vec3};

use super::Pose;
use crate::asset::Model;

/// `out[j] = world(joint j) · inverseBind[j]` for skin `skin`. Entries past the skin's joint
/// count are left untouched; joints past `out.len()` are not written.
pub fn joint_palette(model: &Model, skin: usize, pose: &Pose, out: &mut [Mat4]) {
    let Some(skin) = model.skins.get(skin) else {
        return;
    };
    for ((o, &node), ibm) in out.iter_mut().zip(&skin.joints).zip(&skin.inverse_bind) {
        *o = pose.worlds.get(node).copied().unwrap_or(Mat4::IDENTITY) * *ibm;
    }
}

/// The first node (by index) that has both a mesh and a skin: (node, mesh, skin).
pub fn first_skinned_mesh(model: &Model) -> Option<(usize, usize, usize)> {
    model
        .nodes
        .iter()
        .enumerate()
        .find_map(|(i, n)| Some((i, n.mesh?, n.skin?)))
}

/// World-space positions of every vertex of every primitive of `mesh` (primitive order),
/// skinned with the skin of the first node that uses `mesh`; a rigid mesh gets that node's
/// world transform. Empty when no node uses `mesh`.
pub fn skin_positions(model: &Model, mesh: usize, pose: &Pose) -> Vec<Vec3> {
    let Some(m) = model.meshes.get(mesh) else {
        return Vec::new();
    };
    let Some(node) = model.nodes.iter().position(|n| n.mesh == Some(mesh)) else {
        return Vec::new();
    };
    let count: usize = m.primitives.iter().map(|p| p.vertices.len()).sum();
    let mut out = Vec::with_capacity(count);
    match model.nodes[node]
        .skin
        .and_then(|s| model.skins.get(s).map(|sk| (s, sk)))
    {
        Some((s, skin)) => {
            let mut palette = vec![Mat4::IDENTITY; skin.joints.len()];
            joint_palette(model, s, pose, &mut palette);
            for v in m.primitives.iter().flat_map(|p| &p.vertices) {
                let p = Vec3::from_array(v.position);
                let mut acc = Vec3::ZERO;
                for k in 0..4 {
                    let w = v.weights[k];
                    if w != 0.0 {
                        let j = palette.get(v.joints[k] as usize).unwrap_or(&Mat4::IDENTITY);
                        acc += w * j.transform_point3(p);
                    }
                }
                out.push(acc);
            }
        }
        None => {
            let world = pose.worlds.get(node).copied().unwrap_or(Mat4::IDENTITY);
            out.extend(
                m.primitives
                    .iter()
                    .flat_map(|p| &p.vertices)
                    .map(|v| world.transform_point3(Vec3::from_array(v.position))),
            );
        }
    }
    out
}

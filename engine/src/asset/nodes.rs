//! The node hierarchy (one parent per node, no cycles), node transforms, scene roots and skins.

use glam::{Mat4, Quat, Vec3};
use gltf::accessor::Dimensions;

use super::accessor::{expect_dims, read_f32, Buffers};
use super::{Node, Skin, Transform, MAX_JOINTS};

fn transform(node: &gltf::Node<'_>) -> Result<Transform, String> {
    let i = node.index();
    let t = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if !m.is_finite() {
                return Err(format!("node {i} has a NaN/Inf matrix"));
            }
            let (scale, rotation, translation) = m.to_scale_rotation_translation();
            Transform {
                translation,
                rotation,
                scale,
            }
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => Transform {
            translation: Vec3::from_array(translation),
            rotation: Quat::from_array(rotation),
            scale: Vec3::from_array(scale),
        },
    };
    let ok = t.translation.is_finite() && t.scale.is_finite() && t.rotation.is_finite();
    if !ok {
        return Err(format!("node {i} has a NaN/Inf transform"));
    }
    let len = t.rotation.length();
    if len.is_nan() || len <= 1e-6 {
        return Err(format!("node {i} has a zero-length rotation quaternion"));
    }
    Ok(Transform {
        rotation: t.rotation / len,
        ..t
    })
}

/// Nodes with parents; errors on two parents or cycles.
pub(crate) fn load_nodes(doc: &gltf::Document) -> Result<Vec<Node>, String> {
    let count = doc.nodes().len();
    let mut nodes = Vec::with_capacity(count);
    for node in doc.nodes() {
        let children: Vec<usize> = node.children().map(|c| c.index()).collect();
        nodes.push(Node {
            name: node.name().map(str::to_owned),
            parent: None,
            children,
            local: transform(&node)?,
            mesh: node.mesh().map(|m| m.index()),
            skin: node.skin().map(|s| s.index()),
        });
    }
    for p in 0..count {
        for k in 0..nodes[p].children.len() {
            let c = nodes[p].children[k];
            if c >= count {
                return Err(format!("node {p} has missing child node {c}"));
            }
            if c == p {
                return Err(format!("node cycle: node {p} is its own child"));
            }
            if let Some(other) = nodes[c].parent {
                return Err(format!("node {c} has two parents ({other} and {p})"));
            }
            nodes[c].parent = Some(p);
        }
    }
    // With one parent each, a node unreachable from the parentless nodes lies on a cycle.
    let mut seen = vec![false; count];
    let mut stack: Vec<usize> = (0..count).filter(|&i| nodes[i].parent.is_none()).collect();
    while let Some(i) = stack.pop() {
        seen[i] = true;
        stack.extend(nodes[i].children.iter().copied());
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        return Err(format!("node cycle: node {i} is its own ancestor"));
    }
    Ok(nodes)
}

/// Roots of the default scene (or scene 0), else every parentless node.
pub(crate) fn scene_roots(doc: &gltf::Document, nodes: &[Node]) -> Result<Vec<usize>, String> {
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    match scene {
        Some(s) => {
            let mut roots = Vec::new();
            for n in s.nodes() {
                let i = n.index();
                match nodes.get(i) {
                    None => return Err(format!("scene {} references missing node {i}", s.index())),
                    Some(node) if node.parent.is_some() => {
                        return Err(format!("scene {} root node {i} has a parent", s.index()))
                    }
                    Some(_) => roots.push(i),
                }
            }
            Ok(roots)
        }
        None => Ok((0..nodes.len())
            .filter(|&i| nodes[i].parent.is_none())
            .collect()),
    }
}

pub(crate) fn load_skin(
    buffers: &Buffers<'_>,
    skin: &gltf::Skin<'_>,
    node_count: usize,
) -> Result<Skin, String> {
    let si = skin.index();
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    if joints.is_empty() {
        return Err(format!("skin {si} has no joints"));
    }
    if joints.len() > MAX_JOINTS {
        return Err(format!(
            "skin {si} has {} joints, more than the maximum {MAX_JOINTS}",
            joints.len()
        ));
    }
    if let Some(&j) = joints.iter().find(|&&j| j >= node_count) {
        return Err(format!("skin {si} references missing node {j}"));
    }
    let inverse_bind = match skin.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(acc) => {
            expect_dims(&acc, "inverseBindMatrices", Dimensions::Mat4)?;
            if acc.count() != joints.len() {
                return Err(format!(
                    "skin {si}: inverseBindMatrices has {} matrices for {} joints",
                    acc.count(),
                    joints.len()
                ));
            }
            let raw = read_f32(buffers, &acc, "inverseBindMatrices")?;
            if raw.iter().any(|x| !x.is_finite()) {
                return Err(format!("skin {si}: NaN/Inf in inverseBindMatrices"));
            }
            raw.chunks_exact(16).map(Mat4::from_cols_slice).collect()
        }
    };
    Ok(Skin {
        name: skin.name().map(str::to_owned),
        joints,
        inverse_bind,
    })
}

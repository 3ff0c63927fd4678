//! Mesh primitives: vertex attributes, indices, generated normals/tangents and all per-vertex
//! validation (finite positions, weights, index ranges, matching attribute counts).

use glam::{Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use super::accessor::{expect_dims, read_f32, read_u32, Buffers};
use super::limits::{MAX_TOTAL_INDICES, MAX_TOTAL_VERTICES};
use super::tangents::{generate_tangents, smooth_normals};
use super::{Aabb, Mesh, Primitive, Vertex, DEFAULT_THICKNESS_M};

/// Running totals over the whole model, to cap memory.
#[derive(Default)]
pub(crate) struct Totals {
    pub vertices: usize,
    pub indices: usize,
}

/// What the node/skin validation needs to know about a loaded mesh.
pub(crate) struct MeshInfo {
    /// Largest joint index used by any primitive (`None`: no JOINTS_0 anywhere).
    pub max_joint: Option<u32>,
    /// Whether some primitive lacks JOINTS_0/WEIGHTS_0.
    pub has_rigid_primitive: bool,
}

fn finite3(v: &[f32]) -> bool {
    v.iter().all(|x| x.is_finite())
}

pub(crate) fn load_mesh(
    buffers: &Buffers<'_>,
    mesh: &gltf::Mesh<'_>,
    totals: &mut Totals,
) -> Result<(Mesh, MeshInfo), String> {
    let mut info = MeshInfo {
        max_joint: None,
        has_rigid_primitive: false,
    };
    let mut primitives = Vec::new();
    let mut given = Vec::new();
    for prim in mesh.primitives() {
        let label = format!("mesh {} primitive {}", mesh.index(), prim.index());
        if prim.mode() != Mode::Triangles {
            log::warn!(
                "{label}: mode {:?} is not a triangle list; skipped",
                prim.mode()
            );
            continue;
        }
        let (p, max_joint) = load_primitive(buffers, &prim, &label, totals)?;
        match max_joint {
            Some(j) => info.max_joint = Some(info.max_joint.map_or(j, |m| m.max(j))),
            None => info.has_rigid_primitive = true,
        }
        primitives.push(p);
        given.push(prim.get(&Semantic::Extras("THICKNESS".into())).is_some());
    }
    // Where the file gives no thickness, the mesh's own (ray cast at load); its curvature; the
    // light it returns to itself.
    super::thickness::fill(&mut primitives, &given);
    super::curvature::fill(&mut primitives);
    super::bounce::fill(&mut primitives);
    Ok((
        Mesh {
            name: mesh.name().map(str::to_owned),
            primitives,
        },
        info,
    ))
}

fn load_primitive(
    buffers: &Buffers<'_>,
    prim: &gltf::Primitive<'_>,
    label: &str,
    totals: &mut Totals,
) -> Result<(Primitive, Option<u32>), String> {
    let pos_acc = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| format!("{label} has no POSITION"))?;
    let n = pos_acc.count();
    // Every attribute of a primitive must have the same count.
    for (sem, acc) in prim.attributes() {
        if acc.count() != n {
            return Err(format!(
                "{label}: accessor counts differ: POSITION has {n}, {} has {}",
                sem.to_string(),
                acc.count()
            ));
        }
    }
    totals.vertices = totals.vertices.saturating_add(n);
    if totals.vertices > MAX_TOTAL_VERTICES {
        return Err(format!(
            "too many vertices: above the limit {MAX_TOTAL_VERTICES}"
        ));
    }

    expect_dims(&pos_acc, "POSITION", Dimensions::Vec3)?;
    let raw = read_f32(buffers, &pos_acc, "POSITION")?;
    let mut positions = Vec::with_capacity(n);
    for (i, p) in raw.chunks_exact(3).enumerate() {
        if !finite3(p) {
            return Err(format!("{label}: vertex {i} has a NaN/Inf position"));
        }
        positions.push(Vec3::new(p[0], p[1], p[2]));
    }
    drop(raw);

    // Indices.
    let indices: Vec<u32> = match prim.indices() {
        Some(acc) => {
            expect_dims(&acc, "indices", Dimensions::Scalar)?;
            let idx = read_u32(
                buffers,
                &acc,
                "indices",
                &[DataType::U8, DataType::U16, DataType::U32],
            )?;
            if let Some((k, &i)) = idx.iter().enumerate().find(|(_, &i)| i as usize >= n) {
                return Err(format!("{label}: index {i} (at {k}) ≥ vertex count {n}"));
            }
            idx
        }
        None => (0..n as u32).collect(),
    };
    if !indices.len().is_multiple_of(3) {
        return Err(format!(
            "{label}: index count {} is not a multiple of 3",
            indices.len()
        ));
    }
    totals.indices = totals.indices.saturating_add(indices.len());
    if totals.indices > MAX_TOTAL_INDICES {
        return Err(format!(
            "too many indices: above the limit {MAX_TOTAL_INDICES}"
        ));
    }

    // Normals.
    let normals: Vec<Vec3> = match prim.get(&Semantic::Normals) {
        Some(acc) => {
            expect_dims(&acc, "NORMAL", Dimensions::Vec3)?;
            let raw = read_f32(buffers, &acc, "NORMAL")?;
            let mut out = Vec::with_capacity(n);
            for (i, v) in raw.chunks_exact(3).enumerate() {
                if !finite3(v) {
                    return Err(format!("{label}: vertex {i} has a NaN/Inf normal"));
                }
                out.push(
                    Vec3::new(v[0], v[1], v[2])
                        .try_normalize()
                        .unwrap_or(Vec3::Y),
                );
            }
            out
        }
        None => smooth_normals(&positions, &indices),
    };

    // UVs.
    let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(0)) {
        Some(acc) => {
            expect_dims(&acc, "TEXCOORD_0", Dimensions::Vec2)?;
            let raw = read_f32(buffers, &acc, "TEXCOORD_0")?;
            if !finite3(&raw) {
                return Err(format!("{label}: NaN/Inf in TEXCOORD_0"));
            }
            raw.chunks_exact(2).map(|v| Vec2::new(v[0], v[1])).collect()
        }
        None => vec![Vec2::ZERO; n],
    };

    // Tangents.
    let tangents: Vec<[f32; 4]> = match prim.get(&Semantic::Tangents) {
        Some(acc) => {
            expect_dims(&acc, "TANGENT", Dimensions::Vec4)?;
            let raw = read_f32(buffers, &acc, "TANGENT")?;
            if !finite3(&raw) {
                return Err(format!("{label}: NaN/Inf in TANGENT"));
            }
            raw.chunks_exact(4)
                .map(|t| [t[0], t[1], t[2], if t[3] < 0.0 { -1.0 } else { 1.0 }])
                .collect()
        }
        None => generate_tangents(&positions, &normals, &uvs, &indices),
    };

    // Skinning attributes.
    let joints_acc = prim.get(&Semantic::Joints(0));
    let weights_acc = prim.get(&Semantic::Weights(0));
    if prim.get(&Semantic::Joints(1)).is_some() {
        log::warn!("{label}: JOINTS_1/WEIGHTS_1 ignored (only 4 influences are used)");
    }
    let (joints, weights, max_joint) = match (joints_acc, weights_acc) {
        (None, None) => (vec![[0u16; 4]; n], vec![[1.0, 0.0, 0.0, 0.0]; n], None),
        (Some(_), None) => return Err(format!("{label} has JOINTS_0 but no WEIGHTS_0")),
        (None, Some(_)) => return Err(format!("{label} has WEIGHTS_0 but no JOINTS_0")),
        (Some(ja), Some(wa)) => {
            expect_dims(&ja, "JOINTS_0", Dimensions::Vec4)?;
            expect_dims(&wa, "WEIGHTS_0", Dimensions::Vec4)?;
            let j = read_u32(buffers, &ja, "JOINTS_0", &[DataType::U8, DataType::U16])?;
            if wa.data_type() != DataType::F32 && !wa.normalized() {
                return Err(format!(
                    "accessor {} (WEIGHTS_0) must be float or normalized unsigned byte/short",
                    wa.index()
                ));
            }
            let w = read_f32(buffers, &wa, "WEIGHTS_0")?;
            let mut joints = Vec::with_capacity(n);
            let mut weights = Vec::with_capacity(n);
            let mut max_joint = 0u32;
            for i in 0..n {
                let wv = [w[4 * i], w[4 * i + 1], w[4 * i + 2], w[4 * i + 3]];
                if !finite3(&wv) || wv.iter().any(|&x| x < 0.0) {
                    return Err(format!(
                        "{label}: vertex {i} has NaN/Inf or negative weights"
                    ));
                }
                let sum: f32 = wv.iter().sum();
                if sum <= 0.0 {
                    return Err(format!("{label}: vertex {i} has zero-sum weights"));
                }
                let jv = [j[4 * i], j[4 * i + 1], j[4 * i + 2], j[4 * i + 3]];
                max_joint = jv.iter().fold(max_joint, |m, &x| m.max(x));
                // Both types are at most u16, so the casts are exact.
                joints.push(jv.map(|x| x as u16));
                weights.push(wv.map(|x| x / sum));
            }
            (joints, weights, Some(max_joint))
        }
    };

    // Thickness (custom attribute, metres).
    let thickness: Vec<f32> = match prim.get(&Semantic::Extras("THICKNESS".into())) {
        Some(acc) => {
            expect_dims(&acc, "_THICKNESS", Dimensions::Scalar)?;
            if acc.data_type() != DataType::F32 {
                return Err(format!(
                    "accessor {} (_THICKNESS) must be float",
                    acc.index()
                ));
            }
            let t = read_f32(buffers, &acc, "_THICKNESS")?;
            if let Some(i) = t.iter().position(|x| !x.is_finite() || *x < 0.0) {
                return Err(format!(
                    "{label}: vertex {i} has a NaN/Inf or negative _THICKNESS"
                ));
            }
            t
        }
        None => vec![DEFAULT_THICKNESS_M; n],
    };

    let mut bounds = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    let mut vertices = Vec::with_capacity(n);
    for i in 0..n {
        bounds.min = bounds.min.min(positions[i]);
        bounds.max = bounds.max.max(positions[i]);
        vertices.push(Vertex {
            position: positions[i].to_array(),
            normal: normals[i].to_array(),
            tangent: tangents[i],
            uv: uvs[i].to_array(),
            joints: joints[i],
            weights: weights[i],
            thickness: thickness[i],
            curvature: [0.0; 4],
            bounce: [0.0; 4],
        });
    }
    if n == 0 {
        bounds = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        };
    }
    let material = prim.material().index();
    Ok((
        Primitive {
            vertices,
            indices,
            material,
            bounds,
        },
        max_joint,
    ))
}

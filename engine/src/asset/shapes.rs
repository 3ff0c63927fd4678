//! Procedural skinned shapes (one joint, identity bind), drawn through the character
//! pipeline like a loaded character: a flat plane and a UV sphere. The measurement scenes
//! (`dermis-measure`'s `scenes`) render them, and tests use them as a light stand-in for a
//! glTF character.

use glam::{Mat4, Vec3};

use super::{Aabb, Material, Mesh, Model, Node, Primitive, Skin, Transform, Vertex};

/// A vertex with its thickness (m) and curvature (1/m, the same every way: `asset::curvature`).
fn vertex(position: Vec3, normal: Vec3, thickness_m: f32, curvature: f32) -> Vertex {
    let t = if normal.x.abs() > 0.9 {
        Vec3::Z
    } else {
        Vec3::X
    };
    let tangent = (t - normal * normal.dot(t)).normalize();
    Vertex {
        position: position.to_array(),
        normal: normal.to_array(),
        tangent: tangent.extend(1.0).to_array(),
        uv: [0.0, 0.0],
        joints: [0; 4],
        weights: [1.0, 0.0, 0.0, 0.0],
        thickness: thickness_m,
        curvature: [0.0, 0.0, 0.0, curvature],
        bounce: [0.0; 4],
    }
}

fn skinned_model(name: &str, vertices: Vec<Vertex>, indices: Vec<u32>, half: f32) -> Model {
    let node = |mesh, skin, parent| Node {
        name: None,
        parent,
        children: Vec::new(),
        local: Transform::default(),
        mesh,
        skin,
    };
    Model {
        source: name.into(),
        nodes: vec![node(None, None, None), node(Some(0), Some(0), None)],
        roots: vec![0, 1],
        meshes: vec![Mesh {
            name: None,
            primitives: vec![Primitive {
                vertices,
                indices,
                material: Some(0),
                bounds: Aabb {
                    min: Vec3::splat(-half),
                    max: Vec3::splat(half),
                },
            }],
        }],
        skins: vec![Skin {
            name: None,
            joints: vec![0],
            inverse_bind: vec![Mat4::IDENTITY],
        }],
        // Named for the name rule (`asset::skin`): these shapes are the skin models' subjects.
        materials: vec![Material {
            name: Some("skin".into()),
            metallic_factor: 0.0,
            ..Material::default()
        }],
        textures: Vec::new(),
        animations: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Two triangles per cell of a (cols + 1) × (rows + 1) vertex grid, row-major.
fn grid_indices(cols: u32, rows: u32) -> Vec<u32> {
    let mut indices = Vec::with_capacity((cols * rows * 6) as usize);
    for j in 0..rows {
        for i in 0..cols {
            let a = j * (cols + 1) + i;
            let (b, c, d) = (a + 1, a + cols + 1, a + cols + 2);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    indices
}

/// A plane of half-size `half_m` metres in x–z, facing +y, skinned to one joint.
pub fn plane_model(half_m: f32, thickness_m: f32) -> Model {
    let n = 32u32;
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let p = Vec3::new((u * 2.0 - 1.0) * half_m, 0.0, (v * 2.0 - 1.0) * half_m);
            vertices.push(vertex(p, Vec3::Y, thickness_m, 0.0));
        }
    }
    skinned_model("flat medium", vertices, grid_indices(n, n), half_m)
}

/// A UV sphere of radius `r_m` metres at the origin.
pub fn sphere_model(r_m: f32, thickness_m: f32) -> Model {
    let (rings, segments) = (96u32, 192u32);
    let mut vertices = Vec::new();
    for j in 0..=rings {
        let theta = std::f32::consts::PI * j as f32 / rings as f32;
        for i in 0..=segments {
            let phi = std::f32::consts::TAU * i as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            vertices.push(vertex(n * r_m, n, thickness_m, 1.0 / r_m));
        }
    }
    skinned_model("sphere", vertices, grid_indices(segments, rings), r_m)
}

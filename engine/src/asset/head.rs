//! The scanned head (CC BY 3.0, [`ATTRIBUTION`]) loaded into metres (a real head's size) as a
//! one-joint skinned model with its albedo and normal maps. The face scenes' camera and lights
//! are `scene::face`; drawing it for measurement is `dermis_measure::face::render`.
//!
//! The file is Lee Perry-Smith's head scan (`assets/head/`, CC BY 3.0): a bust in model units,
//! +y up, the face toward +z, 8.55 units across the shoulders and 3.8 across the ears. At
//! [`METRES_PER_UNIT`] the head is 15.2 cm across the ears and ~21 cm from chin to crown.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};

use crate::asset::compressed::{encoded_texture, sidecar_path};
use crate::asset::tangents::generate_tangents;
use crate::asset::{
    dir_reader, load_gltf_slice, Aabb, AssetError, Model, Node, Skin, TextureImage, TextureRole,
    Transform,
};

/// The head's folder under the assets root.
pub const DIR: &str = "head";
/// The mesh (Blender's glTF export, no textures bound).
pub const MESH_FILE: &str = "LeePerrySmith.glb";
/// The albedo (sRGB JPEG, 1024²) on TEXCOORD_0.
pub const ALBEDO_FILE: &str = "Map-COL.jpg";
/// The tangent-space normal map (linear JPEG, 1024², +y up: the OpenGL convention) on
/// TEXCOORD_0: the scan's pores and wrinkles the mesh does not carry.
pub const NORMAL_FILE: &str = "Infinite-Level_02_Tangent_SmoothUV.jpg";
/// Metres per model unit: 3.8 units across the ears → 15.2 cm.
pub const METRES_PER_UNIT: f32 = 0.04;
/// The credit the licence asks for wherever the head is shown or shipped.
pub const ATTRIBUTION: &str = "Head: \"Infinite, 3D Head Scan\" by Lee Perry-Smith / \
Infinite-Realities (ir-ltd.net), based on a work at triplegangers.com, CC BY 3.0";
/// The same credit in two short lines, for a screen that shows the head (the showroom).
pub const CREDIT_LINES: [&str; 2] = [
    "Head scan: Lee Perry-Smith / Infinite-Realities (ir-ltd.net)",
    "based on a work at triplegangers.com, CC BY 3.0",
];

/// The head's maps (files in [`DIR`]) in the roles the head's material reads them: what
/// [`load_from`] loads and `cargo xtask assets` encodes.
pub const MAPS: [(&str, TextureRole); 2] = [
    (ALBEDO_FILE, TextureRole::Colour),
    (NORMAL_FILE, TextureRole::Data),
];

/// Which of the head's maps [`load_with`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Maps {
    /// The albedo map as the base colour (all skin); else white (the homogeneous medium the
    /// path tracer renders).
    pub albedo: bool,
    /// The tangent-space normal map.
    pub normal: bool,
}

/// Loads the head in metres as a one-joint skinned model with its normal map; with
/// `textured`, its albedo map is the base colour (all skin), else the base colour is white
/// (the homogeneous medium the path tracer renders).
pub fn load(assets_dir: &Path, textured: bool) -> Result<Model, AssetError> {
    load_with(
        assets_dir,
        Maps {
            albedo: textured,
            normal: true,
        },
    )
}

/// The files of the head a build ships, relative to the assets root: the mesh, each map's
/// source image and the licence (its block encodings are beside each map, see
/// [`sidecar_path`]).
pub fn files() -> [String; 4] {
    [MESH_FILE, ALBEDO_FILE, NORMAL_FILE, LICENCE_FILE].map(|f| format!("{DIR}/{f}"))
}

/// The licence text that travels with the head.
pub const LICENCE_FILE: &str = "LeePerrySmith_License.txt";

/// One of the head's maps for `role`: its block encodings (`<map>.textures/<role>.<family>.ktx2`,
/// made by `cargo xtask assets`) where usable, else the JPEG decoded. Where the JPEG is not
/// there (the APK carries the encodings only) the encodings are all there is.
fn read_map(
    read: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    file: &str,
    role: TextureRole,
) -> Result<TextureImage, AssetError> {
    let path = format!("{DIR}/{file}");
    let source = read(&path).unwrap_or_default();
    let sidecar = |family| sidecar_path(&path, None, role, family);
    encoded_texture(&source, role, &sidecar, read, &path).map_err(|e| AssetError::new(&path, e))
}

/// Loads the head in metres from `assets_dir` (see [`load_from`]).
pub fn load_with(assets_dir: &Path, maps: Maps) -> Result<Model, AssetError> {
    load_from(&dir_reader(assets_dir), maps)
}

/// Loads the head in metres as a one-joint skinned model with the maps `maps` asks for,
/// reading its files through `read` (a path relative to the assets root to the file's bytes:
/// the file system, or the Android app's asset manager).
///
/// The file's UVs have v up (v = 0 at the images' bottom row, as the three.js example that
/// ships it samples them); the engine samples v down, so v is flipped here and the tangents
/// are generated again for the flipped UVs.
pub fn load_from(
    read: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    maps: Maps,
) -> Result<Model, AssetError> {
    let mesh_path = format!("{DIR}/{MESH_FILE}");
    let bytes = read(&mesh_path).map_err(|e| AssetError::new(&mesh_path, e))?;
    let resolve = |uri: &str| read(&format!("{DIR}/{uri}"));
    let file = load_gltf_slice(&bytes, &mesh_path, &resolve)?;
    let source = file.source.clone();
    let mut primitive = file
        .meshes
        .first()
        .and_then(|m| m.primitives.first())
        .cloned()
        .ok_or_else(|| AssetError::new(&source, "no mesh".to_string()))?;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for v in &mut primitive.vertices {
        let p = Vec3::from_array(v.position) * METRES_PER_UNIT;
        v.position = p.to_array();
        // Thickness (cast at load: the file gives none) and curvature in the file's units.
        v.thickness *= METRES_PER_UNIT;
        let a = METRES_PER_UNIT.sqrt();
        v.curvature = [
            v.curvature[0] / a,
            v.curvature[1] / a,
            v.curvature[2] / a,
            v.curvature[3] / METRES_PER_UNIT,
        ];
        v.uv[1] = 1.0 - v.uv[1];
        v.joints = [0; 4];
        v.weights = [1.0, 0.0, 0.0, 0.0];
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let vs = &primitive.vertices;
    let positions: Vec<Vec3> = vs.iter().map(|v| Vec3::from_array(v.position)).collect();
    let normals: Vec<Vec3> = vs.iter().map(|v| Vec3::from_array(v.normal)).collect();
    let uvs: Vec<Vec2> = vs.iter().map(|v| Vec2::from_array(v.uv)).collect();
    let tangents = generate_tangents(&positions, &normals, &uvs, &primitive.indices);
    for (v, t) in primitive.vertices.iter_mut().zip(tangents) {
        v.tangent = t;
    }
    primitive.bounds = Aabb { min: lo, max: hi };
    primitive.material = Some(0);
    let mut textures = Vec::new();
    let [(albedo, colour), (normal, data)] = MAPS;
    if maps.albedo {
        textures.push(read_map(read, albedo, colour)?);
    }
    if maps.normal {
        textures.push(read_map(read, normal, data)?);
    }
    let node = |mesh, skin| Node {
        name: None,
        parent: None,
        children: Vec::new(),
        local: Transform::default(),
        mesh,
        skin,
    };
    Ok(Model {
        source,
        nodes: vec![node(None, None), node(Some(0), Some(0))],
        roots: vec![0, 1],
        meshes: vec![crate::asset::Mesh {
            name: Some("head".into()),
            primitives: vec![primitive],
        }],
        skins: vec![Skin {
            name: None,
            joints: vec![0],
            inverse_bind: vec![Mat4::IDENTITY],
        }],
        materials: vec![crate::asset::Material {
            name: Some("skin".into()),
            base_color_texture: maps.albedo.then_some(0),
            metallic_factor: 0.0,
            normal_texture: maps.normal.then(|| textures.len() - 1),
            ..crate::asset::Material::default()
        }],
        textures,
        animations: Vec::new(),
        warnings: Vec::new(),
    })
}

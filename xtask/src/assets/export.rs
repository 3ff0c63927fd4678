//! glTF documents for the skinned character and for static props.

use super::clips::Clip;
use super::glb_writer::{GlbBuilder, ARRAY_BUFFER};
use super::humanoid::Character;
use super::mesh::Mesh;
use super::outfit::{self, Mat};
use super::skeleton::{inverse_bind, local_translation};
use glam::Vec3;
use serde_json::{json, Value};

const GENERATOR: &str = "dermis xtask assets (procedural)";
const LINEAR: u32 = 9729;
const LINEAR_MIPMAP_LINEAR: u32 = 9987;
const REPEAT: u32 = 10497;
const CLAMP_TO_EDGE: u32 = 33071;

fn flat3(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Writes the common vertex streams and returns the attribute map.
fn mesh_attributes(b: &mut GlbBuilder, m: &Mesh) -> (Value, usize) {
    let pos = b.floats(&flat3(&m.positions), 3, "VEC3", Some(ARRAY_BUFFER), true);
    let nrm = b.floats(&flat3(&m.normals), 3, "VEC3", Some(ARRAY_BUFFER), false);
    let tan: Vec<f32> = m.tangents.iter().flat_map(|t| t.to_array()).collect();
    let tan = b.floats(&tan, 4, "VEC4", Some(ARRAY_BUFFER), false);
    let uv: Vec<f32> = m.uvs.iter().flat_map(|t| t.to_array()).collect();
    let uv = b.floats(&uv, 2, "VEC2", Some(ARRAY_BUFFER), false);
    let idx = b.indices(&m.indices);
    (
        json!({ "POSITION": pos, "NORMAL": nrm, "TANGENT": tan, "TEXCOORD_0": uv }),
        idx,
    )
}

fn material_json(name: &str, image_view: usize, roughness: f32, wrap: u32) -> Value {
    json!({
        "materials": [{
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorTexture": { "index": 0 },
                "metallicFactor": 0.0,
                "roughnessFactor": roughness as f64,
            },
        }],
        "textures": [{ "sampler": 0, "source": 0 }],
        "samplers": [{ "magFilter": LINEAR, "minFilter": LINEAR_MIPMAP_LINEAR, "wrapS": wrap, "wrapT": wrap }],
        "images": [{ "bufferView": image_view, "mimeType": "image/png", "name": format!("{name}_base_color") }],
    })
}

fn merge(doc: &mut Value, extra: Value) {
    if let (Value::Object(d), Value::Object(e)) = (doc, extra) {
        for (k, v) in e {
            d.insert(k, v);
        }
    }
}

/// The skinned character: one primitive per material (`outfit`), every material's base
/// colour from the one atlas `png`, the skin's multi-scatter colour `skin_factor` × the atlas.
pub fn character_glb(c: &Character, clips: &[Clip], png: &[u8], skin_factor: [f64; 3]) -> Vec<u8> {
    let mut b = GlbBuilder::new();
    let mut primitives = Vec::new();
    for p in c.primitives() {
        let (mut attrs, idx) = mesh_attributes(&mut b, &p.mesh);
        attrs["JOINTS_0"] = json!(b.joints_u8(&p.joints));
        let w: Vec<f32> = p.weights.iter().flatten().copied().collect();
        attrs["WEIGHTS_0"] = json!(b.floats(&w, 4, "VEC4", Some(ARRAY_BUFFER), false));
        attrs["_THICKNESS"] = json!(b.floats(&p.thickness, 1, "SCALAR", Some(ARRAY_BUFFER), true));
        let material = Mat::ALL.iter().position(|&m| m == p.material).unwrap_or(0);
        primitives
            .push(json!({ "attributes": attrs, "indices": idx, "material": material, "mode": 4 }));
    }
    let sk = &c.skeleton;
    let ibm: Vec<f32> = (0..sk.len())
        .flat_map(|i| inverse_bind(sk, i).to_cols_array())
        .collect();
    let ibm = b.floats(&ibm, 16, "MAT4", None, false);
    let image_view = b.view(png, None);

    // Node 0: the skinned mesh; nodes 1..: joints in skeleton order.
    let mut nodes = vec![json!({ "name": "character", "mesh": 0, "skin": 0 })];
    for (i, j) in sk.iter().enumerate() {
        let mut n = json!({ "name": j.name, "translation": local_translation(sk, i).to_array().map(|x| x as f64) });
        let children: Vec<usize> = (0..sk.len())
            .filter(|&k| sk[k].parent == Some(i))
            .map(|k| k + 1)
            .collect();
        if !children.is_empty() {
            n["children"] = json!(children);
        }
        nodes.push(n);
    }
    let mut animations = Vec::new();
    for clip in clips {
        let input = b.floats(&clip.times, 1, "SCALAR", None, true);
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        let hips: Vec<f32> = clip.poses.iter().flat_map(|p| p.hips.to_array()).collect();
        let out = b.floats(&hips, 3, "VEC3", None, false);
        samplers.push(json!({ "input": input, "output": out, "interpolation": "LINEAR" }));
        channels.push(json!({ "sampler": 0, "target": { "node": 1, "path": "translation" } }));
        for j in 0..sk.len() {
            let rot: Vec<f32> = clip
                .poses
                .iter()
                .flat_map(|p| p.rot[j].to_array())
                .collect();
            let out = b.floats(&rot, 4, "VEC4", None, false);
            channels.push(json!({ "sampler": samplers.len(), "target": { "node": j + 1, "path": "rotation" } }));
            samplers.push(json!({ "input": input, "output": out, "interpolation": "LINEAR" }));
        }
        animations.push(json!({ "name": clip.name, "samplers": samplers, "channels": channels }));
    }
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": GENERATOR, "copyright": "dermis contributors, CC0-1.0" },
        "scene": 0,
        "scenes": [{ "name": "character", "nodes": [0, 1] }],
        "nodes": nodes,
        "meshes": [{ "name": "body", "primitives": primitives }],
        "skins": [{ "name": "skeleton", "inverseBindMatrices": ibm, "joints": (1..=sk.len()).collect::<Vec<_>>(), "skeleton": 1 }],
        "animations": animations,
    });
    doc["materials"] = Value::Array(
        Mat::ALL
            .iter()
            .map(|&m| outfit::material_json(m, 0, skin_factor))
            .collect(),
    );
    doc["extensionsUsed"] = json!(outfit::EXTENSIONS_USED);
    doc["textures"] = json!([{ "sampler": 0, "source": 0 }]);
    doc["samplers"] = json!([{ "magFilter": LINEAR, "minFilter": LINEAR_MIPMAP_LINEAR, "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE }]);
    doc["images"] = json!([{ "bufferView": image_view, "mimeType": "image/png", "name": "character_base_color" }]);
    b.finish(doc)
}

pub fn static_glb(name: &str, m: &Mesh, png: &[u8], roughness: f32) -> Vec<u8> {
    let mut b = GlbBuilder::new();
    let (attrs, idx) = mesh_attributes(&mut b, m);
    let image_view = b.view(png, None);
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": GENERATOR, "copyright": "dermis contributors, CC0-1.0" },
        "scene": 0,
        "scenes": [{ "name": name, "nodes": [0] }],
        "nodes": [{ "name": name, "mesh": 0 }],
        "meshes": [{ "name": name, "primitives": [{ "attributes": attrs, "indices": idx, "material": 0, "mode": 4 }] }],
    });
    merge(&mut doc, material_json(name, image_view, roughness, REPEAT));
    b.finish(doc)
}

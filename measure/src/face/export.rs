//! The face scenes as an outside path tracer reads them (`tools/mitsuba/render.py`): the head
//! as a welded, closed triangle mesh in metres (binary PLY with vertex normals) and a JSON file
//! with the camera, the lights, the image size and the material's coefficients in mm⁻¹.
//!
//! The scanned mesh splits vertices along UV seams; welding them (equal positions within
//! [`WELD_M`]) makes it closed and 2-manifold, so it bounds a medium.

use std::collections::HashMap;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use dermis_engine::asset::head;
use dermis_engine::asset::Model;
use dermis_engine::scene::face::{self, Camera, FaceLight};
use dermis_engine::shading::Material;

/// Positions closer than this are one vertex [m].
pub const WELD_M: f32 = 1e-5 * head::METRES_PER_UNIT;

/// A welded triangle mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct WeldedMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl WeldedMesh {
    /// Welds the first primitive of `model` (positions as loaded: metres).
    pub fn from_model(model: &Model) -> Result<Self, String> {
        let prim = model
            .meshes
            .first()
            .and_then(|m| m.primitives.first())
            .ok_or_else(|| format!("{}: no mesh", model.source))?;
        let key = |p: Vec3| {
            let q = (p / WELD_M).round();
            (q.x as i64, q.y as i64, q.z as i64)
        };
        let mut index = HashMap::new();
        let mut positions = Vec::new();
        let mut normal_sums: Vec<Vec3> = Vec::new();
        let mut remap = Vec::with_capacity(prim.vertices.len());
        for v in &prim.vertices {
            let p = Vec3::from_array(v.position);
            let i = *index.entry(key(p)).or_insert_with(|| {
                positions.push(p);
                normal_sums.push(Vec3::ZERO);
                positions.len() as u32 - 1
            });
            normal_sums[i as usize] += Vec3::from_array(v.normal);
            remap.push(i);
        }
        let triangles = prim
            .indices
            .chunks_exact(3)
            .map(|t| {
                [
                    remap[t[0] as usize],
                    remap[t[1] as usize],
                    remap[t[2] as usize],
                ]
            })
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        Ok(Self {
            positions,
            normals: normal_sums
                .into_iter()
                .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
                .collect(),
            triangles,
        })
    }

    /// Edges used by one triangle only, and by more than two (0 and 0: closed, manifold).
    pub fn open_and_nonmanifold_edges(&self) -> (usize, usize) {
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let open = count.values().filter(|&&c| c == 1).count();
        let multi = count.values().filter(|&&c| c > 2).count();
        (open, multi)
    }

    /// Enclosed volume [m³] (positive: triangles wound counter-clockwise seen from outside).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Binary little-endian PLY: float x y z nx ny nz, uchar-count int vertex_indices.
    pub fn to_ply(&self) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat binary_little_endian 1.0\ncomment dermis face scene: {} (metres)\n\
             element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\nproperty list uchar int vertex_indices\nend_header\n",
            head::ATTRIBUTION,
            self.positions.len(),
            self.triangles.len()
        )
        .into_bytes();
        for (p, n) in self.positions.iter().zip(&self.normals) {
            for x in p.to_array().into_iter().chain(n.to_array()) {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        for t in &self.triangles {
            out.push(3);
            for i in t {
                out.extend_from_slice(&(*i as i32).to_le_bytes());
            }
        }
        out
    }

    /// Reads back what [`Self::to_ply`] writes.
    pub fn from_ply(bytes: &[u8]) -> Result<Self, String> {
        let end = b"end_header\n";
        let at = bytes
            .windows(end.len())
            .position(|w| w == end)
            .ok_or("PLY: no end_header")?;
        let header = std::str::from_utf8(&bytes[..at]).map_err(|e| format!("PLY: {e}"))?;
        let count = |what: &str| -> Result<usize, String> {
            header
                .lines()
                .find_map(|l| l.strip_prefix(what))
                .and_then(|n| n.trim().parse().ok())
                .ok_or(format!("PLY: no `{what}` count"))
        };
        let (nv, nf) = (count("element vertex")?, count("element face")?);
        let mut body = &bytes[at + end.len()..];
        if body.len() != nv * 24 + nf * 13 {
            return Err(format!(
                "PLY: {} body bytes for {nv} vertices and {nf} faces",
                body.len()
            ));
        }
        let mut f32s = |n: usize| -> Vec<f32> {
            let v = body[..4 * n]
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect();
            body = &body[4 * n..];
            v
        };
        let mut positions = Vec::with_capacity(nv);
        let mut normals = Vec::with_capacity(nv);
        for _ in 0..nv {
            let v = f32s(6);
            positions.push(Vec3::new(v[0], v[1], v[2]));
            normals.push(Vec3::new(v[3], v[4], v[5]));
        }
        let mut triangles = Vec::with_capacity(nf);
        for f in body.chunks_exact(13) {
            if f[0] != 3 {
                return Err("PLY: a face is not a triangle".into());
            }
            let i = |k: usize| i32::from_le_bytes([f[k], f[k + 1], f[k + 2], f[k + 3]]);
            let t = [i(1), i(5), i(9)];
            if t.iter().any(|&i| i < 0 || i as usize >= nv) {
                return Err("PLY: vertex index out of range".into());
            }
            triangles.push(t.map(|i| i as u32));
        }
        Ok(Self {
            positions,
            normals,
            triangles,
        })
    }
}

/// The material as the path tracer needs it (mm⁻¹; the mesh is in metres, so the tracer
/// scales σ by 1000).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MediumJson {
    pub name: String,
    pub sigma_a_per_mm: [f64; 3],
    /// Scattering coefficient σ_s = σ'_s / (1 − g).
    pub sigma_s_per_mm: [f64; 3],
    pub g: f64,
    pub eta: f64,
}

impl MediumJson {
    pub fn from_material(m: &Material) -> Self {
        Self {
            name: m.name.to_string(),
            sigma_a_per_mm: m.sigma_a,
            sigma_s_per_mm: m.sigma_s_prime.map(|s| s / (1.0 - m.g)),
            g: m.g,
            eta: m.eta,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightJson {
    pub name: String,
    /// Point light position [m].
    pub position: [f32; 3],
    /// Radiant intensity [W/sr], white.
    pub intensity: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraJson {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    pub fov_y_deg: f32,
    pub width: u32,
    pub height: u32,
}

/// Everything but the mesh: `scene.json` beside `head.ply`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneJson {
    pub attribution: String,
    /// The mesh file beside this one, in metres.
    pub mesh: String,
    pub metres_per_model_unit: f32,
    pub camera: CameraJson,
    pub lights: Vec<LightJson>,
    pub medium: MediumJson,
}

/// The reference image size (pixels per side).
pub const REFERENCE_PIXELS: u32 = 128;
/// The mesh file's name.
pub const MESH_FILE: &str = "head.ply";

impl SceneJson {
    pub fn new(material: &Material, camera: &Camera) -> Self {
        Self {
            attribution: head::ATTRIBUTION.into(),
            mesh: MESH_FILE.into(),
            metres_per_model_unit: head::METRES_PER_UNIT,
            camera: CameraJson {
                eye: camera.eye.to_array(),
                target: camera.target.to_array(),
                up: [0.0, 1.0, 0.0],
                fov_y_deg: camera.fov_y_deg,
                width: REFERENCE_PIXELS,
                height: REFERENCE_PIXELS,
            },
            lights: FaceLight::ALL
                .iter()
                .map(|l| LightJson {
                    name: l.name().into(),
                    position: l.position().to_array(),
                    intensity: face::LIGHT_INTENSITY,
                })
                .collect(),
            medium: MediumJson::from_material(material),
        }
    }

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

/// Writes `head.ply` and `scene.json` for `material` into `dir`.
pub fn write(dir: &std::path::Path, model: &Model, material: &Material) -> Result<(), String> {
    let mesh = WeldedMesh::from_model(model)?;
    let (open, multi) = mesh.open_and_nonmanifold_edges();
    if open + multi > 0 {
        return Err(format!(
            "{}: not closed after welding ({open} open, {multi} non-manifold edges)",
            model.source
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))
    };
    write(MESH_FILE, &mesh.to_ply())?;
    write(
        "scene.json",
        SceneJson::new(material, &face::camera())
            .to_json()
            .as_bytes(),
    )
}

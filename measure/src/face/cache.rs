//! The cached path-traced references of the face scenes (`tools/mitsuba/face/`): what
//! `tools/mitsuba/render.py` wrote, checked against the scene files it was made from.
//!
//! Per light: two seeds of the head's full radiance (`<light>-seed<k>.pfm`) and the boundary's
//! reflection alone (`<light>-specular.pfm`); `alpha.pfm`, the head's coverage; `cache.json`,
//! how they were made (Mitsuba version, samples, times) and the FNV-1a hashes of `scene.json`
//! and `head.ply`. The shading models render subsurface light only (the probes' references
//! exclude the specular reflection too), so the reference is the full radiance minus the
//! reflection.

use std::path::Path;

use serde::Deserialize;

use super::export::{SceneJson, MESH_FILE};
use super::score::{Reference, BLOCK};
use dermis_core::face::head::FaceLight;
use dermis_core::face::pfm::FloatImage;

/// FNV-1a, 64 bits: the file hash `render.py` records (the same in Python, no dependency);
/// the engine's (the texture encodings' source hash).
pub use dermis_core::asset::compressed::fnv1a64;

/// One light's record in `cache.json`.
#[derive(Clone, Debug, Deserialize)]
pub struct RenderRecord {
    pub seed1_s: f64,
    pub seed2_s: f64,
    pub specular_s: f64,
}

/// `cache.json`.
#[derive(Clone, Debug, Deserialize)]
pub struct CacheJson {
    pub mitsuba: String,
    pub variant: String,
    pub integrator: String,
    pub boundary: String,
    pub spp: u32,
    pub spp_specular: u32,
    pub seeds: Vec<u64>,
    pub scene_fnv1a64: String,
    pub mesh_fnv1a64: String,
    pub renders: std::collections::BTreeMap<String, RenderRecord>,
}

/// The cache, loaded and checked.
pub struct Cache {
    pub record: CacheJson,
    pub scene: SceneJson,
    /// Per light in [`FaceLight::ALL`] order: the reference (subsurface radiance).
    pub references: Vec<(FaceLight, Reference)>,
}

impl Cache {
    /// Loads `dir`'s cache; fails when a file is missing or the scene files are not the ones
    /// the images were rendered from.
    pub fn load(dir: &Path) -> Result<Self, String> {
        let read = |name: &str| {
            let p = dir.join(name);
            std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))
        };
        let record: CacheJson = serde_json::from_slice(&read("cache.json")?)
            .map_err(|e| format!("{}: {e}", dir.join("cache.json").display()))?;
        let scene_bytes = read("scene.json")?;
        let scene: SceneJson = serde_json::from_slice(&scene_bytes)
            .map_err(|e| format!("{}: {e}", dir.join("scene.json").display()))?;
        let check = |name: &str, bytes: &[u8], want: &str| {
            let got = format!("{:016x}", fnv1a64(bytes));
            if got == want {
                Ok(())
            } else {
                Err(format!(
                    "{}: hash {got} is not the rendered scene's {want}: re-render \
                     (tools/mitsuba/render.py)",
                    dir.join(name).display()
                ))
            }
        };
        check("scene.json", &scene_bytes, &record.scene_fnv1a64)?;
        check(MESH_FILE, &read(MESH_FILE)?, &record.mesh_fnv1a64)?;
        let image = |name: &str| FloatImage::load(&dir.join(name));
        let alpha: Vec<f32> = image("alpha.pfm")?.pixels.iter().map(|p| p[0]).collect();
        let mut references = Vec::new();
        for light in FaceLight::ALL {
            let n = light.name();
            if !record.renders.contains_key(n) {
                return Err(format!("{}: no `{n}` render", dir.display()));
            }
            let spec = image(&format!("{n}-specular.pfm"))?;
            let sub = |img: FloatImage| -> Result<FloatImage, String> {
                if img.pixels.len() != spec.pixels.len() {
                    return Err(format!("{n}: seed and specular images differ in size"));
                }
                let pixels = img
                    .pixels
                    .iter()
                    .zip(&spec.pixels)
                    .map(|(p, s)| std::array::from_fn(|c| p[c] - s[c]))
                    .collect();
                FloatImage::new(img.width, img.height, pixels)
            };
            let a = sub(image(&format!("{n}-seed1.pfm"))?)?;
            let b = sub(image(&format!("{n}-seed2.pfm"))?)?;
            references.push((light, Reference::from_seeds(&a, &b, &alpha, BLOCK)?));
        }
        Ok(Self {
            record,
            scene,
            references,
        })
    }
}

//! The cached face truth (`tools/reference/face/`): what `dermis reference --scene head`
//! wrote, checked against the scene it is asked for.
//!
//! - `truth.json`: per light, its [`LightRecord`] (position, intensity, photons, seed, times,
//!   energy bookkeeping, and the [`FaceScene::hash`] of the scene it was computed for);
//! - `<light>.pfm`: linear radiance [W m⁻² sr⁻¹], `<light>-se.pfm`: its standard error per
//!   pixel; `alpha.pfm`: the head's coverage per pixel.
//!
//! A light whose recorded hash is not the scene's (another mesh, material, camera, image size,
//! light position or method) is refused with one line saying how to regenerate it.

use std::collections::BTreeMap;
use std::path::Path;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::score::{Reference, BLOCK};
use super::truth::{FaceScene, LightRecord, Truth, METHOD};
use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::scene::face;

/// The cache's index file.
pub const INDEX: &str = "truth.json";

/// `truth.json`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct TruthIndex {
    pub method: String,
    pub attribution: String,
    pub lights: BTreeMap<String, LightRecord>,
}

/// One cached light, loaded and checked.
#[derive(Clone, Debug)]
pub struct CachedTruth {
    pub record: LightRecord,
    pub radiance: FloatImage,
    pub std_err: FloatImage,
    pub reference: Reference,
}

fn read_index(dir: &Path) -> Result<TruthIndex, String> {
    let path = dir.join(INDEX);
    let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_slice(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Adds (or replaces) `truth`'s light in the cache at `dir`: its images, the coverage and its
/// record in `truth.json` (other lights' records are kept).
pub fn save(dir: &Path, truth: &Truth) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut index = read_index(dir).unwrap_or_default();
    index.method = METHOD.into();
    index.attribution = head::ATTRIBUTION.into();
    let name = &truth.record.name;
    index.lights.insert(name.clone(), truth.record.clone());
    truth.radiance.save(&dir.join(format!("{name}.pfm")))?;
    truth.std_err.save(&dir.join(format!("{name}-se.pfm")))?;
    let (w, h) = (truth.radiance.width, truth.radiance.height);
    FloatImage::new(w, h, truth.alpha.iter().map(|&a| [a; 3]).collect())?
        .save(&dir.join("alpha.pfm"))?;
    let text = serde_json::to_string_pretty(&index).map_err(|e| e.to_string())? + "\n";
    let path = dir.join(INDEX);
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The head's coverage cached at `dir`.
pub fn load_alpha(dir: &Path) -> Result<Vec<f32>, String> {
    Ok(FloatImage::load(&dir.join("alpha.pfm"))?
        .pixels
        .iter()
        .map(|p| p[0])
        .collect())
}

/// Loads light `name` (at `position` m, `intensity` W/sr) from the cache at `dir`, refusing
/// it when it was computed for another scene than `scene`.
pub fn load(
    dir: &Path,
    scene: &FaceScene,
    name: &str,
    position: Vec3,
    intensity: f32,
) -> Result<CachedTruth, String> {
    let index = read_index(dir)?;
    let regenerate = format!(
        "regenerate it with `dermis reference --scene head --face-light {name} --out {}`",
        dir.display()
    );
    let record = index
        .lights
        .get(name)
        .ok_or_else(|| format!("{}: no `{name}` light; {regenerate}", dir.display()))?;
    let want = scene.hash(position, intensity);
    if record.scene_fnv1a64 != want {
        return Err(format!(
            "{}: `{name}` was computed for another scene (hash {}, this scene's {want}); \
             {regenerate}",
            dir.join(INDEX).display(),
            record.scene_fnv1a64
        ));
    }
    let radiance = FloatImage::load(&dir.join(format!("{name}.pfm")))?;
    let std_err = FloatImage::load(&dir.join(format!("{name}-se.pfm")))?;
    let alpha = load_alpha(dir)?;
    let size = (scene.width, scene.height);
    if (radiance.width, radiance.height) != size || (std_err.width, std_err.height) != size {
        return Err(format!(
            "{}: `{name}`'s images are not {}x{}",
            dir.display(),
            size.0,
            size.1
        ));
    }
    let reference = Reference::from_truth(&radiance, &std_err, &alpha, BLOCK)?;
    Ok(CachedTruth {
        record: record.clone(),
        radiance,
        std_err,
        reference,
    })
}

/// The three named lights of the face scenes from the cache at `dir`, in
/// [`face::FaceLight::ALL`] order.
pub fn load_named(
    dir: &Path,
    scene: &FaceScene,
) -> Result<Vec<(face::FaceLight, CachedTruth)>, String> {
    face::FaceLight::ALL
        .iter()
        .map(|l| load(dir, scene, l.name(), l.position(), face::LIGHT_INTENSITY).map(|t| (*l, t)))
        .collect()
}

/// Every light cached at `dir` (the named ones first, in [`face::FaceLight::ALL`] order, then
/// the others by name), each checked against `scene` at its recorded position and intensity.
pub fn load_all(dir: &Path, scene: &FaceScene) -> Result<Vec<(Vec3, CachedTruth)>, String> {
    let index = read_index(dir)?;
    let named: Vec<&str> = face::FaceLight::ALL.iter().map(|l| l.name()).collect();
    let mut names: Vec<&String> = index.lights.keys().collect();
    names.sort_by_key(|n| (named.iter().position(|m| m == n).unwrap_or(named.len()), *n));
    names
        .into_iter()
        .map(|n| {
            let r = &index.lights[n];
            let p = Vec3::from_array(r.position);
            load(dir, scene, n, p, r.intensity).map(|t| (p, t))
        })
        .collect()
}

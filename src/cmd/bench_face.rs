//! `dermis bench face`: every shading model on the scanned head, scored against the cached
//! Mitsuba 3 references (`tools/mitsuba/face/`): mean |ln(model/reference)| over the skin
//! blocks above the reference's noise, |ln| of the integrated radiance, and ꟻLIP on the
//! tone-mapped pair, per light (front, side across the nose, back through the ear).

use std::path::PathBuf;

use dermis_core::face::head::{self, HeadRenderer};
use dermis_core::face::pfm::FloatImage;
use dermis_core::render::Gpu;
use dermis_core::shading::{material::SKIN1, Material, ShadingModel};
use dermis_measure::face::cache::Cache;
use dermis_measure::face::score::{tone_map, Reference};
use serde_json::json;

use crate::cmd::args::check_out_dir;

#[derive(clap::Args, Debug)]
pub struct FaceArgs {
    /// Directory for face.json, face.md and the tone-mapped images (checked first).
    #[arg(long)]
    pub out: PathBuf,
    /// The cached references (default: the source tree's tools/mitsuba/face).
    #[arg(long)]
    pub cache: Option<PathBuf>,
}

/// The default cache directory.
pub fn default_cache() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tools/mitsuba/face"))
}

/// ꟻLIP's mean error over the head's pixels, on the pair tone-mapped at `exposure`; `None`
/// in a build without the `flip` feature (ꟻLIP is a C++ library: the default build leaves
/// it out, `cargo build --release --features flip` and CI build it).
#[cfg(not(feature = "flip"))]
pub fn flip_mean(_: &FloatImage, _: &Reference, _: f32, _: &[f32]) -> Option<f64> {
    None
}

/// ꟻLIP's mean error over the head's pixels, on the pair tone-mapped at `exposure`.
#[cfg(feature = "flip")]
pub fn flip_mean(
    model: &FloatImage,
    reference: &Reference,
    exposure: f32,
    alpha: &[f32],
) -> Option<f64> {
    let (w, h) = (model.width, model.height);
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(&reference.full, exposure));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(model, exposure));
    let map = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let (mut sum, mut n) = (0.0, 0usize);
    for (e, a) in map.iter().zip(alpha) {
        if *a >= 0.999 {
            sum += *e as f64;
            n += 1;
        }
    }
    Some(sum / n.max(1) as f64)
}

/// The exposure the pairs are tone-mapped at: the front reference's mean over the head to
/// 0.35 (mid-grey after the curve).
fn exposure(front: &Reference, alpha: &[f32]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (p, a) in front.full.pixels.iter().zip(alpha) {
        if *a >= 0.999 {
            sum += (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64;
            n += 1;
        }
    }
    (0.35 / (sum / n.max(1) as f64).max(1e-9)) as f32
}

/// One model's mean |ln(model/reference)| per light (name, error).
pub type FaceScore = (ShadingModel, Vec<(String, f64)>);

/// Each model's mean |ln(model/reference)| on the head under the cached references' lights
/// (front, side, back), for `bench shading`'s face column.
pub fn face_scores(gpu: &Gpu) -> Result<Vec<FaceScore>, String> {
    let dir = default_cache();
    let cache = Cache::load(&dir)?;
    let model = head::load(&crate::paths::assets_dir(), false).map_err(|e| e.to_string())?;
    let (w, h) = (cache.scene.camera.width, cache.scene.camera.height);
    let mut renderer = HeadRenderer::new(gpu, &model, &SKIN1, w, h, true)?;
    let camera = head::camera();
    let mut out = Vec::new();
    for shading in ShadingModel::ALL {
        let mut per_light = Vec::new();
        for (light, reference) in &cache.references {
            let pixels = renderer.radiance(
                gpu,
                shading,
                &camera,
                light.position(),
                head::LIGHT_INTENSITY,
            )?;
            let score = reference.score(&FloatImage::new(w, h, pixels)?)?;
            per_light.push((light.name().to_string(), score.mean_abs_ln));
        }
        out.push((shading, per_light));
    }
    Ok(out)
}

pub fn run(args: FaceArgs) -> Result<(), String> {
    check_out_dir(&args.out)?;
    let dir = args.cache.unwrap_or_else(default_cache);
    let cache = Cache::load(&dir)?;
    let material = Material::preset(&cache.scene.medium.name)
        .filter(|m| *m == SKIN1)
        .ok_or("the cached references are not skin1's (the only material cached)")?;
    let alpha: Vec<f32> = FloatImage::load(&dir.join("alpha.pfm"))?
        .pixels
        .iter()
        .map(|p| p[0])
        .collect();
    let model = head::load(&crate::paths::assets_dir(), false).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = (cache.scene.camera.width, cache.scene.camera.height);
    let mut renderer = HeadRenderer::new(&gpu, &model, &material, w, h, true)?;
    let camera = head::camera();
    let exposure = exposure(&cache.references[0].1, &alpha);
    for (light, reference) in &cache.references {
        let path = args
            .out
            .join(format!("face-{}-reference.png", light.name()));
        save_png(&path, &reference.full, exposure)?;
    }
    let mut rows = Vec::new();
    for shading in ShadingModel::ALL {
        let mut per_light = Vec::new();
        for (light, reference) in &cache.references {
            let pixels = renderer.radiance(
                &gpu,
                shading,
                &camera,
                light.position(),
                head::LIGHT_INTENSITY,
            )?;
            let image = FloatImage::new(w, h, pixels)?;
            let score = reference.score(&image)?;
            let flip = flip_mean(&image, reference, exposure, &alpha);
            let name = format!("face-{}-{}", light.name(), shading.name());
            save_png(&args.out.join(format!("{name}.png")), &image, exposure)?;
            per_light.push((light.name(), score, flip));
        }
        rows.push((shading, per_light));
    }
    let noise: Vec<(String, f64, usize)> = cache
        .references
        .iter()
        .map(|(l, r)| {
            let n = r.mask.iter().flatten().filter(|k| **k).count();
            (l.name().to_string(), r.relative_noise(), n)
        })
        .collect();
    let rec = &cache.record;
    let report = json!({
        "reference": {
            "mitsuba": rec.mitsuba, "variant": rec.variant, "integrator": rec.integrator,
            "boundary": rec.boundary, "spp_per_channel_per_seed": rec.spp, "seeds": rec.seeds,
            "render_seconds": rec.renders.iter().map(|(k, r)| (k.clone(), json!({
                "seed1": r.seed1_s, "seed2": r.seed2_s, "specular": r.specular_s
            }))).collect::<serde_json::Map<_, _>>(),
            "relative_noise": noise.iter().map(|(l, n, c)| (l.clone(), json!({
                "mean_relative_se": n, "scored_block_channels": c
            }))).collect::<serde_json::Map<_, _>>(),
            "size": [w, h], "block": dermis_measure::face::score::BLOCK,
            "attribution": head::ATTRIBUTION,
        },
        "exposure": exposure,
        "adapter": gpu.adapter_name(),
        "models": rows.iter().map(|(m, per)| json!({
            "model": m.name(),
            "lights": per.iter().map(|(l, s, f)| json!({
                "light": l, "mean_abs_ln": s.mean_abs_ln, "integrated_abs_ln": s.integrated,
                "flip": f, "block_channels": s.count,
            })).collect::<Vec<_>>(),
            "face": per.iter().map(|(_, s, _)| s.mean_abs_ln).sum::<f64>() / per.len() as f64,
            "flip": per.iter().map(|(_, _, f)| *f).sum::<Option<f64>>().map(|s| s / per.len() as f64),
        })).collect::<Vec<_>>(),
    });
    let mut md = String::from(
        "| model | front | side | back | face (mean) | integrated front/side/back | ꟻLIP front/side/back |\n\
         |---|---|---|---|---|---|---|\n",
    );
    md += &format!(
        "| *reference rel. SE* | {:.3} | {:.3} | {:.3} | | | |\n",
        noise[0].1, noise[1].1, noise[2].1
    );
    let flip = |f: &Option<f64>| f.map_or("–".to_string(), |f| format!("{f:.3}"));
    for (m, per) in &rows {
        let face = per.iter().map(|(_, s, _)| s.mean_abs_ln).sum::<f64>() / per.len() as f64;
        md += &format!(
            "| {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} / {:.2} / {:.2} | {} / {} / {} |\n",
            m.name(),
            per[0].1.mean_abs_ln,
            per[1].1.mean_abs_ln,
            per[2].1.mean_abs_ln,
            face,
            per[0].1.integrated,
            per[1].1.integrated,
            per[2].1.integrated,
            flip(&per[0].2),
            flip(&per[1].2),
            flip(&per[2].2)
        );
    }
    let write = |name: &str, text: &str| {
        let p = args.out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    write(
        "face.json",
        &(serde_json::to_string_pretty(&report).map_err(|e| e.to_string())? + "\n"),
    )?;
    write("face.md", &md)?;
    println!(
        "face scenes: skin1 head {w}x{h}, Mitsuba {} {} spp per channel and seed; errors: mean \
         |ln(model/reference)| over {}² blocks above the reference's noise\n{md}{}",
        rec.mitsuba,
        rec.spp,
        dermis_measure::face::score::BLOCK,
        head::ATTRIBUTION
    );
    Ok(())
}

fn save_png(path: &std::path::Path, image: &FloatImage, exposure: f32) -> Result<(), String> {
    image::save_buffer(
        path,
        &tone_map(image, exposure),
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(all(test, feature = "flip"))]
mod tests {
    use super::*;

    /// ꟻLIP (the `flip` feature, built and run in CI): a pair that is the same image scores 0,
    /// a darker one more.
    #[test]
    fn flip_scores_a_difference() {
        let (w, h) = (32, 32);
        let px =
            |v: f32| FloatImage::new(w, h, vec![[v, v * 0.8, v * 0.6]; (w * h) as usize]).unwrap();
        let alpha = vec![1.0; (w * h) as usize];
        let reference = Reference::from_seeds(&px(0.5), &px(0.5), &alpha, 4).unwrap();
        let same = flip_mean(&px(0.5), &reference, 1.0, &alpha).unwrap();
        let darker = flip_mean(&px(0.2), &reference, 1.0, &alpha).unwrap();
        assert!(same < 1e-6 && darker > 0.05, "{same} {darker}");
    }
}

//! `dermis bench face`: every shading model on the scanned head, scored against the cached
//! face truth (`tools/reference/face/`, the project's Monte Carlo on the head mesh): mean
//! |ln(model/truth)| over the head's blocks where the truth is precise, |ln| of the
//! integrated radiance, and ꟻLIP on the tone-mapped pair, per light (front, side across the
//! nose, back through the ear).

use std::path::PathBuf;

use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::render::Gpu;
use dermis_engine::scene::face::{self, FaceLight};
use dermis_engine::shading::{material::SKIN1, Material, ShadingModel};
use dermis_measure::face::regions::block_regions;
use dermis_measure::face::render::HeadRenderer;
use dermis_measure::face::score::{tone_map, Reference, BLOCK, MAX_REL_SE, WIDE_REL_SE};
use dermis_measure::face::truth::FaceScene;
use dermis_measure::face::truth_cache::{self, CachedTruth};
use serde_json::json;

use crate::cmd::args::check_out_dir;
use crate::cmd::face_diagnosis::Diagnosis;

#[derive(clap::Args, Debug)]
pub struct FaceArgs {
    /// Directory for face.json, face.md and the tone-mapped images (checked first).
    #[arg(long)]
    pub out: PathBuf,
    /// The cached truth (default: the source tree's tools/reference/face).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Render the head without its normal map (the truth's smooth mesh), to tell the map's
    /// share of the error.
    #[arg(long)]
    pub no_normal_map: bool,
    /// Every light cached in this folder and its sub-folders (one `dermis reference --scene
    /// head --light X,Y,Z --out DIR/NAME` each): the sweep's table (strict and wide score per
    /// model and light against the goal for the light's direction) and a contact sheet per
    /// spatial model (`sweep.md`, `sweep.json`, `sweep-<model>.png`).
    #[arg(long, conflicts_with = "cache")]
    pub sweep: Option<PathBuf>,
}

/// The default cache directory.
pub fn default_cache() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tools/reference/face"))
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
pub fn exposure(front: &Reference, alpha: &[f32]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (p, a) in front.full.pixels.iter().zip(alpha) {
        if *a >= 0.999 {
            sum += (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64;
            n += 1;
        }
    }
    (0.35 / (sum / n.max(1) as f64).max(1e-9)) as f32
}

/// Median and 95th percentile of the truth's relative SE over its scored block channels, and
/// their count.
type Quantiles = (f64, f64, usize);

/// One model's mean |ln(model/reference)| per light (name, error).
pub type FaceScore = (ShadingModel, Vec<(String, f64)>);

/// The face scene as the engine has it and its cached truths under the three named lights.
fn load_truths(
    dir: &std::path::Path,
) -> Result<(FaceScene, Vec<(FaceLight, CachedTruth)>), String> {
    let scene = FaceScene::head(&crate::paths::assets_dir())?;
    let truths = truth_cache::load_named(dir, &scene)?;
    Ok((scene, truths))
}

/// Each model's mean |ln(model/truth)| on the head under the cached truths' lights
/// (front, side, back), for `bench shading`'s face column.
pub fn face_scores(gpu: &Gpu) -> Result<Vec<FaceScore>, String> {
    let (scene, truths) = load_truths(&default_cache())?;
    let model = head::load(&crate::paths::assets_dir(), false).map_err(|e| e.to_string())?;
    let (w, h) = (scene.width, scene.height);
    let mut renderer = HeadRenderer::new(gpu, &model, &SKIN1, w, h, true)?;
    let camera = face::camera();
    let mut out = Vec::new();
    for shading in ShadingModel::ALL {
        let mut per_light = Vec::new();
        for (light, truth) in &truths {
            let reference = &truth.reference;
            let pixels = renderer.radiance(
                gpu,
                shading,
                &camera,
                light.position(),
                face::LIGHT_INTENSITY,
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
    if let Some(dir) = &args.sweep {
        return crate::cmd::bench_face_sweep::run(&args, dir);
    }
    let dir = args.cache.unwrap_or_else(default_cache);
    let scene = FaceScene::head(&crate::paths::assets_dir())?;
    let truths = truth_cache::load_all(&dir, &scene)?;
    if truths.is_empty() {
        return Err(format!("{}: no light cached", dir.display()));
    }
    let material: Material = scene.material.clone();
    let alpha = truth_cache::load_alpha(&dir)?;
    let maps = head::Maps {
        albedo: false,
        normal: !args.no_normal_map,
    };
    let model = head::load_with(&crate::paths::assets_dir(), maps).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = (scene.width, scene.height);
    let mut renderer = HeadRenderer::new(&gpu, &model, &material, w, h, true)?;
    let camera = face::camera();
    let exposure = exposure(&truths[0].1.reference, &alpha);
    for (_, truth) in &truths {
        let path = args
            .out
            .join(format!("face-{}-reference.png", truth.record.name));
        save_png(&path, &truth.reference.full, exposure)?;
    }
    let regions = block_regions(&scene, BLOCK)?;
    let mut rows = Vec::new();
    let mut diagnosis = Diagnosis::default();
    for shading in ShadingModel::ALL {
        let mut per_light = Vec::new();
        for (position, truth) in &truths {
            let reference = &truth.reference;
            let light = truth.record.name.as_str();
            let pixels =
                renderer.radiance(&gpu, shading, &camera, *position, truth.record.intensity)?;
            let image = FloatImage::new(w, h, pixels)?;
            let score = reference.score(&image)?;
            let wide = reference.clone().with_max_rel_se(WIDE_REL_SE);
            let wide_score = wide.score(&image)?;
            let flip = flip_mean(&image, reference, exposure, &alpha);
            let name = format!("face-{light}-{}", shading.name());
            save_png(&args.out.join(format!("{name}.png")), &image, exposure)?;
            diagnosis.add(&args.out, shading, light, &wide, &image, &regions)?;
            per_light.push((light, score, flip, wide_score));
        }
        rows.push((shading, per_light));
    }
    // The truth's own noise: relative standard error of the scored block channels (median,
    // 95th percentile) and how many there are.
    // Per light: name, then (median, 95th percentile, count) under the bar and the wide bar.
    let quantiles = |rel: Vec<f64>| {
        let q = |p: f64| rel.get(((rel.len().max(1) - 1) as f64 * p).round() as usize);
        let q = |p| q(p).copied().unwrap_or(f64::NAN);
        (q(0.5), q(0.95), rel.len())
    };
    let noise: Vec<(String, Quantiles, Quantiles)> = truths
        .iter()
        .map(|(_, t)| {
            let wide = t.reference.clone().with_max_rel_se(WIDE_REL_SE);
            (
                t.record.name.clone(),
                quantiles(t.reference.relative_errors()),
                quantiles(wide.relative_errors()),
            )
        })
        .collect();
    let report = json!({
        "truth": {
            "method": dermis_measure::face::truth::METHOD,
            "lights": truths.iter().map(|(_, t)| (t.record.name.clone(), json!(t.record)))
                .collect::<serde_json::Map<_, _>>(),
            "relative_se": noise.iter().map(|(l, (m, p, c), (wm, wp, wc))| (l.clone(), json!({
                "median": m, "p95": p, "scored_block_channels": c,
                "wide": {"median": wm, "p95": wp, "scored_block_channels": wc},
            }))).collect::<serde_json::Map<_, _>>(),
            "max_relative_se_scored": MAX_REL_SE,
            "wide_max_relative_se": WIDE_REL_SE,
            "size": [w, h], "block": BLOCK,
            "attribution": head::ATTRIBUTION,
        },
        "exposure": exposure,
        "adapter": gpu.adapter_name(),
        "models": rows.iter().map(|(m, per)| json!({
            "model": m.name(),
            "lights": per.iter().map(|(l, s, f, ws)| json!({
                "light": l, "mean_abs_ln": s.mean_abs_ln, "integrated_abs_ln": s.integrated,
                "flip": f, "block_channels": s.count,
                "wide": {"mean_abs_ln": ws.mean_abs_ln, "integrated_abs_ln": ws.integrated,
                         "block_channels": ws.count},
            })).collect::<Vec<_>>(),
            "face": per.iter().map(|p| p.1.mean_abs_ln).sum::<f64>() / per.len() as f64,
            "flip": per.iter().map(|p| p.2).sum::<Option<f64>>().map(|s| s / per.len() as f64),
        })).collect::<Vec<_>>(),
        "diagnosis": diagnosis.json,
    });
    let names: Vec<&str> = noise.iter().map(|n| n.0.as_str()).collect();
    let slash = names.join("/");
    let cells = |f: &dyn Fn(usize) -> String| -> String {
        (0..names.len()).map(|i| format!(" {} |", f(i))).collect()
    };
    let mut md = format!(
        "| model |{} face (mean) | integrated {slash} | ꟻLIP {slash} |\n|---|{}---|---|---|\n",
        cells(&|i| names[i].to_string()),
        "---|".repeat(names.len())
    );
    md += &format!(
        "| *truth rel. SE (median / 95th pct.)* |{} | | |\n",
        cells(&|i| format!("{:.4} / {:.4}", noise[i].1 .0, noise[i].1 .1))
    );
    md += &format!(
        "| *scored block channels* |{} | | |\n",
        cells(&|i| noise[i].1 .2.to_string())
    );
    let mut wide_md = format!(
        "| model |{} mean |\n|---|{}---|\n| *truth rel. SE (median / 95th pct.)* |{} |\n\
         | *scored block channels* |{} |\n",
        cells(&|i| names[i].to_string()),
        "---|".repeat(names.len()),
        cells(&|i| format!("{:.4} / {:.4}", noise[i].2 .0, noise[i].2 .1)),
        cells(&|i| noise[i].2 .2.to_string()),
    );
    let flip = |f: &Option<f64>| f.map_or("–".to_string(), |f| format!("{f:.3}"));
    for (m, per) in &rows {
        let face = per.iter().map(|p| p.1.mean_abs_ln).sum::<f64>() / per.len() as f64;
        let wide = per.iter().map(|p| p.3.mean_abs_ln).sum::<f64>() / per.len() as f64;
        wide_md += &format!(
            "| {} |{} {wide:.3} |\n",
            m.name(),
            cells(&|i| format!("{:.3}", per[i].3.mean_abs_ln))
        );
        let join =
            |f: &dyn Fn(usize) -> String| (0..per.len()).map(f).collect::<Vec<_>>().join(" / ");
        md += &format!(
            "| {} |{} {face:.3} | {} | {} |\n",
            m.name(),
            cells(&|i| format!("{:.3}", per[i].1.mean_abs_ln)),
            join(&|i| format!("{:.3}", per[i].1.integrated)),
            join(&|i| flip(&per[i].2)),
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
    md += &format!(
        "\nThe same, scored wherever the truth's relative SE ≤ {WIDE_REL_SE} (the dimmer blocks \
         too: the terminator, the eye sockets, the back light's rim):\n\n{wide_md}"
    );
    write("face.md", &md)?;
    write("diagnosis.md", &diagnosis.markdown())?;
    println!(
        "face scenes: skin1 head {w}x{h} against the Monte Carlo truth ({:?} photons per \
         channel, front light); errors: mean |ln(model/truth)| over {}² blocks where the truth's relative \
         SE ≤ {MAX_REL_SE}\n{md}{}",
        truths[0].1.record.photons_per_channel,
        BLOCK,
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
        let reference = Reference::from_truth(&px(0.5), &px(0.01), &alpha, 4).unwrap();
        let same = flip_mean(&px(0.5), &reference, 1.0, &alpha).unwrap();
        let darker = flip_mean(&px(0.2), &reference, 1.0, &alpha).unwrap();
        assert!(same < 1e-6 && darker > 0.05, "{same} {darker}");
    }
}

//! The shading models render the project's character through the real renderer on a real
//! driver (lavapipe in CI): coverage, relative brightness, distinctness, colour, finiteness,
//! and golden images for a fixed pose.

use std::path::{Path, PathBuf};

use dermis_engine::render::{Gpu, RgbaImage};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};

const W: u32 = 240;
const H: u32 = 180;

fn gpu() -> Gpu {
    // No skip: every machine that runs the tests has a Vulkan driver (lavapipe at least);
    // the error explains how to get one.
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn assets() -> SceneAssets {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    SceneAssets::load(&dir, None).unwrap_or_else(|e| panic!("{e}"))
}

/// A fixed pose: mid-stride in the run clip.
fn shot(model: ShadingModel) -> Shot {
    Shot {
        clip: 1,
        time: 0.2,
        props: false,
        fill: 1.0,
        ..Shot::new(model, SKIN1)
    }
}

fn px(img: &RgbaImage, i: usize) -> [f32; 3] {
    let p = &img.pixels[i * 4..i * 4 + 3];
    [
        p[0] as f32 / 255.0,
        p[1] as f32 / 255.0,
        p[2] as f32 / 255.0,
    ]
}

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Pixels that differ from the background (the top-left corner's colour).
fn mask(img: &RgbaImage) -> Vec<bool> {
    let bg = px(img, 0);
    (0..(img.width * img.height) as usize)
        .map(|i| {
            let c = px(img, i);
            (0..3).any(|k| (c[k] - bg[k]).abs() > 3.0 / 255.0)
        })
        .collect()
}

fn mean_in(img: &RgbaImage, mask: &[bool]) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    let mut n = 0usize;
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let c = px(img, i);
        for k in 0..3 {
            sum[k] += c[k] as f64;
        }
        n += 1;
    }
    sum.map(|s| (s / n.max(1) as f64) as f32)
}

#[test]
fn every_model_renders_the_character() {
    let gpu = gpu();
    let assets = assets();
    let mut still = StillRenderer::new(&gpu, &assets, W, H).unwrap();
    let images: Vec<(ShadingModel, RgbaImage)> = ShadingModel::ALL
        .iter()
        .map(|&m| (m, still.render(&gpu, &assets, &shot(m)).unwrap()))
        .collect();
    let ward = &images[0].1;
    let m = mask(ward);
    let coverage = m.iter().filter(|x| **x).count() as f32 / m.len() as f32;
    assert!(
        (0.05..=0.60).contains(&coverage),
        "character coverage {coverage:.3} outside 5–60 %"
    );
    let ward_mean = mean_in(ward, &m);
    let ward_lum = luminance(ward_mean);
    let ward_rb = ward_mean[0] / ward_mean[2].max(1e-4);
    println!("coverage {:.1} %", coverage * 100.0);
    for (model, img) in &images {
        let mean = mean_in(img, &m);
        let lum = luminance(mean);
        let rb = mean[0] / mean[2].max(1e-4);
        println!(
            "{:>15}: mean rgb {:.3?} luminance {:.3} ({:.2}× ward) R/B {:.2}",
            model.name(),
            mean,
            lum,
            lum / ward_lum,
            rb
        );
        assert!(
            (0.25..=4.0).contains(&(lum / ward_lum)),
            "{model}: luminance {lum:.3} vs ward {ward_lum:.3}"
        );
        // Only the dipole: `oss` tints its skin with the same texture as ward (skin R/B 3.8
        // vs 3.9); its redder mean came from the cloth, now shaded alike under every model
        // (tests/render/materials_per_region.rs).
        if matches!(model, ShadingModel::Dipole) {
            assert!(
                rb > ward_rb,
                "{model}: R/B {rb:.2} not redder than ward's {ward_rb:.2}"
            );
        }
    }
    // Every pair of models differs visibly on the skin. Cloth is shaded alike by every model
    // (tests/render/materials_per_region.rs), so the skin is where the models disagree at all: the
    // character's pixels some model moves by more than 1/255 from ward. A printed variant only
    // has to differ from its default variant at all: with skin1 σ'_t ≈ 1 mm⁻¹, eq. 3's extra
    // 1/σ'_t is nearly invisible (which is why the unit error goes unnoticed in renders).
    let skin: Vec<bool> = m
        .iter()
        .enumerate()
        .map(|(p, &inside)| {
            inside
                && images.iter().any(|(_, img)| {
                    let (c, w) = (px(img, p), px(ward, p));
                    (0..3).any(|k| (c[k] - w[k]).abs() > 1.0 / 255.0)
                })
        })
        .collect();
    let skin_share =
        skin.iter().filter(|x| **x).count() as f32 / m.iter().filter(|x| **x).count() as f32;
    println!("skin: {:.0} % of the character", skin_share * 100.0);
    assert!(
        skin_share > 0.2,
        "the models agree almost everywhere: {skin_share}"
    );
    for (i, (a, ia)) in images.iter().enumerate() {
        for (b, ib) in images.iter().skip(i + 1) {
            let mut diff = 0.0f64;
            let mut n = 0;
            for (p, _) in skin.iter().enumerate().filter(|(_, x)| **x) {
                let (ca, cb) = (px(ia, p), px(ib, p));
                diff += (0..3).map(|k| (ca[k] - cb[k]).abs() as f64).sum::<f64>() / 3.0;
                n += 1;
            }
            let diff = diff / n as f64;
            println!(
                "{:>15} vs {:<15} mean |Δ| = {:.2}/255",
                a.name(),
                b.name(),
                diff * 255.0
            );
            let variants = a.module() == b.module();
            let bound = if variants { 0.2 / 255.0 } else { 2.0 / 255.0 };
            assert!(
                diff > bound,
                "{a} and {b} differ by only {:.2}/255",
                diff * 255.0
            );
        }
    }
}

#[test]
fn radiance_is_finite_and_non_negative_for_every_model_and_material() {
    let gpu = gpu();
    let assets = assets();
    let mut still =
        StillRenderer::with_format(&gpu, &assets, W, H, wgpu::TextureFormat::Rgba16Float).unwrap();
    for material in dermis_engine::shading::material::PRESETS {
        for model in ShadingModel::ALL {
            for (clip, time) in [(0, 0.0), (1, 0.3), (2, 0.45)] {
                let s = Shot {
                    clip,
                    time,
                    props: true,
                    ..Shot::new(model, material.clone())
                };
                let pixels = still.render_radiance(&gpu, &assets, &s).unwrap();
                let bad = pixels
                    .iter()
                    .filter(|p| p.iter().any(|c| !c.is_finite() || *c < 0.0))
                    .count();
                assert_eq!(
                    bad, 0,
                    "{model} / {} clip {clip}: {bad} non-finite or negative pixels",
                    material.name
                );
            }
        }
    }
}

fn golden_path(model: ShadingModel) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{}.png", model.name()))
}

/// Golden images: regenerate with `DERMIS_UPDATE_GOLDEN=1 cargo test --test render_models`.
/// Tolerance: mean |Δ| ≤ 1.5/255 and at most 1 % of pixels off by more than 24/255
/// (rasterizer and driver differences move edges, not shading).
#[test]
fn golden_images_for_a_fixed_pose() {
    let gpu = gpu();
    let assets = assets();
    let mut still = StillRenderer::new(&gpu, &assets, 120, 90).unwrap();
    let update = std::env::var_os("DERMIS_UPDATE_GOLDEN").is_some();
    for model in ShadingModel::ALL {
        let img = still.render(&gpu, &assets, &shot(model)).unwrap();
        let path = golden_path(model);
        if update {
            img.save_png(&path).unwrap();
            continue;
        }
        let golden = image::open(&path)
            .unwrap_or_else(|e| {
                panic!(
                    "{}: {e} (regenerate with DERMIS_UPDATE_GOLDEN=1)",
                    path.display()
                )
            })
            .to_rgba8();
        assert_eq!((golden.width(), golden.height()), (img.width, img.height));
        let diffs: Vec<u8> = golden
            .as_raw()
            .iter()
            .zip(&img.pixels)
            .map(|(a, b)| a.abs_diff(*b))
            .collect();
        let mean = diffs.iter().map(|d| *d as f64).sum::<f64>() / diffs.len() as f64;
        let big = diffs.iter().filter(|d| **d > 24).count() as f64 / diffs.len() as f64;
        assert!(
            mean <= 1.5 && big <= 0.01,
            "{model}: mean |Δ| {mean:.2}/255, {:.2} % pixels off by > 24",
            big * 100.0
        );
    }
}

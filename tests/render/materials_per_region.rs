//! Materials per region (issue 12, issue 28): the character's skin material (declared by
//! `KHR_materials_volume_scatter`, `asset::skin`) is shaded by the subsurface models, its
//! other materials (tank top, shorts, hair, eyes) the same under every model, and their
//! albedo texture stays on them.

use std::path::Path;

use dermis_engine::asset::{skin, Model, TextureImage};
use dermis_engine::render::{Gpu, RgbaImage};
use dermis_engine::scene::{Roles, SceneAssets};
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};

const W: u32 = 240;
const H: u32 = 270;

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn assets_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

fn assets() -> SceneAssets {
    SceneAssets::load(&assets_dir(), None).unwrap_or_else(|e| panic!("{e}"))
}

/// Mid-stride in the run clip, lit from the front right: torso, shorts, arms and legs show.
fn shot(model: ShadingModel) -> Shot {
    Shot {
        clip: 1,
        time: 0.2,
        props: false,
        fill: 0.9,
        ..Shot::new(model, SKIN1)
    }
}

fn rgb(img: &RgbaImage, i: usize) -> [f32; 3] {
    let p = &img.pixels[i * 4..i * 4 + 3];
    [p[0] as f32, p[1] as f32, p[2] as f32]
}

/// The character with every material's colour replaced by a flat one, red on its skin
/// materials and green on the others: rendered, cloth has no red at all (its BRDF scales the
/// albedo) and skin (under ward: red diffuse, white specular) little green.
fn mask_character(model: &Model) -> Model {
    let classes = skin::classify(model, None).unwrap();
    let mut m = model.clone();
    let solid = |rgba: [u8; 4]| TextureImage::rgba(1, 1, rgba.to_vec(), true);
    m.textures.push(solid([255, 0, 0, 255]));
    m.textures.push(solid([0, 255, 0, 255]));
    let (red, green) = (m.textures.len() - 2, m.textures.len() - 1);
    for (i, mat) in m.materials.iter_mut().enumerate() {
        mat.base_color_factor = [1.0; 4];
        mat.base_color_texture = Some(if classes.is_skin(i) { red } else { green });
        // A skin's albedo is its multi-scatter colour where it declares one.
        if let Some(scatter) = &mut mat.volume_scatter {
            scatter.multiscatter_color = [1.0; 3];
            scatter.multiscatter_texture = mat.base_color_texture;
        }
    }
    m
}

/// Pixels whose whole 5×5 neighbourhood satisfies `pred` (away from edges and blends).
fn eroded(img: &RgbaImage, pred: impl Fn([f32; 3]) -> bool) -> Vec<bool> {
    let (w, h) = (img.width as i64, img.height as i64);
    let raw: Vec<bool> = (0..(w * h) as usize).map(|i| pred(rgb(img, i))).collect();
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (-2..=2).all(|dy| {
                (-2..=2).all(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx >= 0 && ny >= 0 && nx < w && ny < h && raw[(ny * w + nx) as usize]
                })
            })
        })
        .collect()
}

fn mean_in(img: &RgbaImage, region: &[bool]) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    let mut n = 0usize;
    for (i, _) in region.iter().enumerate().filter(|(_, r)| **r) {
        let c = rgb(img, i);
        for k in 0..3 {
            sum[k] += c[k] as f64;
        }
        n += 1;
    }
    sum.map(|s| (s / n.max(1) as f64) as f32)
}

/// Mean per-pixel |Δ| (0–255, averaged over channels) inside `region`.
fn mean_abs_diff(a: &RgbaImage, b: &RgbaImage, region: &[bool]) -> f32 {
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for (i, _) in region.iter().enumerate().filter(|(_, r)| **r) {
        let (ca, cb) = (rgb(a, i), rgb(b, i));
        sum += (0..3).map(|k| (ca[k] - cb[k]).abs() as f64).sum::<f64>() / 3.0;
        n += 1;
    }
    (sum / n.max(1) as f64) as f32
}

#[test]
fn cloth_is_the_same_under_every_model_and_skin_is_not() {
    let gpu = gpu();
    let assets = assets();
    // The regions, from the mask rendered as albedo.
    let character = mask_character(&assets.character);
    let masked = SceneAssets {
        roles: Roles::of(&character),
        character,
        props: Vec::new(),
        head: Default::default(),
    };
    let mut still = StillRenderer::new(&gpu, &masked, W, H).unwrap();
    let regions = still
        .render(&gpu, &masked, &shot(ShadingModel::Ward))
        .unwrap();
    let bg = rgb(&regions, 0);
    let not_bg = |c: [f32; 3]| (0..3).any(|k| (c[k] - bg[k]).abs() > 3.0);
    // (The standard materials' specular lobe adds a little white to the green.)
    let cloth = eroded(&regions, |c| c[1] >= 3.0 && c[1] > 2.0 * c[0] && not_bg(c));
    let skin = eroded(&regions, |c| {
        c[0] >= 12.0 && c[1] <= 0.5 * c[0] && not_bg(c)
    });
    let (n_cloth, n_skin) = (
        cloth.iter().filter(|x| **x).count(),
        skin.iter().filter(|x| **x).count(),
    );
    println!("cloth {n_cloth} px, skin {n_skin} px");
    assert!(n_cloth > 1000, "too little cloth in view: {n_cloth} px");
    assert!(n_skin > 1000, "too little skin in view: {n_skin} px");

    let mut still = StillRenderer::new(&gpu, &assets, W, H).unwrap();
    let images: Vec<(ShadingModel, RgbaImage)> = ShadingModel::ALL
        .iter()
        .map(|&m| (m, still.render(&gpu, &assets, &shot(m)).unwrap()))
        .collect();
    let (_, ward) = &images[0];
    assert_eq!(images[0].0, ShadingModel::Ward);
    let ward_cloth = mean_in(ward, &cloth);
    // The texture stays on the cloth: the tank top is teal, the shorts navy; the mean is
    // bluer than red (skin-coloured cloth would be the opposite).
    assert!(
        ward_cloth[2] > ward_cloth[0] * 1.2,
        "cloth lost its texture: mean {ward_cloth:?}"
    );
    for (model, img) in &images {
        let c = mean_in(img, &cloth);
        let d_cloth = mean_abs_diff(img, ward, &cloth);
        let d_skin = mean_abs_diff(img, ward, &skin);
        println!(
            "{:>15}: cloth mean {c:.1?} |Δ| vs ward {d_cloth:.2}/255; skin |Δ| vs ward {d_skin:.2}/255",
            model.name()
        );
        assert!(
            (0..3).all(|k| (c[k] - ward_cloth[k]).abs() <= 1.0) && d_cloth <= 1.0,
            "{model}: cloth differs from ward's (mean {c:?} vs {ward_cloth:?}, |Δ| {d_cloth:.2}/255)"
        );
        if model.effects().subsurface {
            assert!(
                d_skin > 4.0,
                "{model}: skin too close to ward's (|Δ| {d_skin:.2}/255)"
            );
        }
    }
}

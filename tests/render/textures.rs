//! Textures on a real device (lavapipe samples BC, not ETC2 or ASTC): the character's base
//! colour uploaded as its BC encoding as stored, as its ETC2 encoding (which lavapipe lacks:
//! decoded to RGBA8 on the CPU) and as its PNG decoded — the three draw the same character
//! (within the encodings' error) and not a white or black one; the GPU bytes are counted; and
//! the pipeline cache survives a launch and refuses a file from another driver.

use std::path::{Path, PathBuf};

use dermis_engine::asset::{dir_reader, load_gltf_slice, Model, Texels};
use dermis_engine::render::pipeline_cache::{self, PipelineCacheFile};
use dermis_engine::render::{upload_bytes, upload_texture, Gpu, RgbaImage};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn assets_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

/// The character, read with the files `hidden` names out of the loader's sight.
fn character(hidden: fn(&str) -> bool) -> Model {
    let files = dir_reader(&assets_dir());
    let read = |p: &str| match hidden(p) {
        true => Err(format!("{p} hidden")),
        false => files(p),
    };
    let bytes = read("character.glb").unwrap();
    load_gltf_slice(&bytes, "character.glb", &read).unwrap_or_else(|e| panic!("{e}"))
}

fn render(gpu: &Gpu, character: Model) -> RgbaImage {
    let mut assets = SceneAssets::load(&assets_dir(), None).unwrap();
    assets.character = character;
    let mut still = StillRenderer::new(gpu, &assets, 160, 180).unwrap();
    let shot = Shot {
        clip: 1,
        time: 0.2,
        props: false,
        fill: 0.9,
        ..Shot::new(ShadingModel::BASELINE, SKIN1)
    };
    still.render(gpu, &assets, &shot).unwrap()
}

fn mean_abs_diff(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let n = a.pixels.len() as f64;
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum::<f64>()
        / n
}

#[test]
fn compressed_decoded_and_source_textures_draw_the_same_character() {
    let gpu = gpu();
    assert!(
        gpu.device
            .features()
            .contains(wgpu::Features::TEXTURE_COMPRESSION_BC)
            && !gpu
                .device
                .features()
                .contains(wgpu::Features::TEXTURE_COMPRESSION_ETC2),
        "this test expects lavapipe's BC and no ETC2"
    );
    let native = character(|_| false);
    let etc2 = character(|p| p.ends_with(".bc.ktx2"));
    let source = character(|p| p.ends_with(".ktx2"));
    assert!(matches!(native.textures[0].texels, Texels::Blocks(_)));
    assert!(matches!(source.textures[0].texels, Texels::Rgba8(_)));
    // GPU bytes: BC1 (the atlas has no alpha) with its mips is an eighth of RGBA8's.
    let bytes = |m: &Model| {
        let _view = upload_texture(&gpu.device, &gpu.queue, &m.textures[0], "test");
        upload_bytes(&gpu.device, &m.textures[0])
    };
    let (bc, decoded, png) = (bytes(&native), bytes(&etc2), bytes(&source));
    assert_eq!(decoded, png, "ETC2 decoded takes what the PNG does");
    // (The 2×2 and 1×1 levels take a whole 4×4 block.)
    assert!(
        (png..png + 512).contains(&(bc * 8)),
        "BC1 is half a byte a texel, RGBA8 4: {bc} vs {png}"
    );
    let [a, b, c] = [native, etc2, source].map(|m| render(&gpu, m));
    let white = {
        let mut m = character(|p| p.ends_with(".ktx2"));
        for px in m.textures[0].rgba8_mut().unwrap().chunks_exact_mut(4) {
            px[..3].copy_from_slice(&[255, 255, 255]);
        }
        render(&gpu, m)
    };
    let (bc_err, etc2_err, white_err) = (
        mean_abs_diff(&a, &c),
        mean_abs_diff(&b, &c),
        mean_abs_diff(&white, &c),
    );
    println!("mean |Δ| per channel against the PNG's: BC {bc_err:.3}, ETC2 {etc2_err:.3}, white {white_err:.3}");
    assert!(
        bc_err < 1.5 && etc2_err < 1.5 && white_err > 4.0 * bc_err.max(etc2_err),
        "BC {bc_err:.2}, ETC2 {etc2_err:.2}, white {white_err:.2} (mean |Δ| per channel)"
    );
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dermis-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Whether opening the cache in `dir` with `file`'s bytes there starts from them.
fn loads(gpu: &Gpu, dir: &Path, bytes: &[u8]) -> bool {
    std::fs::write(dir.join(pipeline_cache::FILE), bytes).unwrap();
    let cache = PipelineCacheFile::open(&gpu.device, &gpu.adapter.get_info(), dir)
        .expect("a cache, empty or not");
    let loaded = cache.loaded;
    // Dropping saves: put the file back as it was for the next case.
    drop(cache);
    loaded
}

#[test]
fn the_pipeline_cache_is_kept_and_a_foreign_or_broken_one_ignored() {
    let mut gpu = gpu();
    let dir = temp_dir("pipeline-cache");
    assert!(
        gpu.device
            .features()
            .contains(wgpu::Features::PIPELINE_CACHE),
        "lavapipe keeps a pipeline cache"
    );
    // A launch: the cache starts empty, the scene's pipelines go through it, it is saved.
    gpu.use_pipeline_cache(&dir);
    assert!(gpu.pipeline_cache.as_ref().is_some_and(|c| !c.loaded));
    let assets = SceneAssets::load(&assets_dir(), None).unwrap();
    drop(StillRenderer::new(&gpu, &assets, 64, 64).unwrap());
    let saved = gpu.save_pipeline_cache().expect("saved");
    assert!(saved > 64, "{saved} bytes");
    gpu.pipeline_cache = None;
    let good = std::fs::read(dir.join(pipeline_cache::FILE)).unwrap();
    // The next launch starts from it; another driver's file, one cut short or one corrupt
    // does not reach the driver (one logged line each).
    assert!(loads(&gpu, &dir, &good), "the saved cache");
    let foreign = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pipeline-cache/other-driver.bin"),
    )
    .unwrap();
    assert!(!loads(&gpu, &dir, &foreign), "another driver's cache");
    assert!(
        !loads(&gpu, &dir, &good[..good.len() / 2]),
        "a truncated cache"
    );
    let mut corrupt = good.clone();
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0x5a;
    assert!(!loads(&gpu, &dir, &corrupt), "a corrupt cache");
    let _ = std::fs::remove_dir_all(&dir);
}

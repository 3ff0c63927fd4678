//! The GLES path: the whole character renders under OpenGL (llvmpipe on CI) with the same
//! shaders, inside downlevel limits (16 KiB uniform blocks, no storage buffers).

use std::path::Path;

use dermis_engine::render::Gpu;
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};

#[test]
fn character_renders_under_gl() {
    let gpu = Gpu::headless_on(wgpu::Backends::GL)
        .unwrap_or_else(|e| panic!("GL backend: {e} (install libegl1 and Mesa)"));
    assert_eq!(
        gpu.adapter.get_info().backend,
        wgpu::Backend::Gl,
        "{}",
        gpu.adapter_name()
    );
    println!("adapter: {}", gpu.adapter_name());
    let assets =
        SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None).unwrap();
    let mut still = StillRenderer::new(&gpu, &assets, 120, 90).unwrap();
    for model in ShadingModel::ALL {
        let img = still
            .render(
                &gpu,
                &assets,
                &Shot {
                    clip: 1,
                    time: 0.2,
                    props: false,
                    fill: 1.0,
                    ..Shot::new(model, SKIN1)
                },
            )
            .unwrap();
        let bg = &img.pixels[0..3];
        let covered = img
            .pixels
            .chunks_exact(4)
            .filter(|p| (0..3).any(|k| p[k].abs_diff(bg[k]) > 3))
            .count();
        let coverage = covered as f32 / (img.width * img.height) as f32;
        println!("{model}: coverage {:.1} %", coverage * 100.0);
        assert!(
            (0.05..=0.6).contains(&coverage),
            "{model} under GL: coverage {coverage}"
        );
    }
}

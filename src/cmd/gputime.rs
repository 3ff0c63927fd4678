//! GPU pass timing shared by the benches: the close-up character pass per shading model,
//! interleaved so slow drift affects every model alike.

use dermis_engine::render::passes::PassId;
use dermis_engine::render::Gpu;
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_engine::still::{Shot, StillRenderer};

/// Zooms `shot` until the character covers at least `min_coverage` of the frame; returns the
/// coverage reached.
pub fn frame_close_up(
    gpu: &Gpu,
    still: &mut StillRenderer,
    assets: &SceneAssets,
    shot: &mut Shot,
    min_coverage: f64,
) -> Result<f64, String> {
    let mut coverage = 0.0;
    for fill in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0] {
        shot.fill = fill;
        let image = still.render(
            gpu,
            assets,
            &Shot {
                shading: Some(ShadingModel::BASELINE),
                props: false,
                ..shot.clone()
            },
        )?;
        let bg = &image.pixels[0..3];
        let covered = image
            .pixels
            .chunks_exact(4)
            .filter(|p| (0..3).any(|k| p[k].abs_diff(bg[k]) > 3))
            .count();
        coverage = covered as f64 / (image.width * image.height) as f64;
        if coverage >= min_coverage {
            break;
        }
    }
    Ok(coverage)
}

/// `rounds` timings (ms) of `shot`'s character pass (no props) for each of `models`
/// (`None`: unlit).
pub fn time_models(
    gpu: &Gpu,
    (still, assets): (&mut StillRenderer, &SceneAssets),
    shot: &Shot,
    models: &[Option<ShadingModel>],
    rounds: usize,
    mut tick: impl FnMut(),
) -> Result<Vec<Vec<f64>>, String> {
    let with = |shading| Shot {
        shading,
        props: false,
        ..shot.clone()
    };
    let mut out = vec![Vec::with_capacity(rounds); models.len()];
    for _ in 0..3 {
        still.time_pass(gpu, assets, &with(Some(ShadingModel::BASELINE)));
    }
    for r in 0..rounds {
        for k in 0..models.len() {
            let i = (k + r) % models.len();
            out[i].push(
                still
                    .time_pass(gpu, assets, &with(models[i]))
                    .ok_or("timestamp read failed")?,
            );
        }
        tick();
    }
    Ok(out)
}

/// `rounds` timings (ms) of the close-up pass with the showroom props (the floor) for each of
/// `models`, blob shadows off (`[0]`) and on (`[1]`); the pair's order alternates by round
/// and model. The still's blob shadows must be built
/// ([`StillRenderer::enable_blob_shadows`]); they are left on.
pub fn time_blob_shadows(
    gpu: &Gpu,
    (still, assets): (&mut StillRenderer, &SceneAssets),
    shot: &Shot,
    models: &[ShadingModel],
    rounds: usize,
    mut tick: impl FnMut(),
) -> Result<Vec<[Vec<f64>; 2]>, String> {
    let with = |model| Shot {
        shading: Some(model),
        props: true,
        ..shot.clone()
    };
    let mut out = vec![[Vec::with_capacity(rounds), Vec::with_capacity(rounds)]; models.len()];
    for on in [false, true] {
        still.renderer.switch(PassId::blobs, on);
        still.time_pass(gpu, assets, &with(ShadingModel::BASELINE));
    }
    for r in 0..rounds {
        for k in 0..models.len() {
            let i = (k + r) % models.len();
            for j in 0..2 {
                let on = (j + k + r) % 2 == 1;
                still.renderer.switch(PassId::blobs, on);
                out[i][usize::from(on)].push(
                    still
                        .time_pass(gpu, assets, &with(models[i]))
                        .ok_or("timestamp read failed")?,
                );
            }
        }
        tick();
    }
    still.renderer.switch(PassId::blobs, true);
    Ok(out)
}

/// The fraction of the frame's pixels that blob shadows change in `shot` (drawn with the
/// props): whether the blobs are in view at all. The still's blob shadows must be built;
/// they are left on.
pub fn blob_shadow_coverage(
    gpu: &Gpu,
    still: &mut StillRenderer,
    assets: &SceneAssets,
    shot: &Shot,
) -> Result<f64, String> {
    let shot = Shot {
        props: true,
        ..shot.clone()
    };
    still.renderer.switch(PassId::blobs, false);
    let off = still.render(gpu, assets, &shot)?;
    still.renderer.switch(PassId::blobs, true);
    let on = still.render(gpu, assets, &shot)?;
    let changed = off
        .pixels
        .chunks_exact(4)
        .zip(on.pixels.chunks_exact(4))
        .filter(|(a, b)| a[..3] != b[..3])
        .count();
    Ok(changed as f64 / (off.width * off.height) as f64)
}

//! GPU pass timing shared by the benches: the close-up character pass per shading model,
//! interleaved so slow drift affects every model alike.

use dermis_core::render::Gpu;
use dermis_core::scene::SceneAssets;
use dermis_core::shading::ShadingModel;
use dermis_core::still::{Shot, StillRenderer};

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
                shading: Some(ShadingModel::Ward),
                props: false,
                ..*shot
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

/// `rounds` timings (ms) of the character pass for each of `models` (`None`: unlit).
pub fn time_models(
    gpu: &Gpu,
    still: &mut StillRenderer,
    models: &[Option<ShadingModel>],
    rounds: usize,
    mut tick: impl FnMut(),
) -> Result<Vec<Vec<f64>>, String> {
    let mut out = vec![Vec::with_capacity(rounds); models.len()];
    for _ in 0..3 {
        still.time_character_pass(gpu, Some(ShadingModel::Ward));
    }
    for r in 0..rounds {
        for k in 0..models.len() {
            let i = (k + r) % models.len();
            out[i].push(
                still
                    .time_character_pass(gpu, models[i])
                    .ok_or("timestamp read failed")?,
            );
        }
        tick();
    }
    Ok(out)
}

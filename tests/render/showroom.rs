//! The main menu's showroom on the real renderer (lavapipe at least): the game's menu frame,
//! rendered headless as the shells render it (session update → uploads → one pass with the
//! UI), shows the character close up — it covers a good part of the frame — and two shading
//! models give visibly different skin. `DERMIS_SHOWROOM_PNG=prefix` saves the frames.

use crate::common;

use std::path::Path;

use common::Rig;
use dermis_engine::render::RgbaImage;
use dermis_engine::shading::ShadingModel;
use dermis_game::rules::Screen;

const W: u32 = 960;
const H: u32 = 540;

/// The showroom's frames on the shared rig.
impl Rig {
    /// Renders the frame last updated: the game's own frame, or with `character: false`
    /// the same frame without the character.
    fn render(&mut self, character: bool) -> RgbaImage {
        self.prepare(|p| p.draw.character = character);
        self.draw()
    }

    /// The menu frame with `model` chosen, at the same moment (no time passes).
    fn frame_with(&mut self, model: ShadingModel) -> RgbaImage {
        self.session.settings.set_shading_model(model);
        self.update(0.0);
        assert_eq!(self.session.draw_set().shading, Some(model));
        self.render(true)
    }
}

fn rgb(img: &RgbaImage, i: usize) -> [i32; 3] {
    let p = &img.pixels[i * 4..i * 4 + 3];
    [p[0] as i32, p[1] as i32, p[2] as i32]
}

fn save(img: &RgbaImage, name: &str) {
    if let Ok(prefix) = std::env::var("DERMIS_SHOWROOM_PNG") {
        img.save_png(Path::new(&format!("{prefix}{name}.png")))
            .unwrap();
    }
}

#[test]
fn the_menu_shows_the_character_close_up_and_the_models_differ() {
    let mut rig = Rig::new(W, H);
    let scope = rig
        .gpu
        .device
        .push_error_scope(wgpu::ErrorFilter::Validation);
    // Half a second on the menu: the light has moved off its start, the character idles.
    let viewport = rig.viewport();
    for _ in 0..30 {
        rig.session
            .update(1.0 / 60.0, &rig.assets.character, viewport);
    }
    assert_eq!(rig.session.game.screen(), Screen::Main);
    let ward = rig.frame_with(ShadingModel::Ward);
    let empty = rig.render(false);
    let burley = rig.frame_with(ShadingModel::Burley);
    save(&ward, "ward");
    save(&burley, "burley");
    save(&empty, "empty");
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");

    // The character: where the frame differs from the same frame without it.
    let n = (W * H) as usize;
    let mask: Vec<bool> = (0..n)
        .map(|i| {
            let (a, b) = (rgb(&ward, i), rgb(&empty, i));
            (0..3).any(|k| (a[k] - b[k]).abs() > 4)
        })
        .collect();
    let covered = mask.iter().filter(|m| **m).count();
    let fraction = covered as f64 / n as f64;
    println!(
        "the character covers {:.1} % of the frame",
        fraction * 100.0
    );
    assert!(
        fraction > 0.10,
        "the character covers only {:.1} % of the menu frame",
        fraction * 100.0
    );
    // Skin: character pixels where red dominates (the tank top is teal, the shorts navy).
    let skin: Vec<usize> = (0..n)
        .filter(|&i| {
            let c = rgb(&ward, i);
            mask[i] && c[0] > 40 && c[0] > c[2] + 15
        })
        .collect();
    assert!(
        skin.len() > n / 50,
        "too little skin in view: {} px",
        skin.len()
    );
    let diffs: Vec<i32> = skin
        .iter()
        .map(|&i| {
            let (a, b) = (rgb(&ward, i), rgb(&burley, i));
            (0..3).map(|k| (a[k] - b[k]).abs()).sum::<i32>()
        })
        .collect();
    let mean = diffs.iter().map(|d| *d as f64).sum::<f64>() / diffs.len() as f64 / 3.0;
    let visible = diffs.iter().filter(|d| **d >= 3 * 6).count();
    println!(
        "skin: {} px, mean |Δ| ward vs burley {mean:.2}/255, {visible} px differ by ≥ 6/255",
        skin.len()
    );
    assert!(
        mean > 3.0 && visible > skin.len() / 10,
        "ward and burley look alike in the showroom: mean |Δ| {mean:.2}, {visible} px"
    );
}

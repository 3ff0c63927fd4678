//! The showroom's scanned head on the real renderer (lavapipe at least), through the game's
//! own path (session update → uploads → the game's pass): with the head loaded the menu
//! offers it, and chosen it is drawn instead of the runner — skin in view, a different
//! picture from the runner's, changing as the key light orbits, the model switch still
//! working, its credit on screen, finite radiance — and showing it creates no GPU object.
//! `DERMIS_SHOWROOM_PNG=prefix` saves the frames.

use crate::common;

use std::path::Path;

use common::Rig;
use dermis_engine::asset::head::CREDIT_LINES;
use dermis_engine::render::{LiveObjects, Offscreen, RgbaImage};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameGpu, Subject};
use dermis_game::rules::Screen;

const W: u32 = 640;
const H: u32 = 360;

fn rgb(img: &RgbaImage, i: usize) -> [i32; 3] {
    let p = &img.pixels[i * 4..i * 4 + 3];
    [p[0] as i32, p[1] as i32, p[2] as i32]
}

fn differ(a: &RgbaImage, b: &RgbaImage, i: usize, by: i32) -> bool {
    let (a, b) = (rgb(a, i), rgb(b, i));
    (0..3).any(|k| (a[k] - b[k]).abs() > by)
}

/// Mean |Δ| (per channel, /255) of two frames over `pixels`.
fn mean_diff(a: &RgbaImage, b: &RgbaImage, pixels: &[usize]) -> f64 {
    let sum: i64 = pixels
        .iter()
        .map(|&i| {
            let (x, y) = (rgb(a, i), rgb(b, i));
            (0..3).map(|k| (x[k] - y[k]).abs() as i64).sum::<i64>()
        })
        .sum();
    sum as f64 / (pixels.len().max(1) * 3) as f64
}

fn save(img: &RgbaImage, name: &str) {
    if let Ok(prefix) = std::env::var("DERMIS_SHOWROOM_PNG") {
        img.save_png(Path::new(&format!("{prefix}{name}.png")))
            .unwrap();
    }
}

/// The game's own frame: the scene and the menu's UI.
fn menu_frame(rig: &mut Rig) -> RgbaImage {
    rig.prepare(|_| {});
    rig.draw()
}

fn credit_shown(rig: &Rig) -> bool {
    rig.session
        .ui
        .label_rects()
        .any(|(text, _)| text == CREDIT_LINES[0])
}

#[test]
fn the_showroom_shows_the_scanned_head_under_its_orbiting_light() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let assets = SceneAssets::load(&root, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .with_head(&root);
    assert!(assets.head.wait().is_some(), "the head did not load");
    let mut rig = Rig::with_assets(W, H, assets);
    assert!(rig.gg.has_head());
    let scope = rig
        .gpu
        .device
        .push_error_scope(wgpu::ErrorFilter::Validation);
    // Half a second on the menu with the runner (the option starts on it).
    for _ in 0..30 {
        rig.update(1.0 / 60.0);
    }
    assert_eq!(rig.session.game.screen(), Screen::Main);
    assert_eq!(rig.session.shown_subject(), Subject::Runner);
    assert!(!credit_shown(&rig), "the head's credit without the head");
    let runner = rig.shoot_frame(true);
    // Every model's pipeline in (the background builder's), before counting.
    rig.gg.finish_loading(&rig.gpu);
    let live = LiveObjects::read(&rig.gpu.device);

    // The head, at the same moment.
    rig.session.gui.set_subject(Subject::Head);
    rig.update(0.0);
    assert_eq!(rig.session.shown_subject(), Subject::Head);
    assert!(!rig.session.draw_set().props, "props around the head");
    assert!(credit_shown(&rig), "the head is shown without its credit");
    let head = rig.shoot_frame(true);
    let empty = rig.shoot_frame(false);
    let menu = menu_frame(&mut rig);
    // Four seconds later: the light has turned a quarter of its orbit.
    for _ in 0..240 {
        rig.update(1.0 / 60.0);
    }
    let later = rig.shoot_frame(true);
    // The model switch on the head.
    rig.session.settings.set_shading_model(ShadingModel::Ward);
    rig.update(0.0);
    let ward = rig.shoot_frame(true);
    rig.session.settings.set_shading_model(ShadingModel::Burley);
    rig.update(0.0);
    let burley = rig.shoot_frame(true);
    // Back to the runner: its frame again.
    rig.session.gui.set_subject(Subject::Runner);
    rig.update(0.0);
    assert_eq!(rig.session.shown_subject(), Subject::Runner);
    assert!(rig.session.draw_set().props);
    // Counted where the first count was: after a frame was submitted and read back.
    let runner_again = rig.shoot_frame(true);
    assert_eq!(
        LiveObjects::read(&rig.gpu.device),
        live,
        "showing the head created or dropped GPU objects"
    );
    let n = (W * H) as usize;
    for (img, name) in [
        (&runner, "runner"),
        (&menu, "head-menu"),
        (&head, "head"),
        (&empty, "head-empty"),
        (&later, "head-later"),
        (&ward, "head-ward"),
        (&burley, "head-burley"),
        (&runner_again, "runner-again"),
    ] {
        save(img, name);
    }
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");

    let mask: Vec<usize> = (0..n).filter(|&i| differ(&head, &empty, i, 4)).collect();
    let covered = mask.len() as f64 / n as f64;
    let skin: Vec<usize> = mask
        .iter()
        .copied()
        .filter(|&i| {
            let c = rgb(&head, i);
            c[0] > 40 && c[0] > c[2] + 15
        })
        .collect();
    let vs_runner = (0..n).filter(|&i| differ(&head, &runner, i, 8)).count();
    let orbit = mean_diff(&head, &later, &skin);
    let models = mean_diff(&ward, &burley, &skin);
    println!(
        "head covers {:.1} % ({} skin px); {:.1} % of the frame differs from the runner's; \
         mean |Δ| over the skin: light 4 s later {orbit:.2}/255, ward vs burley {models:.2}/255",
        covered * 100.0,
        skin.len(),
        vs_runner as f64 / n as f64 * 100.0
    );
    assert!(covered > 0.08, "the head covers {:.1} %", covered * 100.0);
    assert!(skin.len() > n / 20, "too little skin: {} px", skin.len());
    assert!(
        vs_runner > n / 10,
        "the head's frame looks like the runner's"
    );
    assert!(orbit > 3.0, "the orbiting light changes little: {orbit:.2}");
    assert!(
        models > 1.0,
        "ward and burley alike on the head: {models:.2}"
    );

    // Finite radiance on the head: the game's GPU side on a float target (raw radiance).
    let format = wgpu::TextureFormat::Rgba16Float;
    let mut float_gg = GameGpu::new(&rig.gpu, format, &rig.assets, rig.session.shading()).unwrap();
    let target = Offscreen::with_format(&rig.gpu, W, H, format);
    rig.session.gui.set_subject(Subject::Head);
    rig.session
        .update(0.0, &rig.assets.character, rig.viewport());
    float_gg.finish_loading(&rig.gpu);
    float_gg.renderer.resize(&rig.gpu, (W, H));
    let head = float_gg.head.clone();
    let packet = rig
        .session
        .extract(&rig.assets.character, head.as_deref(), false);
    let frame = float_gg.prepare(&rig.gpu, &packet);
    float_gg
        .renderer
        .draw_offscreen(&rig.gpu, &target, &frame)
        .unwrap();
    let radiance = target.read_f16(&rig.gpu);
    let bad = radiance
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite() || *c < 0.0))
        .count();
    assert_eq!(bad, 0, "{bad} pixels not finite or negative");
    let lit = skin
        .iter()
        .filter(|&&i| radiance[i][0] > 1e-3 && radiance[i][0] >= radiance[i][2])
        .count();
    assert!(
        lit > skin.len() / 2,
        "the head is dark on the float target: {lit} of {} skin px",
        skin.len()
    );
}

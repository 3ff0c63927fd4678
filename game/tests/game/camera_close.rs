//! The close-up play camera (C key / the play screen's "View" button): the runner is large
//! enough to see its skin while playing — five times the wide camera's share of the screen,
//! more than half the screen's height (from the hips up) — in landscape and portrait, every
//! Play frame keeps its head in view (jumps included), the switch glides rather than cuts,
//! and the choice is a saved setting.

use dermis_engine::scene::SceneAssets;
use dermis_engine::scene::CHARACTER;
use dermis_engine::ui::Insets;
use dermis_game::app::{Key, Session, Viewport};
use dermis_game::rules::Screen;
use std::path::Path;

const FRAME: f32 = 1.0 / 60.0;

/// Mean coverage and mean on-screen height (fraction of the screen) of the runner over the
/// Play frames of an autoplayed session.
fn play(close: bool, width: u32, height: u32) -> (f32, f32) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let assets = SceneAssets::load(&root, None).unwrap_or_else(|e| panic!("{e}"));
    let character = &assets.character;
    let mut s = Session::new(character, 5, None, true);
    if close {
        s.key(Key::Camera);
        assert!(s.settings.close_camera);
    }
    let vp = Viewport {
        width,
        height,
        scale: 1.0,
        insets: Insets::default(),
    };
    let aspect = width as f32 / height as f32;
    let (mut coverage, mut tall, mut n) = (0.0, 0.0, 0);
    for i in 0..2400 {
        s.update(FRAME, character, vp);
        if s.game.screen() != Screen::Play || s.showroom.weight() > 0.0 {
            continue;
        }
        let at = format!("close {close}, {width}x{height}, frame {i}");
        assert!(s.character_visible, "culled: {at}");
        assert!(s.needs.coverage > 0.004, "{}: {at}", s.needs.coverage);
        let (feet, _) = s.game.player_transform();
        let m = s.view().view_proj(aspect);
        let ndc = |p: glam::Vec3| {
            let c = m * p.extend(1.0);
            assert!(c.w > 0.0, "behind the camera: {at}");
            c.truncate() / c.w
        };
        let (a, b) = (ndc(feet), ndc(feet + glam::Vec3::Y * CHARACTER.height));
        // The head in view (the feet may leave the bottom edge in the close-up).
        assert!(
            b.x.abs() <= 1.0 && b.y.abs() <= 1.0,
            "head off screen: {at}"
        );
        coverage += s.needs.coverage;
        // The part of the body on screen (the legs leave the bottom edge in the close-up).
        tall += (b.y.min(1.0) - a.y.max(-1.0)) * 0.5;
        n += 1;
    }
    assert!(n > 600, "only {n} play frames");
    (coverage / n as f32, tall / n as f32)
}

#[test]
fn the_close_up_shows_the_runner_large_in_every_frame() {
    for (w, h) in [(1280, 720), (720, 1280)] {
        let (wide_cov, wide_h) = play(false, w, h);
        let (close_cov, close_h) = play(true, w, h);
        println!(
            "{w}x{h}: coverage {wide_cov:.3} → {close_cov:.3}, height {wide_h:.2} → {close_h:.2} of the screen"
        );
        assert!(
            close_cov > 5.0 * wide_cov,
            "{w}x{h}: close {close_cov} vs wide {wide_cov}"
        );
        assert!(
            close_h > 0.5 && close_h > 2.0 * wide_h,
            "{w}x{h}: the runner is {close_h} of the screen tall (wide: {wide_h})"
        );
    }
}

#[test]
fn switching_the_camera_glides_and_is_saved() {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    let dir = std::env::temp_dir().join(format!("dermis-camera-{}", std::process::id()));
    let path = dir.join("settings.txt");
    let mut s = Session::new(&model, 2, Some(path.clone()), true);
    let vp = Viewport {
        width: 640,
        height: 360,
        scale: 1.0,
        insets: Insets::default(),
    };
    for _ in 0..180 {
        s.update(FRAME, &model, vp);
    }
    assert_eq!(s.game.screen(), Screen::Play);
    assert_eq!(s.close_up(), 0.0);
    s.key(Key::Camera);
    let mut eye = s.view().eye;
    let mut between = 0;
    for _ in 0..60 {
        s.update(FRAME, &model, vp);
        let step = s.view().eye - eye;
        // The runner moves forward; the camera's sideways and vertical moves stay small.
        assert!(step.x.abs() < 0.2 && step.y.abs() < 0.2, "a cut: {step}");
        eye = s.view().eye;
        between += (s.close_up() > 0.0 && s.close_up() < 1.0) as u32;
    }
    assert!(between > 10, "a glide, not a cut: {between} frames");
    assert_eq!(s.close_up(), 1.0);
    // Saved: a new session starts with the close-up.
    let again = Session::new(&model, 2, Some(path), true);
    assert!(again.settings.close_camera);
    assert_eq!(again.close_up(), 1.0);
    let _ = std::fs::remove_dir_all(&dir);
}

//! The camera never loses the runner: over many autoplayed runs — deaths, game-over screens,
//! replays, the menu's showroom blending to play — with frame times from 1/240 s to hitches
//! of a quarter second, in landscape and portrait, every frame of the Play and GameOver
//! screens shows the character (a real share of the screen, in front of the camera) and the
//! camera stays above the ground, looking ahead rather than at the floor. (A player once saw
//! one frame of floor without the character; this is the hunt for that edge case.)

use dermis_engine::scene::SceneAssets;
use dermis_engine::ui::Insets;
use dermis_game::app::{Session, Viewport};
use dermis_game::rules::Screen;
use std::path::Path;

/// Frame times: mostly steady, with the odd long frame (a hitch, a window drag).
fn dt(i: u64, seed: u64) -> f32 {
    let h = (i ^ seed.rotate_left(17))
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .rotate_left(29);
    match h % 100 {
        0 => 0.25,
        1..=3 => 0.1,
        4..=20 => 1.0 / 240.0,
        21..=40 => 1.0 / 30.0,
        _ => 1.0 / 60.0,
    }
}

#[test]
fn every_play_and_game_over_frame_shows_the_runner() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let assets = SceneAssets::load(&root, None).unwrap_or_else(|e| panic!("{e}"));
    let character = &assets.character;
    let mut worst = f32::INFINITY;
    let mut runs = 0;
    for (seed, (width, height)) in [(1u64, (1280, 720)), (2, (720, 1280)), (3, (2400, 1080))] {
        let mut s = Session::new(character, seed, None, true);
        let viewport = Viewport {
            width,
            height,
            scale: 1.0,
            insets: Insets::default(),
        };
        let aspect = width as f32 / height as f32;
        for i in 0..20_000u64 {
            s.update(dt(i, seed), character, viewport);
            let screen = s.game.screen();
            if screen == Screen::Main {
                continue;
            }
            let pose = s.view();
            let (feet, _) = s.game.player_transform();
            let at = format!(
                "seed {seed}, {width}x{height}, frame {i}, {screen:?}, run {}, feet {feet}, eye {}, look {}",
                s.game.runs(),
                pose.eye,
                pose.look
            );
            // In front of the camera and covering a real share of the screen.
            assert!(s.character_visible, "character culled: {at}");
            let coverage = s.needs.coverage;
            assert!(coverage > 0.004, "coverage {coverage}: {at}");
            worst = worst.min(coverage);
            // Above the ground and looking ahead: never down at the floor.
            let dir = (pose.look - pose.eye).normalize();
            assert!(pose.eye.y > 0.3, "eye below the ground's clearance: {at}");
            assert!(dir.y > -0.7, "looking down at the floor ({dir}): {at}");
            let centre = feet + glam::Vec3::Y;
            let clip = pose.view_proj(aspect) * centre.extend(1.0);
            assert!(clip.w > 0.0, "the runner is behind the camera: {at}");
        }
        runs += s.game.runs();
    }
    assert!(
        runs >= 6,
        "only {runs} runs: the hunt needs deaths and replays"
    );
    println!("{runs} runs; smallest coverage in play / game over: {worst:.4}");
}

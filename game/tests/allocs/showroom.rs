//! The main menu's showroom (CPU side): the camera frames the character's head and torso
//! close up, inside the screen and clear of the menu's panel, title and hint, in landscape
//! and portrait with safe-area insets; the key light orbits; the character idles; starting a
//! run hands the camera back to the follow camera (and game over keeps it); and a menu frame
//! allocates nothing.

use dermis_engine::asset::Model;
use dermis_engine::scene::{key_light, CHARACTER};
use dermis_engine::ui::{Insets, Rect};
use dermis_game::app::menu;
use dermis_game::app::showroom::{self, BUST_HI, BUST_LO, LIGHT_PERIOD_S};
use dermis_game::app::{Key, Session, Viewport};
use dermis_game::rules::{Clip, Input, Screen};
use glam::{Vec3, Vec4Swizzles};

const FRAME: f32 = 1.0 / 60.0;

fn session() -> (Session, Model) {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    let s = Session::new(&model, 3, None, false);
    (s, model)
}

/// A 16:9 window, a landscape phone (notch left, gesture bar right), a portrait phone (notch
/// top, gesture bar bottom), a portrait tablet.
fn viewports() -> [Viewport; 4] {
    let vp = |width, height, scale, insets| Viewport {
        width,
        height,
        scale,
        insets,
    };
    [
        vp(1280, 720, 1.0, Insets::ZERO),
        vp(
            2400,
            1080,
            2.75,
            Insets {
                left: 132.0,
                top: 0.0,
                right: 66.0,
                bottom: 0.0,
            },
        ),
        vp(
            1080,
            2400,
            2.75,
            Insets {
                left: 0.0,
                top: 132.0,
                right: 0.0,
                bottom: 66.0,
            },
        ),
        vp(1600, 2560, 2.0, Insets::ZERO),
    ]
}

/// The head-and-torso bound of the character at `feet` projected by the session's drawn
/// camera: its screen rectangle in logical units.
fn bust_on_screen(s: &Session, vp: &Viewport, feet: Vec3) -> Rect {
    let aspect = vp.width as f32 / vp.height as f32;
    let m = s.view().view_proj(aspect);
    let (w, h) = (vp.width as f32 / vp.scale, vp.height as f32 / vp.scale);
    let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { BUST_LO.x } else { BUST_HI.x },
            if i & 2 == 0 { BUST_LO.y } else { BUST_HI.y },
            if i & 4 == 0 { BUST_LO.z } else { BUST_HI.z },
        );
        let p = m * (feet + c).extend(1.0);
        assert!(p.w > 0.0, "a corner behind the camera");
        let ndc = p.xy() / p.w;
        let (x, y) = ((ndc.x + 1.0) * 0.5 * w, (1.0 - ndc.y) * 0.5 * h);
        lo = [lo[0].min(x), lo[1].min(y)];
        hi = [hi[0].max(x), hi[1].max(y)];
    }
    Rect::new(lo[0], lo[1], hi[0] - lo[0], hi[1] - lo[1])
}

fn overlap(a: &Rect, b: &Rect) -> bool {
    a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h
}

#[test]
fn the_menu_frames_head_and_torso_close_up_clear_of_the_panel() {
    let _shared = crate::shared();
    for vp in viewports() {
        let (mut s, model) = session();
        for _ in 0..3 {
            s.update(FRAME, &model, vp);
        }
        assert_eq!(s.game.screen(), Screen::Main);
        let (feet, _) = s.game.player_transform();
        let bust = bust_on_screen(&s, &vp, feet);
        let (w, h) = (vp.width as f32 / vp.scale, vp.height as f32 / vp.scale);
        let tag = format!("{}x{}@{}", vp.width, vp.height, vp.scale);
        // Inside the central part of the screen (5 % in from every edge) and inside the safe
        // area.
        let central = Rect::new(0.05 * w, 0.05 * h, 0.9 * w, 0.9 * h);
        let safe = s.ui.safe_rect();
        for r in [central, safe] {
            assert!(
                bust.x >= r.x
                    && bust.y >= r.y
                    && bust.x + bust.w <= r.x + r.w
                    && bust.y + bust.h <= r.y + r.h,
                "{tag}: the bust {bust:?} is not inside {r:?}"
            );
        }
        // A close-up: head and torso fill a good part of the screen.
        assert!(
            bust.h > 0.35 * h || bust.w > 0.6 * w,
            "{tag}: the bust {bust:?} is small on a {w}x{h} screen"
        );
        // Not under the panel, the title or the hint.
        let panels: Vec<Rect> = s.ui.panel_rects().collect();
        assert_eq!(panels.len(), 1, "{tag}");
        assert!(
            !overlap(&bust, &panels[0]),
            "{tag}: the panel {:?} covers the bust {bust:?}",
            panels[0]
        );
        for (text, r) in s.ui.label_rects() {
            if text == menu::TITLE || menu::HINT.contains(&text) {
                assert!(!overlap(&bust, &r), "{tag}: {text:?} {r:?} over the bust");
            }
        }
        // Landscape: the panel beside the character; portrait: below it.
        if w > h {
            assert!(panels[0].x >= bust.x + bust.w, "{tag}: panel not beside");
        } else {
            assert!(panels[0].y >= bust.y + bust.h, "{tag}: panel not below");
        }
        // The character faces the camera (it runs towards +z; the eye is in front of it).
        assert!(s.view().eye.z > feet.z + 1.0, "{tag}: {:?}", s.view());
        // Idle, not running.
        let anim = s.game.anim_state();
        assert_eq!(anim.blend[1], (Clip::Idle as usize, 1.0), "{tag}");
        assert!(s.character_visible && s.needs.lit, "{tag}");
    }
}

#[test]
fn the_key_light_orbits_the_character() {
    let _shared = crate::shared();
    let (mut s, model) = session();
    let vp = viewports()[0];
    s.update(FRAME, &model, vp);
    let (feet, _) = s.game.player_transform();
    let chest = CHARACTER.chest_at(feet);
    let dir0 = (s.light.position - chest).normalize();
    // Two seconds later the light has visibly moved (it turns slowest in front).
    for _ in 0..120 {
        s.update(FRAME, &model, vp);
    }
    let dir1 = (s.light.position - chest).normalize();
    let angle = dir0.dot(dir1).clamp(-1.0, 1.0).acos().to_degrees();
    assert!(angle > 10.0, "the light turned {angle:.1}°");
    // The orbit: round the character once per period (it passes behind it: backlit), at one
    // height and reach, always turning the same way.
    let a = showroom::orbit_light(feet, 1.0);
    let c = showroom::orbit_light(feet, 1.0 + LIGHT_PERIOD_S);
    assert!(a.distance(c) < 1e-3, "{a} {c}");
    let steps = 64;
    let mut behind = 0;
    let mut prev = showroom::orbit_light(feet, 0.0) - feet;
    for i in 1..=steps {
        let p = showroom::orbit_light(feet, LIGHT_PERIOD_S * i as f32 / steps as f32) - feet;
        assert!((p.y - a.y + feet.y).abs() < 1e-5);
        assert!((p.with_y(0.0).length() - (a - feet).with_y(0.0).length()).abs() < 1e-3);
        // Always the same way round (from +z towards +x).
        let turn = prev.z * p.x - prev.x * p.z;
        assert!(turn > 0.0, "step {i}: the light turned back");
        if p.z < -0.5 {
            behind += 1;
        }
        prev = p;
    }
    assert!(
        behind > 0 && behind < steps / 2,
        "{behind} of {steps} steps behind"
    );
    // It stays as far from the chest as the play key light (same exposure).
    let key = key_light(feet).position.distance(chest);
    assert!((a.distance(chest) - key).abs() < 1e-3, "{key}");
}

#[test]
fn starting_a_run_returns_to_the_follow_camera() {
    let _shared = crate::shared();
    let (mut s, model) = session();
    let vp = viewports()[0];
    for _ in 0..10 {
        s.update(FRAME, &model, vp);
    }
    assert_ne!(s.view(), s.camera.pose(), "the menu shows the showroom");
    s.key(Key::Jump);
    s.update(FRAME, &model, vp);
    assert_eq!(s.game.screen(), Screen::Play);
    // The blend: the eye swings round the character, never into it.
    let frames = (showroom::BLEND_S / FRAME).ceil() as usize + 1;
    let mut between = 0;
    for _ in 0..frames {
        let (feet, _) = s.game.player_transform();
        let capsule = CHARACTER.capsule_at(feet, 1.0);
        assert!(!capsule.contains(s.view().eye), "{:?}", s.view());
        if s.view() != s.camera.pose() {
            between += 1;
        }
        s.update(FRAME, &model, vp);
    }
    assert!(between > 10, "a blend, not a cut: {between} frames");
    assert_eq!(s.showroom.weight(), 0.0);
    assert_eq!(s.view(), s.camera.pose(), "play draws the follow camera");
    let (feet, _) = s.game.player_transform();
    assert_eq!(s.light.position, key_light(feet).position);
    // The camera is behind the runner again.
    assert!(s.view().eye.z < feet.z);
    // Game over: the follow camera still (the normal game-over view).
    while s.game.screen() == Screen::Play {
        s.game.tick(&Input::NONE);
    }
    for _ in 0..5 {
        s.update(FRAME, &model, vp);
        assert_eq!(s.game.screen(), Screen::GameOver);
        assert_eq!(s.view(), s.camera.pose());
    }
}

#[test]
fn a_menu_frame_allocates_nothing() {
    let _shared = crate::shared();
    let (mut s, model) = session();
    for vp in viewports() {
        for _ in 0..30 {
            s.update(FRAME, &model, vp);
        }
        let before = crate::thread_allocations();
        for _ in 0..120 {
            s.update(FRAME, &model, vp);
        }
        let after = crate::thread_allocations();
        assert_eq!(after - before, 0, "{vp:?}");
        assert_eq!(s.game.screen(), Screen::Main);
    }
}

#[test]
fn the_penumbra_maps_region_is_found_without_allocating() {
    let _shared = crate::shared();
    // What a frame that draws the penumbra map asks of the shadow view (the showroom's
    // close-up): where in the map the part of the subject's box the camera sees lies.
    use dermis_engine::render::ShadowView;
    let (lo, hi) = (Vec3::new(-0.3, 0.0, -0.2), Vec3::new(0.3, 1.8, 0.2));
    let map = ShadowView::fit(Vec3::new(2.0, 3.0, 1.0), 0.5 * (lo + hi), 1.0, 1024);
    let camera = dermis_engine::camera::look_at(
        Vec3::new(0.0, 1.65, 0.6),
        Vec3::new(0.0, 1.6, 0.0),
        0.6,
        16.0 / 9.0,
    );
    let before = crate::thread_allocations();
    let mut area = 0.0;
    for k in 0..100 {
        let lift = Vec3::Y * (k as f32 * 1e-3);
        if let Some((a, b)) = map.seen_box_uv(camera, (lo + lift, hi + lift)) {
            area += (b - a).max(glam::Vec2::ZERO).element_product();
        }
    }
    assert_eq!(crate::thread_allocations() - before, 0);
    // (and found something: the head is in view)
    assert!(area > 0.0);
}

#[test]
fn a_tiny_window_still_shows_the_character_close_up() {
    let _shared = crate::shared();
    // 160×90 (a test target, a thumbnail): no room beside or above the panel, so the
    // character is framed in the whole screen rather than shrunk to a speck.
    for (width, height) in [(160, 90), (90, 160), (320, 120)] {
        let vp = Viewport {
            width,
            height,
            scale: 1.0,
            insets: Insets::ZERO,
        };
        let (mut s, model) = session();
        s.update(FRAME, &model, vp);
        assert!(
            s.character_visible && s.needs.coverage > 0.1,
            "{width}x{height}: {:?}",
            s.needs
        );
    }
}

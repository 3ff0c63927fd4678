//! The main menu on small screens (a phone is 360–420 dp across, in either orientation) and
//! on a desktop window: the panel leaves most of the screen to the character, the best score
//! and every key hint are shown, nothing overlaps anything else, everything is inside the safe
//! area, and the key hints never cover the character's close-up.

use crate::screen;

use dermis_engine::scene::CHARACTER;
use dermis_engine::ui::{Insets, Rect};
use dermis_game::app::menu::{self, MARGIN};
use dermis_game::app::{Session, Viewport};
use dermis_game::rules::Screen;
use screen::{inside, on_screen};

const FRAME: f32 = 1.0 / 60.0;

fn vp(width: u32, height: u32, scale: f32) -> Viewport {
    Viewport {
        width,
        height,
        scale,
        insets: Insets::ZERO,
    }
}

fn overlap(a: &Rect, b: &Rect) -> bool {
    a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h
}

#[test]
fn small_screens_show_the_whole_menu_without_overlaps() {
    for v in [
        vp(640, 360, 1.0),
        vp(360, 640, 1.0),
        vp(1280, 720, 1.0),
        // A 6.1" phone (1080×2340 at 2.75: 393×851 dp), both ways round.
        vp(2340, 1080, 2.75),
        vp(1080, 2340, 2.75),
        // A small phone in portrait (320×568 dp).
        vp(640, 1136, 2.0),
    ] {
        let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
        let mut s = Session::new(&model, 3, None, false);
        s.game.set_best(1234);
        for _ in 0..3 {
            s.update(FRAME, &model, v);
        }
        assert_eq!(s.game.screen(), Screen::Main);
        let tag = format!("{}x{}@{}", v.width, v.height, v.scale);
        let safe = s.ui.safe_rect();
        let screen = s.ui.screen_rect();
        let labels: Vec<(String, Rect)> =
            s.ui.label_rects()
                .map(|(t, r)| (t.to_string(), r))
                .collect();
        let panels: Vec<Rect> = s.ui.panel_rects().collect();
        assert_eq!(panels.len(), 1, "{tag}");
        let panel = panels[0];
        // The panel leaves most of the screen to the character (it covers at most a third).
        assert!(
            3.0 * panel.w * panel.h <= screen.w * screen.h,
            "{tag}: the panel {panel:?} covers too much of {screen:?}"
        );
        if screen.w > screen.h {
            assert!(panel.w <= 0.45 * screen.w, "{tag}: panel {panel:?}");
        }
        // Everything is shown: the title, the best score, every hint line, both buttons.
        let shown = |text: &str| labels.iter().find(|(t, _)| t == text).map(|l| l.1);
        let title = shown(menu::TITLE).unwrap_or_else(|| panic!("{tag}: no title"));
        let best = labels
            .iter()
            .find(|(t, _)| t.starts_with("Best: 1234"))
            .unwrap_or_else(|| panic!("{tag}: no best score in {labels:?}"))
            .1;
        let hints: Vec<Rect> = menu::HINT
            .iter()
            .map(|h| shown(h).unwrap_or_else(|| panic!("{tag}: hint {h:?} not shown")))
            .collect();
        let buttons: Vec<Rect> = s.ui.button_rects().collect();
        assert_eq!(buttons.len(), 2, "{tag}");
        // Inside the safe area; the best score and the buttons inside the panel.
        for r in [title, best, panel].iter().chain(&hints).chain(&buttons) {
            assert!(
                inside(r, &safe),
                "{tag}: {r:?} outside the safe area {safe:?}"
            );
        }
        for r in [best].iter().chain(&buttons) {
            assert!(
                inside(r, &panel),
                "{tag}: {r:?} outside the panel {panel:?}"
            );
        }
        assert!(!overlap(&best, &buttons[1]), "{tag}: best under a button");
        // Nothing overlaps: title, panel, each hint line.
        let mut blocks = vec![("title", title), ("panel", panel)];
        blocks.extend(hints.iter().map(|h| ("hint", *h)));
        for (i, (a, ra)) in blocks.iter().enumerate() {
            for (b, rb) in &blocks[i + 1..] {
                assert!(!overlap(ra, rb), "{tag}: {a} {ra:?} overlaps {b} {rb:?}");
            }
        }
        // The hints are readable: at least 12 units, on one line each (inside the safe area,
        // checked above).
        for (h, r) in menu::HINT.iter().zip(&hints) {
            assert!(r.h >= 12.0, "{tag}: {h:?} {r:?}");
        }
        // The hints never cover the character: in landscape the standing body (feet to head),
        // in portrait (the panel and the hints sit over the legs) its head and torso.
        let (feet, _) = s.game.player_transform();
        let (lo, hi) = CHARACTER.box_at(feet);
        let body = if screen.w > screen.h {
            on_screen(&s, &v, lo, hi)
        } else {
            on_screen(
                &s,
                &v,
                feet + dermis_game::app::showroom::BUST_LO,
                feet + dermis_game::app::showroom::BUST_HI,
            )
        };
        for h in &hints {
            assert!(
                !overlap(&body, h),
                "{tag}: a hint {h:?} covers the body {body:?}"
            );
        }
        assert!(!overlap(&body, &title), "{tag}: the title covers the body");
        let _ = MARGIN;
    }
}

#[test]
fn the_pause_and_game_over_panels_fit_a_narrow_phone() {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    let v = vp(640, 1136, 2.0); // 320 × 568 dp
    let mut s = Session::new(&model, 3, None, false);
    s.game.start();
    while s.game.screen() == Screen::Play {
        s.game.tick(&dermis_game::rules::Input::NONE);
    }
    s.update(FRAME, &model, v);
    assert_eq!(s.game.screen(), Screen::GameOver);
    let safe = s.ui.safe_rect();
    for r in s.ui.panel_rects().chain(s.ui.button_rects()) {
        assert!(inside(&r, &safe), "{r:?} outside {safe:?}");
    }
}

#[test]
fn the_game_over_panel_leaves_the_runner_in_view() {
    // The runner stands at the crate it hit: the panel goes beside it, not over it, whichever
    // lane it died in.
    for (v, lane) in [
        (vp(640, 360, 1.0), 0),
        (vp(640, 360, 1.0), 1),
        (vp(640, 360, 1.0), -1),
        (vp(360, 640, 1.0), 1),
        (vp(1280, 720, 1.0), 0),
        (vp(2340, 1080, 2.75), 1),
    ] {
        let tag = format!("{}x{}@{} lane {lane}", v.width, v.height, v.scale);
        let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
        let mut s = Session::new(&model, 4, None, false);
        s.game.start();
        let mut turn = dermis_game::rules::Input::NONE;
        turn.left = lane < 0;
        turn.right = lane > 0;
        s.game.tick(&turn);
        s.game.debug_clear_obstacles_until(40.0);
        assert!(s
            .game
            .debug_place_obstacle(dermis_game::rules::ObstacleKind::Tall, lane, 30.0));
        for _ in 0..120 {
            s.update(FRAME, &model, v);
        }
        while s.game.screen() == Screen::Play {
            s.game.tick(&dermis_game::rules::Input::NONE);
        }
        for _ in 0..30 {
            s.update(FRAME, &model, v);
        }
        assert_eq!(s.game.screen(), Screen::GameOver, "{tag}");
        assert_eq!(s.game.lane(), lane, "{tag}");
        let (feet, _) = s.game.player_transform();
        let (lo, hi) = CHARACTER.box_at(feet);
        let body = on_screen(&s, &v, lo, hi);
        let safe = s.ui.safe_rect();
        for r in s.ui.panel_rects().chain(s.ui.button_rects()) {
            assert!(inside(&r, &safe), "{tag}: {r:?} outside {safe:?}");
            assert!(
                !overlap(&r, &body),
                "{tag}: {r:?} covers the runner {body:?}"
            );
        }
    }
}

//! The game's screens laid out inside the safe area: with display-cutout and system-bar
//! insets injected (as the Android app reads them over JNI), no button sits under a cutout,
//! on any screen, in portrait or landscape, at phone densities.

use dermis_engine::ui::{Insets, Rect, Ui};
use dermis_game::app::{GameUi, Settings};
use dermis_game::rules::{Game, Input, Screen};

/// Draws the game's current screen for one frame and returns its buttons and safe area.
fn layout(game: &mut Game, w: f32, h: f32, scale: f32, insets: Insets) -> (Vec<Rect>, Rect) {
    let mut ui = Ui::with_embedded_atlas();
    let mut screens = GameUi::new();
    let mut settings = Settings::default();
    ui.begin(w, h, scale, insets);
    screens.draw(&mut ui, game, &mut settings);
    let buttons: Vec<Rect> = ui.button_rects().collect();
    let safe = ui.safe_rect();
    ui.end();
    (buttons, safe)
}

fn inside(r: &Rect, safe: &Rect) -> bool {
    r.x >= safe.x - 1e-3
        && r.y >= safe.y - 1e-3
        && r.x + r.w <= safe.x + safe.w + 1e-3
        && r.y + r.h <= safe.y + safe.h + 1e-3
}

#[test]
fn no_button_under_a_cutout_on_any_screen() {
    // (width, height, density, insets): a portrait phone with a top notch and gesture bar,
    // the same phone in landscape (notch on the left), a tablet with no cutout.
    let cases = [
        (
            1080.0,
            2400.0,
            2.75,
            Insets {
                left: 0.0,
                top: 132.0,
                right: 0.0,
                bottom: 66.0,
            },
        ),
        (
            2400.0,
            1080.0,
            2.75,
            Insets {
                left: 132.0,
                top: 0.0,
                right: 66.0,
                bottom: 0.0,
            },
        ),
        (
            1280.0,
            720.0,
            1.0,
            Insets {
                left: 90.0,
                top: 40.0,
                right: 90.0,
                bottom: 30.0,
            },
        ),
        (1600.0, 2560.0, 2.0, Insets::ZERO),
    ];
    for (w, h, scale, insets) in cases {
        let mut game = Game::new(3);
        let mut seen = Vec::new();
        for screen in [Screen::Main, Screen::Play, Screen::GameOver] {
            match screen {
                Screen::Main => {}
                Screen::Play => game.start(),
                Screen::GameOver => {
                    // Run straight ahead until something is hit.
                    let mut ticks = 0;
                    while game.screen() != Screen::GameOver && ticks < 100_000 {
                        game.tick(&Input::NONE);
                        ticks += 1;
                    }
                }
            }
            assert_eq!(game.screen(), screen);
            let (buttons, safe) = layout(&mut game, w, h, scale, insets);
            for b in &buttons {
                assert!(
                    inside(b, &safe),
                    "{screen:?} at {w}x{h} insets {insets:?}: button {b:?} outside {safe:?}"
                );
            }
            seen.push(buttons.len());
        }
        // The menu and game-over screens have buttons to check.
        assert!(seen[0] > 0 && seen[2] > 0, "{seen:?}");
    }
}

fn overlap(a: &Rect, b: &Rect) -> bool {
    a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h
}

#[test]
fn the_main_menu_never_overlaps_its_title_or_hint() {
    // From a tall phone down to a 1280×300 strip of a window.
    for (w, h, scale) in [
        (1280.0, 720.0, 1.0),
        (1280.0, 300.0, 1.0),
        (800.0, 600.0, 1.0),
        (2400.0, 1080.0, 2.75),
        (1280.0, 240.0, 1.0),
    ] {
        let mut game = Game::new(3);
        let mut ui = Ui::with_embedded_atlas();
        let mut screens = GameUi::new();
        let mut settings = Settings::default();
        ui.begin(w, h, scale, Insets::ZERO);
        screens.draw(&mut ui, &mut game, &mut settings);
        let safe = ui.safe_rect();
        let panels: Vec<Rect> = ui.panel_rects().collect();
        let labels: Vec<(String, Rect)> =
            ui.label_rects().map(|(t, r)| (t.to_string(), r)).collect();
        let buttons: Vec<Rect> = ui.button_rects().collect();
        ui.end();
        assert_eq!(panels.len(), 1, "{w}x{h}");
        let panel = panels[0];
        let hint = labels
            .iter()
            .find(|(t, _)| t.starts_with("Space"))
            .map(|(_, r)| *r)
            .expect("the hint is always shown");
        assert!(
            inside(&panel, &safe),
            "{w}x{h}: panel {panel:?} outside {safe:?}"
        );
        assert!(
            !overlap(&panel, &hint),
            "{w}x{h}: panel {panel:?} over the hint {hint:?}"
        );
        if let Some((_, title)) = labels.iter().find(|(t, _)| t == "XICOM RUNNER") {
            assert!(!overlap(&panel, title), "{w}x{h}: panel over the title");
            assert!(!overlap(title, &hint), "{w}x{h}: title over the hint");
        } else {
            assert!(
                h / scale < 400.0,
                "{w}x{h}: the title is dropped only on short screens"
            );
        }
        assert_eq!(buttons.len(), 2, "{w}x{h}: model and start");
        for b in &buttons {
            assert!(
                inside(b, &panel),
                "{w}x{h}: button {b:?} outside the panel {panel:?}"
            );
        }
        assert!(hint.h >= 12.0, "the hint is readable: {hint:?}");
    }
}

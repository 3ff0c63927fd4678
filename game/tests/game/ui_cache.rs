//! The immediate-mode UI: vertex-cache rebuild counts, hit-testing, layout with safe-area
//! insets and density, and the game's screens.

use std::fmt::Write;

use dermis_engine::shading::ShadingModel;
use dermis_engine::ui::{Anchor, Insets, Rect, Ui, UiVertex};
use dermis_game::app::{GameUi, Settings};
use dermis_game::rules::{Game, Screen, TICK_DT};

fn ui() -> Ui {
    Ui::with_embedded_atlas()
}

fn frame(ui: &mut Ui, score: u32, buf: &mut String) -> bool {
    ui.begin(1280.0, 720.0, 1.0, Insets::ZERO);
    let panel = ui.anchored(Anchor::Top, [0.0, 10.0], [200.0, 50.0]);
    ui.panel(panel);
    buf.clear();
    write!(buf, "{score} m").unwrap();
    ui.label_centered(panel, buf, 32.0, [1.0; 4]);
    let clicked = ui.button("go", Rect::new(100.0, 200.0, 160.0, 48.0), "Go");
    ui.end();
    clicked
}

#[test]
fn rebuilds_only_when_the_score_text_changes() {
    let mut ui = ui();
    let mut buf = String::new();
    frame(&mut ui, 0, &mut buf);
    assert_eq!(ui.rebuilds(), 1, "first frame builds");
    assert!(ui.needs_upload());
    assert!(!ui.vertices().is_empty() && ui.vertices().len().is_multiple_of(6));
    ui.mark_uploaded();
    // Nothing changes: no rebuild, nothing to upload.
    for _ in 0..100 {
        frame(&mut ui, 0, &mut buf);
        assert!(!ui.rebuilt_this_frame());
        assert!(!ui.needs_upload());
    }
    assert_eq!(ui.rebuilds(), 1);
    // The score changes every 10th frame: exactly one rebuild on each of those frames.
    let mut expected = 1;
    for f in 1..=100u32 {
        let score = f / 10;
        let changed = f % 10 == 0;
        frame(&mut ui, score, &mut buf);
        if changed {
            expected += 1;
        }
        assert_eq!(ui.rebuilt_this_frame(), changed, "frame {f}");
        assert_eq!(ui.rebuilds(), expected);
    }
    // A resize or density change is a layout change.
    ui.begin(1000.0, 700.0, 1.0, Insets::ZERO);
    ui.end();
    assert_eq!(ui.rebuilds(), expected + 1);
}

#[test]
fn identical_content_in_a_new_string_does_not_rebuild() {
    let mut ui = ui();
    for _ in 0..10 {
        let text = format!("Score {}", std::hint::black_box(5));
        ui.begin(800.0, 600.0, 2.0, Insets::ZERO);
        ui.label([10.0, 10.0], &text, 20.0);
        ui.end();
    }
    assert_eq!(ui.rebuilds(), 1);
}

#[test]
fn press_and_release_inside_the_same_button_clicks() {
    let mut ui = ui();
    let mut buf = String::new();
    let button = Rect::new(100.0, 200.0, 160.0, 48.0);
    frame(&mut ui, 0, &mut buf);
    // Both in one frame.
    ui.pointer_down(150.0, 220.0);
    ui.pointer_up(160.0, 230.0);
    assert!(frame(&mut ui, 0, &mut buf));
    assert!(!frame(&mut ui, 0, &mut buf), "one click only");
    // Across frames: pressed (drawn pressed, a rebuild), then released inside.
    let before = ui.rebuilds();
    ui.pointer_down(150.0, 220.0);
    assert!(!frame(&mut ui, 0, &mut buf));
    assert!(ui.is_pointer_captured());
    assert_eq!(
        ui.rebuilds(),
        before + 1,
        "the pressed look is a content change"
    );
    assert!(!frame(&mut ui, 0, &mut buf), "held, not yet clicked");
    ui.pointer_up(151.0, 221.0);
    assert!(frame(&mut ui, 0, &mut buf));
    assert!(!ui.is_pointer_captured());
    // Press inside, release outside: no click.
    ui.pointer_down(150.0, 220.0);
    frame(&mut ui, 0, &mut buf);
    ui.pointer_up(500.0, 500.0);
    assert!(!frame(&mut ui, 0, &mut buf));
    // Press outside, release inside: no click.
    ui.pointer_down(5.0, 5.0);
    ui.pointer_up(150.0, 220.0);
    assert!(!frame(&mut ui, 0, &mut buf));
    // Edges: the rect is half-open.
    assert!(button.contains([100.0, 200.0]) && !button.contains([260.0, 248.0]));
}

#[test]
fn hit_testing_uses_physical_pixels_and_density() {
    let mut ui = ui();
    let run = |ui: &mut Ui| {
        ui.begin(2000.0, 1000.0, 2.5, Insets::ZERO);
        let c = ui.button("b", Rect::new(100.0, 100.0, 100.0, 40.0), "B");
        ui.end();
        c
    };
    run(&mut ui);
    // Logical (150, 120) is physical (375, 300).
    ui.pointer_down(375.0, 300.0);
    ui.pointer_up(375.0, 300.0);
    assert!(run(&mut ui));
    // Physical (150, 120) is logical (60, 48): outside.
    ui.pointer_down(150.0, 120.0);
    ui.pointer_up(150.0, 120.0);
    assert!(!run(&mut ui));
}

#[test]
fn layout_respects_insets_and_density() {
    let mut ui = ui();
    let insets = Insets {
        left: 90.0,
        top: 60.0,
        right: 30.0,
        bottom: 120.0,
    };
    ui.begin(1080.0, 2400.0, 3.0, insets);
    let safe = ui.safe_rect();
    assert_eq!(safe, Rect::new(30.0, 20.0, 320.0, 740.0));
    assert_eq!(ui.screen_rect(), Rect::new(0.0, 0.0, 360.0, 800.0));
    let tl = ui.anchored(Anchor::TopLeft, [10.0, 10.0], [100.0, 50.0]);
    assert_eq!(tl, Rect::new(40.0, 30.0, 100.0, 50.0));
    let br = ui.anchored(Anchor::BottomRight, [10.0, 10.0], [100.0, 50.0]);
    assert_eq!(
        br,
        Rect::new(30.0 + 320.0 - 110.0, 20.0 + 740.0 - 60.0, 100.0, 50.0)
    );
    let c = ui.anchored(Anchor::Center, [0.0, 0.0], [100.0, 50.0]);
    assert_eq!(c.center(), safe.center());
    let bottom = ui.anchored(Anchor::Bottom, [0.0, 0.0], [100.0, 50.0]);
    assert_eq!(bottom.y + bottom.h, safe.y + safe.h);
    // Vertices come out in physical pixels: the panel spans 3× its logical size.
    ui.panel(br);
    ui.end();
    let (min, max) = bounds(ui.vertices());
    assert_eq!(min, [(br.x * 3.0).round(), (br.y * 3.0).round()]);
    assert_eq!(
        max,
        [((br.x + br.w) * 3.0).round(), ((br.y + br.h) * 3.0).round()]
    );
    // Entirely inside the safe area, in physical pixels.
    assert!(max[0] <= 1080.0 - insets.right && max[1] <= 2400.0 - insets.bottom);
}

fn bounds(v: &[UiVertex]) -> ([f32; 2], [f32; 2]) {
    let mut min = [f32::MAX; 2];
    let mut max = [f32::MIN; 2];
    for p in v {
        for i in 0..2 {
            min[i] = min[i].min(p.pos[i]);
            max[i] = max[i].max(p.pos[i]);
        }
    }
    (min, max)
}

#[test]
fn text_measures_and_scales() {
    let mut ui = ui();
    let w = ui.text_width("Hello", 24.0);
    assert!(w > 0.0);
    assert!((ui.text_width("Hello", 48.0) - 2.0 * w).abs() < 1e-3);
    ui.begin(800.0, 600.0, 2.0, Insets::ZERO);
    ui.label([10.0, 10.0], "Hi ~\u{e9}", 24.0);
    ui.end();
    // 'H', 'i', '~', and two '?' for the two UTF-8 bytes of é; the space draws nothing.
    assert_eq!(ui.vertices().len(), 5 * 6);
}

#[test]
fn game_screens_cycle_the_model_start_and_replay() {
    let mut ui = ui();
    let mut game = Game::new(11);
    let mut gui = GameUi::new();
    let mut settings = Settings::default();
    let mut frame = |ui: &mut Ui, game: &mut Game, settings: &mut Settings| {
        ui.begin(1280.0, 720.0, 1.0, Insets::ZERO);
        let out = gui.draw(ui, game, settings);
        ui.end();
        out
    };
    frame(&mut ui, &mut game, &mut settings);
    let rebuilds = ui.rebuilds();
    frame(&mut ui, &mut game, &mut settings);
    assert_eq!(ui.rebuilds(), rebuilds, "the main screen is static");
    // The menu's panel stands beside the showroom's character (game::showroom): its buttons,
    // in declaration order, are the model option and start.
    let buttons: Vec<Rect> = ui.button_rects().collect();
    let (option, start) = (buttons[0], buttons[1]);
    let mut seen = Vec::new();
    for _ in 0..ShadingModel::ALL.len() {
        seen.push(settings.shading_model());
        let c = option.center();
        ui.pointer_down(c[0], c[1]);
        ui.pointer_up(c[0], c[1]);
        let out = frame(&mut ui, &mut game, &mut settings);
        assert!(out.shading_changed && out.settings_changed);
    }
    // From the default, in menu order, wrapping.
    let first = ShadingModel::ALL
        .iter()
        .position(|m| *m == ShadingModel::DEFAULT);
    let mut order = ShadingModel::ALL.to_vec();
    order.rotate_left(first.unwrap_or(0));
    assert_eq!(seen, order, "cycles every model");
    assert_eq!(settings.shading_model(), ShadingModel::DEFAULT);
    let c = start.center();
    ui.pointer_down(c[0], c[1]);
    ui.pointer_up(c[0], c[1]);
    assert!(frame(&mut ui, &mut game, &mut settings).started);
    assert_eq!(game.screen(), Screen::Play);
    // Play: the score label rebuilds the UI only when the score changes.
    let mut last = (game.score(), ui.rebuilds());
    frame(&mut ui, &mut game, &mut settings);
    last.1 = ui.rebuilds();
    for _ in 0..600 {
        game.update(TICK_DT, &dermis_game::rules::Input::NONE);
        if game.screen() != Screen::Play {
            break;
        }
        let before = ui.rebuilds();
        frame(&mut ui, &mut game, &mut settings);
        let rebuilt = ui.rebuilds() - before;
        assert_eq!(
            rebuilt,
            (game.score() != last.0) as u64,
            "score {} -> {}",
            last.0,
            game.score()
        );
        last.0 = game.score();
    }
    // Run into something, then replay with the button.
    while game.screen() == Screen::Play {
        game.update(TICK_DT, &dermis_game::rules::Input::NONE);
    }
    let out = frame(&mut ui, &mut game, &mut settings);
    assert!(out.settings_changed, "a new best is saved");
    assert_eq!(settings.best, game.best());
    // The game-over screen's one button.
    let buttons: Vec<Rect> = ui.button_rects().collect();
    assert_eq!(buttons.len(), 1, "{buttons:?}");
    let replay = buttons[0].center();
    ui.pointer_down(replay[0], replay[1]);
    ui.pointer_up(replay[0], replay[1]);
    assert!(frame(&mut ui, &mut game, &mut settings).started);
    assert_eq!(
        (game.screen(), game.score(), game.runs()),
        (Screen::Play, 0, 1)
    );
}

//! Pause (key, focus loss, the pause panel's Resume button) and the frame-time overlay.

use dermis_engine::asset::Model;
use dermis_engine::ui::{Insets, Rect};
use dermis_game::app::{Key, Session, Viewport};
use dermis_game::rules::{Game, Input, Screen, TICK_DT};

const FRAME: f32 = 1.0 / 60.0;

fn playing() -> Game {
    let mut g = Game::new(3);
    g.start();
    g.debug_clear_obstacles_until(200.0);
    g
}

fn viewport() -> Viewport {
    Viewport {
        width: 640,
        height: 360,
        scale: 1.0,
        insets: Insets::default(),
    }
}

fn session(autoplay: bool) -> (Session, Model) {
    let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
    let s = Session::new(&model, 3, None, autoplay);
    (s, model)
}

#[test]
fn pausing_stops_the_simulation_and_resuming_continues_without_a_jump() {
    let mut g = playing();
    for _ in 0..30 {
        g.update(FRAME, &Input::NONE);
    }
    g.pause();
    assert!(g.is_paused());
    let (ticks, pos, hash, alpha) = (g.ticks(), g.player_position(), g.state_hash(), g.alpha());
    let (drawn, _) = g.player_transform();
    // Ten seconds of paused frames, some long (a window dragged, an app in the background),
    // with presses: nothing moves, nothing is queued.
    let jump = Input {
        jump: true,
        ..Input::NONE
    };
    for i in 0..600 {
        let dt = if i % 100 == 0 { 5.0 } else { FRAME };
        assert_eq!(g.update(dt, &jump), 0);
        assert_eq!(g.update_with(dt, |_| jump), 0);
    }
    assert_eq!(g.ticks(), ticks);
    assert_eq!(g.player_position(), pos);
    assert_eq!(g.player_transform().0, drawn);
    assert_eq!(g.alpha(), alpha);
    assert_eq!(g.state_hash(), hash);
    // Resume: the next frame runs a frame's worth of ticks, no more, and the jump pressed
    // while paused is gone.
    g.resume();
    assert!(!g.is_paused());
    let speed = g.speed();
    assert_eq!(g.update(FRAME, &Input::NONE), 2);
    let moved = g.player_position().z - pos.z;
    assert!(
        (moved - 2.0 * TICK_DT * speed).abs() < 0.01,
        "moved {moved} m in one frame after resuming"
    );
    assert!(!g.is_airborne());
    assert_eq!(g.screen(), Screen::Play);
}

#[test]
fn only_a_run_pauses_and_leaving_it_unpauses() {
    let mut g = Game::new(3);
    g.pause();
    assert!(!g.is_paused(), "the main screen does not pause");
    assert!(g.update(0.1, &Input::NONE) > 0);
    g.start();
    g.toggle_pause();
    assert!(g.is_paused());
    g.toggle_pause();
    assert!(!g.is_paused());
    g.pause();
    g.to_main();
    assert!(!g.is_paused());
    assert_eq!(g.screen(), Screen::Main);
}

fn buttons(s: &Session) -> Vec<Rect> {
    s.ui.button_rects().collect()
}

#[test]
fn the_pause_panel_resumes_with_its_button() {
    let (mut s, model) = session(false);
    s.key(Key::Jump);
    for _ in 0..10 {
        s.update(FRAME, &model, viewport());
    }
    assert_eq!(s.game.screen(), Screen::Play);
    // While running, one button: the camera switch (top right, away from the play area).
    assert_eq!(buttons(&s).len(), 1, "only the view switch while running");
    s.key(Key::Pause);
    assert!(s.is_paused());
    let ticks = s.game.ticks();
    let info = s.update(FRAME, &model, viewport());
    assert_eq!(info.ticks, 0);
    assert!(info.ui_rebuilt, "the pause panel appears");
    let b = buttons(&s);
    assert_eq!(b.len(), 1, "the Resume button: {b:?}");
    // A click on Resume: resumes, and is not taken for a jump tap.
    let [x, y] = b[0].center();
    s.pointer_down(x, y);
    s.update(FRAME, &model, viewport());
    assert!(s.is_paused());
    assert_eq!(s.game.ticks(), ticks);
    s.pointer_up(x, y);
    s.update(FRAME, &model, viewport());
    assert!(!s.is_paused());
    let info = s.update(FRAME, &model, viewport());
    assert_eq!(info.ticks, 2);
    assert!(!s.game.is_airborne(), "the click did not jump");
    assert_eq!(
        buttons(&s).len(),
        1,
        "the panel is gone; the view switch is back"
    );
    // The key resumes too.
    s.key(Key::Pause);
    s.key(Key::Pause);
    assert!(!s.is_paused());
}

#[test]
fn focus_loss_pauses_a_players_run_but_not_an_autoplayed_one() {
    let (mut s, model) = session(false);
    s.auto_pause();
    assert!(!s.is_paused(), "nothing to pause on the main screen");
    s.key(Key::Jump);
    s.update(FRAME, &model, viewport());
    s.auto_pause();
    assert!(s.is_paused());
    // It stays paused until the player resumes (focus coming back does not resume).
    for _ in 0..10 {
        assert_eq!(s.update(FRAME, &model, viewport()).ticks, 0);
    }

    let (mut bot, model) = session(true);
    for _ in 0..60 {
        bot.update(FRAME, &model, viewport());
    }
    assert_eq!(bot.game.screen(), Screen::Play);
    bot.auto_pause();
    assert!(!bot.is_paused());
    assert!(bot.update(FRAME, &model, viewport()).ticks > 0);
}

#[test]
fn the_frame_time_overlay_is_off_by_default_and_adds_a_label() {
    let (mut s, model) = session(true);
    assert!(!s.gui.show_frame_stats);
    s.update(FRAME, &model, viewport());
    let without = s.ui.vertices().len();
    s.key(Key::FrameStats);
    assert!(s.gui.show_frame_stats);
    s.update(FRAME, &model, viewport());
    let placeholder = s.ui.vertices().len();
    assert!(placeholder > without, "{placeholder} vs {without} vertices");
    // Fed frame times, it shows their averages once per period.
    for _ in 0..40 {
        s.gui.record_frame_time(1.0 / 50.0, 4.0, 6.0);
    }
    let text = s.gui.frame_stats_text();
    assert!(text.starts_with("50 fps  frame 20.0 ms"), "{text}");
    assert!(text.contains("\ncpu 4.0 ms  gpu 6.0 ms"), "{text}");
    s.update(FRAME, &model, viewport());
    assert!(s.ui.vertices().len() > placeholder);
    // Without GPU timing it says so rather than showing a number.
    for _ in 0..40 {
        s.gui.record_frame_time(1.0 / 50.0, 4.0, f64::NAN);
    }
    assert!(s.gui.frame_stats_text().ends_with("gpu not timed"));
    // Bad frame times are ignored.
    s.gui.record_frame_time(f64::NAN, 1.0, 1.0);
    s.gui.record_frame_time(-1.0, 1.0, 1.0);
    s.key(Key::FrameStats);
    s.update(FRAME, &model, viewport());
    assert_eq!(s.ui.vertices().len(), without);
}

#[test]
fn the_overlay_shows_the_wall_clock_time_between_frames() {
    // A slow machine: 1.45 s between pictures. The game clock's step is clamped to 0.1 s, so
    // the overlay must not take it from there: it shows the wall clock.
    let (mut s, _) = session(true);
    let t0 = std::time::Instant::now();
    assert!(s.gui.frame_started(t0).is_nan());
    for i in 1..=3u32 {
        let at = t0 + std::time::Duration::from_millis(1450 * i as u64);
        let interval = s.gui.frame_started(at);
        assert!((interval - 1.45).abs() < 1e-9, "{interval}");
        s.gui.record_frame_time(interval, 12.0, 1400.0);
    }
    let text = s.gui.frame_stats_text();
    assert!(text.starts_with("1 fps  frame 1450.0 ms"), "{text}");
    assert!(text.ends_with("cpu 12.0 ms  gpu 1400.0 ms"), "{text}");
    // After a pause the clock starts afresh (no interval spanning the pause).
    s.gui.reset_frame_clock();
    assert!(s.gui.frame_started(t0).is_nan());
}

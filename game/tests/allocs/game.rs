//! The game's and the UI's per-frame code allocates nothing in steady state (§4.3 item 1):
//! game update (bot sampled per tick), prop placement export, animation state, camera
//! target and building the UI (including frames where the score text changes and the vertex
//! data is rebuilt), with the frame-time overlay on and runs paused and resumed. Counted on
//! this thread (the allocation tests' binary).

use dermis_engine::scene::PropInstance;
use dermis_engine::ui::{Insets, Ui};
use dermis_game::app::{GameUi, Settings};
use dermis_game::rules::{Bot, Game, Screen};

#[test]
fn steady_state_frames_allocate_nothing() {
    let _shared = crate::shared();
    let mut game = Game::new(77);
    let bot = Bot::new(77);
    let mut ui = Ui::with_embedded_atlas();
    let mut gui = GameUi::new();
    gui.show_frame_stats = true;
    let mut n = 0u64;
    let mut paused_frames = 0u32;
    let mut settings = Settings::default();
    let mut props: Vec<PropInstance> = Vec::with_capacity(Game::MAX_PROPS);
    let mut checksum = 0.0f32;
    let mut frame = |game: &mut Game, ui: &mut Ui, props: &mut Vec<PropInstance>| {
        // Now and then a pause of a second (the pause panel is built).
        n += 1;
        if n.is_multiple_of(900) {
            game.pause();
        } else if n % 900 == 60 {
            game.resume();
        }
        paused_frames += game.is_paused() as u32;
        game.update_with(1.0 / 60.0, |g| bot.decide(g));
        gui.record_frame_time(1.0 / 60.0 + (n % 7) as f64 * 1e-3, 3.0, 5.0);
        game.props(props);
        let anim = game.anim_state();
        let (cam, _) = game.camera_target();
        let m = game.player_matrix();
        ui.begin(
            1920.0,
            1080.0,
            1.5,
            Insets {
                left: 0.0,
                top: 30.0,
                right: 0.0,
                bottom: 40.0,
            },
        );
        gui.draw(ui, game, &mut settings);
        ui.end();
        if ui.needs_upload() {
            checksum += ui.vertices().len() as f32;
            ui.mark_uploaded();
        }
        checksum += anim.blend[1].1 + cam.z + m.w_axis.z + props.len() as f32;
    };
    // Warm-up: the main screen, a first run and its growth of every buffer.
    for _ in 0..60 * 60 {
        frame(&mut game, &mut ui, &mut props);
    }
    let (rebuilds0, runs0) = (ui.rebuilds(), game.runs());
    let mut screens = [false; 3];
    let before = crate::thread_allocations();
    for _ in 0..60 * 240 {
        frame(&mut game, &mut ui, &mut props);
        screens[game.screen() as usize] = true;
    }
    let allocations = crate::thread_allocations() - before;
    assert!(paused_frames > 0, "a run was paused");
    assert!(
        ui.rebuilds() > rebuilds0 + 100,
        "the score changed and the UI was rebuilt"
    );
    assert!(
        screens[Screen::Play as usize] && screens[Screen::GameOver as usize],
        "{screens:?}"
    );
    eprintln!(
        "{allocations} allocations in {} frames ({} UI rebuilds, {} runs, checksum {checksum})",
        60 * 240,
        ui.rebuilds() - rebuilds0,
        game.runs() - runs0
    );
    assert_eq!(allocations, 0);
}

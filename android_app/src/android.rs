//! Platform glue: `android_main`, logging, start-up (assets, intent extras, settings), the
//! event loop and input. Translates android-activity's events into
//! [`lifecycle`](crate::lifecycle) events and performs the actions on the
//! [`Renderer`](crate::app::Renderer); touches and keys go to the game's session.

use crate::app::{Game, Renderer};
use crate::intent::Extras;
use crate::lifecycle::{self, Action, Event, Lifecycle};
use crate::soak::{Soak, SoakConfig};
use android_activity::input::{InputEvent, KeyAction, Keycode, MotionAction};
use android_activity::{AndroidApp, InputStatus, MainEvent, PollEvent, WindowManagerFlags};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{Key, Session};
use dermis_game::governor::GovernorConfig;
use std::time::Instant;

/// Entry point called by android-activity on its own thread.
#[no_mangle]
fn android_main(app: AndroidApp) {
    android_logger::init_once(
        android_logger::Config::default()
            .with_tag("dermis")
            .with_max_level(log::LevelFilter::Info),
    );
    install_panic_hook();
    log::info!(
        "dermis {} starting (Android SDK {})",
        env!("CARGO_PKG_VERSION"),
        AndroidApp::sdk_version()
    );
    app.set_window_flags(
        WindowManagerFlags::KEEP_SCREEN_ON | WindowManagerFlags::FULLSCREEN,
        WindowManagerFlags::empty(),
    );

    let mut lc = Lifecycle::new();
    let extras = crate::intent::read(&app);
    log::info!("intent extras: {extras:?}");
    match crate::intent::display_refresh_rate(&app) {
        Some(hz) => log::info!("display refresh rate: {hz:.1} Hz"),
        None => log::info!("display refresh rate: unknown"),
    }
    let (soak, soak_error) = soak_config(&app, &extras);
    let test_loop = extras.is_test_loop();
    let mut renderer = Renderer::new(load_game(&app, &extras, soak.as_ref()), display_scale(&app));
    renderer.soak = soak.map(Soak::new);
    renderer.cache_dir = crate::intent::cache_dir(&app);
    if let Some(error) = soak_error {
        log::error!("{error}; finishing");
        if test_loop {
            write_test_loop_results(&app, &serde_json::json!({"error": error}));
        }
        finish(&app);
    } else if renderer.game().is_none() {
        // Nothing to show: leave through the normal lifecycle (events until Destroy).
        if test_loop {
            write_test_loop_results(
                &app,
                &serde_json::json!({"error": "the assets could not be loaded"}),
            );
        }
        finish(&app);
    }
    let mut soak_finished = false;
    let mut pointer = Pointer::default();
    let mut exit = false;
    while !exit {
        app.poll_events(lc.poll_timeout(), |event| {
            let PollEvent::Main(main) = event else {
                return;
            };
            let ev = match main {
                MainEvent::Start => Event::Start,
                MainEvent::Resume { loader, .. } => {
                    if let Some(state) = loader.load() {
                        if lc.restore(&state) {
                            log::info!("state restored: {:?}", lc.screen());
                        }
                    }
                    Event::Resume
                }
                MainEvent::SaveState { saver, .. } => {
                    sync_screen(&mut lc, &renderer);
                    saver.store(&lc.save());
                    if let Some(game) = renderer.game() {
                        game.save_settings();
                        log::info!(
                            "SaveState: screen {:?}, seed {}, best {}",
                            game.session.game.screen(),
                            game.session.game.seed(),
                            game.session.game.best()
                        );
                    }
                    return;
                }
                MainEvent::Pause => {
                    renderer.reset_clock();
                    renderer.pause_soak();
                    if let Some(game) = renderer.game_mut() {
                        game.session.auto_pause();
                    }
                    Event::Pause
                }
                MainEvent::Stop => Event::Stop,
                MainEvent::GainedFocus => {
                    // The system shows the bars again while the app is away.
                    crate::display::enter_immersive(&app);
                    Event::GainedFocus
                }
                MainEvent::LostFocus => {
                    renderer.pause_soak();
                    if let Some(game) = renderer.game_mut() {
                        game.session.auto_pause();
                    }
                    Event::LostFocus
                }
                MainEvent::InitWindow { .. } => {
                    crate::display::enter_immersive(&app);
                    renderer.set_insets(crate::display::safe_insets(&app));
                    let (width, height) = window_size(&app);
                    Event::InitWindow { width, height }
                }
                MainEvent::TerminateWindow { .. } => {
                    renderer.pause_soak();
                    Event::TermWindow
                }
                MainEvent::ConfigChanged { .. } => {
                    renderer.set_scale(display_scale(&app));
                    renderer.set_insets(crate::display::safe_insets(&app));
                    let (width, height) = window_size(&app);
                    Event::Resized { width, height }
                }
                MainEvent::WindowResized { .. } | MainEvent::ContentRectChanged { .. } => {
                    renderer.set_insets(crate::display::safe_insets(&app));
                    let (width, height) = window_size(&app);
                    Event::Resized { width, height }
                }
                MainEvent::Destroy => Event::Destroy,
                MainEvent::LowMemory => {
                    log::warn!("low memory");
                    return;
                }
                _ => return,
            };
            log::debug!("lifecycle event {ev:?}");
            // Actions run inside the callback: TermWindow's surface must be gone before the
            // callback returns (the window is destroyed right after).
            for action in lc.handle(ev) {
                exit |= perform(&app, &mut renderer, action);
            }
        });

        handle_input(&app, &mut lc, &mut renderer, &mut pointer, &mut exit);

        if lc.should_render() && renderer.has_surface() {
            let status = renderer.draw();
            if let Some(action) = lc.frame(status) {
                log::info!("frame {status:?} -> {action:?}");
                exit |= perform(&app, &mut renderer, action);
            }
        }
        if !soak_finished && renderer.soak.as_ref().is_some_and(|s| s.done()) {
            soak_finished = true;
            end_soak(&app, &mut renderer, test_loop);
            finish(&app);
        }
    }
    drop(renderer);
    log::info!("android_main returns");
}

fn window_size(app: &AndroidApp) -> (u32, u32) {
    app.native_window().map_or((0, 0), |w| {
        (w.width().max(0) as u32, w.height().max(0) as u32)
    })
}

/// Display density / 160 (1 when unknown).
fn display_scale(app: &AndroidApp) -> f32 {
    match app.config().density() {
        Some(dpi) if dpi > 0 && dpi < 0xfffe => dpi as f32 / 160.0,
        _ => 1.0,
    }
}

/// Loads the assets (all of them, now), reads the intent extras and builds the session with
/// the settings file in the app's internal data directory.
fn load_game(app: &AndroidApp, extras: &Extras, soak: Option<&SoakConfig>) -> Option<Game> {
    let t0 = Instant::now();
    let assets = match crate::assets::load(&app.asset_manager()) {
        Ok(a) => a,
        Err(e) => {
            log::error!("cannot load the assets: {e}; finishing");
            return None;
        }
    };
    log::info!(
        "assets loaded in {} ms ({} props)",
        t0.elapsed().as_millis(),
        assets.props.len()
    );
    let autoplay = extras.autoplay || soak.is_some();
    let settings_path = app.internal_data_path().map(|d| d.join("settings.txt"));
    if settings_path.is_none() {
        log::warn!("no internal data path: settings are not persisted");
    }
    let seed = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(1, |d| d.as_nanos() as u64);
    let session = Session::new(&assets.character, seed, settings_path.clone(), autoplay);
    let mut game = Game::new(assets, session, settings_path);
    if let Some(soak) = soak {
        game.session.settings.set_shading_model(soak.shading);
        // The governor's budget is the soak's target frame rate, as `dermis soak` sets it.
        game.session
            .configure_governor(GovernorConfig::for_fps(soak.target_fps), true, true);
        game.save_settings_on_save_state = false;
    } else if let Some(name) = &extras.shading {
        match ShadingModel::from_name(name) {
            Some(model) => {
                game.session.settings.set_shading_model(model);
                game.save_settings_on_save_state = false;
            }
            None => log::warn!(
                "intent extra shading={name:?} is not a model (known: {}); ignored",
                ShadingModel::names()
            ),
        }
    }
    log::info!(
        "settings: shading {}{}, best {}, autoplay {}, seed {seed}, file {}",
        game.session.shading().name(),
        if !game.save_settings_on_save_state {
            " (from the intent)"
        } else {
            ""
        },
        game.session.settings.best,
        autoplay,
        game.settings_path
            .as_deref()
            .map_or("<none>".into(), |p| p.display().to_string())
    );
    Some(game)
}

/// The soak the intent asks for: a Game Loop test's scenario, or `soak_seconds` > 0 (with
/// `shading` and `target_fps`). `Err`-like second value: why the requested run is impossible.
fn soak_config(app: &AndroidApp, extras: &Extras) -> (Option<SoakConfig>, Option<String>) {
    let named = |name: &str| {
        ShadingModel::from_name(name).ok_or_else(|| {
            format!(
                "shading {name:?} is not a model (known: {})",
                ShadingModel::names()
            )
        })
    };
    let (seconds, shading, scenario) = if extras.is_test_loop() {
        let n = extras.scenario.unwrap_or(0);
        let Some((seconds, m)) = crate::soak::scenario(n) else {
            return (
                None,
                Some(format!("Game Loop scenario {n} is not defined (1, 2, 3)")),
            );
        };
        (seconds as f64, m, Some(n))
    } else if extras.soak_seconds > 0 {
        let shading = match &extras.shading {
            Some(name) => match named(name) {
                Ok(m) => m,
                Err(e) => return (None, Some(e)),
            },
            None => ShadingModel::DEFAULT,
        };
        (extras.soak_seconds as f64, shading, None)
    } else {
        return (None, None);
    };
    let target_fps = if extras.target_fps > 0 {
        extras.target_fps.min(1000) as f64
    } else {
        60.0
    };
    let out_dir = crate::intent::external_files_dir(app);
    if let Some(dir) = &out_dir {
        if let Err(e) = std::fs::create_dir_all(dir) {
            log::warn!("{}: {e}", dir.display());
        }
    }
    log::info!(
        "soak requested: {seconds} s, {} at {target_fps} fps, report to {}{}",
        shading.name(),
        out_dir
            .as_deref()
            .map_or("<no external files dir>".into(), |d| d
                .join("soak.json")
                .display()
                .to_string()),
        if extras.is_test_loop() {
            format!(" and {}", extras.data.as_deref().unwrap_or("<no data URI>"))
        } else {
            String::new()
        }
    );
    (
        Some(SoakConfig {
            seconds,
            target_fps,
            shading,
            scenario,
            out_dir,
        }),
        None,
    )
}

/// Ends the soak: the summary to logcat, `soak.json` to the external files directory and, for
/// a Game Loop test, the report to the intent's data URI.
fn end_soak(app: &AndroidApp, renderer: &mut Renderer, test_loop: bool) {
    let out_dir = renderer.soak.as_ref().and_then(|s| s.cfg.out_dir.clone());
    let Some(report) = renderer.finish_soak() else {
        log::error!("soak: no GPU, no report");
        return;
    };
    if let Some(dir) = out_dir {
        let path = dir.join("soak.json");
        match dermis_game::soak::write_atomic(&path, &report) {
            Ok(()) => log::info!("soak: report written to {}", path.display()),
            Err(e) => log::error!("soak: {e}"),
        }
    }
    if test_loop {
        write_test_loop_results(app, &report);
    }
}

/// Writes `value` to the file the Game Loop intent's data URI names.
fn write_test_loop_results(app: &AndroidApp, value: &serde_json::Value) {
    use std::io::Write;
    let result = crate::intent::open_data_for_write(app).and_then(|fd| {
        let mut file = std::fs::File::from(fd);
        let text = serde_json::to_vec_pretty(value).map_err(|e| e.to_string())?;
        file.write_all(&text)
            .and_then(|()| file.sync_all())
            .map_err(|e| e.to_string())
    });
    match result {
        Ok(()) => log::info!("Game Loop results written to the intent's data URI"),
        Err(e) => log::error!("Game Loop results not written: {e}"),
    }
}

fn finish(app: &AndroidApp) {
    // SAFETY: the activity pointer is valid until Destroy, which has not been seen yet;
    // ANativeActivity_finish may be called from any thread.
    unsafe { android_activity::ndk_sys::ANativeActivity_finish(app.activity_as_ptr().cast()) };
}

/// Tells the lifecycle which screen the game shows (the game decides what back does).
fn sync_screen(lc: &mut Lifecycle, renderer: &Renderer) {
    if let Some(game) = renderer.game() {
        lc.set_screen(if game.in_play() {
            lifecycle::Screen::Play
        } else {
            lifecycle::Screen::Main
        });
    }
}

/// Performs one lifecycle action; returns whether to leave the loop.
fn perform(app: &AndroidApp, renderer: &mut Renderer, action: Action) -> bool {
    match action {
        Action::CreateSurface { width, height } | Action::RecreateSurface { width, height } => {
            match app.native_window() {
                Some(window) => {
                    if let Some(soak) = &renderer.soak {
                        crate::ndk_dl::set_frame_rate(
                            window.ptr().as_ptr().cast(),
                            soak.cfg.target_fps as f32,
                        );
                    }
                    if let Err(e) = renderer.create_surface(window, width, height) {
                        log::error!("cannot create the surface: {e}");
                    }
                }
                None => log::warn!("{action:?} without a native window"),
            }
        }
        Action::DropSurface => renderer.drop_surface(),
        Action::Reconfigure { width, height } => renderer.reconfigure(width, height),
        Action::LeavePlay => {
            log::info!("back: leaving play for the main screen");
            if let Some(game) = renderer.game_mut() {
                game.leave_play();
            }
        }
        Action::Finish => {
            log::info!("back on the main screen: finishing the activity");
            finish(app);
        }
        Action::Exit => return true,
    }
    false
}

/// The first pointer of the current touch (its id), as android-activity reports it.
#[derive(Default)]
struct Pointer {
    id: Option<i32>,
}

fn handle_input(
    app: &AndroidApp,
    lc: &mut Lifecycle,
    renderer: &mut Renderer,
    pointer: &mut Pointer,
    exit: &mut bool,
) {
    let mut iter = match app.input_events_iter() {
        Ok(iter) => iter,
        Err(e) => {
            log::warn!("input events: {e:?}");
            return;
        }
    };
    let mut actions = Vec::new();
    while iter.next(|event| match event {
        InputEvent::KeyEvent(key) if key.key_code() == Keycode::Back => {
            if key.action() == KeyAction::Up {
                sync_screen(lc, renderer);
                actions.extend(lc.handle(Event::Back));
            }
            // Handled on down and up: the system's default back would finish the activity
            // even while playing.
            InputStatus::Handled
        }
        InputEvent::KeyEvent(key) => {
            let game_key = match key.key_code() {
                Keycode::DpadLeft | Keycode::A => Key::Left,
                Keycode::DpadRight | Keycode::D => Key::Right,
                Keycode::DpadUp
                | Keycode::W
                | Keycode::Space
                | Keycode::Enter
                | Keycode::DpadCenter
                | Keycode::ButtonA => Key::Jump,
                Keycode::M => Key::NextModel,
                Keycode::P | Keycode::MediaPlayPause | Keycode::ButtonStart => Key::Pause,
                Keycode::F => Key::FrameStats,
                _ => return InputStatus::Unhandled,
            };
            if key.action() == KeyAction::Down && key.repeat_count() == 0 {
                if let Some(game) = renderer.game_mut() {
                    game.key(game_key);
                }
            }
            InputStatus::Handled
        }
        InputEvent::MotionEvent(motion) => {
            let Some(game) = renderer.game_mut() else {
                return InputStatus::Unhandled;
            };
            // The pointer this event is about (for Down / Up: the only one).
            let p = motion.pointer_at_index(motion.pointer_index());
            let id = p.pointer_id();
            match motion.action() {
                MotionAction::Down => {
                    pointer.id = Some(id);
                    game.session.pointer_down(p.x(), p.y());
                }
                MotionAction::Up | MotionAction::PointerUp if pointer.id == Some(id) => {
                    pointer.id = None;
                    game.session.pointer_up(p.x(), p.y());
                }
                MotionAction::Cancel => pointer.id = None,
                _ => {}
            }
            InputStatus::Handled
        }
        _ => InputStatus::Unhandled,
    }) {}
    for action in actions {
        *exit |= perform(app, renderer, action);
    }
}

/// Panics go to logcat (tag `dermis`) before the default handling.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let thread = std::thread::current();
        let name = thread.name().unwrap_or("<unnamed>");
        log::error!("panic in thread '{name}': {info}");
        let bt = std::backtrace::Backtrace::force_capture();
        log::error!("backtrace:\n{bt}");
    }));
}

//! Platform glue: `android_main`, logging, the event loop. Translates android-activity's
//! events into [`lifecycle`](crate::lifecycle) events and performs the actions on the
//! [`Renderer`](crate::app::Renderer).

use crate::app::Renderer;
use crate::lifecycle::{Action, Event, Lifecycle};
use android_activity::input::{InputEvent, KeyAction, Keycode};
use android_activity::{AndroidApp, InputStatus, MainEvent, PollEvent, WindowManagerFlags};

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
    let mut renderer = Renderer::new();
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
                    saver.store(&lc.save());
                    return;
                }
                MainEvent::Pause => Event::Pause,
                MainEvent::Stop => Event::Stop,
                MainEvent::GainedFocus => Event::GainedFocus,
                MainEvent::LostFocus => Event::LostFocus,
                MainEvent::InitWindow { .. } => {
                    let (width, height) = window_size(&app);
                    Event::InitWindow { width, height }
                }
                MainEvent::TerminateWindow { .. } => Event::TermWindow,
                MainEvent::WindowResized { .. }
                | MainEvent::ConfigChanged { .. }
                | MainEvent::ContentRectChanged { .. } => {
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

        handle_input(&app, &mut lc, &mut renderer, &mut exit);

        if lc.should_render() && renderer.has_surface() {
            let status = renderer.draw();
            if let Some(action) = lc.frame(status) {
                log::info!("frame {status:?} -> {action:?}");
                exit |= perform(&app, &mut renderer, action);
            }
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

/// Performs one lifecycle action; returns whether to leave the loop.
fn perform(app: &AndroidApp, renderer: &mut Renderer, action: Action) -> bool {
    match action {
        Action::CreateSurface { width, height } | Action::RecreateSurface { width, height } => {
            match app.native_window() {
                Some(window) => {
                    if let Err(e) = renderer.create_surface(window, width, height) {
                        log::error!("cannot create the surface: {e}");
                    }
                }
                None => log::warn!("{action:?} without a native window"),
            }
        }
        Action::DropSurface => renderer.drop_surface(),
        Action::Reconfigure { width, height } => renderer.reconfigure(width, height),
        Action::LeavePlay => log::info!("back: leaving play for the main screen"),
        Action::Finish => {
            log::info!("back on the main screen: finishing the activity");
            // SAFETY: the activity pointer is valid until Destroy, which has not been seen
            // yet; ANativeActivity_finish may be called from any thread.
            unsafe {
                android_activity::ndk_sys::ANativeActivity_finish(app.activity_as_ptr().cast())
            };
        }
        Action::Exit => return true,
    }
    false
}

fn handle_input(app: &AndroidApp, lc: &mut Lifecycle, renderer: &mut Renderer, exit: &mut bool) {
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
                actions.extend(lc.handle(Event::Back));
            }
            // Handled on down and up: the system's default back would finish the activity
            // even while playing.
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

//! The Android activity lifecycle as a small pure state machine (no Android or GPU types), so
//! it is unit-tested on the host. The platform glue (`android.rs`) turns android-activity's
//! `MainEvent`s and key events into [`Event`]s, asks [`Lifecycle::poll_timeout`] how long to
//! block, and performs the returned [`Action`]s on the real window / GPU objects.
//!
//! Rules (what Android users expect and what wgpu requires):
//! - the surface exists exactly between `InitWindow` and `TermWindow` (the native window is
//!   invalid after `TermWindow` returns); the device and everything else live on;
//! - resizes and configuration changes (rotation, density, night mode: the manifest declares
//!   them in `configChanges`, so the activity is not recreated) reconfigure the surface;
//! - a frame reporting `Outdated`, `Suboptimal` or `Lost` reconfigures; `Lost` twice in a row
//!   recreates the surface;
//! - frames are drawn only while resumed with a surface of non-zero size; otherwise the loop
//!   blocks on the event queue (no timeout: no busy loop while paused);
//! - back leaves play for the main screen, and finishes the activity from the main screen;
//! - `SaveState` saves the small state below; `Resume` restores it.

use std::time::Duration;

/// What the surface reports for a frame (declared with the surface code, which produces it).
pub use dermis_engine::render::FrameStatus;

/// Lifecycle input, as the glue observed it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    Start,
    Resume,
    Pause,
    Stop,
    /// A native window exists (size read from it).
    InitWindow {
        width: u32,
        height: u32,
    },
    /// The native window is about to be destroyed.
    TermWindow,
    /// `WindowResized`, `ConfigChanged` or `ContentRectChanged`, with the window's new size.
    Resized {
        width: u32,
        height: u32,
    },
    GainedFocus,
    LostFocus,
    /// The back key was released.
    Back,
    Destroy,
}

/// What the glue must do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    CreateSurface {
        width: u32,
        height: u32,
    },
    DropSurface,
    Reconfigure {
        width: u32,
        height: u32,
    },
    /// Drop and create the surface again (after repeated `Lost`).
    RecreateSurface {
        width: u32,
        height: u32,
    },
    /// Leave play for the main screen.
    LeavePlay,
    /// Ask the system to finish the activity (`ANativeActivity_finish`); events keep coming
    /// until `Destroy`.
    Finish,
    /// Leave `android_main`.
    Exit,
}

/// Which screen the app shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screen {
    Main,
    Play,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lifecycle {
    started: bool,
    resumed: bool,
    focused: bool,
    /// Size of the current window, when there is one.
    window: Option<(u32, u32)>,
    screen: Screen,
    finishing: bool,
    destroyed: bool,
    lost_in_a_row: u32,
}

impl Default for Lifecycle {
    fn default() -> Self {
        Self::new()
    }
}

impl Lifecycle {
    pub fn new() -> Self {
        Lifecycle {
            started: false,
            resumed: false,
            focused: false,
            window: None,
            screen: Screen::Main,
            finishing: false,
            destroyed: false,
            lost_in_a_row: 0,
        }
    }

    pub fn screen(&self) -> Screen {
        self.screen
    }

    pub fn set_screen(&mut self, screen: Screen) {
        self.screen = screen;
    }

    pub fn is_resumed(&self) -> bool {
        self.resumed
    }

    pub fn is_focused(&self) -> bool {
        self.focused
    }

    pub fn has_window(&self) -> bool {
        self.window.is_some()
    }

    pub fn is_finishing(&self) -> bool {
        self.finishing
    }

    pub fn is_destroyed(&self) -> bool {
        self.destroyed
    }

    /// Whether a frame should be drawn now.
    pub fn should_render(&self) -> bool {
        self.resumed && !self.destroyed && matches!(self.window, Some((w, h)) if w > 0 && h > 0)
    }

    /// How long the event loop may block: `None` = until an event arrives (paused, no
    /// window), zero while frames are drawn (presentation paces the loop).
    pub fn poll_timeout(&self) -> Option<Duration> {
        if self.should_render() {
            Some(Duration::ZERO)
        } else {
            None
        }
    }

    /// Feeds one event; returns the actions to perform, in order.
    pub fn handle(&mut self, event: Event) -> Vec<Action> {
        let mut out = Vec::new();
        match event {
            Event::Start => self.started = true,
            Event::Stop => self.started = false,
            Event::Resume => self.resumed = true,
            Event::Pause => self.resumed = false,
            Event::GainedFocus => self.focused = true,
            Event::LostFocus => self.focused = false,
            Event::InitWindow { width, height } => {
                if self.window.is_some() {
                    // A new window without TermWindow: never keep a surface of the old one.
                    out.push(Action::DropSurface);
                }
                self.window = Some((width, height));
                self.lost_in_a_row = 0;
                out.push(Action::CreateSurface { width, height });
            }
            Event::TermWindow => {
                if self.window.take().is_some() {
                    out.push(Action::DropSurface);
                }
            }
            Event::Resized { width, height } => {
                if let Some(size) = &mut self.window {
                    if *size != (width, height) {
                        *size = (width, height);
                        out.push(Action::Reconfigure { width, height });
                    }
                }
            }
            Event::Back => match self.screen {
                Screen::Play => {
                    self.screen = Screen::Main;
                    out.push(Action::LeavePlay);
                }
                Screen::Main => {
                    if !self.finishing {
                        self.finishing = true;
                        out.push(Action::Finish);
                    }
                }
            },
            Event::Destroy => {
                self.destroyed = true;
                self.resumed = false;
                if self.window.take().is_some() {
                    out.push(Action::DropSurface);
                }
                out.push(Action::Exit);
            }
        }
        out
    }

    /// Feeds the outcome of a frame; returns what to do about the surface.
    pub fn frame(&mut self, status: FrameStatus) -> Option<Action> {
        let (width, height) = self.window?;
        match status {
            FrameStatus::Presented | FrameStatus::Timeout | FrameStatus::Occluded => {
                self.lost_in_a_row = 0;
                None
            }
            FrameStatus::Suboptimal | FrameStatus::Outdated | FrameStatus::Validation => {
                self.lost_in_a_row = 0;
                Some(Action::Reconfigure { width, height })
            }
            FrameStatus::Lost => {
                self.lost_in_a_row += 1;
                if self.lost_in_a_row >= 2 {
                    self.lost_in_a_row = 0;
                    Some(Action::RecreateSurface { width, height })
                } else {
                    Some(Action::Reconfigure { width, height })
                }
            }
        }
    }

    /// The state saved on `SaveState` (versioned, tiny).
    pub fn save(&self) -> Vec<u8> {
        vec![
            1,
            match self.screen {
                Screen::Main => 0,
                Screen::Play => 1,
            },
        ]
    }

    /// Restores what [`save`](Self::save) wrote; ignores anything else.
    pub fn restore(&mut self, bytes: &[u8]) -> bool {
        match bytes {
            [1, 0] => self.screen = Screen::Main,
            [1, 1] => self.screen = Screen::Play,
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(lc: &mut Lifecycle, events: &[Event]) -> Vec<Action> {
        events.iter().flat_map(|e| lc.handle(*e)).collect()
    }

    #[test]
    fn launch_pause_resume() {
        let mut lc = Lifecycle::new();
        assert_eq!(lc.poll_timeout(), None);
        let a = run(
            &mut lc,
            &[
                Event::Start,
                Event::Resume,
                Event::InitWindow {
                    width: 1920,
                    height: 1080,
                },
                Event::GainedFocus,
            ],
        );
        assert_eq!(
            a,
            vec![Action::CreateSurface {
                width: 1920,
                height: 1080
            }]
        );
        assert!(lc.should_render());
        assert_eq!(lc.poll_timeout(), Some(Duration::ZERO));

        // Home: pause, window goes, stop. Nothing renders, the loop blocks.
        let a = run(
            &mut lc,
            &[
                Event::LostFocus,
                Event::Pause,
                Event::TermWindow,
                Event::Stop,
            ],
        );
        assert_eq!(a, vec![Action::DropSurface]);
        assert!(!lc.should_render());
        assert_eq!(lc.poll_timeout(), None);

        // Back to the app.
        let a = run(
            &mut lc,
            &[
                Event::Start,
                Event::Resume,
                Event::InitWindow {
                    width: 1920,
                    height: 1080,
                },
            ],
        );
        assert_eq!(
            a,
            vec![Action::CreateSurface {
                width: 1920,
                height: 1080
            }]
        );
        assert!(lc.should_render());
    }

    #[test]
    fn paused_with_window_does_not_render() {
        let mut lc = Lifecycle::new();
        run(
            &mut lc,
            &[
                Event::Start,
                Event::InitWindow {
                    width: 100,
                    height: 100,
                },
            ],
        );
        assert!(lc.has_window());
        assert!(!lc.should_render());
        assert_eq!(lc.poll_timeout(), None);
        run(&mut lc, &[Event::Resume]);
        assert!(lc.should_render());
        run(&mut lc, &[Event::Pause]);
        assert!(!lc.should_render());
    }

    #[test]
    fn zero_size_window_does_not_render() {
        let mut lc = Lifecycle::new();
        run(
            &mut lc,
            &[
                Event::Resume,
                Event::InitWindow {
                    width: 0,
                    height: 0,
                },
            ],
        );
        assert!(!lc.should_render());
    }

    #[test]
    fn resize_and_rotation_reconfigure_once() {
        let mut lc = Lifecycle::new();
        run(
            &mut lc,
            &[
                Event::Resume,
                Event::InitWindow {
                    width: 1920,
                    height: 1080,
                },
            ],
        );
        let a = lc.handle(Event::Resized {
            width: 1080,
            height: 1920,
        });
        assert_eq!(
            a,
            vec![Action::Reconfigure {
                width: 1080,
                height: 1920
            }]
        );
        // Same size again (ConfigChanged after WindowResized): nothing to do.
        assert!(lc
            .handle(Event::Resized {
                width: 1080,
                height: 1920
            })
            .is_empty());
        // Without a window a resize is ignored.
        lc.handle(Event::TermWindow);
        assert!(lc
            .handle(Event::Resized {
                width: 10,
                height: 10
            })
            .is_empty());
    }

    #[test]
    fn init_window_twice_drops_first() {
        let mut lc = Lifecycle::new();
        lc.handle(Event::InitWindow {
            width: 1,
            height: 1,
        });
        let a = lc.handle(Event::InitWindow {
            width: 2,
            height: 2,
        });
        assert_eq!(
            a,
            vec![
                Action::DropSurface,
                Action::CreateSurface {
                    width: 2,
                    height: 2
                }
            ]
        );
    }

    #[test]
    fn term_window_without_window_is_noop() {
        let mut lc = Lifecycle::new();
        assert!(lc.handle(Event::TermWindow).is_empty());
    }

    #[test]
    fn frame_outcomes() {
        let mut lc = Lifecycle::new();
        assert_eq!(
            lc.frame(FrameStatus::Outdated),
            None,
            "no window, nothing to do"
        );
        run(
            &mut lc,
            &[
                Event::Resume,
                Event::InitWindow {
                    width: 8,
                    height: 4,
                },
            ],
        );
        let rc = Some(Action::Reconfigure {
            width: 8,
            height: 4,
        });
        assert_eq!(lc.frame(FrameStatus::Presented), None);
        assert_eq!(lc.frame(FrameStatus::Timeout), None);
        assert_eq!(lc.frame(FrameStatus::Occluded), None);
        assert_eq!(lc.frame(FrameStatus::Outdated), rc);
        assert_eq!(lc.frame(FrameStatus::Suboptimal), rc);
        assert_eq!(lc.frame(FrameStatus::Lost), rc);
        assert_eq!(
            lc.frame(FrameStatus::Lost),
            Some(Action::RecreateSurface {
                width: 8,
                height: 4
            })
        );
        assert_eq!(lc.frame(FrameStatus::Lost), rc);
        assert_eq!(lc.frame(FrameStatus::Presented), None);
        assert_eq!(
            lc.frame(FrameStatus::Lost),
            rc,
            "a good frame resets the count"
        );
    }

    #[test]
    fn back_leaves_play_then_finishes_once() {
        let mut lc = Lifecycle::new();
        lc.set_screen(Screen::Play);
        assert_eq!(lc.handle(Event::Back), vec![Action::LeavePlay]);
        assert_eq!(lc.screen(), Screen::Main);
        assert_eq!(lc.handle(Event::Back), vec![Action::Finish]);
        assert!(lc.is_finishing());
        assert!(lc.handle(Event::Back).is_empty(), "finish is asked once");
    }

    #[test]
    fn destroy_drops_surface_and_exits() {
        let mut lc = Lifecycle::new();
        run(
            &mut lc,
            &[
                Event::Resume,
                Event::InitWindow {
                    width: 8,
                    height: 8,
                },
            ],
        );
        assert_eq!(
            lc.handle(Event::Destroy),
            vec![Action::DropSurface, Action::Exit]
        );
        assert!(lc.is_destroyed());
        assert!(!lc.should_render());
        assert_eq!(lc.handle(Event::Destroy), vec![Action::Exit]);
    }

    #[test]
    fn save_restore() {
        let mut lc = Lifecycle::new();
        lc.set_screen(Screen::Play);
        let saved = lc.save();
        let mut fresh = Lifecycle::new();
        assert!(fresh.restore(&saved));
        assert_eq!(fresh.screen(), Screen::Play);
        assert!(!fresh.restore(b"garbage"));
        assert!(!fresh.restore(&[]));
        assert_eq!(fresh.screen(), Screen::Play);
    }

    /// Many random-ish event sequences: a surface is never created twice without a drop in
    /// between, never dropped without having been created, and rendering implies a window.
    #[test]
    fn surface_invariants_under_event_storm() {
        let events = [
            Event::Start,
            Event::Resume,
            Event::Pause,
            Event::Stop,
            Event::InitWindow {
                width: 640,
                height: 360,
            },
            Event::TermWindow,
            Event::Resized {
                width: 360,
                height: 640,
            },
            Event::GainedFocus,
            Event::LostFocus,
        ];
        let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut lc = Lifecycle::new();
        let mut surface = false;
        for _ in 0..100_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let ev = events[(seed % events.len() as u64) as usize];
            for a in lc.handle(ev) {
                match a {
                    Action::CreateSurface { .. } => {
                        assert!(!surface, "surface created twice");
                        surface = true;
                    }
                    Action::DropSurface => {
                        assert!(surface, "dropped a surface that does not exist");
                        surface = false;
                    }
                    Action::Reconfigure { .. } => assert!(surface),
                    other => panic!("unexpected {other:?}"),
                }
            }
            assert_eq!(surface, lc.has_window());
            if lc.should_render() {
                assert!(surface && lc.is_resumed());
            }
        }
    }
}

//! The game's screens, drawn with the immediate-mode UI: main (title, shading-model option
//! button, start, best score; laid out beside or below the showroom's close-up of the
//! character, see [`super::menu`]), play (score; when paused a "Paused" panel with
//! Resume) and game over (score, best, replay), plus an optional frame-time overlay on every
//! screen.
//! Where the scanned head was loaded, the main screen also has a subject option in the
//! showroom's corner (runner / head) and, while the head is shown, its credit (CC BY 3.0).
//! Text that changes is formatted into reused `String`s, so a frame allocates nothing.

use std::fmt::Write;
use std::time::Instant;

use super::showroom::Subject;
use super::{menu, Settings};
use crate::rules::{Game, Screen};
use dermis_engine::asset::head::CREDIT_LINES;
use dermis_engine::ui::{Anchor, Color, Ui};

const TITLE: Color = [1.0, 0.86, 0.45, 1.0];
const DIM: Color = [0.85, 0.88, 0.95, 1.0];

/// What happened in the UI this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UiOutcome {
    /// The player picked another shading model (`settings.shading` holds it).
    pub shading_changed: bool,
    /// The settings changed (model or best score): save them.
    pub settings_changed: bool,
    /// A run started (start or replay button).
    pub started: bool,
    /// The Resume button resumed a paused run.
    pub resumed: bool,
    /// The play screen's "View" button: switch the camera (wide ↔ close-up).
    pub camera_toggled: bool,
    /// The showroom's subject option switched runner ↔ head.
    pub subject_changed: bool,
}

/// How often the frame-time overlay's numbers change (seconds of frames averaged), so the
/// UI is not rebuilt every frame for it.
pub const FRAME_STATS_PERIOD_S: f64 = 0.5;

/// The game-over panel's share of a landscape screen's width (at least
/// [`menu::PANEL_MIN_W`], at most [`menu::PANEL_W`]).
pub const GAME_OVER_SHARE: f32 = 0.4;

/// The showroom's subject option (logical units) and the head's credit's largest text size.
pub const SUBJECT_W: f32 = 190.0;
pub const SUBJECT_H: f32 = 44.0;
pub const CREDIT_SIZE: f32 = 14.0;

/// Per-screen text buffers, reused every frame.
pub struct GameUi {
    option: String,
    line1: String,
    line2: String,
    /// Show the frame-time overlay. Off by default.
    pub show_frame_stats: bool,
    /// The showroom's subject; `None` where the scanned head is not loaded (the option is
    /// absent).
    subject: Option<Subject>,
    stats_text: String,
    stats: FrameStats,
    last_frame_start: Option<Instant>,
}

/// Frame times accumulated over [`FRAME_STATS_PERIOD_S`] for the overlay.
#[derive(Clone, Copy, Debug, Default)]
struct FrameStats {
    frame_s: f64,
    cpu_ms: f64,
    gpu_ms: f64,
    gpu_frames: u32,
    frames: u32,
    worst_s: f64,
}

impl Default for GameUi {
    fn default() -> Self {
        Self::new()
    }
}

impl GameUi {
    pub fn new() -> Self {
        Self {
            option: String::with_capacity(64),
            line1: String::with_capacity(64),
            line2: String::with_capacity(64),
            show_frame_stats: false,
            subject: None,
            stats_text: String::with_capacity(128),
            stats: FrameStats::default(),
            last_frame_start: None,
        }
    }

    /// Offers the showroom's subject option (runner / head) when `head` is loaded, else
    /// takes it away (the runner is shown).
    pub fn offer_head(&mut self, head: bool) {
        self.subject = match (head, self.subject) {
            (false, _) => None,
            (true, None) => Some(Subject::Runner),
            (true, s) => s,
        };
    }

    /// The showroom's subject (the runner where the head is not offered).
    pub fn subject(&self) -> Subject {
        self.subject.unwrap_or_default()
    }

    /// Chooses the showroom's subject; the head only where it is offered.
    pub fn set_subject(&mut self, subject: Subject) {
        if self.subject.is_some() {
            self.subject = Some(subject);
        }
    }

    /// A frame's work began at `at`: returns the wall-clock time since the previous frame's
    /// start (s; NaN for the first) — what the player waits between two pictures, unlike the
    /// game clock's step, which is clamped (a 1.4 s frame advances the game by 0.1 s).
    pub fn frame_started(&mut self, at: Instant) -> f64 {
        let interval = self
            .last_frame_start
            .map_or(f64::NAN, |t| at.saturating_duration_since(t).as_secs_f64());
        self.last_frame_start = Some(at);
        interval
    }

    /// Forgets the previous frame's start (after a pause, the window hidden, …).
    pub fn reset_frame_clock(&mut self) {
        self.last_frame_start = None;
    }

    /// Feeds one drawn frame to the overlay: the wall-clock time since the frame before
    /// (`frame_s`, s: [`GameUi::frame_started`]), its CPU time (update + upload + encode, ms)
    /// and the GPU's time drawing a frame (ms, from timestamp queries; NaN when the device
    /// cannot time frames). Every [`FRAME_STATS_PERIOD_S`] the overlay's text is rewritten
    /// (in place, no allocation) with the averages:
    ///
    /// `50 fps  frame 20.0 ms (worst 24.1)` / `cpu 4.0 ms  gpu 6.0 ms` — frames per second
    /// and the time between frames on the wall clock, the CPU's and the GPU's share of a frame.
    /// The governor is told the larger of the two shares.
    pub fn record_frame_time(&mut self, frame_s: f64, cpu_ms: f64, gpu_ms: f64) {
        if !frame_s.is_finite() || frame_s <= 0.0 {
            return;
        }
        let s = &mut self.stats;
        s.frame_s += frame_s;
        s.cpu_ms += if cpu_ms.is_finite() { cpu_ms } else { 0.0 };
        if gpu_ms.is_finite() && gpu_ms >= 0.0 {
            s.gpu_ms += gpu_ms;
            s.gpu_frames += 1;
        }
        s.worst_s = s.worst_s.max(frame_s);
        s.frames += 1;
        if s.frame_s < FRAME_STATS_PERIOD_S && !self.stats_text.is_empty() {
            return;
        }
        let n = s.frames as f64;
        self.stats_text.clear();
        let _ = write!(
            self.stats_text,
            "{:.0} fps  frame {:.1} ms (worst {:.1})\ncpu {:.1} ms  ",
            n / s.frame_s,
            s.frame_s * 1e3 / n,
            s.worst_s * 1e3,
            s.cpu_ms / n,
        );
        if s.gpu_frames > 0 {
            let _ = write!(
                self.stats_text,
                "gpu {:.1} ms",
                s.gpu_ms / s.gpu_frames as f64
            );
        } else {
            self.stats_text.push_str("gpu not timed");
        }
        *s = FrameStats::default();
    }

    /// The overlay's current text, two lines (empty until a frame time was recorded).
    pub fn frame_stats_text(&self) -> &str {
        &self.stats_text
    }

    /// Declares this frame's widgets for the game's screen (between `ui.begin` and `ui.end`).
    pub fn draw(&mut self, ui: &mut Ui, game: &mut Game, settings: &mut Settings) -> UiOutcome {
        let mut out = UiOutcome::default();
        if game.best() > settings.best {
            settings.best = game.best();
            out.settings_changed = true;
        } else if settings.best > game.best() {
            game.set_best(settings.best);
        }
        match game.screen() {
            Screen::Main => self.main(ui, game, settings, &mut out),
            Screen::Play => self.play(ui, game, &mut out),
            Screen::GameOver => self.game_over(ui, game, &mut out),
        }
        if self.show_frame_stats {
            self.frame_stats(ui);
        }
        out
    }

    /// The frame-time overlay: two lines, top left, on a dark box (below the score in play
    /// on a screen too narrow for both side by side).
    fn frame_stats(&mut self, ui: &mut Ui) {
        let text = if self.stats_text.is_empty() {
            "-- fps"
        } else {
            self.stats_text.as_str()
        };
        let size = 16.0;
        let w = text
            .split('\n')
            .map(|l| ui.text_width(l, size))
            .fold(0.0, f32::max);
        let lines = text.split('\n').count() as f32;
        let r = ui.anchored(
            Anchor::TopLeft,
            [8.0, 8.0],
            [w + 12.0, lines * (size + 2.0) + 6.0],
        );
        ui.fill(r, [0.0, 0.0, 0.0, 0.55]);
        for (i, line) in text.split('\n').enumerate() {
            let y = r.y + 4.0 + i as f32 * (size + 2.0);
            ui.label_colored([r.x + 6.0, y], line, size, [0.7, 1.0, 0.7, 1.0]);
        }
    }

    /// The main menu, laid out around the showroom's character ([`menu::menu_layout`]):
    /// landscape, the title, the panel and the key hints in a column on the right; portrait,
    /// the title at the top and the panel and the hints at the bottom. On a small or short
    /// safe area (a phone, a landscape phone with a keyboard, a 1280×300 window) the column
    /// narrows, text shrinks to fit and pieces are dropped, so nothing overlaps.
    fn main(&mut self, ui: &mut Ui, game: &mut Game, settings: &mut Settings, out: &mut UiOutcome) {
        let layout = menu::menu_layout(
            ui.safe_rect(),
            ui.text_width(menu::TITLE, menu::TITLE_SIZE),
            menu::hint_width(ui),
        );
        if let Some(strip) = layout.hint {
            ui.fill(strip, [0.0, 0.0, 0.0, 0.6]);
            for (i, line) in menu::HINT.iter().enumerate() {
                if let Some(pos) = layout.hint_line(i) {
                    ui.label_colored(pos, line, layout.hint_size, DIM);
                }
            }
        }
        if let Some(r) = layout.title {
            ui.label_colored([r.x, r.y], menu::TITLE, layout.title_size, TITLE);
        }
        // The panel: the two buttons, and the best score where there is room.
        let panel = layout.panel;
        ui.panel(panel);
        let model = settings.shading_model();
        self.option.clear();
        let _ = write!(self.option, "Skin: {}", model.label());
        let bw = layout.button_w();
        let option = Anchor::Top.place(panel, [0.0, layout.gap()], [bw, menu::BUTTON_H]);
        if ui.button("shading", option, &self.option) {
            settings.set_shading_model(model.next());
            out.shading_changed = true;
            out.settings_changed = true;
        }
        let start = option.below(12.0);
        if ui.button("start", start, "Start") {
            game.start();
            out.started = true;
        }
        if layout.best {
            self.line1.clear();
            let _ = write!(self.line1, "Best: {} m", settings.best.max(game.best()));
            let best = Anchor::Bottom.place(panel, [0.0, layout.gap()], [bw, menu::BEST_H]);
            ui.label_centered(best, &self.line1, menu::BEST_H, DIM);
        }
        if let Some(subject) = self.subject {
            self.subject_option(ui, layout.stage, subject, out);
        }
    }

    /// The showroom's subject option in the stage's top-left corner and, while the head is
    /// shown, its credit along the stage's bottom.
    fn subject_option(
        &mut self,
        ui: &mut Ui,
        stage: dermis_engine::ui::Rect,
        subject: Subject,
        out: &mut UiOutcome,
    ) {
        let option = dermis_engine::ui::Rect::new(
            stage.x,
            stage.y,
            SUBJECT_W.min(stage.w),
            SUBJECT_H.min(stage.h),
        );
        if ui.button("subject", option, subject.label()) {
            self.subject = Some(subject.other());
            out.subject_changed = true;
        }
        if subject != Subject::Head {
            return;
        }
        let widest = CREDIT_LINES
            .iter()
            .map(|l| ui.text_width(l, CREDIT_SIZE))
            .fold(0.0, f32::max);
        let pad = 4.0;
        let size = (CREDIT_SIZE * (stage.w - 2.0 * pad) / widest.max(1.0)).clamp(1.0, CREDIT_SIZE);
        let line_h = size + 2.0;
        let h = CREDIT_LINES.len() as f32 * line_h + 2.0 * pad;
        let w = (widest * size / CREDIT_SIZE + 2.0 * pad).min(stage.w);
        let r = dermis_engine::ui::Rect::new(stage.x, stage.y + stage.h - h, w, h);
        ui.fill(r, [0.0, 0.0, 0.0, 0.55]);
        for (i, line) in CREDIT_LINES.iter().enumerate() {
            let pos = [r.x + pad, r.y + pad + i as f32 * line_h];
            ui.label_colored(pos, line, size, DIM);
        }
    }

    fn play(&mut self, ui: &mut Ui, game: &mut Game, out: &mut UiOutcome) {
        self.line1.clear();
        let _ = write!(self.line1, "{} m", game.score());
        let panel = ui.anchored(Anchor::Top, [0.0, 12.0], [160.0, 56.0]);
        ui.panel(panel);
        ui.label_centered(panel, &self.line1, 32.0, [1.0; 4]);
        // The camera switch, for touch screens (the C key on a keyboard).
        let view = ui.anchored(Anchor::TopRight, [12.0, 12.0], [88.0, 48.0]);
        if !game.is_paused() && ui.button("view", view, "View") {
            out.camera_toggled = true;
        }
        if game.is_paused() {
            let w = centre_panel_w(ui);
            let panel = ui.anchored(Anchor::Center, [0.0, 0.0], [w, 220.0]);
            ui.panel(panel);
            let head = Anchor::Top.place(panel, [0.0, 24.0], [w - 40.0, 40.0]);
            ui.label_centered(head, "PAUSED", 40.0, TITLE);
            let resume = Anchor::Bottom.place(panel, [0.0, 24.0], [(w - 40.0).min(220.0), 56.0]);
            if ui.button("resume", resume, "Resume") {
                game.resume();
                out.resumed = true;
            }
        }
    }

    /// The game-over panel, beside the runner so the runner standing at the crate it hit
    /// stays in view: landscape, on the side of the screen away from it (the right unless it
    /// died in the right-hand lane); portrait, at the top.
    fn game_over(&mut self, ui: &mut Ui, game: &mut Game, out: &mut UiOutcome) {
        let safe = ui.safe_rect();
        let (w, anchor, offset) = if safe.w > safe.h {
            let w = (GAME_OVER_SHARE * safe.w).clamp(menu::PANEL_MIN_W, menu::PANEL_W);
            // Lane 1 is the runner's right: the right of the screen (the camera is behind it).
            let anchor = if game.lane() > 0 {
                Anchor::Left
            } else {
                Anchor::Right
            };
            (w.min(centre_panel_w(ui)), anchor, [menu::MARGIN, 0.0])
        } else {
            (centre_panel_w(ui), Anchor::Top, [0.0, menu::MARGIN])
        };
        let panel = ui.anchored(anchor, offset, [w, 240.0]);
        ui.panel(panel);
        let head = Anchor::Top.place(panel, [0.0, 24.0], [w - 40.0, 40.0]);
        ui.label_centered(head, "GAME OVER", 40.0, TITLE);
        self.line1.clear();
        let _ = write!(self.line1, "Score: {} m", game.score());
        let score = head.below(16.0);
        ui.label_centered(score, &self.line1, 28.0, [1.0; 4]);
        self.line2.clear();
        if game.is_new_best() {
            let _ = write!(self.line2, "New best!");
        } else {
            let _ = write!(self.line2, "Best: {} m", game.best());
        }
        let best = Anchor::Top.place(score, [0.0, 40.0], [w - 40.0, 24.0]);
        ui.label_centered(best, &self.line2, 22.0, DIM);
        let replay = Anchor::Bottom.place(panel, [0.0, 24.0], [(w - 40.0).min(220.0), 56.0]);
        if ui.button("replay", replay, "Replay") {
            game.replay();
            out.started = true;
        }
    }
}

/// The pause panel's width (and the game-over panel's in portrait): 340 units, less on a
/// screen narrower than that.
fn centre_panel_w(ui: &Ui) -> f32 {
    (ui.safe_rect().w - 2.0 * menu::MARGIN).clamp(240.0, 340.0)
}

//! The game's screens, drawn with the immediate-mode UI: main (title, shading-model option
//! button, start, best score; laid out beside or below the showroom's close-up of the
//! character, see [`super::showroom`]), play (score; when paused a "Paused" panel with
//! Resume) and game over (score, best, replay), plus an optional frame-time overlay on every
//! screen.
//! Text that changes is formatted into reused `String`s, so a frame allocates nothing.

use std::fmt::Write;

use super::{showroom, Game, Screen, Settings};
use crate::ui::{Anchor, Color, Ui};

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
}

/// How often the frame-time overlay's numbers change (seconds of frames averaged), so the
/// UI is not rebuilt every frame for it.
pub const FRAME_STATS_PERIOD_S: f64 = 0.5;

/// Per-screen text buffers, reused every frame.
pub struct GameUi {
    option: String,
    line1: String,
    line2: String,
    /// Show the frame-time overlay (FPS, frame time, CPU time). Off by default.
    pub show_frame_stats: bool,
    stats_text: String,
    stats: FrameStats,
}

/// Frame times accumulated over [`FRAME_STATS_PERIOD_S`] for the overlay.
#[derive(Clone, Copy, Debug, Default)]
struct FrameStats {
    dt_s: f64,
    cpu_ms: f64,
    cost_ms: f64,
    frames: u32,
    worst_dt_s: f64,
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
            stats_text: String::with_capacity(96),
            stats: FrameStats::default(),
        }
    }

    /// Feeds one drawn frame's times to the overlay: the time it covered (`dt_s`, s), its CPU
    /// time (update + upload + encode, ms) and the cost the governor was told (ms; NaN when
    /// unknown). Every [`FRAME_STATS_PERIOD_S`] the overlay's text is rewritten (in place,
    /// no allocation) with the averages.
    pub fn record_frame_time(&mut self, dt_s: f64, cpu_ms: f64, cost_ms: f64) {
        if !dt_s.is_finite() || dt_s <= 0.0 {
            return;
        }
        let s = &mut self.stats;
        s.dt_s += dt_s;
        s.cpu_ms += if cpu_ms.is_finite() { cpu_ms } else { 0.0 };
        s.cost_ms += if cost_ms.is_finite() { cost_ms } else { 0.0 };
        s.worst_dt_s = s.worst_dt_s.max(dt_s);
        s.frames += 1;
        if s.dt_s < FRAME_STATS_PERIOD_S && !self.stats_text.is_empty() {
            return;
        }
        let n = s.frames as f64;
        self.stats_text.clear();
        let _ = write!(
            self.stats_text,
            "{:.0} fps  {:.1} ms (max {:.1})  cpu {:.1} ms  cost {:.1} ms",
            n / s.dt_s,
            s.dt_s * 1e3 / n,
            s.worst_dt_s * 1e3,
            s.cpu_ms / n,
            s.cost_ms / n
        );
        *s = FrameStats::default();
    }

    /// The overlay's current text (empty until a frame time was recorded).
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

    /// The frame-time overlay: one line, top left, on a dark strip.
    fn frame_stats(&mut self, ui: &mut Ui) {
        let text = if self.stats_text.is_empty() {
            "-- fps"
        } else {
            self.stats_text.as_str()
        };
        let size = 16.0;
        let w = ui.text_width(text, size);
        let r = ui.anchored(Anchor::TopLeft, [8.0, 8.0], [w + 12.0, size + 8.0]);
        ui.fill(r, [0.0, 0.0, 0.0, 0.55]);
        ui.label_colored([r.x + 6.0, r.y + 4.0], text, size, [0.7, 1.0, 0.7, 1.0]);
    }

    /// The main menu, laid out around the showroom's character ([`showroom::menu_layout`]):
    /// landscape, the title and the panel in a column on the right; portrait, the title at
    /// the top and the panel at the bottom; the hint on a dark strip at the bottom. On a short
    /// safe area (a landscape phone with a keyboard, a 1280×300 window) the panel shrinks to
    /// its buttons and the title goes first, so nothing overlaps.
    fn main(&mut self, ui: &mut Ui, game: &mut Game, settings: &mut Settings, out: &mut UiOutcome) {
        let layout = showroom::menu_layout(
            ui.safe_rect(),
            ui.text_width(showroom::TITLE, showroom::TITLE_SIZE),
            ui.text_width(showroom::HINT, showroom::HINT_SIZE),
        );
        // Bottom: the hint, readable (20 units, light on a dark strip).
        let strip = layout.hint;
        ui.fill(strip, [0.0, 0.0, 0.0, 0.6]);
        ui.label_colored(
            [strip.x + 8.0, strip.y + 4.0],
            showroom::HINT,
            showroom::HINT_SIZE,
            DIM,
        );
        if let Some(r) = layout.title {
            ui.label_colored([r.x, r.y], showroom::TITLE, showroom::TITLE_SIZE, TITLE);
        }
        // The panel: full (two buttons and the best score) or compact (buttons only).
        let panel = layout.panel;
        ui.panel(panel);
        let model = settings.shading_model();
        self.option.clear();
        let _ = write!(self.option, "Skin: {}", model.label());
        let gap = if layout.full { 24.0 } else { 12.0 };
        let bw = layout.button_w();
        let option = Anchor::Top.place(panel, [0.0, gap], [bw, 56.0]);
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
        if layout.full {
            self.line1.clear();
            let _ = write!(self.line1, "Best: {} m", settings.best.max(game.best()));
            let best = Anchor::Bottom.place(panel, [0.0, 24.0], [bw, 24.0]);
            ui.label_centered(best, &self.line1, 24.0, DIM);
        }
    }

    fn play(&mut self, ui: &mut Ui, game: &mut Game, out: &mut UiOutcome) {
        self.line1.clear();
        let _ = write!(self.line1, "{} m", game.score());
        let panel = ui.anchored(Anchor::Top, [0.0, 12.0], [200.0, 56.0]);
        ui.panel(panel);
        ui.label_centered(panel, &self.line1, 32.0, [1.0; 4]);
        if game.is_paused() {
            let panel = ui.anchored(Anchor::Center, [0.0, 0.0], [340.0, 220.0]);
            ui.panel(panel);
            let head = Anchor::Top.place(panel, [0.0, 24.0], [300.0, 40.0]);
            ui.label_centered(head, "PAUSED", 40.0, TITLE);
            let resume = Anchor::Bottom.place(panel, [0.0, 24.0], [220.0, 56.0]);
            if ui.button("resume", resume, "Resume") {
                game.resume();
                out.resumed = true;
            }
        }
    }

    fn game_over(&mut self, ui: &mut Ui, game: &mut Game, out: &mut UiOutcome) {
        let panel = ui.anchored(Anchor::Center, [0.0, 0.0], [340.0, 280.0]);
        ui.panel(panel);
        let head = Anchor::Top.place(panel, [0.0, 24.0], [300.0, 40.0]);
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
        let best = Anchor::Top.place(score, [0.0, 40.0], [300.0, 24.0]);
        ui.label_centered(best, &self.line2, 22.0, DIM);
        let replay = Anchor::Bottom.place(panel, [0.0, 24.0], [220.0, 56.0]);
        if ui.button("replay", replay, "Replay") {
            game.replay();
            out.started = true;
        }
    }
}

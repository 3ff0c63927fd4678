//! The game's screens, drawn with the immediate-mode UI: main (title, shading-model option
//! button, start, best score), play (score) and game over (score, best, replay).
//! Text that changes is formatted into reused `String`s, so a frame allocates nothing.

use std::fmt::Write;

use super::{Game, Screen, Settings};
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
}

/// Per-screen text buffers, reused every frame.
pub struct GameUi {
    option: String,
    line1: String,
    line2: String,
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
        }
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
            Screen::Play => self.play(ui, game),
            Screen::GameOver => self.game_over(ui, game, &mut out),
        }
        out
    }

    fn main(&mut self, ui: &mut Ui, game: &mut Game, settings: &mut Settings, out: &mut UiOutcome) {
        let title = "XICOM RUNNER";
        let size = 44.0;
        let w = ui.text_width(title, size);
        let r = ui.anchored(Anchor::Top, [0.0, 40.0], [w, size]);
        ui.label_colored([r.x, r.y], title, size, TITLE);

        let panel = ui.anchored(Anchor::Center, [0.0, 20.0], [340.0, 250.0]);
        ui.panel(panel);
        let model = settings.shading_model();
        self.option.clear();
        let _ = write!(self.option, "Skin: {}", model.label());
        let option = Anchor::Top.place(panel, [0.0, 24.0], [300.0, 56.0]);
        if ui.button("shading", option, &self.option) {
            settings.set_shading_model(model.next());
            out.shading_changed = true;
            out.settings_changed = true;
        }
        let start = option.below(16.0);
        if ui.button("start", start, "Start") {
            game.start();
            out.started = true;
        }
        self.line1.clear();
        let _ = write!(self.line1, "Best: {} m", settings.best.max(game.best()));
        let best = Anchor::Bottom.place(panel, [0.0, 24.0], [300.0, 24.0]);
        ui.label_centered(best, &self.line1, 24.0, DIM);

        let hint = "Space/tap: jump   Arrows/swipe: change lane";
        let hint_size = 16.0;
        let hw = ui.text_width(hint, hint_size);
        let h = ui.anchored(Anchor::Bottom, [0.0, 16.0], [hw, hint_size]);
        ui.label_colored([h.x, h.y], hint, hint_size, DIM);
    }

    fn play(&mut self, ui: &mut Ui, game: &Game) {
        self.line1.clear();
        let _ = write!(self.line1, "{} m", game.score());
        let panel = ui.anchored(Anchor::Top, [0.0, 12.0], [200.0, 56.0]);
        ui.panel(panel);
        ui.label_centered(panel, &self.line1, 32.0, [1.0; 4]);
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

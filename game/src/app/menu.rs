//! Where the main menu's pieces go (logical units, density-independent): the title, the panel
//! (skin-model option, start, best score), the key hints, and the *stage* — the part of the
//! screen left to the showroom's close-up of the character ([`super::showroom`]).
//!
//! Landscape: the character on the left; on the right a column holding the title, the panel
//! and the hints. Portrait (or too narrow for a column): the title at the top, the character
//! under it, the panel and the hints at the bottom. Nothing overlaps the stage. On a small
//! screen (a phone is 360–420 dp across) the column narrows, the title and the hints shrink to
//! fit, and pieces are dropped in a fixed order when there is no height for them: first the
//! panel's roomy spacing, then the title, then the hints shrink to their smallest size, then
//! the best score goes, then the hints; the two buttons always stay.

use super::Viewport;
use dermis_engine::ui::{Rect, Ui};

/// Space between the menu's pieces and the safe area's edges.
pub const MARGIN: f32 = 12.0;
/// The menu panel's widest width; it takes [`PANEL_SHARE`] of a narrower landscape screen, but
/// never less than [`PANEL_MIN_W`].
pub const PANEL_W: f32 = 340.0;
pub const PANEL_MIN_W: f32 = 240.0;
pub const PANEL_SHARE: f32 = 0.42;
/// The panel's heights: roomy with the best score, tight with it, its two buttons only.
pub const PANEL_FULL_H: f32 = 250.0;
pub const PANEL_TIGHT_H: f32 = 2.0 * BUTTON_H + BEST_H + 4.0 * 12.0;
pub const PANEL_COMPACT_H: f32 = 2.0 * BUTTON_H + 3.0 * 12.0;
/// A button's height (a comfortable touch target) and the best score's line.
pub const BUTTON_H: f32 = 56.0;
pub const BEST_H: f32 = 24.0;
pub const TITLE: &str = "XICOM RUNNER";
/// The title's and the hints' largest sizes (line heights); they shrink to fit a narrow
/// screen, the hints not below [`HINT_MIN_SIZE`].
pub const TITLE_SIZE: f32 = 44.0;
pub const HINT: [&str; 3] = [
    "Space / tap: jump",
    "Arrows / swipe: change lane",
    "P: pause   C / View: close-up",
];
pub const HINT_SIZE: f32 = 18.0;
pub const HINT_MIN_SIZE: f32 = 12.0;
/// Space between the hints' lines, and around them inside their dark box.
pub const HINT_LINE_GAP: f32 = 3.0;
pub const HINT_PAD: f32 = 6.0;
/// The narrowest stage that puts the panel beside the character rather than below it.
pub const MIN_SIDE_STAGE_W: f32 = 240.0;
/// Portrait: the stage keeps at least this height before pieces are dropped.
pub const MIN_STAGE_H: f32 = 200.0;

/// Where the main menu's pieces go, in logical units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MenuLayout {
    /// The title's rectangle and text size; `None` on a screen too short for it.
    pub title: Option<Rect>,
    pub title_size: f32,
    /// The hints' dark box (lines inside, [`HINT_PAD`] in) and their text size; `None` when
    /// there is no room for them.
    pub hint: Option<Rect>,
    pub hint_size: f32,
    pub panel: Rect,
    /// Whether the panel shows the best score (else only its two buttons).
    pub best: bool,
    /// Whether the panel has its roomy spacing.
    pub roomy: bool,
    /// Where the character is shown: clear of the panel, the title and the hints (on a window
    /// too small for that, the whole safe area).
    pub stage: Rect,
    /// Landscape (panel beside the stage) or portrait (panel below it).
    pub side: bool,
}

impl MenuLayout {
    /// The widgets' width inside the panel.
    pub fn button_w(&self) -> f32 {
        (self.panel.w - 40.0).clamp(0.0, 300.0)
    }

    /// The gap above the first button (and below the best score).
    pub fn gap(&self) -> f32 {
        if self.roomy {
            24.0
        } else {
            12.0
        }
    }

    /// The top-left corner of each hint line.
    pub fn hint_line(&self, i: usize) -> Option<[f32; 2]> {
        let r = self.hint?;
        Some([
            r.x + HINT_PAD,
            r.y + HINT_PAD + i as f32 * (self.hint_size + HINT_LINE_GAP),
        ])
    }
}

/// The hints' box height at text size `size`.
fn hint_h(size: f32) -> f32 {
    HINT.len() as f32 * size + (HINT.len() - 1) as f32 * HINT_LINE_GAP + 2.0 * HINT_PAD
}

/// What fits in `room` (height) besides the two buttons, taken in this order: the hints at
/// their smallest size ([`HINT_MIN_SIZE`]), the best score, the hints at `hint_size`, the
/// title, the panel's roomy spacing (which needs `roomy_room`).
struct Fit {
    best: bool,
    /// The hints' text size, when they are shown.
    hint: Option<f32>,
    title: bool,
    roomy: bool,
}

fn fit(room: f32, roomy_room: f32, title_h: f32, hint_size: f32) -> Fit {
    let mut used = PANEL_COMPACT_H;
    let mut take = |h: f32| {
        let ok = used + h <= room;
        if ok {
            used += h;
        }
        ok
    };
    let small = HINT_MIN_SIZE.min(hint_size);
    let shown = take(hint_h(small) + MARGIN);
    let best = take(PANEL_TIGHT_H - PANEL_COMPACT_H);
    let hint = match shown {
        true if take(hint_h(hint_size) - hint_h(small)) => Some(hint_size),
        true => Some(small),
        false => None,
    };
    let title = take(title_h + MARGIN);
    let roomy = best && used + PANEL_FULL_H - PANEL_TIGHT_H <= roomy_room;
    Fit {
        best,
        hint,
        title,
        roomy,
    }
}

/// The main menu's layout in `safe` (logical units) for a title `title_w` wide at
/// [`TITLE_SIZE`] and hints whose widest line is `hint_w` at [`HINT_SIZE`].
pub fn menu_layout(safe: Rect, title_w: f32, hint_w: f32) -> MenuLayout {
    let side_w = (PANEL_SHARE * safe.w).clamp(PANEL_MIN_W, PANEL_W);
    let side = safe.w > safe.h && safe.w >= side_w + 3.0 * MARGIN + MIN_SIDE_STAGE_W;
    let col_w = if side {
        side_w
    } else {
        (safe.w - 2.0 * MARGIN).max(0.0)
    };
    let title_size = TITLE_SIZE * (col_w / title_w.max(1.0)).min(1.0);
    let title_w = title_w * title_size / TITLE_SIZE;
    let hint_fit =
        (HINT_SIZE * ((col_w - 2.0 * HINT_PAD) / hint_w.max(1.0)).min(1.0)).max(HINT_MIN_SIZE);
    let f = if side {
        let room = safe.h - 2.0 * MARGIN;
        fit(room, room, title_size, hint_fit)
    } else {
        // The panel's roomy spacing only where the character keeps half the height.
        fit(
            safe.h - 3.0 * MARGIN - MIN_STAGE_H,
            safe.h - 3.0 * MARGIN - MIN_STAGE_H.max(0.5 * safe.h),
            title_size,
            hint_fit,
        )
    };
    let panel_h = panel_h(&f);
    let hint_size = f.hint.unwrap_or(hint_fit);
    let hint_box_w = (hint_w * hint_size / HINT_SIZE + 2.0 * HINT_PAD).min(col_w);
    let bottom = safe.y + safe.h - MARGIN;
    // The column (landscape: beside the stage) or the full width (portrait), and the hints'
    // box at its bottom.
    let (col_x, col_w) = if side {
        (safe.x + safe.w - MARGIN - col_w, col_w)
    } else {
        (safe.x, safe.w)
    };
    let mut below = bottom;
    let hint = f.hint.map(|size| {
        let h = hint_h(size);
        below -= h + MARGIN;
        Rect::new(
            col_x + (col_w - hint_box_w) * 0.5,
            bottom - h,
            hint_box_w,
            h,
        )
    });
    let top = safe.y + MARGIN;
    let title = f
        .title
        .then(|| Rect::new(col_x + (col_w - title_w) * 0.5, top, title_w, title_size));
    let under_title = if f.title {
        top + title_size + MARGIN
    } else {
        top
    };
    if side {
        let y = under_title + ((below - under_title - panel_h) * 0.5).max(0.0);
        let panel = Rect::new(col_x, y, col_w, panel_h);
        // The full height, less a twentieth top and bottom: the close-up keeps clear of the
        // screen's edges.
        let x0 = safe.x + MARGIN;
        let m = MARGIN.max(0.05 * safe.h);
        let stage = Rect::new(
            x0,
            safe.y + m,
            (col_x - MARGIN - x0).max(1.0),
            (safe.h - 2.0 * m).max(1.0),
        );
        return MenuLayout {
            title,
            title_size,
            hint,
            hint_size,
            panel,
            best: f.best,
            roomy: f.roomy,
            stage,
            side,
        };
    }
    let panel_w = (safe.w - 2.0 * MARGIN).clamp(0.0, PANEL_W);
    // At the bottom above the hints; on a short screen right under the title.
    let y = (below - panel_h).max(under_title);
    let panel = Rect::new(safe.x + (safe.w - panel_w) * 0.5, y, panel_w, panel_h);
    let stage = if y - MARGIN - under_title >= 0.5 * MIN_STAGE_H {
        Rect::new(
            safe.x + MARGIN,
            under_title,
            (safe.w - 2.0 * MARGIN).max(1.0),
            y - MARGIN - under_title,
        )
    } else {
        // No room beside or above the panel (a tiny window): the whole safe area.
        safe.inset(MARGIN.min(0.25 * safe.w.min(safe.h)))
    };
    MenuLayout {
        title,
        title_size,
        hint,
        hint_size,
        panel,
        best: f.best,
        roomy: f.roomy,
        stage,
        side,
    }
}

fn panel_h(f: &Fit) -> f32 {
    match (f.best, f.roomy) {
        (true, true) => PANEL_FULL_H,
        (true, false) => PANEL_TIGHT_H,
        _ => PANEL_COMPACT_H,
    }
}

/// The widest hint line at [`HINT_SIZE`], measured with `ui`'s font.
pub fn hint_width(ui: &Ui) -> f32 {
    HINT.iter()
        .map(|l| ui.text_width(l, HINT_SIZE))
        .fold(0.0, f32::max)
}

/// The whole screen and the safe area of `viewport` in logical units (as [`Ui::begin`] sees
/// them).
pub fn viewport_rects(viewport: &Viewport) -> (Rect, Rect) {
    let s = if viewport.scale.is_finite() && viewport.scale > 0.0 {
        viewport.scale
    } else {
        1.0
    };
    let (w, h) = (viewport.width.max(1) as f32, viewport.height.max(1) as f32);
    let i = viewport.insets;
    (
        Rect::new(0.0, 0.0, w / s, h / s),
        Rect::new(
            i.left / s,
            i.top / s,
            ((w - i.left - i.right) / s).max(0.0),
            ((h - i.top - i.bottom) / s).max(0.0),
        ),
    )
}

/// The menu's layout for `viewport`, measured with `ui`'s font.
pub fn layout_for(ui: &Ui, viewport: &Viewport) -> (Rect, MenuLayout) {
    let (screen, safe) = viewport_rects(viewport);
    let layout = menu_layout(safe, ui.text_width(TITLE, TITLE_SIZE), hint_width(ui));
    (screen, layout)
}

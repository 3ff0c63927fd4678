//! An immediate-mode UI drawn from the project's own skin atlas with one pipeline and one
//! draw call (§4.3 items 3 and 4).
//!
//! Every frame the app calls [`Ui::begin`], declares widgets (`if ui.button(..) { .. }`) and
//! calls [`Ui::end`]. Widgets are recorded as a small command list (no vertices); `end`
//! hashes the list (content + layout + screen) and rebuilds the vertex data only when the hash
//! differs from the previous frame's — [`Ui::rebuilds`] counts those rebuilds and
//! [`Ui::needs_upload`] says when the GPU copy is stale. Coordinates are logical units
//! (density-independent pixels): `begin` takes the density `scale` and the safe-area insets,
//! vertices come out in physical pixels. All buffers are reused, so a steady-state frame
//! allocates nothing.

mod atlas;
mod layout;
mod quads;

pub use atlas::{atlas_rgba, Atlas, Glyph, Sprite, TexRect, ATLAS_JSON, ATLAS_PNG};
pub use layout::{Anchor, Insets, Rect};
use quads::Builder;

use std::ops::Range;

/// One UI vertex: position in physical pixels (origin top-left), atlas UV, premultiplied
/// display-space (sRGB-encoded) colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct UiVertex {
    pub pos: [f32; 2],
    pub uv: [f32; 2],
    pub color: [u8; 4],
}

/// Vertices the UI can emit per frame (6 per quad); the GPU buffer has this capacity.
pub const MAX_VERTICES: usize = 6 * 4096;

/// A straight-alpha display-space colour.
pub type Color = [f32; 4];
pub const WHITE: Color = [1.0, 1.0, 1.0, 1.0];

/// Pointer events queued between frames (physical pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointerEvent {
    Down([f32; 2]),
    Up([f32; 2]),
}

const MAX_EVENTS: usize = 16;

#[derive(Clone, Debug, PartialEq)]
enum Cmd {
    Panel {
        rect: Rect,
    },
    Button {
        rect: Rect,
        pressed: bool,
        text: Range<u32>,
        size: f32,
    },
    Label {
        pos: [f32; 2],
        text: Range<u32>,
        size: f32,
        color: Color,
    },
    Fill {
        rect: Rect,
        color: Color,
    },
}

/// FNV-1a, 64 bit.
#[derive(Clone, Copy)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }
    fn rect(&mut self, r: &Rect) {
        for v in [r.x, r.y, r.w, r.h] {
            self.f32(v);
        }
    }
}

fn id_hash(id: &str) -> u64 {
    let mut h = Fnv::new();
    h.bytes(id.as_bytes());
    h.0
}

pub struct Ui {
    atlas: Atlas,
    screen: [f32; 2],
    scale: f32,
    insets: Insets,
    cmds: Vec<Cmd>,
    text: String,
    vertices: Vec<UiVertex>,
    prev_hash: Option<u64>,
    rebuilds: u64,
    rebuilt_this_frame: bool,
    needs_upload: bool,
    events: [PointerEvent; MAX_EVENTS],
    event_count: usize,
    /// The button held down since an earlier frame (id hash).
    active: Option<u64>,
    next_active: Option<u64>,
    in_frame: bool,
}

impl Ui {
    pub fn new(atlas: Atlas) -> Self {
        Self {
            atlas,
            screen: [1.0, 1.0],
            scale: 1.0,
            insets: Insets::ZERO,
            cmds: Vec::with_capacity(64),
            text: String::with_capacity(1024),
            vertices: Vec::with_capacity(MAX_VERTICES),
            prev_hash: None,
            rebuilds: 0,
            rebuilt_this_frame: false,
            needs_upload: false,
            events: [PointerEvent::Up([0.0; 2]); MAX_EVENTS],
            event_count: 0,
            active: None,
            next_active: None,
            in_frame: false,
        }
    }

    /// A UI on the embedded atlas.
    pub fn with_embedded_atlas() -> Self {
        Self::new(Atlas::embedded())
    }

    pub fn atlas(&self) -> &Atlas {
        &self.atlas
    }

    // ---- input (between frames) ----

    /// Queues a press at physical pixel `(x, y)` (mouse button / touch down).
    pub fn pointer_down(&mut self, x: f32, y: f32) {
        self.push_event(PointerEvent::Down([x, y]));
    }

    /// Queues a release at physical pixel `(x, y)`.
    pub fn pointer_up(&mut self, x: f32, y: f32) {
        self.push_event(PointerEvent::Up([x, y]));
    }

    fn push_event(&mut self, e: PointerEvent) {
        if self.event_count < MAX_EVENTS {
            self.events[self.event_count] = e;
            self.event_count += 1;
        }
    }

    /// Whether a button is being held (the app should not treat the pointer as game input).
    pub fn is_pointer_captured(&self) -> bool {
        self.active.is_some()
    }

    // ---- frame ----

    /// Starts a frame on a `screen_w`×`screen_h` pixel surface with density `scale`
    /// (physical pixels per logical unit) and the safe-area `insets` (physical pixels).
    pub fn begin(&mut self, screen_w: f32, screen_h: f32, scale: f32, insets: Insets) {
        self.screen = [screen_w.max(1.0), screen_h.max(1.0)];
        self.scale = if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        };
        self.insets = insets;
        self.cmds.clear();
        self.text.clear();
        self.next_active = if self.event_count == 0 {
            self.active
        } else {
            None
        };
        self.rebuilt_this_frame = false;
        self.in_frame = true;
    }

    /// Density scale of the current frame.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The whole screen in logical units.
    pub fn screen_rect(&self) -> Rect {
        Rect::new(
            0.0,
            0.0,
            self.screen[0] / self.scale,
            self.screen[1] / self.scale,
        )
    }

    /// The safe area (screen minus insets) in logical units.
    pub fn safe_rect(&self) -> Rect {
        let s = self.scale;
        let i = self.insets;
        Rect::new(
            i.left / s,
            i.top / s,
            ((self.screen[0] - i.left - i.right) / s).max(0.0),
            ((self.screen[1] - i.top - i.bottom) / s).max(0.0),
        )
    }

    /// A `size` rectangle (logical) anchored in the safe area, `offset` inwards.
    pub fn anchored(&self, anchor: Anchor, offset: [f32; 2], size: [f32; 2]) -> Rect {
        anchor.place(self.safe_rect(), offset, size)
    }

    /// Width of `text` at `size` (logical units; `size` is the line height).
    pub fn text_width(&self, text: &str, size: f32) -> f32 {
        let k = size / self.atlas.line_height;
        text.bytes()
            .map(|c| self.atlas.glyph(c).advance)
            .sum::<f32>()
            * k
    }

    fn push_text(&mut self, s: &str) -> Range<u32> {
        let start = self.text.len() as u32;
        self.text.push_str(s);
        start..self.text.len() as u32
    }

    /// A skinned 9-slice panel.
    pub fn panel(&mut self, rect: Rect) {
        self.cmds.push(Cmd::Panel { rect });
    }

    /// A solid rectangle.
    pub fn fill(&mut self, rect: Rect, color: Color) {
        self.cmds.push(Cmd::Fill { rect, color });
    }

    /// White text with its line box's top-left at `pos` (logical), `size` = line height.
    pub fn label(&mut self, pos: [f32; 2], text: &str, size: f32) {
        self.label_colored(pos, text, size, WHITE);
    }

    pub fn label_colored(&mut self, pos: [f32; 2], text: &str, size: f32, color: Color) {
        let text = self.push_text(text);
        self.cmds.push(Cmd::Label {
            pos,
            text,
            size,
            color,
        });
    }

    /// Text centred in `rect`.
    pub fn label_centered(&mut self, rect: Rect, text: &str, size: f32, color: Color) {
        let w = self.text_width(text, size);
        let pos = [rect.x + (rect.w - w) * 0.5, rect.y + (rect.h - size) * 0.5];
        self.label_colored(pos, text, size, color);
    }

    /// A button; true on the frame it is clicked (pressed and released inside it).
    pub fn button(&mut self, id: &str, rect: Rect, label: &str) -> bool {
        let id = id_hash(id);
        let inv = 1.0 / self.scale;
        let mut held = self.active == Some(id);
        let mut clicked = false;
        for e in &self.events[..self.event_count] {
            match *e {
                PointerEvent::Down(p) => held = rect.contains([p[0] * inv, p[1] * inv]),
                PointerEvent::Up(p) => {
                    clicked |= held && rect.contains([p[0] * inv, p[1] * inv]);
                    held = false;
                }
            }
        }
        if held {
            self.next_active = Some(id);
        }
        let size = (rect.h * 0.42)
            .min(rect.w / (label.len().max(1) as f32 * 0.55))
            .max(1.0);
        let text = self.push_text(label);
        self.cmds.push(Cmd::Button {
            rect,
            pressed: held,
            text,
            size,
        });
        clicked
    }

    /// The rectangles (logical units) of this frame's buttons, in declaration order — for
    /// layout checks (nothing a player must touch may sit under a display cutout).
    pub fn button_rects(&self) -> impl Iterator<Item = Rect> + '_ {
        self.cmds.iter().filter_map(|c| match c {
            Cmd::Button { rect, .. } => Some(*rect),
            _ => None,
        })
    }

    /// This frame's panels (logical units), in declaration order.
    pub fn panel_rects(&self) -> impl Iterator<Item = Rect> + '_ {
        self.cmds.iter().filter_map(|c| match c {
            Cmd::Panel { rect } => Some(*rect),
            _ => None,
        })
    }

    /// This frame's labels with the rectangle their text covers (logical units).
    pub fn label_rects(&self) -> impl Iterator<Item = (&str, Rect)> + '_ {
        self.cmds.iter().filter_map(|c| match c {
            Cmd::Label {
                pos, text, size, ..
            } => {
                let t = &self.text[text.start as usize..text.end as usize];
                Some((
                    t,
                    Rect::new(pos[0], pos[1], self.text_width(t, *size), *size),
                ))
            }
            _ => None,
        })
    }

    /// Ends the frame: consumes the queued pointer events and rebuilds the vertices if any
    /// widget's content or layout changed.
    pub fn end(&mut self) {
        debug_assert!(self.in_frame, "Ui::end without begin");
        self.in_frame = false;
        self.event_count = 0;
        self.active = self.next_active;
        let hash = self.frame_hash();
        if self.prev_hash != Some(hash) {
            self.prev_hash = Some(hash);
            self.rebuild();
            self.rebuilds += 1;
            self.rebuilt_this_frame = true;
            self.needs_upload = true;
        }
    }

    fn frame_hash(&self) -> u64 {
        let mut h = Fnv::new();
        h.f32(self.screen[0]);
        h.f32(self.screen[1]);
        h.f32(self.scale);
        h.u32(self.cmds.len() as u32);
        for c in &self.cmds {
            match c {
                Cmd::Panel { rect } => {
                    h.u32(1);
                    h.rect(rect);
                }
                Cmd::Button {
                    rect,
                    pressed,
                    text: t,
                    size,
                } => {
                    h.u32(2 + *pressed as u32);
                    h.rect(rect);
                    h.f32(*size);
                    h.u32(t.len() as u32);
                    h.bytes(self.text_of(t));
                }
                Cmd::Label {
                    pos,
                    text: t,
                    size,
                    color,
                } => {
                    h.u32(4);
                    h.f32(pos[0]);
                    h.f32(pos[1]);
                    h.f32(*size);
                    color.iter().for_each(|v| h.f32(*v));
                    h.u32(t.len() as u32);
                    h.bytes(self.text_of(t));
                }
                Cmd::Fill { rect, color } => {
                    h.u32(5);
                    h.rect(rect);
                    color.iter().for_each(|v| h.f32(*v));
                }
            }
        }
        h.0
    }

    fn text_of(&self, r: &Range<u32>) -> &[u8] {
        &self.text.as_bytes()[r.start as usize..r.end as usize]
    }

    // ---- vertex building ----

    fn rebuild(&mut self) {
        let mut vertices = std::mem::take(&mut self.vertices);
        vertices.clear();
        let b = Builder {
            atlas: &self.atlas,
            scale: self.scale,
            out: &mut vertices,
        };
        let mut b = b;
        for c in &self.cmds {
            match c {
                Cmd::Panel { rect } => b.nine_slice(rect, &self.atlas.panel),
                Cmd::Fill { rect, color } => {
                    let r = b.px(rect);
                    b.quad(r, self.atlas.white, *color);
                }
                Cmd::Button {
                    rect,
                    pressed,
                    text,
                    size,
                } => {
                    let sprite = if *pressed {
                        &self.atlas.button_pressed
                    } else {
                        &self.atlas.button
                    };
                    b.nine_slice(rect, sprite);
                    let s = &self.text[text.start as usize..text.end as usize];
                    let k = size / self.atlas.line_height;
                    let w: f32 = s.bytes().map(|c| self.atlas.glyph(c).advance).sum::<f32>() * k;
                    let dy = if *pressed { 1.0 } else { 0.0 };
                    let pos = [
                        rect.x + (rect.w - w) * 0.5,
                        rect.y + (rect.h - size) * 0.5 + dy,
                    ];
                    b.text(pos, s, *size, WHITE);
                }
                Cmd::Label {
                    pos,
                    text,
                    size,
                    color,
                } => {
                    b.text(
                        *pos,
                        &self.text[text.start as usize..text.end as usize],
                        *size,
                        *color,
                    );
                }
            }
        }
        vertices.truncate(MAX_VERTICES - MAX_VERTICES % 6);
        self.vertices = vertices;
    }

    // ---- output ----

    /// The vertex data (physical pixels; a triangle list).
    pub fn vertices(&self) -> &[UiVertex] {
        &self.vertices
    }

    /// The surface size the vertices were built for (physical pixels).
    pub fn screen_size(&self) -> [f32; 2] {
        self.screen
    }

    /// How many times the vertex data has been rebuilt.
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Whether the last `end` rebuilt the vertices.
    pub fn rebuilt_this_frame(&self) -> bool {
        self.rebuilt_this_frame
    }

    /// Whether the vertices changed since the last [`Ui::mark_uploaded`].
    pub fn needs_upload(&self) -> bool {
        self.needs_upload
    }

    pub fn mark_uploaded(&mut self) {
        self.needs_upload = false;
    }

    /// Forces a rebuild on the next `end` (e.g. after the GPU buffer was recreated).
    pub fn invalidate(&mut self) {
        self.prev_hash = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_is_20_bytes() {
        assert_eq!(std::mem::size_of::<UiVertex>(), 20);
    }
}

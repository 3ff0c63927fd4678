//! UI geometry: rectangles in logical units (density-independent pixels), safe-area insets
//! and anchors.

/// A rectangle in logical units, origin top-left, y down.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rect {
    pub x: f32,
    pub y: f32,
    pub w: f32,
    pub h: f32,
}

impl Rect {
    pub const fn new(x: f32, y: f32, w: f32, h: f32) -> Self {
        Self { x, y, w, h }
    }

    pub fn contains(&self, p: [f32; 2]) -> bool {
        p[0] >= self.x && p[0] < self.x + self.w && p[1] >= self.y && p[1] < self.y + self.h
    }

    pub fn center(&self) -> [f32; 2] {
        [self.x + self.w * 0.5, self.y + self.h * 0.5]
    }

    /// Shrunk by `d` on every side.
    pub fn inset(&self, d: f32) -> Self {
        Self::new(
            self.x + d,
            self.y + d,
            (self.w - 2.0 * d).max(0.0),
            (self.h - 2.0 * d).max(0.0),
        )
    }

    /// Scaled about the origin (logical → physical pixels).
    pub fn scaled(&self, s: f32) -> Self {
        Self::new(self.x * s, self.y * s, self.w * s, self.h * s)
    }

    /// The same size, moved down by `dy` (for stacking widgets).
    pub fn below(&self, gap: f32) -> Self {
        Self::new(self.x, self.y + self.h + gap, self.w, self.h)
    }
}

/// Safe-area insets in physical pixels (display cutouts, system bars).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Insets {
    pub left: f32,
    pub top: f32,
    pub right: f32,
    pub bottom: f32,
}

impl Insets {
    pub const ZERO: Insets = Insets {
        left: 0.0,
        top: 0.0,
        right: 0.0,
        bottom: 0.0,
    };
}

/// Where a widget is attached inside the safe area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    TopLeft,
    Top,
    TopRight,
    Left,
    Center,
    Right,
    BottomLeft,
    Bottom,
    BottomRight,
}

impl Anchor {
    /// (horizontal, vertical) factors: 0 = start, 0.5 = middle, 1 = end.
    fn factors(self) -> (f32, f32) {
        match self {
            Self::TopLeft => (0.0, 0.0),
            Self::Top => (0.5, 0.0),
            Self::TopRight => (1.0, 0.0),
            Self::Left => (0.0, 0.5),
            Self::Center => (0.5, 0.5),
            Self::Right => (1.0, 0.5),
            Self::BottomLeft => (0.0, 1.0),
            Self::Bottom => (0.5, 1.0),
            Self::BottomRight => (1.0, 1.0),
        }
    }

    /// A `size` rectangle attached to `area` at this anchor, moved by `offset` *inwards*
    /// (towards the area's centre on anchored edges; plain +x / +y on centred axes).
    pub fn place(self, area: Rect, offset: [f32; 2], size: [f32; 2]) -> Rect {
        let (fx, fy) = self.factors();
        let along = |start: f32, len: f32, f: f32, off: f32, sz: f32| {
            let sign = if f > 0.75 { -1.0 } else { 1.0 };
            start + (len - sz) * f + sign * off
        };
        Rect::new(
            along(area.x, area.w, fx, offset[0], size[0]),
            along(area.y, area.h, fy, offset[1], size[1]),
            size[0],
            size[1],
        )
    }
}

//! The player's input: key presses, taps and swipes, per frame or tick.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Swipe {
    Left,
    Right,
    Up,
    Down,
}

/// One frame's (or tick's) input. Booleans are *presses* (edges), not held keys.
/// `tap` (a touch in Play, physical pixels) jumps; `swipe` changes lane / jumps. Outside Play
/// only `jump` acts (it starts / replays); taps there belong to the UI.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Input {
    pub left: bool,
    pub right: bool,
    pub jump: bool,
    pub tap: Option<(f32, f32)>,
    pub swipe: Option<Swipe>,
}

impl Input {
    pub const NONE: Input = Input {
        left: false,
        right: false,
        jump: false,
        tap: None,
        swipe: None,
    };

    /// A touch gesture from press to release (physical pixels): a tap when it moved less
    /// than `threshold` pixels, else a swipe in its dominant direction (screen y grows down).
    pub fn from_gesture(down: (f32, f32), up: (f32, f32), threshold: f32) -> Input {
        let (dx, dy) = (up.0 - down.0, up.1 - down.1);
        let mut input = Input::NONE;
        if dx * dx + dy * dy < threshold * threshold {
            input.tap = Some(up);
        } else if dx.abs() >= dy.abs() {
            input.swipe = Some(if dx < 0.0 { Swipe::Left } else { Swipe::Right });
        } else {
            input.swipe = Some(if dy < 0.0 { Swipe::Up } else { Swipe::Down });
        }
        input
    }

    pub(crate) fn merge(&mut self, o: &Input) {
        self.left |= o.left;
        self.right |= o.right;
        self.jump |= o.jump;
        self.tap = self.tap.or(o.tap);
        self.swipe = self.swipe.or(o.swipe);
    }

    pub(crate) fn is_empty(&self) -> bool {
        *self == Input::NONE
    }
}

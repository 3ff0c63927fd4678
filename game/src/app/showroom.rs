//! The showroom: on the main menu (where the player picks the skin's shading model) the
//! camera frames the character's head and torso close up, facing it from the paper's
//! Fig. 1/2 direction, while the key light orbits it slowly, so the models' differences —
//! light bleeding past the terminator, translucency — show as the light moves. The menu's
//! panel sits beside the character (landscape) or below it (portrait), inside the safe area,
//! and the camera's lens is shifted so the character lands in the part of the screen the
//! panel leaves free ([`super::menu::menu_layout`]'s `stage`). When a run starts the camera swings round
//! to the follow camera in [`BLEND_S`] (and back when the menu returns); with the blend done
//! the follow camera is drawn unchanged. Everything here is plain arithmetic: no allocation.
//!
//! Its subject is the runner or, where the scanned head was loaded (the desktop; the APK does
//! not carry it), the head ([`Subject::Head`]): placed where the runner's head would be
//! ([`head_matrix`]), framed close up, the key light orbiting it at the same distance as the
//! runner's chest, so the terminator sweeps across the face.

use std::f32::consts::{PI, TAU};

use glam::{Mat4, Vec2, Vec3};

use super::menu::layout_for;
use super::Viewport;
use crate::rules::{Game, Screen};
use dermis_engine::camera::{CameraPose, FollowCamera};
use dermis_engine::scene::face::HEAD_CENTRE;
use dermis_engine::scene::{key_light, CHARACTER, KEY_LIGHT_OFFSET};
use dermis_engine::ui::{Rect, Ui};

/// Camera ↔ showroom blend duration (s).
pub const BLEND_S: f32 = 0.8;
/// One turn of the key light around the character (s).
pub const LIGHT_PERIOD_S: f32 = 16.0;
/// The orbiting light's height above the feet (m), a little above the head; its radius keeps
/// the key light's distance to the chest, so the exposure matches play.
pub const LIGHT_HEIGHT: f32 = 2.3;
/// The showroom's vertical field of view.
pub const FOV_Y_DEG: f32 = 30.0;
/// Fraction of the stage's height, and of its width, the head-and-torso bound fills at most.
pub const FILL: f32 = 0.85;
pub const FILL_W: f32 = 0.95;
/// The head and torso (waist to the top of the head, shoulders and upper arms at rest),
/// feet at the origin.
pub const BUST_LO: Vec3 = Vec3::new(-0.3, 1.0, -0.2);
pub const BUST_HI: Vec3 = Vec3::new(0.3, 1.8, 0.2);
/// Where the camera looks from, towards the character's front (+z): Fig. 1/2's direction
/// (`scene::frame_bounds`), a little to its left and above.
const VIEW_DIR: Vec3 = Vec3::new(0.35, 0.12, 1.0);

/// What the showroom shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Subject {
    /// The game's runner (its head and torso).
    #[default]
    Runner,
    /// The scanned head (`face::head`, CC BY 3.0: its credit is shown with it).
    Head,
}

impl Subject {
    /// The menu option's text.
    pub fn label(self) -> &'static str {
        match self {
            Subject::Runner => "Subject: runner",
            Subject::Head => "Subject: head",
        }
    }

    /// The other subject (the menu option toggles).
    pub fn other(self) -> Self {
        match self {
            Subject::Runner => Subject::Head,
            Subject::Head => Subject::Runner,
        }
    }
}

/// The height of the head's centre (between the ears, at the eyes) above the feet: where
/// the runner's head is.
pub const HEAD_HEIGHT: f32 = 1.6;
/// The box the head's close-up frames, around its centre (m): crown to chin, ear to ear,
/// the back of the head to the nose (the shoulders below are cut).
pub const HEAD_LO: Vec3 = Vec3::new(-0.1, -0.13, -0.1);
pub const HEAD_HI: Vec3 = Vec3::new(0.1, 0.115, 0.13);

/// Where the scanned head (in its own metres, `face::head::load`) stands for a runner at
/// `feet`: its centre [`HEAD_HEIGHT`] above them, facing +z like the runner.
pub fn head_matrix(feet: Vec3) -> Mat4 {
    Mat4::from_translation(feet + Vec3::Y * HEAD_HEIGHT - HEAD_CENTRE)
}

/// Whether `screen` shows the showroom (the main menu, with the model option).
pub fn is_showroom(screen: Screen) -> bool {
    matches!(screen, Screen::Main)
}

/// The showroom camera for a character standing at `feet` (facing +z) on a screen of
/// `aspect`, its head and torso filling [`FILL`] of `stage`'s height or [`FILL_W`] of its
/// width, whichever is reached first (`stage`: a fraction of the screen, x
/// right, y down, 0..1) and centred on it by a lens shift.
pub fn framing(feet: Vec3, aspect: f32, stage: Rect) -> CameraPose {
    let aspect = aspect.max(1e-3);
    let fov_y = FOV_Y_DEG.to_radians();
    let t = (fov_y * 0.5).tan();
    let size = BUST_HI - BUST_LO;
    let centre = feet + (BUST_LO + BUST_HI) * 0.5;
    // The bound spans size / (d·t) in NDC vertically (÷ aspect horizontally); the stage spans
    // twice its fraction of the screen.
    let (sw, sh) = (2.0 * stage.w.max(0.2), 2.0 * stage.h.max(0.2));
    let d = (size.y / (t * sh * FILL)).max(size.x / (t * aspect * sw * FILL_W)) + size.z * 0.5;
    stage_pose(centre, d, fov_y, stage)
}

/// The showroom camera for the scanned head of a runner at `feet` ([`head_matrix`]): the
/// sphere around the box [`HEAD_LO`]..[`HEAD_HI`] filling [`FILL`] of `stage`'s height or
/// [`FILL_W`] of its width (a sphere, since at arm's length the box's near corners would
/// reach past a box fitted by its faces), centred on it by a lens shift.
pub fn head_framing(feet: Vec3, aspect: f32, stage: Rect) -> CameraPose {
    let centre = feet + Vec3::Y * HEAD_HEIGHT + (HEAD_LO + HEAD_HI) * 0.5;
    let radius = 0.5 * (HEAD_HI - HEAD_LO).length();
    let fov_y = FOV_Y_DEG.to_radians();
    let t = (fov_y * 0.5).tan();
    // The half-angles the stage spans around its centre, vertically and horizontally.
    let up = (t * stage.h.max(0.1) * FILL).atan();
    let across = (t * aspect.max(1e-3) * stage.w.max(0.1) * FILL_W).atan();
    let d = radius / up.min(across).sin();
    stage_pose(centre, d, fov_y, stage)
}

/// The showroom's camera looking at `centre` from `distance` along its view direction, its
/// lens shifted so `centre` sits in the middle of `stage`.
fn stage_pose(centre: Vec3, distance: f32, fov_y: f32, stage: Rect) -> CameraPose {
    let c = stage.center();
    CameraPose {
        eye: centre + VIEW_DIR.normalize() * distance,
        look: centre,
        fov_y,
        shift: Vec2::new(2.0 * c[0] - 1.0, 1.0 - 2.0 * c[1]),
        near: 0.05,
        far: 200.0,
    }
}

/// How much slower the light turns in front of the character than behind it (0: uniform).
const LIGHT_EASE: f32 = 0.6;

/// The orbiting key light `time` seconds into the showroom, for a character at `feet`: it
/// starts where the play key light stands (in front, to the right) and turns about the
/// character's vertical axis once every [`LIGHT_PERIOD_S`], at [`LIGHT_HEIGHT`] — slowly
/// across the front (the terminator sweeps the face: about two thirds of the turn), faster
/// behind (backlit: translucency at the ears and the rims).
pub fn orbit_light(feet: Vec3, time: f32) -> Vec3 {
    let chest_to_key = KEY_LIGHT_OFFSET - Vec3::Y * CHARACTER.chest;
    let dy = LIGHT_HEIGHT - CHARACTER.chest;
    let radius = (chest_to_key.length_squared() - dy * dy).max(0.25).sqrt();
    let phase = TAU * (time / LIGHT_PERIOD_S).fract();
    // Monotonic for LIGHT_EASE < 1: d/dphase = 1 − ease·cos(phase) > 0.
    let a = KEY_LIGHT_OFFSET.x.atan2(KEY_LIGHT_OFFSET.z) + phase - LIGHT_EASE * phase.sin();
    feet + Vec3::new(radius * a.sin(), LIGHT_HEIGHT, radius * a.cos())
}

/// The orbiting key light for the scanned head of a runner at `feet`: [`orbit_light`]'s
/// turn about the head's centre instead of the chest, at the same distance and height above
/// it (the face gets the irradiance the chest gets in play).
pub fn head_orbit_light(feet: Vec3, time: f32) -> Vec3 {
    let chest = Vec3::Y * CHARACTER.chest;
    orbit_light(feet, time) - chest + Vec3::Y * HEAD_HEIGHT
}

/// Interpolates two cameras by `t`, the eye swinging around `centre` (angle, radius and
/// height) so it never passes through the character.
pub fn orbit_lerp(a: &CameraPose, b: &CameraPose, t: f32, centre: Vec3) -> CameraPose {
    if t <= 0.0 {
        return *a;
    }
    if t >= 1.0 {
        return *b;
    }
    let (ra, rb) = (a.eye - centre, b.eye - centre);
    let (aa, ab) = (ra.x.atan2(ra.z), rb.x.atan2(rb.z));
    let mut turn = ab - aa;
    if turn > PI {
        turn -= TAU;
    } else if turn < -PI {
        turn += TAU;
    }
    let az = aa + turn * t;
    let (la, lb) = (
        Vec2::new(ra.x, ra.z).length(),
        Vec2::new(rb.x, rb.z).length(),
    );
    let r = la + (lb - la) * t;
    let lerp = |x: f32, y: f32| x + (y - x) * t;
    CameraPose {
        eye: centre + Vec3::new(r * az.sin(), lerp(ra.y, rb.y), r * az.cos()),
        look: a.look.lerp(b.look, t),
        fov_y: lerp(a.fov_y, b.fov_y),
        shift: a.shift.lerp(b.shift, t),
        near: lerp(a.near, b.near),
        far: lerp(a.far, b.far),
    }
}

/// The showroom's state in a session: how far the camera is into it and the light's clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Showroom {
    /// 1: the showroom camera and light; 0: the follow camera and the play key light.
    weight: f32,
    /// Seconds the light has orbited.
    light_time: f32,
    view: CameraPose,
    light: Vec3,
    /// What it shows (set by the session each frame).
    subject: Subject,
}

impl Showroom {
    /// A showroom starting on `screen`, at rest (no blend).
    pub fn new(screen: Screen, follow: &FollowCamera) -> Self {
        Self {
            weight: if is_showroom(screen) { 1.0 } else { 0.0 },
            light_time: 0.0,
            view: follow.pose(),
            light: key_light(Vec3::ZERO).position,
            subject: Subject::Runner,
        }
    }

    /// Shows `subject` from the next [`Showroom::update`] on.
    pub fn set_subject(&mut self, subject: Subject) {
        self.subject = subject;
    }

    /// What it shows.
    pub fn subject(&self) -> Subject {
        self.subject
    }

    /// Advances `dt` seconds and places this frame's camera and key light: the showroom's on
    /// the menu, the follow camera's and the play key light elsewhere, blended in between.
    pub fn update(
        &mut self,
        dt: f32,
        game: &Game,
        follow: &FollowCamera,
        ui: &Ui,
        viewport: &Viewport,
    ) {
        let dt = if dt.is_finite() { dt.max(0.0) } else { 0.0 };
        let target = if is_showroom(game.screen()) { 1.0 } else { 0.0 };
        let step = dt / BLEND_S;
        self.weight = if self.weight < target {
            (self.weight + step).min(target)
        } else {
            (self.weight - step).max(target)
        };
        let (feet, _) = game.player_transform();
        let key = key_light(feet).position;
        if self.weight <= 0.0 {
            self.view = follow.pose();
            self.light = key;
            return;
        }
        self.light_time = (self.light_time + dt) % LIGHT_PERIOD_S;
        let (screen, layout) = layout_for(ui, viewport);
        let s = layout.stage;
        let stage = Rect::new(
            s.x / screen.w,
            s.y / screen.h,
            s.w / screen.w,
            s.h / screen.h,
        );
        let aspect = viewport.width.max(1) as f32 / viewport.height.max(1) as f32;
        let (close, orbit) = match self.subject {
            Subject::Runner => (
                framing(feet, aspect, stage),
                orbit_light(feet, self.light_time),
            ),
            Subject::Head => (
                head_framing(feet, aspect, stage),
                head_orbit_light(feet, self.light_time),
            ),
        };
        let t = self.weight * self.weight * (3.0 - 2.0 * self.weight);
        self.view = orbit_lerp(&follow.pose(), &close, t, feet);
        self.light = key.lerp(orbit, t);
    }

    /// The camera drawn this frame.
    pub fn view(&self) -> CameraPose {
        self.view
    }

    /// The key light's position this frame.
    pub fn light(&self) -> Vec3 {
        self.light
    }

    /// 1 in the showroom, 0 in play, in between while the camera swings.
    pub fn weight(&self) -> f32 {
        self.weight
    }

    /// Seconds the light has orbited (modulo a turn).
    pub fn light_time(&self) -> f32 {
        self.light_time
    }
}

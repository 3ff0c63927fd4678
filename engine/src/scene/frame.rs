//! One frame as plain data: what the camera sees ([`FrameView`]), what is drawn ([`DrawSet`])
//! and everything the renderer needs to prepare it ([`FramePacket`]) — made by whoever runs
//! the frame (the game's session, a still, a measurement scene) and handed to
//! `Renderer::prepare`, which returns the prepared frame its passes encode. Nothing here
//! holds a GPU object.

use glam::{Mat4, Vec3};

use super::light::Light;
use super::props::PropInstance;
use crate::anim::Pose;
use crate::asset::Model;
use crate::shading::ShadingModel;
use crate::ui::UiVertex;

/// What the camera sees this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameView {
    pub view_proj: Mat4,
    pub camera_pos: Vec3,
    pub light: Light,
    pub exposure: f32,
}

/// What a frame draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawSet {
    /// The subject's shading model; `None` draws it with the unlit baseline.
    pub shading: Option<ShadingModel>,
    /// Draw the subject (the character, or the showroom's other subject).
    pub character: bool,
    pub props: bool,
    /// Draw the UI handed over (last, over everything).
    pub ui: bool,
}

/// A subject as the scene names it (the renderer keeps its GPU side under the id it was
/// uploaded with): the character, or another the scene shows instead (the showroom's head).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SubjectId(pub u32);

impl SubjectId {
    /// The character (the renderer's first subject).
    pub const CHARACTER: SubjectId = SubjectId(0);
}

/// The subject posed this frame: its model, pose and placement in the world.
#[derive(Clone, Copy)]
pub struct SubjectPose<'a> {
    pub model: &'a Model,
    pub pose: &'a Pose,
    pub world: Mat4,
}

/// Everything one frame hands the renderer (the extract step: plain data, read once).
#[derive(Clone, Copy)]
pub struct FramePacket<'a> {
    /// The target's size in pixels.
    pub viewport: (u32, u32),
    pub view: FrameView,
    pub draw: DrawSet,
    /// The subject drawn, by the scene's id for it.
    pub subject_id: SubjectId,
    /// The subject's pose this frame; `None`: not posed (out of view: its palette is left).
    pub subject: Option<SubjectPose<'a>>,
    /// The props placed this frame (the renderer draws those its view can see).
    pub props: &'a [PropInstance],
    /// The UI's vertices (drawn when `draw.ui`).
    pub ui: &'a [UiVertex],
    /// Whether every pipeline the scene can reach must be ready before this frame (play:
    /// nothing is created from its first frame on); otherwise only the one drawn.
    pub settled: bool,
}

impl<'a> FramePacket<'a> {
    /// A frame of `viewport` pixels seen by `view`, drawing `draw` with nothing posed, placed
    /// or overlaid (fill in what the frame has).
    pub fn new(viewport: (u32, u32), view: FrameView, draw: DrawSet) -> Self {
        Self {
            viewport,
            view,
            draw,
            subject_id: SubjectId::CHARACTER,
            subject: None,
            props: &[],
            ui: &[],
            settled: false,
        }
    }
}

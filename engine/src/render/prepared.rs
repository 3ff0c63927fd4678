//! A frame as the renderer prepared it ([`PreparedFrame`]: plain data, worked out once by
//! `Renderer::prepare`) and what its passes record into ([`PassCtx`]). Encoding reads only
//! these two: no cell, no lock, no call back into whoever made the frame.

use super::passes::PASS_COUNT;
use super::shadow_view::ShadowView;
use super::targets::Targets;
use super::timer::PassTimer;
use super::FrameUniform;
use crate::scene::{DrawSet, FrameView, PropKind};
use crate::shading::ShadingModel;
use glam::Mat4;

/// How many prepared frames may wait to be encoded: every buffer `Renderer::prepare` writes
/// (the frame uniform, the subject's joint palettes, the passes' per-frame constants and
/// instances, the UI's vertices) has this many copies, made at load and used in turn, so a
/// frame encodes what was prepared for it while later ones are prepared, and no GPU object
/// is made per frame. A frame prepared this many frames before the latest is stale:
/// `Renderer::encode` refuses it. (Submit a frame's commands before preparing this many
/// more: the queue applies its buffer writes at the next submit.)
pub const FRAMES_PREPARED: usize = 2;

/// One value per prepared frame's copy (see [`FRAMES_PREPARED`]).
pub fn per_frame<T>(f: impl FnMut(usize) -> T) -> [T; FRAMES_PREPARED] {
    std::array::from_fn(f)
}

/// What one pass does in a frame, decided when the frame is prepared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassFrame {
    /// Whether the pass records anything this frame.
    pub runs: bool,
    /// A count the pass chose for this frame (the penumbra map's jump passes, the blobs
    /// staged, the UI's vertices); 0 for most.
    pub steps: u32,
}

/// The subject drawn this frame, where, and the shading model its skin is drawn with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubjectDraw {
    /// Where the renderer keeps its GPU side (found from the packet's scene id).
    pub slot: usize,
    /// Its skin's shading model; `None`: the unlit baseline.
    pub shading: Option<ShadingModel>,
    /// Its placement in the world this frame.
    pub world: Mat4,
}

/// Everything the passes need to record one frame, worked out once by `Renderer::prepare`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedFrame {
    /// Its number among the frames its renderer prepared (from 0).
    pub seq: u64,
    /// Which copy of the per-frame buffers it was written into (`seq` mod
    /// [`FRAMES_PREPARED`]).
    pub copy: usize,
    /// The target's size in pixels.
    pub size: (u32, u32),
    pub view: FrameView,
    pub draw: DrawSet,
    /// The subject drawn (`None`: no subject this frame).
    pub subject: Option<SubjectDraw>,
    /// The key light's shadow map: its frustum, and whether it is drawn this frame.
    pub shadow: ShadowView,
    /// Instances of each prop kind inside the view ([`PropKind::ALL`] order).
    pub visible_props: [u32; PropKind::ALL.len()],
    /// The screen-space model whose subsurface pass ends this frame (`None`: one pass).
    pub split: Option<ShadingModel>,
    /// The frame uniform as written for this frame.
    pub uniform: FrameUniform,
    /// What each pass does this frame (`passes::NAMES` order).
    pub passes: [PassFrame; PASS_COUNT],
    /// Buffer writes made while preparing it.
    pub uploads: u32,
}

impl PreparedFrame {
    /// What pass `slot` does this frame.
    pub fn pass(&self, slot: usize) -> PassFrame {
        self.passes[slot]
    }
}

/// Where a frame's passes record: the encoder, the frame's per-size targets (MSAA colour and
/// depth), the output the last pass resolves into and, when the frame is timed, the timer
/// whose queries bracket the scene's passes.
pub struct PassCtx<'a> {
    pub encoder: &'a mut wgpu::CommandEncoder,
    pub targets: &'a Targets,
    pub output: &'a wgpu::TextureView,
    pub timer: Option<&'a PassTimer>,
}

/// Counts for one encoded frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    pub draw_calls: u32,
    pub triangles: u32,
    /// Draw calls per pass (`passes::NAMES` order).
    pub passes: [u32; PASS_COUNT],
    /// Texels per pass that its full-screen draws shade ([`Drawn::texels`]).
    pub texels: [[u64; 2]; PASS_COUNT],
}

/// What a pass recorded: draw calls and triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Drawn {
    pub draw_calls: u32,
    pub triangles: u32,
    /// The texels a pass of full-screen draws shades (a scissor may keep a draw to part of
    /// its target): its first draw's, and its other draws' together (the penumbra map's seed
    /// pass, its jump passes); 0 where not counted.
    pub texels: [u64; 2],
}

impl Drawn {
    /// `n` draw calls of no counted triangles (full-screen passes, the UI).
    pub fn calls(n: u32) -> Self {
        Self {
            draw_calls: n,
            triangles: 0,
            texels: [0; 2],
        }
    }
}

impl std::ops::AddAssign for Drawn {
    fn add_assign(&mut self, o: Self) {
        self.draw_calls += o.draw_calls;
        self.triangles += o.triangles;
        self.texels[0] += o.texels[0];
        self.texels[1] += o.texels[1];
    }
}

impl RenderStats {
    /// Adds what pass `slot` recorded.
    pub fn add(&mut self, slot: usize, drawn: Drawn) {
        self.passes[slot] += drawn.draw_calls;
        self.texels[slot][0] += drawn.texels[0];
        self.texels[slot][1] += drawn.texels[1];
        self.draw_calls += drawn.draw_calls;
        self.triangles += drawn.triangles;
    }
}

//! The game's GPU side: the renderer with the scene uploaded, its blob shadows and its UI,
//! created at load — the first model's pipeline with them, the other reachable models' on a
//! background thread once the first frame is out, all in place before play starts, so nothing
//! is created in play. Where the scanned head was loaded ([`SceneAssets::head`]) it is
//! uploaded here too, after the first frame, beside the runner, for the showroom: showing it
//! swaps what is drawn and creates nothing. It sees frame packets, never the session
//! ([`GameFrame`](super::GameFrame) hands them over).

use dermis_engine::render::passes::PassId;
use std::sync::Arc;

use dermis_engine::anim::Pose;
use dermis_engine::asset::Model;
use dermis_engine::render::{Gpu, PipelineSet, PreparedFrame, Renderer};
use dermis_engine::scene::{FramePacket, HeadLoad, Roles, SceneAssets, SubjectId};
use dermis_engine::shading::ShadingModel;

pub struct GameGpu {
    pub renderer: Renderer,
    /// The showroom's scanned head, once uploaded (shared with the packets that pose it).
    pub head: Option<Arc<ShowroomHead>>,
    /// The head as it loads, until it is uploaded.
    head_load: HeadLoad,
    /// Frames prepared.
    frames: u64,
}

/// The scene's id for the showroom's scanned head.
pub const HEAD: SubjectId = SubjectId(1);

/// The scanned head as the showroom draws it (uploaded as [`HEAD`]): the model and its
/// (rest) pose for the joint palette.
pub struct ShowroomHead {
    pub model: Model,
    pub pose: Pose,
}

impl GameGpu {
    /// The game's GPU objects; `first` (the model the first frame draws: the player's saved
    /// choice) gets its pipeline now, the others' arrive while the first frames render.
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        assets: &SceneAssets,
        first: ShadingModel,
    ) -> Result<Self, String> {
        // Only what the game can reach: every menu model (the governor's tiers are among them).
        let set = PipelineSet::game();
        let mut renderer = Renderer::with_scene(
            gpu,
            format,
            (&set, first),
            (&assets.character, &assets.roles, &assets.props),
        )?;
        // Contact shadows under the runner and the props, so nothing floats.
        renderer.enable(gpu, PassId::blobs);
        renderer.enable(gpu, PassId::ui);
        Ok(Self {
            renderer,
            head: None,
            head_load: assets.head.clone(),
            frames: 0,
        })
    }

    /// Whether the showroom can show the scanned head (uploaded after the first frame, once
    /// it is decoded).
    pub fn has_head(&self) -> bool {
        self.head.is_some() || self.head_load.expected()
    }

    /// Prepares the frame `packet` describes, for the renderer's `encode`. What
    /// waits until the first frame is out (it would delay it) but not into play (a `settled`
    /// packet) is done first: the showroom's head, then the pipeline builder — the head
    /// first, so its normal-mapped pipelines join the builder's list.
    pub fn prepare(&mut self, gpu: &Gpu, packet: &FramePacket) -> PreparedFrame {
        if self.frames > 0 || packet.settled {
            self.upload_head(gpu);
            self.renderer.start_pipeline_builder();
        }
        self.frames += 1;
        self.renderer.prepare(gpu, packet)
    }

    /// Uploads the showroom's head, waiting for its decoder if it is not done (it started
    /// with the assets, so it rarely is): a subject beside the runner; a head that cannot be
    /// drawn is left out (logged).
    fn upload_head(&mut self, gpu: &Gpu) {
        let load = std::mem::take(&mut self.head_load);
        let Some(model) = load.wait().cloned() else {
            return;
        };
        match self
            .renderer
            .add_subject(gpu, HEAD, &model, &Roles::of(&model))
        {
            Ok(()) => {
                let mut pose = Pose::new(&model);
                pose.update_world(&model);
                self.head = Some(Arc::new(ShowroomHead { model, pose }));
            }
            Err(e) => log::warn!("the showroom's head is left out: {e}"),
        }
    }

    /// Waits for the showroom's head and every pipeline still being built in the
    /// background (before counting GPU objects; play waits for them by itself).
    pub fn finish_loading(&mut self, gpu: &Gpu) {
        self.upload_head(gpu);
        self.renderer.start_pipeline_builder();
        self.renderer.receive_pipelines(None, true);
    }

    /// Whether what loads after the first frame is in place: the showroom's head uploaded
    /// (or none to upload) and every pipeline built (the window saves its pipeline cache then).
    pub fn loaded(&self) -> bool {
        self.frames > 0 && !self.head_load.expected() && !self.renderer.pipelines_loading()
    }
}

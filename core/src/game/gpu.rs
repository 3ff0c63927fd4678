//! The game's GPU side: the renderer with the scene uploaded plus the UI renderer, all
//! created at load (every shading model's pipeline included), so nothing is created in play.
//! Where the scanned head was loaded ([`SceneAssets::head`]) it is uploaded here too, beside
//! the runner, for the showroom: showing it swaps what is drawn and creates nothing.

use super::Session;
use crate::anim::Pose;
use crate::asset::Model;
use crate::render::{Gpu, PipelineSet, RenderStats, Renderer, Targets, UiRenderer, MSAA_SAMPLES};
use crate::scene::SceneAssets;
use crate::shading::material::SKIN1;

pub struct GameGpu {
    pub renderer: Renderer,
    pub ui: UiRenderer,
    /// The showroom's scanned head, when it was loaded and uploaded.
    pub head: Option<ShowroomHead>,
}

/// The scanned head as the showroom draws it: its renderer slot, the model and its (rest)
/// pose for the joint palette.
pub struct ShowroomHead {
    pub slot: usize,
    pub model: Model,
    pub pose: Pose,
}

impl GameGpu {
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        assets: &SceneAssets,
    ) -> Result<Self, String> {
        // Only what the game can reach: every menu model (the governor's tiers are among them).
        let mut renderer = Renderer::with_pipelines(gpu, format, &PipelineSet::game());
        renderer.load_scene(gpu, &assets.character, &assets.props, &SKIN1)?;
        // Contact shadows under the runner and the props, so nothing floats.
        renderer.enable_blob_shadows(gpu);
        let head =
            assets
                .head
                .as_ref()
                .and_then(|model| match renderer.add_subject(gpu, model, &SKIN1) {
                    Ok(slot) => {
                        let mut pose = Pose::new(model);
                        pose.update_world(model);
                        Some(ShowroomHead {
                            slot,
                            model: model.clone(),
                            pose,
                        })
                    }
                    Err(e) => {
                        log::warn!("the showroom's head is left out: {e}");
                        None
                    }
                });
        let (rgba, w, h) = crate::ui::atlas_rgba();
        let ui = UiRenderer::new(&gpu.device, &gpu.queue, format, MSAA_SAMPLES, &rgba, w, h);
        Ok(Self { renderer, ui, head })
    }

    /// Whether the showroom can show the scanned head.
    pub fn has_head(&self) -> bool {
        self.head.is_some()
    }

    /// This frame's uploads (palettes, uniforms, props, UI when it changed).
    pub fn upload(&mut self, queue: &wgpu::Queue, session: &mut Session, character: &Model) {
        session.upload(
            queue,
            &mut self.renderer,
            &mut self.ui,
            character,
            self.head.as_ref(),
        );
    }

    /// Records the frame's single pass into `encoder`.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        output: &wgpu::TextureView,
        session: &Session,
    ) -> RenderStats {
        self.renderer.encode(
            encoder,
            targets,
            output,
            session.draw_set(),
            Some(&self.ui),
            None,
        )
    }
}

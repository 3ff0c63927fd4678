//! The game's GPU side: the renderer with the scene uploaded plus the UI renderer, all
//! created at load (every shading model's pipeline included), so nothing is created in play.

use super::Session;
use crate::asset::Model;
use crate::render::{Gpu, PipelineSet, RenderStats, Renderer, Targets, UiRenderer, MSAA_SAMPLES};
use crate::scene::SceneAssets;
use crate::shading::material::SKIN1;

pub struct GameGpu {
    pub renderer: Renderer,
    pub ui: UiRenderer,
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
        let (rgba, w, h) = crate::ui::atlas_rgba();
        let ui = UiRenderer::new(&gpu.device, &gpu.queue, format, MSAA_SAMPLES, &rgba, w, h);
        Ok(Self { renderer, ui })
    }

    /// This frame's uploads (palettes, uniforms, props, UI when it changed).
    pub fn upload(&mut self, queue: &wgpu::Queue, session: &mut Session, character: &Model) {
        session.upload(queue, &mut self.renderer, &mut self.ui, character);
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

//! The game's GPU side: the renderer with the scene uploaded plus the UI renderer, created at
//! load — the first model's pipeline with them, the other reachable models' on a background
//! thread once the first frame is out, all in place before play starts, so nothing is
//! created in play. Where the scanned head was loaded ([`SceneAssets::head`]) it is uploaded
//! here too, after the first frame, beside the runner, for the showroom: showing it swaps what
//! is drawn and creates nothing.

use super::Session;
use crate::anim::Pose;
use crate::asset::Model;
use crate::game::Screen;
use crate::render::{Gpu, PipelineSet, RenderStats, Renderer, Targets, UiRenderer, MSAA_SAMPLES};
use crate::scene::{HeadLoad, SceneAssets};
use crate::shading::material::SKIN1;
use crate::shading::ShadingModel;

pub struct GameGpu {
    pub renderer: Renderer,
    pub ui: UiRenderer,
    /// The showroom's scanned head, once uploaded.
    pub head: Option<ShowroomHead>,
    /// The head as it loads, until it is uploaded.
    head_load: HeadLoad,
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// Frames uploaded.
    frames: u64,
}

/// The scanned head as the showroom draws it: its renderer slot, the model and its (rest)
/// pose for the joint palette.
pub struct ShowroomHead {
    pub slot: usize,
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
            (&assets.character, &assets.props),
            &SKIN1,
        )?;
        // Contact shadows under the runner and the props, so nothing floats.
        renderer.enable_blob_shadows(gpu);
        let (rgba, w, h) = crate::ui::atlas_rgba();
        let ui = UiRenderer::new(&gpu.device, &gpu.queue, format, MSAA_SAMPLES, &rgba, w, h);
        Ok(Self {
            renderer,
            ui,
            head: None,
            head_load: assets.head.clone(),
            device: gpu.device.clone(),
            queue: gpu.queue.clone(),
            frames: 0,
        })
    }

    /// Whether the showroom can show the scanned head (uploaded after the first frame, once
    /// it is decoded).
    pub fn has_head(&self) -> bool {
        self.head.is_some() || self.head_load.expected()
    }

    /// Uploads the showroom's head (after the first frame, before play), waiting for its
    /// decoder if it is not done (it started with the assets, so it rarely is): a subject
    /// beside the runner; a head that cannot be drawn is left out (logged).
    fn upload_head(&mut self) {
        let load = std::mem::take(&mut self.head_load);
        let Some(model) = load.wait().cloned() else {
            return;
        };
        match self
            .renderer
            .add_subject((&self.device, &self.queue), &model)
        {
            Ok(slot) => {
                let mut pose = Pose::new(&model);
                pose.update_world(&model);
                self.head = Some(ShowroomHead { slot, model, pose });
            }
            Err(e) => log::warn!("the showroom's head is left out: {e}"),
        }
    }

    /// Waits for the showroom's head and every pipeline still being built in the
    /// background (before counting GPU objects; play waits for them by itself).
    pub fn finish_loading(&mut self) {
        self.upload_head();
        self.renderer.start_pipeline_builder();
        self.renderer.receive_pipelines(None, true);
    }

    /// This frame's uploads (palettes, uniforms, props, UI when it changed), after installing
    /// the pipelines built so far: waiting for the one this frame draws if it is not ready,
    /// and for all of them once play starts.
    pub fn upload(&mut self, queue: &wgpu::Queue, session: &mut Session, character: &Model) {
        // The showroom's head and the pipeline builder wait until the first frame is out
        // (they would delay it), but not into play; the head first, so its normal-mapped
        // pipelines join the builder's list.
        let play = session.game.screen() == Screen::Play;
        if self.frames > 0 || play {
            self.upload_head();
            self.renderer.start_pipeline_builder();
        }
        self.frames += 1;
        let packet = session.extract(character, self.head.as_ref());
        let r = &mut self.renderer;
        let mut uploads = 0;
        r.select_subject(packet.slot);
        if let Some((model, pose, world)) = packet.subject {
            r.update_character(queue, model, pose, world);
            uploads += 1;
        }
        uploads += r.set_props(queue, packet.props);
        uploads += r.prepare(queue, &packet.view);
        self.ui.resize(queue, packet.viewport.0, packet.viewport.1);
        if let Some(vertices) = packet.ui {
            self.ui.upload(queue, vertices);
            uploads += 1;
        }
        let ui = packet.ui.is_some();
        session.uploaded(uploads, ui);
        // After the upload: the subject it shows decides which variant is waited for.
        self.renderer
            .receive_pipelines(session.draw_set().shading, play);
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

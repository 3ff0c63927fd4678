//! The subject drawn with its shading model: the model's character pipeline (for a mesh with a
//! normal map or without: `model_gpu.rs`, built at load or by the background builder), the
//! model's constants at group 1, the subject's parts (`skinned.rs`) at group 2. It draws first
//! in the scene's pass: what the camera frames covers the floor and the props behind it, whose
//! hidden texels then fail the early depth test. A model outside the scene's pipeline set is
//! not drawn (and never compiled at run time).

use super::{BuildCtx, Pass, Stage};
use crate::render::prepared::{Drawn, PassFrame, PreparedFrame};
use crate::render::resources::Resources;
use crate::scene::FramePacket;

pub struct CharacterPass;

impl Pass for CharacterPass {
    fn build(_ctx: &BuildCtx) -> Option<Self> {
        Some(Self)
    }

    fn stage(&self) -> Stage {
        Stage::Scene
    }

    /// Runs when the frame draws a subject whose pipeline is built.
    fn prepare(
        &mut self,
        _queue: &wgpu::Queue,
        _packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame {
        let runs = frame
            .subject
            .is_some_and(|s| res.models.draws(s.pipeline) && res.subjects.active().is_some());
        PassFrame { runs, steps: 0 }
    }

    fn draw(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let (Some(subject), Some(drawn)) = (res.subjects.active(), frame.subject) else {
            return Drawn::default();
        };
        let pipeline = res.models.pipeline(drawn.pipeline);
        let group = res.models.params_group(drawn.pipeline.map(|(m, _)| m));
        let (Some(pipeline), Some(group)) = (pipeline, group) else {
            return Drawn::default();
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(1, group, &[]);
        Drawn {
            draw_calls: subject.gpu.draw(pass),
            triangles: subject.gpu.triangles,
        }
    }
}

//! The subject, a part per primitive, each as its material's role says (`scene::Roles`): skin
//! parts with the frame's shading model — the model's character pipeline (`model_gpu.rs`,
//! built at load or by the background builder), its constants at group 1 — and standard
//! parts with the glTF metallic-roughness lighting the props share, through this pass's own
//! pipelines (one per variant the scene's materials need: masked, blended, double-sided,
//! normal-mapped; and their two-target forms where the scene can reach a screen-space model).
//! Every part binds its palette (group 2) and its material (group 3). Opaque parts first,
//! blended ones last; the subject itself draws first in the scene's pass, so what the camera
//! frames covers the floor and the props behind it, whose hidden texels then fail the early
//! depth test. A model outside the scene's pipeline set is not drawn (and never compiled at
//! run time).

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::material_gpu::{standard_source, StandardKey};
use crate::render::mesh::vertex_layout;
use crate::render::pipelines::{pipeline_layout, pipeline_with, wgsl_module, Surfaces};
use crate::render::prepared::{Drawn, PassFrame, PreparedFrame};
use crate::render::resources::Resources;
use crate::render::targets::scene_targets;
use crate::scene::{FramePacket, Role};

struct Standard {
    key: StandardKey,
    split: bool,
    pipeline: wgpu::RenderPipeline,
}

pub struct CharacterPass {
    standard: Vec<Standard>,
}

impl CharacterPass {
    fn standard(&self, key: StandardKey, split: bool) -> Option<&wgpu::RenderPipeline> {
        self.standard
            .iter()
            .find(|s| s.key == key && s.split == split)
            .map(|s| &s.pipeline)
    }
}

/// The colour targets of a standard part's pipeline: opaque, or blended over what is behind
/// it (straight alpha into the output; premultiplied into the split scene's colour target,
/// whose alpha — the skin marker — and other targets it leaves).
fn standard_targets(
    format: wgpu::TextureFormat,
    blend: bool,
    split: bool,
) -> Vec<Option<wgpu::ColorTargetState>> {
    let state = |blend, write_mask| wgpu::ColorTargetState {
        format,
        blend,
        write_mask,
    };
    let all = wgpu::ColorWrites::ALL;
    let (first, rest) = match (blend, split) {
        (false, _) => (state(None, all), state(None, all)),
        (true, false) => (
            state(Some(wgpu::BlendState::ALPHA_BLENDING), all),
            state(None, all),
        ),
        (true, true) => (
            state(
                Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                wgpu::ColorWrites::COLOR,
            ),
            state(None, wgpu::ColorWrites::empty()),
        ),
    };
    scene_targets(format, split, first, rest)
}

/// The subject, lit (shadowed, its shadow filtered by the penumbra map), into the scene.
impl Declared for CharacterPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[Target::ShadowMap, Target::PenumbraMap],
        writes: &[Target::Scene],
    };
}

impl Pass for CharacterPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        let device = ctx.device;
        let layout = pipeline_layout(
            device,
            "standard",
            &[
                Some(&ctx.layouts.frame),
                Some(&ctx.layouts.model),
                Some(&ctx.layouts.skinned),
                Some(&ctx.layouts.material),
            ],
        );
        let splits: &[bool] = if ctx.split() {
            &[false, true]
        } else {
            &[false]
        };
        let mut standard = Vec::new();
        for &key in ctx.standard {
            for &split in splits {
                let module = wgsl_module(device, "standard", standard_source(key, split));
                let (variant, _) = key;
                let surfaces = Surfaces {
                    cull: (!variant.double_sided).then_some(wgpu::Face::Back),
                    depth_write: !variant.blend,
                };
                let targets = standard_targets(ctx.format, variant.blend, split);
                let pipeline = pipeline_with(
                    ctx.pipelines(),
                    &layout,
                    &module,
                    &targets,
                    &[vertex_layout()],
                    "standard",
                    surfaces,
                );
                standard.push(Standard {
                    key,
                    split,
                    pipeline,
                });
            }
        }
        Some(Self { standard })
    }

    /// A standard material the scene now has without its pipeline.
    fn stale(&self, ctx: &BuildCtx) -> bool {
        ctx.standard
            .iter()
            .any(|k| !self.standard.iter().any(|s| s.key == *k))
    }

    /// Runs when the frame draws a subject.
    fn prepare(
        &mut self,
        _queue: &wgpu::Queue,
        _packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame {
        let runs = frame
            .subject
            .is_some_and(|d| res.subjects.get(d.slot).is_some());
        PassFrame { runs, steps: 0 }
    }

    fn draw(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let Some(drawn) = frame.subject else {
            return Drawn::default();
        };
        let Some(subject) = res.subjects.get(drawn.slot) else {
            return Drawn::default();
        };
        let Some(group) = res.models.params_group(drawn.shading) else {
            return Drawn::default();
        };
        pass.set_bind_group(1, group, &[]);
        let split = frame.split.is_some();
        let mut out = Drawn::default();
        let gpu = &subject.gpu;
        // Opaque parts (skin, then standard), then blended ones.
        for blended in [false, true] {
            for part in gpu.parts() {
                let m = &part.material;
                if m.variant.blend != blended {
                    continue;
                }
                let pipeline = match m.role {
                    Role::Skin { .. } => res
                        .models
                        .pipeline(drawn.shading.map(|s| (s, m.normal_mapped))),
                    Role::Standard => self.standard((m.variant, m.normal_mapped), split),
                };
                let Some(pipeline) = pipeline else { continue };
                pass.set_pipeline(pipeline);
                gpu.draw_part(pass, part, true, frame.copy);
                out.draw_calls += 1;
                out.triangles += part.triangles;
            }
        }
        out
    }
}

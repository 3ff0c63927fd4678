//! The key light's shadow map: the subject (and a measurement scene's occluder) drawn
//! depth-only from the light once per frame, before the scene; every shading model reads the
//! map through `light_visible` in `shaders/common.wgsl` (one bilinear depth comparison). The
//! light's frustum is the frame's [`ShadowView`](crate::render::ShadowView); the map itself is
//! one of the renderer's light maps (`light_maps.rs`). Built once something casts.

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::layouts;
use crate::render::light_maps::{depth_pass, SHADOW_FORMAT};
use crate::render::mesh::vertex_layout;
use crate::render::pipelines::PipelineDevice;
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{per_frame, Drawn, PassFrame, PreparedFrame, FRAMES_PREPARED};
use crate::render::resources::Resources;
use crate::scene::FramePacket;
use crate::shader::uniforms::CasterUniform;
use crate::shader::{compose, ShaderDefs};

/// The composed caster shader (depth only).
pub fn caster_shader_source() -> String {
    compose("shadow_caster", &ShaderDefs::new()).expect("built-in shaders compose")
}

pub struct ShadowMapPass {
    skinned: wgpu::RenderPipeline,
    /// Where a measurement scene sets an occluder.
    occluder: Option<wgpu::RenderPipeline>,
    /// The light's matrix, one per prepared frame's copy.
    caster_buffers: [wgpu::Buffer; FRAMES_PREPARED],
    caster_groups: [wgpu::BindGroup; FRAMES_PREPARED],
}

fn depth_only(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
) -> wgpu::RenderPipeline {
    dev.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow caster"),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                buffers,
            },
            // Both faces: thin parts (ears, fingers, the occluder blade) cast from either side.
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                // Slope-scaled: surfaces grazing the light move back by more.
                bias: wgpu::DepthBiasState {
                    constant: 2,
                    slope_scale: 1.5,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: dev.cache,
        })
}

/// The subject and the occluder drawn depth-only into the light's depth map.
impl Declared for ShadowMapPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[],
        writes: &[Target::ShadowMap],
    };
}

impl Pass for ShadowMapPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.light_maps?;
        let device = ctx.device;
        let caster_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow caster"),
            entries: &[layouts::uniform(0, wgpu::ShaderStages::VERTEX)],
        });
        let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("empty"),
            entries: &[],
        });
        let module = wgsl_module(device, "shadow caster", caster_shader_source());
        let skinned_layout = pipeline_layout(
            device,
            "shadow caster",
            &[
                Some(&caster_layout),
                Some(&empty),
                Some(&ctx.layouts.skinned),
            ],
        );
        let skinned = depth_only(
            ctx.pipelines(),
            &skinned_layout,
            &module,
            "vs_skinned",
            &[Some(vertex_layout())],
        );
        let occluder = ctx.occluder.then(|| {
            let layout = pipeline_layout(device, "shadow occluder", &[Some(&caster_layout)]);
            depth_only(
                ctx.pipelines(),
                &layout,
                &module,
                "vs_occluder",
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                })],
            )
        });
        let caster_buffers = per_frame(|_| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shadow caster"),
                size: std::mem::size_of::<CasterUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let caster_groups = per_frame(|k| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow caster"),
                layout: &caster_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: caster_buffers[k].as_entire_binding(),
                }],
            })
        });
        Some(Self {
            skinned,
            occluder,
            caster_buffers,
            caster_groups,
        })
    }

    fn stale(&self, ctx: &BuildCtx) -> bool {
        ctx.occluder && self.occluder.is_none()
    }

    /// Runs when the frame's shadow view says a map is drawn; writes the light's matrix.
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        _packet: &FramePacket,
        frame: &mut PreparedFrame,
        _res: &Resources,
    ) -> PassFrame {
        let runs = frame.shadow.drawn;
        if runs {
            let caster = CasterUniform {
                view_proj: frame.shadow.view_proj,
            };
            let buffer = &self.caster_buffers[frame.copy];
            queue.write_buffer(buffer, 0, bytemuck::bytes_of(&caster));
            frame.uploads += 1;
        }
        PassFrame { runs, steps: 0 }
    }

    /// The depth-only pass: the subject if it casts and is drawn, the occluder.
    fn encode(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Drawn {
        let Some(maps) = &res.light_maps else {
            return Drawn::default();
        };
        let mut pass = depth_pass(encoder, &maps.shadow_target, "shadow map");
        pass.set_bind_group(0, &self.caster_groups[frame.copy], &[]);
        let mut drawn = Drawn::default();
        let subject = frame.subject.and_then(|d| res.subjects.get(d.slot));
        if let (Some(subject), true) = (subject, res.subject_casts) {
            pass.set_pipeline(&self.skinned);
            drawn.draw_calls += subject.gpu.draw(&mut pass, frame.copy);
        }
        if let (Some(o), Some(pipeline)) = (&res.occluder, &self.occluder) {
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.draw(0..o.count, 0..1);
            drawn.draw_calls += 1;
        }
        drawn
    }
}

//! The screen-space subsurface pass (`shaders/sss_pass.wgsl`). It exists only where the scene
//! can reach a model with the `screen_space` effect: then a frame drawn with such a model
//! renders the scene in linear radiance into two 4× MSAA targets (radiance that stays + exit
//! factor, irradiance to spread + pixel size), resolves them, and in the frame's last pass a
//! full-screen triangle gathers the spread irradiance ring by ring, adds it, tone-maps and
//! resolves into the output. Frames with other models have one pass.
//!
//! It declares that it creates the split targets ([`Target::Split`]: `targets::SplitTargets`),
//! so the renderer makes them for the frame's size (`Renderer::resize`); this pass keeps one
//! bind group per screen-space model (its kernel, the resolved targets), made again when
//! they are.

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::layouts::Layouts;
use crate::render::pipelines::PipelineDevice;
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{Drawn, PassFrame, PreparedFrame};
use crate::render::resources::Resources;
use crate::render::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::scene::FramePacket;
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// The composed gather shader.
pub fn shader_source() -> String {
    compose("sss_pass", &ShaderDefs::new()).expect("built-in shaders compose")
}

fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty,
        count: None,
    }
}

pub struct SubsurfacePass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// One per screen-space model, for the targets of the last resize.
    groups: Vec<(ShadingModel, wgpu::BindGroup)>,
}

impl SubsurfacePass {
    fn new(dev: PipelineDevice, layouts: &Layouts, format: wgpu::TextureFormat) -> Self {
        let device = dev.device;
        let texture = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("subsurface pass"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(1, texture),
                entry(2, texture),
                entry(
                    3,
                    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                ),
                entry(4, texture),
            ],
        });
        let pipeline_layout = pipeline_layout(
            device,
            "subsurface pass",
            &[Some(&layouts.frame), Some(&layout)],
        );
        let module = wgsl_module(device, "subsurface pass", shader_source());
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("subsurface pass"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth_state(false, wgpu::CompareFunction::Always)),
            multisample: multisample(MSAA_SAMPLES),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: dev.cache,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("subsurface spread"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Self {
            pipeline,
            layout,
            sampler,
            groups: Vec::new(),
        }
    }

    fn group(&self, model: ShadingModel) -> Option<&wgpu::BindGroup> {
        self.groups
            .iter()
            .find(|(m, _)| *m == model)
            .map(|(_, g)| g)
    }
}

/// The split targets, made for the frame's size, read by the gather, which writes the
/// output.
impl Declared for SubsurfacePass {
    const ACCESS: Access = Access {
        creates: &[Target::Split],
        reads: &[Target::Split],
        writes: &[Target::Output],
    };
}

impl Pass for SubsurfacePass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.split()
            .then(|| Self::new(ctx.pipelines(), ctx.layouts, ctx.format))
    }

    /// Runs in frames that end with it (the renderer decided: a screen-space model drawn).
    fn prepare(
        &mut self,
        _queue: &wgpu::Queue,
        _packet: &FramePacket,
        frame: &mut PreparedFrame,
        _res: &Resources,
    ) -> PassFrame {
        let runs = frame.split.is_some_and(|m| self.group(m).is_some());
        PassFrame { runs, steps: 0 }
    }

    /// One bind group per screen-space model's kernel over the new targets.
    fn resize(&mut self, device: &wgpu::Device, res: &Resources) {
        let Some(targets) = &res.split else {
            self.groups.clear();
            return;
        };
        self.groups = res
            .models
            .kernels()
            .map(|(model, kernel)| {
                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("subsurface pass"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: kernel.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&targets.colour),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::TextureView(&targets.spread),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::Sampler(&self.sampler),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: wgpu::BindingResource::TextureView(&targets.exit),
                        },
                    ],
                });
                (model, group)
            })
            .collect();
    }

    /// The gather: one full-screen triangle.
    fn draw(
        &self,
        frame: &PreparedFrame,
        _res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let Some(group) = frame.split.and_then(|m| self.group(m)) else {
            return Drawn::default();
        };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, group, &[]);
        pass.draw(0..3, 0..1);
        Drawn::calls(1)
    }
}

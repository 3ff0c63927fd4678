//! The screen-space subsurface pass (`shaders/sss_pass.wgsl`). It exists only where the scene
//! can reach a model with the `screen_space` effect: then a frame drawn with such a model
//! renders the scene in linear radiance into two 4× MSAA targets (radiance that stays + exit
//! factor, irradiance to spread + pixel size), resolves them, and in the frame's last pass a
//! full-screen triangle gathers the spread irradiance ring by ring, adds it, tone-maps and
//! resolves into the output. Frames with other models have one pass.
//!
//! The targets are the renderer's ([`SplitTargets`], made for the frame's size by
//! `Renderer::resize`); this pass keeps one bind group per screen-space model (its kernel,
//! the resolved targets), made again when they are.

use super::{BuildCtx, Pass, Stage};
use crate::render::layouts::Layouts;
use crate::render::passes::resolve;
use crate::render::pipelines::PipelineDevice;
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{Drawn, PassCtx, PassFrame, PreparedFrame};
use crate::render::resources::Resources;
use crate::render::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::scene::FramePacket;
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// Format of both intermediate targets (linear radiance; irradiance and pixel size in mm).
pub const SPLIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The composed gather shader.
pub fn shader_source() -> String {
    compose("sss_pass", &ShaderDefs::new()).expect("built-in shaders compose")
}

/// The scene's three targets in a frame with the subsurface pass, for one size: radiance that
/// stays (with the skin marker), irradiance to spread (with the pixel's size), the exit
/// factor per channel.
pub struct SplitTargets {
    pub size: (u32, u32),
    pub colour_msaa: wgpu::TextureView,
    pub spread_msaa: wgpu::TextureView,
    pub exit_msaa: wgpu::TextureView,
    pub colour: wgpu::TextureView,
    pub spread: wgpu::TextureView,
    pub exit: wgpu::TextureView,
}

impl SplitTargets {
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Self {
        let make = |label, samples, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format: SPLIT_FORMAT,
                    usage,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = attach | wgpu::TextureUsages::TEXTURE_BINDING;
        Self {
            size: (width, height),
            colour_msaa: make("subsurface colour msaa", MSAA_SAMPLES, attach),
            spread_msaa: make("subsurface spread msaa", MSAA_SAMPLES, attach),
            exit_msaa: make("subsurface exit msaa", MSAA_SAMPLES, attach),
            colour: make("subsurface colour", 1, sampled),
            spread: make("subsurface spread", 1, sampled),
            exit: make("subsurface exit", 1, sampled),
        }
    }

    /// Opens the scene's pass into these targets: all cleared, alpha −1 in the colour target
    /// telling the gather that nothing was drawn there, resolved at its end.
    pub fn scene_pass<'e>(
        &self,
        ctx: &'e mut PassCtx<'_>,
        clear: wgpu::Color,
    ) -> wgpu::RenderPass<'e> {
        let clear = wgpu::Color { a: -1.0, ..clear };
        let attachment = |view, resolve| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: Some(resolve),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Discard,
                },
            })
        };
        let timer = ctx.timer.map(|t| t.begin_writes());
        ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene (subsurface)"),
            color_attachments: &[
                attachment(&self.colour_msaa, &self.colour),
                attachment(&self.spread_msaa, &self.spread),
                attachment(&self.exit_msaa, &self.exit),
            ],
            depth_stencil_attachment: Some(resolve::depth_attachment(ctx.targets)),
            timestamp_writes: timer,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
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

impl Pass for SubsurfacePass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.set
            .needs_subsurface_pass()
            .then(|| Self::new(ctx.pipelines(), ctx.layouts, ctx.format))
    }

    fn stage(&self) -> Stage {
        Stage::Last
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

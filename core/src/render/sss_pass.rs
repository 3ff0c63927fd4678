//! The screen-space subsurface pass (`shaders/sss_pass.wgsl`). It exists only in a renderer
//! whose pipeline set reaches a model with the `screen_space` effect: then a frame drawn with
//! such a model renders the scene in linear radiance into two 4× MSAA targets (radiance that
//! stays + exit factor, irradiance to spread + pixel size), resolves them, and a full-screen
//! pass gathers the spread irradiance ring by ring, adds it, tone-maps and resolves into the
//! output; the UI is drawn in that second pass. Frames with other models use the one-pass path.

use std::sync::Mutex;

use super::layouts::Layouts;
use super::model_gpu::ModelTable;
use super::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// Format of both intermediate targets (linear radiance; irradiance and pixel size in mm).
pub const SPLIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The sized intermediate targets, made on the first frame of each size.
pub struct SplitTargets {
    pub width: u32,
    pub height: u32,
    pub colour_msaa: wgpu::TextureView,
    pub spread_msaa: wgpu::TextureView,
    pub colour: wgpu::TextureView,
    pub spread: wgpu::TextureView,
    /// One bind group per screen-space model (its kernel, the resolved targets).
    groups: Vec<(ShadingModel, wgpu::BindGroup)>,
}

impl SplitTargets {
    pub fn group(&self, model: ShadingModel) -> Option<&wgpu::BindGroup> {
        self.groups
            .iter()
            .find(|(m, _)| *m == model)
            .map(|(_, g)| g)
    }
}

pub struct SssPass {
    pub pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    device: wgpu::Device,
    targets: Mutex<Option<SplitTargets>>,
}

fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty,
        count: None,
    }
}

impl SssPass {
    /// The pass (its kernels are the screen-space models' records, [`ModelTable::kernels`]).
    pub fn new(device: &wgpu::Device, layouts: &Layouts, format: wgpu::TextureFormat) -> Self {
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
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("subsurface pass"),
            bind_group_layouts: &[Some(&layouts.frame), Some(&layout)],
            immediate_size: 0,
        });
        let source = compose("sss_pass", &ShaderDefs::new()).expect("built-in shaders compose");
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("subsurface pass"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
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
            cache: super::pipeline_cache::for_device(device).as_ref(),
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
            device: device.clone(),
            targets: Mutex::new(None),
        }
    }

    /// Runs `f` with the split targets for `width × height`, making them (and a bind group
    /// per kernel of `models`) on the first frame of a size.
    pub fn with_targets<R>(
        &self,
        (width, height): (u32, u32),
        models: &ModelTable,
        f: impl FnOnce(&SplitTargets) -> R,
    ) -> R {
        let mut guard = self.targets.lock().unwrap_or_else(|e| e.into_inner());
        if !matches!(&*guard, Some(t) if t.width == width && t.height == height) {
            *guard = Some(self.make_targets(width, height, models));
        }
        f(guard.as_ref().expect("made above"))
    }

    fn make_targets(&self, width: u32, height: u32, models: &ModelTable) -> SplitTargets {
        let make = |label, samples, usage| {
            self.device
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
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = attach | wgpu::TextureUsages::TEXTURE_BINDING;
        let colour = make("subsurface colour", 1, sampled);
        let spread = make("subsurface spread", 1, sampled);
        let groups = models
            .kernels()
            .map(|(model, kernel)| {
                let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("subsurface pass"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: kernel.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&colour),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::TextureView(&spread),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::Sampler(&self.sampler),
                        },
                    ],
                });
                (model, group)
            })
            .collect();
        SplitTargets {
            width,
            height,
            colour_msaa: make("subsurface colour msaa", MSAA_SAMPLES, attach),
            spread_msaa: make("subsurface spread msaa", MSAA_SAMPLES, attach),
            colour,
            spread,
            groups,
        }
    }
}

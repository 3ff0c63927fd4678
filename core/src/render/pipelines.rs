//! Render pipelines: one per character shading model (composed from `character.wgsl` with
//! `shading_model` bound to the model's file) and one for props. All built at load.

use super::layouts::Layouts;
use super::mesh::{instance_layout, vertex_layout};
use super::targets::{DEPTH_FORMAT, MSAA_SAMPLES};
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// The composed WGSL of the character shader for `model`.
pub fn build_shader_source(model: ShadingModel) -> String {
    compose("character", &model.defs()).expect("built-in shaders compose (checked by tests)")
}

/// A character pipeline for every registry model, plus the unlit baseline.
pub struct CharacterPipelines {
    pub models: Vec<(ShadingModel, wgpu::RenderPipeline)>,
    pub unlit: wgpu::RenderPipeline,
}

impl CharacterPipelines {
    pub fn get(&self, model: ShadingModel) -> &wgpu::RenderPipeline {
        &self
            .models
            .iter()
            .find(|(m, _)| *m == model)
            .expect("every registry model has a pipeline")
            .1
    }
}

pub struct Pipelines {
    pub character: CharacterPipelines,
    pub prop: wgpu::RenderPipeline,
}

impl Pipelines {
    pub fn new(device: &wgpu::Device, layouts: &Layouts, format: wgpu::TextureFormat) -> Self {
        let character_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("character"),
            bind_group_layouts: &[
                Some(&layouts.frame),
                Some(&layouts.model),
                Some(&layouts.skinned),
            ],
            immediate_size: 0,
        });
        let prop_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("prop"),
            bind_group_layouts: &[Some(&layouts.frame), Some(&layouts.prop_material)],
            immediate_size: 0,
        });
        let character = |label: &str, source: String| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            pipeline(
                device,
                &character_layout,
                &module,
                format,
                &[vertex_layout()],
                label,
            )
        };
        let models = ShadingModel::ALL
            .iter()
            .map(|&m| (m, character(m.name(), build_shader_source(m))))
            .collect();
        let unlit_src = compose(
            "character",
            &ShaderDefs::new().alias("shading_model", "unlit"),
        )
        .expect("built-in shaders compose");
        let unlit = character("unlit", unlit_src);
        let prop_src = compose("prop", &ShaderDefs::new()).expect("built-in shaders compose");
        let prop_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("prop"),
            source: wgpu::ShaderSource::Wgsl(prop_src.into()),
        });
        let prop = pipeline(
            device,
            &prop_layout,
            &prop_module,
            format,
            &[vertex_layout(), instance_layout()],
            "prop",
        );
        Self {
            character: CharacterPipelines { models, unlit },
            prop,
        }
    }
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    buffers: &[wgpu::VertexBufferLayout<'_>],
    label: &str,
) -> wgpu::RenderPipeline {
    let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> =
        buffers.iter().cloned().map(Some).collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: MSAA_SAMPLES,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

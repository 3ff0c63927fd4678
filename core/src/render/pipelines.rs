//! Render pipelines: one per character shading model (composed from `character.wgsl` with
//! `shading_model` bound to the model's file) and one for props. All built at load.

use super::layouts::Layouts;
use super::mesh::{instance_layout, vertex_layout};
use super::sss_pass::SPLIT_FORMAT;
use super::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// The composed WGSL of the character shader for `model`.
pub fn build_shader_source(model: ShadingModel) -> String {
    compose("character", &model.defs()).expect("built-in shaders compose (checked by tests)")
}

/// Which character pipelines to build: the shading models a scene can reach (its materials ×
/// every tier the governor or the menu can select) and, for benches only, the unlit
/// baseline. Nothing else is compiled, so no pass or pipeline exists for an effect that no
/// material uses. Props always get the plain default-lit pipeline.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PipelineSet {
    pub models: Vec<ShadingModel>,
    pub unlit: bool,
}

impl PipelineSet {
    /// Whether a model in the set needs the screen-space subsurface pass.
    pub fn needs_subsurface_pass(&self) -> bool {
        self.models.iter().any(|m| m.effects().screen_space)
    }

    /// Every registry model plus the unlit baseline (tools and benches).
    pub fn everything() -> Self {
        Self {
            models: ShadingModel::ALL.to_vec(),
            unlit: true,
        }
    }

    /// The runner game: its menu can select every registry model, the governor's tiers are
    /// among them; no unlit baseline.
    pub fn game() -> Self {
        Self {
            models: ShadingModel::ALL.to_vec(),
            unlit: false,
        }
    }
}

/// A character pipeline for each requested model, plus the unlit baseline if requested.
pub struct CharacterPipelines {
    pub models: Vec<(ShadingModel, wgpu::RenderPipeline)>,
    pub unlit: Option<wgpu::RenderPipeline>,
}

impl CharacterPipelines {
    pub fn get(&self, model: Option<ShadingModel>) -> Option<&wgpu::RenderPipeline> {
        match model {
            Some(model) => self
                .models
                .iter()
                .find(|(m, _)| *m == model)
                .map(|(_, p)| p),
            None => self.unlit.as_ref(),
        }
    }

    /// What was built.
    pub fn built(&self) -> PipelineSet {
        PipelineSet {
            models: self.models.iter().map(|(m, _)| *m).collect(),
            unlit: self.unlit.is_some(),
        }
    }
}

pub struct Pipelines {
    pub character: CharacterPipelines,
    pub prop: wgpu::RenderPipeline,
    /// Props in a frame with the subsurface pass (two linear targets); only when the set
    /// needs that pass.
    pub prop_split: Option<wgpu::RenderPipeline>,
}

/// The colour targets of a pipeline: the output format, or the two linear targets of a
/// frame with the subsurface pass.
fn targets(format: wgpu::TextureFormat, split: bool) -> Vec<Option<wgpu::ColorTargetState>> {
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    if split {
        vec![target(SPLIT_FORMAT), target(SPLIT_FORMAT)]
    } else {
        vec![target(format)]
    }
}

impl Pipelines {
    pub fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
    ) -> Self {
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
        let character = |label: &str, source: String, split: bool| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            pipeline(
                device,
                &character_layout,
                &module,
                &targets(format, split),
                &[vertex_layout()],
                label,
            )
        };
        let models = set
            .models
            .iter()
            .map(|&m| {
                let split = m.effects().screen_space;
                (m, character(m.name(), build_shader_source(m), split))
            })
            .collect();
        let unlit = set.unlit.then(|| {
            let src = compose(
                "character",
                &ShaderDefs::new().alias("shading_model", "unlit"),
            )
            .expect("built-in shaders compose");
            character("unlit", src, false)
        });
        let prop = |defs: &ShaderDefs, split: bool| {
            let src = compose("prop", defs).expect("built-in shaders compose");
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("prop"),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            pipeline(
                device,
                &prop_layout,
                &module,
                &targets(format, split),
                &[vertex_layout(), instance_layout()],
                "prop",
            )
        };
        let prop_split = set
            .needs_subsurface_pass()
            .then(|| prop(&ShaderDefs::new().flag("SCREEN_SPACE"), true));
        Self {
            character: CharacterPipelines { models, unlit },
            prop: prop(&ShaderDefs::new(), false),
            prop_split,
        }
    }
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    targets: &[Option<wgpu::ColorTargetState>],
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
        depth_stencil: Some(depth_state(true, wgpu::CompareFunction::Less)),
        multisample: multisample(MSAA_SAMPLES),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

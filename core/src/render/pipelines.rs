//! Render pipelines: one per character shading model (composed from `character.wgsl` with
//! `shading_model` bound to the model's file) and one for props. All built at load — or, for
//! a quick first frame, the first model's at load and the others' on a background thread
//! started after the first frame ([`Pipelines::new`] with `first`), installed as they arrive.

use std::sync::mpsc;

use super::layouts::Layouts;
use super::mesh::{instance_layout, vertex_layout};
use super::sss_pass::SPLIT_FORMAT;
use super::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// The composed WGSL of the character shader for `model` (a mesh without a normal map).
pub fn build_shader_source(model: ShadingModel) -> String {
    shader_source(model, false)
}

/// The same for a mesh with a normal map (or without).
pub fn shader_source(model: ShadingModel, normal_map: bool) -> String {
    let defs = model.defs();
    let defs = if normal_map {
        defs.flag("NORMAL_MAP")
    } else {
        defs
    };
    compose("character", &defs).expect("built-in shaders compose (checked by tests)")
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
    models: Vec<(ShadingModel, wgpu::RenderPipeline)>,
    /// The same models for meshes with a normal map, once one is loaded
    /// ([`Self::add_normal_mapped`]).
    normal_mapped: Vec<(ShadingModel, wgpu::RenderPipeline)>,
    layout: wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    unlit: Option<wgpu::RenderPipeline>,
    /// The requested models not yet received from the background builder.
    pending: Vec<ShadingModel>,
    /// What the builder needs, until [`Self::start_builder`] spawns it.
    builder: Option<Builder>,
    arrivals: Option<mpsc::Receiver<(ShadingModel, wgpu::RenderPipeline)>>,
}

/// The background builder's inputs.
struct Builder {
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
}

impl CharacterPipelines {
    /// Installs the pipelines the background builder has finished; blocks for `need`'s (a
    /// model about to be drawn) or, with `all`, for every one still pending. A builder that
    /// died leaves its models without a pipeline (logged; they draw nothing).
    pub fn receive(&mut self, need: Option<ShadingModel>, all: bool) {
        if all || need.is_some_and(|m| self.pending.contains(&m)) {
            self.start_builder();
        }
        while !self.pending.is_empty() {
            let Some(rx) = &self.arrivals else { break };
            let block = all || need.is_some_and(|m| self.pending.contains(&m));
            let got = if block {
                rx.recv().ok()
            } else {
                match rx.try_recv() {
                    Ok(p) => Some(p),
                    Err(mpsc::TryRecvError::Empty) => return,
                    Err(mpsc::TryRecvError::Disconnected) => None,
                }
            };
            let Some((model, pipeline)) = got else {
                log::error!(
                    "pipeline builder stopped; without a pipeline: {:?}",
                    self.pending
                );
                self.pending.clear();
                self.arrivals = None;
                break;
            };
            self.pending.retain(|m| *m != model);
            self.models.push((model, pipeline));
        }
        self.arrivals = None;
    }

    /// Starts building the pending models' pipelines on a background thread (once; called
    /// after the first frame, so the builder does not compete with it).
    pub fn start_builder(&mut self) {
        let Some(Builder {
            device,
            layout,
            format,
        }) = self.builder.take()
        else {
            return;
        };
        let (tx, rx) = mpsc::channel();
        let rest = self.pending.clone();
        let spawned = std::thread::Builder::new()
            .name("dermis-pipelines".into())
            .spawn(move || {
                for m in rest {
                    let p = model_pipeline(&device, &layout, format, m, false);
                    if tx.send((m, p)).is_err() {
                        return;
                    }
                }
            });
        if let Err(e) = spawned {
            log::error!("cannot start the pipeline builder: {e}");
        }
        self.arrivals = Some(rx);
    }

    /// Whether some requested model's pipeline is still being built.
    pub fn loading(&self) -> bool {
        !self.pending.is_empty()
    }

    /// The pipeline drawing `model` (`None`: the unlit baseline) on a mesh with a normal map
    /// or without.
    pub fn get(
        &self,
        model: Option<ShadingModel>,
        normal_mapped: bool,
    ) -> Option<&wgpu::RenderPipeline> {
        let list = if normal_mapped {
            &self.normal_mapped
        } else {
            &self.models
        };
        match model {
            Some(model) => list.iter().find(|(m, _)| *m == model).map(|(_, p)| p),
            None => self.unlit.as_ref(),
        }
    }

    /// Builds every requested model's pipeline for meshes with a normal map (once, when the
    /// first such mesh is loaded: a scene without one has no normal-map code anywhere).
    pub fn add_normal_mapped(&mut self, device: &wgpu::Device) {
        if !self.normal_mapped.is_empty() {
            return;
        }
        self.normal_mapped = self
            .built()
            .models
            .into_iter()
            .map(|m| {
                (
                    m,
                    model_pipeline(device, &self.layout, self.format, m, true),
                )
            })
            .collect();
    }

    /// What was requested: built, or being built (in menu order).
    pub fn built(&self) -> PipelineSet {
        let mut models: Vec<ShadingModel> = self
            .models
            .iter()
            .map(|(m, _)| *m)
            .chain(self.pending.iter().copied())
            .collect();
        models.sort();
        PipelineSet {
            models,
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
    /// The pipelines of `set`: every one now, or with `first` (a model of the set) only that
    /// model's character pipeline now and the others' on a background thread
    /// ([`CharacterPipelines::receive`] installs them).
    pub fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
        first: Option<ShadingModel>,
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
            character_pipeline(device, &character_layout, format, label, source, split)
        };
        let now: Vec<ShadingModel> = match first.filter(|m| set.models.contains(m)) {
            Some(m) => vec![m],
            None => set.models.clone(),
        };
        let models = now
            .iter()
            .map(|&m| {
                (
                    m,
                    model_pipeline(device, &character_layout, format, m, false),
                )
            })
            .collect();
        let pending: Vec<ShadingModel> = set
            .models
            .iter()
            .copied()
            .filter(|m| !now.contains(m))
            .collect();
        let builder = (!pending.is_empty()).then(|| Builder {
            device: device.clone(),
            layout: character_layout.clone(),
            format,
        });
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
            character: CharacterPipelines {
                models,
                unlit,
                normal_mapped: Vec::new(),
                layout: character_layout,
                format,
                pending,
                builder,
                arrivals: None,
            },
            prop: prop(&ShaderDefs::new(), false),
            prop_split,
        }
    }
}

/// The character pipeline of `model`, for meshes with a normal map or without.
fn model_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    model: ShadingModel,
    normal_map: bool,
) -> wgpu::RenderPipeline {
    let split = model.effects().screen_space;
    let source = shader_source(model, normal_map);
    character_pipeline(device, layout, format, model.name(), source, split)
}

/// A character pipeline from composed WGSL.
fn character_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    label: &str,
    source: String,
    split: bool,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    pipeline(
        device,
        layout,
        &module,
        &targets(format, split),
        &[vertex_layout()],
        label,
    )
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

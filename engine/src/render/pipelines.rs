//! The character pipelines: one per shading model the scene can reach (composed from
//! `character.wgsl` with `shading_model` bound to the model's file), for meshes without a
//! normal map and with one. All built at load — or, for a quick first frame, the first model's
//! at load and the others' on a background thread started after the first frame
//! ([`CharacterPipelines::new`] with `first`), installed into the models' records as they
//! arrive. Also the one way every render pipeline of the renderer is described
//! ([`pipeline`], [`targets`]).

use std::sync::mpsc;

use super::layouts::Layouts;
use super::mesh::vertex_layout;
use super::model_gpu::{ModelTable, PipelineKey};
use super::targets::scene_targets;
use super::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::shader::{compose, ShaderDefs};
use crate::shading::ShadingModel;

/// A pipeline layout over `groups`, bind groups 0, 1, … in order (`None`: a group the
/// pipeline leaves unbound).
pub(crate) fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[Option<&wgpu::BindGroupLayout>],
) -> wgpu::PipelineLayout {
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: groups,
        immediate_size: 0,
    })
}

/// A shader module from composed WGSL.
pub(crate) fn wgsl_module(
    device: &wgpu::Device,
    label: &str,
    source: String,
) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

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

    /// One model's pipelines (a still of that model), no unlit baseline.
    pub fn only(model: ShadingModel) -> Self {
        Self {
            models: vec![model],
            unlit: false,
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

/// The character pipelines: those built at load wait in `ready` until the renderer installs
/// them into its [`ModelTable`] (the unlit baseline's among them, where the set asks for it);
/// the rest of the set is built on a background thread and installed as it arrives.
pub struct CharacterPipelines {
    /// Built, not yet installed (`None`: the unlit baseline).
    ready: Vec<(Option<PipelineKey>, wgpu::RenderPipeline)>,
    layout: wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    /// The requested pipelines not yet received from the background builder.
    pending: Vec<PipelineKey>,
    /// The pipeline cache every pipeline passes through (the `Gpu`'s, if it keeps one).
    cache: Option<wgpu::PipelineCache>,
    /// What the builder needs, until [`Self::start_builder`] spawns it.
    builder: Option<wgpu::Device>,
    arrivals: Option<mpsc::Receiver<(PipelineKey, wgpu::RenderPipeline)>>,
}

impl CharacterPipelines {
    /// Installs into `table` the pipelines built at load and those the background builder
    /// has finished; blocks for `need`'s (the pipeline about to draw) or, with `all`, for
    /// every one still pending. A builder that died leaves its pipelines unbuilt (logged;
    /// their models draw nothing).
    pub fn receive(&mut self, table: &mut ModelTable, need: &[PipelineKey], all: bool) {
        for (key, pipeline) in self.ready.drain(..) {
            match key {
                Some(key) => table.install(key, pipeline),
                None => table.install_unlit(pipeline),
            }
        }
        let blocking = |pending: &[PipelineKey]| all || need.iter().any(|k| pending.contains(k));
        if blocking(&self.pending) {
            self.start_builder();
        }
        while !self.pending.is_empty() {
            let Some(rx) = &self.arrivals else { break };
            let got = if blocking(&self.pending) {
                rx.recv().ok()
            } else {
                match rx.try_recv() {
                    Ok(p) => Some(p),
                    Err(mpsc::TryRecvError::Empty) => return,
                    Err(mpsc::TryRecvError::Disconnected) => None,
                }
            };
            let Some((key, pipeline)) = got else {
                log::error!(
                    "pipeline builder stopped; without a pipeline: {:?}",
                    self.pending
                );
                self.pending.clear();
                break;
            };
            self.pending.retain(|k| *k != key);
            table.install(key, pipeline);
        }
        self.arrivals = None;
    }

    /// Starts building the pending pipelines on a background thread (once; called after the
    /// first frame, so the builder does not compete with it).
    pub fn start_builder(&mut self) {
        let Some(device) = self.builder.take() else {
            return;
        };
        let (tx, rx) = mpsc::channel();
        let (layout, format, rest) = (self.layout.clone(), self.format, self.pending.clone());
        let cache = self.cache.clone();
        let spawned = std::thread::Builder::new()
            .name("dermis-pipelines".into())
            .spawn(move || {
                let dev = PipelineDevice {
                    device: &device,
                    cache: cache.as_ref(),
                };
                for key in rest {
                    let p = model_pipeline(dev, &layout, format, key);
                    if tx.send((key, p)).is_err() {
                        return;
                    }
                }
            });
        if let Err(e) = spawned {
            log::error!("cannot start the pipeline builder: {e}");
        }
        self.arrivals = Some(rx);
    }

    /// The pipeline layout every character pipeline shares (frame, model, palette, material).
    pub fn layout(&self) -> &wgpu::PipelineLayout {
        &self.layout
    }

    /// Whether some requested pipeline is still being built.
    pub fn loading(&self) -> bool {
        !self.pending.is_empty()
    }

    /// Adds every recorded model's pipeline for meshes with a normal map (once, when the
    /// first such mesh is loaded: a scene without one has no normal-map code anywhere): to
    /// the background builder's list if it has not started, else built now.
    pub fn add_normal_mapped(&mut self, table: &mut ModelTable, device: &wgpu::Device) {
        for model in table.models() {
            let key = (model, true);
            let built = table.draws(Some(key)) || self.ready.iter().any(|(k, _)| *k == Some(key));
            if built || self.pending.contains(&key) {
                continue;
            }
            if self.builder.is_some() {
                self.pending.push(key);
            } else {
                let dev = PipelineDevice {
                    device,
                    cache: self.cache.as_ref(),
                };
                table.install(key, model_pipeline(dev, &self.layout, self.format, key));
            }
        }
    }
}

/// The colour targets of an opaque pipeline drawing the scene: the output format, or the
/// split targets of a frame with the subsurface pass.
pub fn targets(format: wgpu::TextureFormat, split: bool) -> Vec<Option<wgpu::ColorTargetState>> {
    let all = wgpu::ColorTargetState {
        format,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    };
    scene_targets(format, split, all.clone(), all)
}

impl CharacterPipelines {
    /// The pipelines of `set`: every one now, or with `first` (a model of the set) only that
    /// model's now and the others' on a background thread ([`Self::receive`] installs them).
    pub fn new(
        dev: PipelineDevice,
        layouts: &Layouts,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
        first: Option<ShadingModel>,
    ) -> Self {
        let device = dev.device;
        let layout = pipeline_layout(
            device,
            "character",
            &[
                Some(&layouts.frame),
                Some(&layouts.model),
                Some(&layouts.skinned),
                Some(&layouts.material),
            ],
        );
        let now: Vec<ShadingModel> = match first.filter(|m| set.models.contains(m)) {
            Some(m) => vec![m],
            None => set.models.clone(),
        };
        let mut ready: Vec<(Option<PipelineKey>, wgpu::RenderPipeline)> = now
            .iter()
            .map(|&m| {
                let key = (m, false);
                (Some(key), model_pipeline(dev, &layout, format, key))
            })
            .collect();
        if set.unlit {
            let src = compose(
                "character",
                &ShaderDefs::new().alias("shading_model", "unlit"),
            )
            .expect("built-in shaders compose");
            ready.push((
                None,
                character_pipeline(dev, &layout, format, "unlit", src, false),
            ));
        }
        let pending: Vec<PipelineKey> = set
            .models
            .iter()
            .filter(|m| !now.contains(m))
            .map(|&m| (m, false))
            .collect();
        Self {
            ready,
            layout,
            format,
            pending,
            cache: dev.cache.cloned(),
            // Deferred (`first`): the builder starts later, with what is pending then.
            builder: first.is_some().then(|| device.clone()),
            arrivals: None,
        }
    }
}

/// The character pipeline of `model`, for meshes with a normal map or without.
fn model_pipeline(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    (model, normal_map): PipelineKey,
) -> wgpu::RenderPipeline {
    let split = model.effects().screen_space;
    let source = shader_source(model, normal_map);
    character_pipeline(dev, layout, format, model.name(), source, split)
}

/// A character pipeline from composed WGSL.
fn character_pipeline(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    label: &str,
    source: String,
    split: bool,
) -> wgpu::RenderPipeline {
    let module = wgsl_module(dev.device, label, source);
    pipeline(
        dev,
        layout,
        &module,
        &targets(format, split),
        &[vertex_layout()],
        label,
    )
}

/// What the renderer's pipelines are made with: the device and the pipeline cache they pass
/// through (the `Gpu`'s, kept on disk between launches: [`super::Gpu::use_pipeline_cache`];
/// `None`: none, as on GL).
#[derive(Clone, Copy)]
pub struct PipelineDevice<'a> {
    pub device: &'a wgpu::Device,
    pub cache: Option<&'a wgpu::PipelineCache>,
}

/// A render pipeline of the renderer: triangles, back faces culled, depth tested and
/// written, 4× MSAA, `vs_main`/`fs_main` of `module`.
pub fn pipeline(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    targets: &[Option<wgpu::ColorTargetState>],
    buffers: &[wgpu::VertexBufferLayout<'_>],
    label: &str,
) -> wgpu::RenderPipeline {
    let opaque = Surfaces {
        cull: Some(wgpu::Face::Back),
        depth_write: true,
    };
    pipeline_with(dev, layout, module, targets, buffers, label, opaque)
}

/// Which faces a pipeline draws and whether it writes depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Surfaces {
    /// The face culled (`None`: both drawn).
    pub cull: Option<wgpu::Face>,
    pub depth_write: bool,
}

/// [`pipeline`], with the faces drawn and depth writes as `surfaces` says (double-sided and
/// blended materials).
pub fn pipeline_with(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    targets: &[Option<wgpu::ColorTargetState>],
    buffers: &[wgpu::VertexBufferLayout<'_>],
    label: &str,
    surfaces: Surfaces,
) -> wgpu::RenderPipeline {
    let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> =
        buffers.iter().cloned().map(Some).collect();
    dev.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
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
                cull_mode: surfaces.cull,
                ..Default::default()
            },
            depth_stencil: Some(depth_state(
                surfaces.depth_write,
                wgpu::CompareFunction::Less,
            )),
            multisample: multisample(MSAA_SAMPLES),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets,
            }),
            multiview_mask: None,
            cache: dev.cache,
        })
}

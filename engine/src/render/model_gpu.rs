//! What the renderer keeps for each shading model its pipeline set reaches, in one record:
//! the model's character pipelines (for meshes without a normal map and with one, installed
//! as they are built), its constants for the material (uniform, LUT, their bind group) and,
//! for a screen-space model, its subsurface kernel. Every subject (the character, the
//! showroom's head) draws with the same records; the subsurface pass makes its per-size bind
//! groups from the kernels when a target size first appears.

use super::layouts::Layouts;
use super::texture;
use crate::shading::subsurface::{KernelUniform, ANGLES};
use crate::shading::{Lut, Material, ModelParams, ShadingModel};

/// Which character pipeline: a model, for meshes without a normal map or with one.
pub type PipelineKey = (ShadingModel, bool);

/// One shading model's GPU side.
pub struct ModelGpu {
    pub model: ShadingModel,
    /// Its character pipelines, indexed by "the mesh has a normal map".
    pipelines: [Option<wgpu::RenderPipeline>; 2],
    params: wgpu::Buffer,
    /// The LUT of a model that samples one (`Effects::lut`).
    lut: Option<wgpu::Texture>,
    /// The uniform and the LUT (or a 1×1 stand-in), bound as group 1.
    group: wgpu::BindGroup,
    /// The screen-space models' kernel, bound by the subsurface pass.
    pub kernel: Option<wgpu::Buffer>,
}

/// The records of the models a renderer can draw, plus the unlit baseline's constants and,
/// where the set asks for it, its pipeline.
pub struct ModelTable {
    models: Vec<ModelGpu>,
    unlit: wgpu::BindGroup,
    unlit_pipeline: Option<wgpu::RenderPipeline>,
    /// The material's longest diffusion length (mm, f32 bits; `edge_spread::diffusion_length_mm`):
    /// how far its shadows bleed, for the passes that filter them.
    diffusion_mm: std::sync::atomic::AtomicU32,
}

impl ModelTable {
    /// Records for `models`, kept in menu order (a model no pipeline can draw gets no
    /// buffer, no LUT, no bake), their constants unwritten until [`Self::set_material`].
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &Layouts,
        models: &[ShadingModel],
    ) -> Self {
        let uniform = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let lut_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("LUT"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let no_lut = texture::rgba16f(device, (1, 1), "no LUT");
        texture::write_rgba16f(queue, &no_lut, &[[0.0; 4]]);
        let bind = |buffer: &wgpu::Buffer, lut: &wgpu::Texture| {
            let view = lut.create_view(&wgpu::TextureViewDescriptor::default());
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shading model params"),
                layout: &layouts.model,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&lut_sampler),
                    },
                ],
            })
        };
        let mut sorted = models.to_vec();
        sorted.sort();
        sorted.dedup();
        let models = sorted
            .into_iter()
            .map(|model| {
                let params = uniform(model.name(), ModelParams::SIZE);
                let effects = model.effects();
                let lut = effects
                    .lut
                    .then(|| texture::rgba16f(device, Lut::SIZE, model.name()));
                let group = bind(&params, lut.as_ref().unwrap_or(&no_lut));
                let kernel_size = std::mem::size_of::<KernelUniform>() as u64;
                let kernel = effects
                    .screen_space
                    .then(|| uniform(model.name(), kernel_size));
                ModelGpu {
                    model,
                    pipelines: [None, None],
                    params,
                    lut,
                    group,
                    kernel,
                }
            })
            .collect();
        let unlit = bind(&uniform("unlit", ModelParams::SIZE), &no_lut);
        Self {
            models,
            unlit,
            unlit_pipeline: None,
            diffusion_mm: (crate::shading::edge_spread::SPAN_MM as f32)
                .to_bits()
                .into(),
        }
    }

    /// The models recorded, in menu order.
    pub fn models(&self) -> Vec<ShadingModel> {
        self.models.iter().map(|m| m.model).collect()
    }

    pub fn get(&self, model: ShadingModel) -> Option<&ModelGpu> {
        self.models.iter().find(|m| m.model == model)
    }

    /// Writes every model's constants, LUT and kernel for `material` (when the material
    /// changes; the shipped tables are read once per material, see `shading::bake`).
    /// `background` is the clear colour the subsurface pass keeps where nothing was drawn.
    pub fn set_material(&self, queue: &wgpu::Queue, material: &Material, background: wgpu::Color) {
        let bg = [background.r, background.g, background.b, background.a].map(|c| c as f32);
        let l = crate::shading::edge_spread::diffusion_length_mm(material) as f32;
        self.diffusion_mm
            .store(l.to_bits(), std::sync::atomic::Ordering::Relaxed);
        for m in &self.models {
            let params = m.model.params(material);
            queue.write_buffer(&m.params, 0, bytemuck::bytes_of(&params));
            if let (Some(texture), Some(lut)) = (&m.lut, m.model.lut(material)) {
                texture::write_rgba16f(queue, texture, &lut.texels);
            }
            if let (Some(buffer), Some(kernel)) = (&m.kernel, m.model.kernel(material)) {
                queue.write_buffer(buffer, 0, bytemuck::bytes_of(&kernel.pack(ANGLES, bg)));
            }
        }
    }

    /// The current material's longest diffusion length (mm): see
    /// [`crate::shading::edge_spread::diffusion_length_mm`].
    pub fn diffusion_mm(&self) -> f32 {
        f32::from_bits(self.diffusion_mm.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// The bind group of `model`'s constants (`None`: the unlit baseline's); `None` for a
    /// model not recorded.
    pub fn params_group(&self, model: Option<ShadingModel>) -> Option<&wgpu::BindGroup> {
        match model {
            Some(m) => self.get(m).map(|m| &m.group),
            None => Some(&self.unlit),
        }
    }

    /// The built pipeline of `key` (`None`: the unlit baseline's), if any.
    pub fn pipeline(&self, key: Option<PipelineKey>) -> Option<&wgpu::RenderPipeline> {
        match key {
            Some((model, normal_mapped)) => {
                self.get(model)?.pipelines[usize::from(normal_mapped)].as_ref()
            }
            None => self.unlit_pipeline.as_ref(),
        }
    }

    /// Whether the pipeline of `key` is built.
    pub fn draws(&self, key: Option<PipelineKey>) -> bool {
        self.pipeline(key).is_some()
    }

    /// Installs the unlit baseline's pipeline.
    pub fn install_unlit(&mut self, pipeline: wgpu::RenderPipeline) {
        self.unlit_pipeline = Some(pipeline);
    }

    /// Installs the pipeline of `key` (a model not recorded has nowhere to keep it: dropped).
    pub fn install(&mut self, (model, normal_mapped): PipelineKey, pipeline: wgpu::RenderPipeline) {
        if let Some(m) = self.models.iter_mut().find(|m| m.model == model) {
            m.pipelines[usize::from(normal_mapped)] = Some(pipeline);
        }
    }

    /// The screen-space models' kernels.
    pub fn kernels(&self) -> impl Iterator<Item = (ShadingModel, &wgpu::Buffer)> {
        self.models
            .iter()
            .filter_map(|m| m.kernel.as_ref().map(|k| (m.model, k)))
    }
}

//! Making a renderer: its layouts, samplers and frame uniform, the shading models' records,
//! the character pipelines and the passes its pipeline set calls for — for the game, with the
//! scene uploaded on one thread while the pipelines compile on a second
//! ([`Renderer::with_scene`]).

use super::layouts::Layouts;
use super::light_maps::{self, LightMaps, SHADOW_MAP_SIZE};
use super::model_gpu::ModelTable;
use super::passes::{BuildCtx, Passes, PASS_COUNT};
use super::pipelines::{CharacterPipelines, PipelineSet};
use super::prepared::per_frame;
use super::prop_gpu::PropGpu;
use super::renderer::Renderer;
use super::resources::{Resources, Subjects};
use super::skinned::SkinnedGpu;
use super::{FrameUniform, Gpu};
use crate::asset::Model;
use crate::render::material_gpu::standard_keys;
use crate::scene::PropKind;
use crate::scene::Roles;
use crate::shading::ShadingModel;

/// The textures' sampler: trilinear, repeating.
fn trilinear_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("trilinear"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

/// What the background of every frame is cleared to.
const CLEAR: wgpu::Color = wgpu::Color {
    r: 0.015,
    g: 0.017,
    b: 0.022,
    a: 1.0,
};

/// Resources with nothing loaded, around `models` (and `light_maps` where the scene casts).
fn resources(
    gpu: &Gpu,
    format: wgpu::TextureFormat,
    (layouts, sampler): (Layouts, wgpu::Sampler),
    models: ModelTable,
    light_maps: Option<LightMaps>,
) -> Resources {
    let device = &gpu.device;
    let frame_buffers = per_frame(|_| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    });
    let light_defaults = light_maps::Defaults::new(device, &gpu.queue);
    let frame_groups = per_frame(|k| {
        light_maps::frame_group(
            device,
            &layouts,
            &frame_buffers[k],
            light_maps.as_ref(),
            &light_defaults,
        )
    });
    Resources {
        layouts,
        sampler,
        frame_buffers,
        frame_groups,
        models,
        subjects: Subjects::default(),
        standard: Vec::new(),
        props: Vec::new(),
        light_maps,
        occluder: None,
        shadow_fit: None,
        subject_casts: true,
        split: None,
        light_defaults,
        format,
        clear: CLEAR,
    }
}

impl Renderer {
    /// Builds every pipeline (all shading models and the unlit baseline) for `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        Self::with_pipelines(gpu, format, &PipelineSet::everything())
    }

    /// A renderer that builds only the character pipelines in `set`.
    pub fn with_pipelines(gpu: &Gpu, format: wgpu::TextureFormat, set: &PipelineSet) -> Self {
        let device = &gpu.device;
        let layouts = Layouts::new(device);
        let pipelines = CharacterPipelines::new(gpu.pipelines(), &layouts, format, set, None);
        let models = ModelTable::new(device, &gpu.queue, &layouts, &set.models);
        let res = resources(
            gpu,
            format,
            (layouts, trilinear_sampler(device)),
            models,
            None,
        );
        let mut renderer = Self::assemble(res, pipelines, Passes::default(), set);
        renderer.refresh_passes(gpu);
        renderer
    }

    /// The game's renderer with its scene uploaded, building only `first`'s character
    /// pipeline now and the set's others on a background thread once
    /// [`Self::start_pipeline_builder`] is called (after the first frame: a quick first
    /// frame; see [`Self::receive_pipelines`]). The pipelines and passes compile on a second
    /// thread while this one uploads the scene (textures, meshes, constants), which takes
    /// about as long, so the start-up waits for the longer of the two rather than their sum.
    pub fn with_scene(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        (set, first): (&PipelineSet, ShadingModel),
        (character, roles, props): (&Model, &Roles, &[(PropKind, Model)]),
    ) -> Result<Self, String> {
        let (device, queue) = (&gpu.device, &gpu.queue);
        let layouts = Layouts::new(device);
        let sampler = trilinear_sampler(device);
        // The character casts: its light maps exist from the start.
        let penumbra = set.models.iter().any(|m| m.effects().penumbra);
        let light_maps = LightMaps::new(device, SHADOW_MAP_SIZE, penumbra);
        let standard = standard_keys(character, roles);
        let ctx = BuildCtx {
            device,
            cache: gpu.pipelines().cache,
            queue,
            layouts: &layouts,
            format,
            set,
            light_maps: Some(&light_maps),
            occluder: false,
            character: true,
            props: PropKind::ALL.map(|k| props.iter().any(|(p, _)| *p == k)),
            wanted: [false; PASS_COUNT],
            standard: &standard,
        };
        let compile = || {
            let pipelines =
                CharacterPipelines::new(ctx.pipelines(), &layouts, format, set, Some(first));
            (pipelines, Passes::build(&ctx))
        };
        let (compiled, subject, prop_gpus) = std::thread::scope(|s| {
            let compiling = std::thread::Builder::new()
                .name("dermis-compile".into())
                .spawn_scoped(s, compile);
            let subject = SkinnedGpu::new(device, queue, (&layouts, &sampler), character, roles);
            let prop_gpus: Vec<PropGpu> = props
                .iter()
                .map(|(kind, model)| PropGpu::new(device, queue, &layouts, &sampler, *kind, model))
                .collect();
            // No thread to spare: compile here.
            let compiled = match compiling {
                Ok(handle) => handle
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
                Err(_) => compile(),
            };
            (compiled, subject, prop_gpus)
        });
        let (pipelines, passes) = compiled;
        let models = ModelTable::new(device, queue, &layouts, &set.models);
        let res = resources(gpu, format, (layouts, sampler), models, Some(light_maps));
        let mut renderer = Self::assemble(res, pipelines, passes, set);
        for ((kind, _), prop) in props.iter().zip(prop_gpus) {
            renderer.install_prop(*kind, prop);
        }
        renderer.install_character(gpu, (character, roles), subject?);
        Ok(renderer)
    }

    /// A renderer around its resources, pipelines and passes; the pipelines built so far go
    /// into their models' records.
    fn assemble(
        res: Resources,
        pipelines: CharacterPipelines,
        passes: Passes,
        set: &PipelineSet,
    ) -> Self {
        let mut renderer = Self {
            res,
            passes,
            pipelines,
            set: set.clone(),
            wanted: [false; PASS_COUNT],
            off: [false; PASS_COUNT],
            warned_size: false,
            prepared: 0,
        };
        renderer.receive_pipelines(None, false);
        renderer
    }
}

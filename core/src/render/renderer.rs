//! The frame: resources created at load, per-frame uniform writes, one render pass.

use glam::{Mat4, Vec3};

use super::character::CharacterGpu;
use super::frame::{FrameUniform, Light};
use super::layouts::Layouts;
use super::model_gpu::ModelTable;
use super::offscreen::Offscreen;
use super::penumbra::{self, Penumbra};
use super::pipelines::{PipelineSet, Pipelines};
use super::props::{PropGpu, PropInstance, PropKind, MAX_INSTANCES};
use super::rig::CHARACTER;
use super::shadow::{BlobShadows, Casters};
use super::shadow_map::{self, ShadowMap, ShadowView, SHADOW_MAP_SIZE};
use super::sss_pass::{SplitTargets, SssPass};
use super::targets::Targets;
use super::timer::PassTimer;
use super::ui::UiRenderer;
use super::Gpu;
use crate::anim::Pose;
use crate::asset::Model;
use crate::camera::Frustum;
use crate::shading::{Material, ShadingModel};

/// What the camera sees this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameView {
    pub view_proj: Mat4,
    pub camera_pos: Vec3,
    pub light: Light,
    pub exposure: f32,
}

/// The pipelines a renderer compiles at load: the shading models' and the props', and the
/// subsurface pass where the set reaches a screen-space model.
struct Compiled {
    pipelines: Pipelines,
    sss: Option<SssPass>,
}

impl Compiled {
    fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
        first: Option<ShadingModel>,
    ) -> Self {
        Self {
            pipelines: Pipelines::new(device, layouts, format, set, first),
            sss: set
                .needs_subsurface_pass()
                .then(|| SssPass::new(device, layouts, format)),
        }
    }
}

/// A shadow map of `size` and, where one of `models` filters its shadow with it, its
/// penumbra map.
fn shadow_maps(
    device: &wgpu::Device,
    layouts: &Layouts,
    size: u32,
    models: &[ShadingModel],
) -> (ShadowMap, Option<Penumbra>) {
    let map = ShadowMap::new(device, layouts, size);
    let penumbra = models
        .iter()
        .any(|m| m.effects().penumbra)
        .then(|| Penumbra::new(device, &map));
    (map, penumbra)
}

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

/// Counts for one encoded frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    pub draw_calls: u32,
    pub triangles: u32,
}

/// What to draw in [`Renderer::encode`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawSet {
    /// The character's shading model; `None` draws it with the unlit baseline.
    pub shading: Option<ShadingModel>,
    pub character: bool,
    pub props: bool,
}

pub struct Renderer {
    layouts: Layouts,
    pipelines: Pipelines,
    /// One record per shading model: its pipelines, constants and kernel.
    models: ModelTable,
    /// The screen-space subsurface pass, when the pipeline set reaches a model that needs it.
    sss: Option<SssPass>,
    sampler: wgpu::Sampler,
    frame_buffer: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    /// The key light's shadow map, once something that casts is loaded (`shadow_map.rs`).
    shadow_map: Option<ShadowMap>,
    /// The penumbra map, when the pipelines reach a model that filters its shadow with it.
    penumbra: Option<Penumbra>,
    shadow_sampler: wgpu::Sampler,
    /// Whether this frame's uniform says a shadow map is drawn (set by `prepare`).
    shadow_drawn: std::cell::Cell<bool>,
    /// The sphere the light's frustum is fitted to; `None`: the character's bound at its
    /// placement.
    shadow_bound: Option<(Vec3, f32)>,
    /// Where the character was last placed.
    character_world: Mat4,
    /// The loaded character's bounding sphere in its own space (centre, radius).
    character_bound: (Vec3, f32),
    character: Option<CharacterGpu>,
    /// Subjects uploaded beside the character (the showroom's scanned head), each with its
    /// bounding sphere; slot 0 is the character's. The one drawn sits in `character` and
    /// `character_bound` (its slot empty): [`Renderer::select_subject`] swaps, creating nothing.
    subjects: Vec<Subject>,
    /// The slot in `character` now.
    active_subject: usize,
    props: Vec<PropGpu>,
    /// Scratch for grouping prop instances by kind (reused, no per-frame allocation).
    scratch: Vec<[[f32; 4]; 4]>,
    /// The props placed by [`Self::set_props`], before culling.
    placed: Vec<PropInstance>,
    /// What casts a blob shadow (recorded at load).
    casters: Casters,
    /// Blob shadows, once enabled with a caster loaded (`shadow.rs`).
    shadows: Option<BlobShadows>,
    pub format: wgpu::TextureFormat,
    pub clear: wgpu::Color,
}

impl Renderer {
    /// Builds every pipeline (all shading models) for `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        Self::with_pipelines(gpu, format, &PipelineSet::everything())
    }

    /// A renderer that builds only the character pipelines in `set`.
    pub fn with_pipelines(gpu: &Gpu, format: wgpu::TextureFormat, set: &PipelineSet) -> Self {
        Self::build(gpu, format, set, None)
    }

    /// The game's renderer with its scene uploaded, building only `first`'s character
    /// pipeline now and the set's others on a background thread once
    /// [`Self::start_pipeline_builder`] is called (after the first frame: a quick first
    /// frame; see [`Self::receive_pipelines`]). The pipelines compile on a second thread
    /// while this one uploads the scene (textures, meshes, constants), which takes about as
    /// long, so the start-up waits for the longer of the two rather than their sum.
    pub fn with_scene(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        (set, first): (&PipelineSet, ShadingModel),
        (character, props): (&Model, &[(PropKind, Model)]),
        material: &Material,
    ) -> Result<Self, String> {
        let (device, queue) = (&gpu.device, &gpu.queue);
        let layouts = Layouts::new(device);
        let sampler = trilinear_sampler(device);
        let models = &set.models;
        let compile = || {
            let compiled = Compiled::new(device, &layouts, format, set, Some(first));
            let shadows = shadow_maps(device, &layouts, SHADOW_MAP_SIZE, models);
            (compiled, shadows)
        };
        let (compiled, character_gpu, prop_gpus) = std::thread::scope(|s| {
            let compiling = std::thread::Builder::new()
                .name("dermis-compile".into())
                .spawn_scoped(s, compile);
            let character_gpu = CharacterGpu::new(device, queue, &layouts, &sampler, character);
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
            (compiled, character_gpu, prop_gpus)
        });
        let (compiled, shadows) = compiled;
        let table = ModelTable::new(device, queue, &layouts, models);
        let mut renderer = Self::assemble(gpu, format, (layouts, sampler, table), compiled);
        renderer.install_shadow_maps(device, shadows);
        renderer.install_character(gpu, character, character_gpu?, material);
        for ((kind, model), prop) in props.iter().zip(prop_gpus) {
            renderer.install_prop(*kind, model, prop);
        }
        Ok(renderer)
    }

    /// Installs the character pipelines built in the background so far; blocks for the one
    /// that draws `need` on the character shown (the model about to be drawn) or, with `all`,
    /// for every one (before play, where nothing may be created).
    pub fn receive_pipelines(&mut self, need: Option<ShadingModel>, all: bool) {
        let mapped = self.character.as_ref().is_some_and(|c| c.normal_mapped);
        self.pipelines
            .character
            .receive(&mut self.models, need.map(|m| (m, mapped)), all);
    }

    /// Starts building the other character pipelines in the background (after the first
    /// frame; a frame that needs one starts it too).
    pub fn start_pipeline_builder(&mut self) {
        self.pipelines.character.start_builder();
    }

    /// Whether some character pipeline is still being built in the background.
    pub fn pipelines_loading(&self) -> bool {
        self.pipelines.character.loading()
    }

    fn build(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
        first: Option<ShadingModel>,
    ) -> Self {
        let layouts = Layouts::new(&gpu.device);
        let compiled = Compiled::new(&gpu.device, &layouts, format, set, first);
        let sampler = trilinear_sampler(&gpu.device);
        let table = ModelTable::new(&gpu.device, &gpu.queue, &layouts, &set.models);
        Self::assemble(gpu, format, (layouts, sampler, table), compiled)
    }

    /// A renderer around its compiled pipelines, with nothing loaded.
    fn assemble(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        (layouts, sampler, models): (Layouts, wgpu::Sampler, ModelTable),
        Compiled { pipelines, sss }: Compiled,
    ) -> Self {
        let device = &gpu.device;
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shadow_sampler = shadow_map::comparison_sampler(device);
        let placeholder = shadow_map::placeholder(device, &gpu.queue);
        let no_penumbra = penumbra::grid_texture(device, 1, "no penumbra map");
        let frame_group = frame_group(
            device,
            &layouts,
            &frame_buffer,
            (&placeholder, &shadow_sampler, &no_penumbra),
        );
        let mut renderer = Self {
            layouts,
            pipelines,
            models,
            sss,
            sampler,
            frame_buffer,
            frame_group,
            shadow_map: None,
            penumbra: None,
            shadow_sampler,
            shadow_drawn: std::cell::Cell::new(false),
            shadow_bound: None,
            character_world: Mat4::IDENTITY,
            character_bound: CHARACTER.sphere_at(Vec3::ZERO),
            character: None,
            subjects: Vec::new(),
            active_subject: 0,
            props: Vec::new(),
            scratch: Vec::with_capacity(MAX_INSTANCES as usize),
            placed: Vec::with_capacity(PropKind::ALL.len() * MAX_INSTANCES as usize),
            casters: Casters::default(),
            shadows: None,
            format,
            clear: wgpu::Color {
                r: 0.015,
                g: 0.017,
                b: 0.022,
                a: 1.0,
            },
        };
        // The pipelines built now go into their models' records.
        renderer.receive_pipelines(None, false);
        renderer
    }

    /// Uploads the character (replacing any previous one) with `material`'s constants.
    pub fn load_character(
        &mut self,
        gpu: &Gpu,
        model: &Model,
        material: &Material,
    ) -> Result<(), String> {
        let character =
            CharacterGpu::new(&gpu.device, &gpu.queue, &self.layouts, &self.sampler, model)?;
        self.install_character(gpu, model, character, material);
        Ok(())
    }

    /// Makes `character`, uploaded from `model`, the character drawn.
    fn install_character(
        &mut self,
        gpu: &Gpu,
        model: &Model,
        character: CharacterGpu,
        material: &Material,
    ) {
        self.prepare_for(&gpu.device, &character);
        self.select_subject(0);
        self.character = Some(character);
        self.casters.character = Some(CHARACTER);
        self.character_bound = model_sphere(model).unwrap_or(CHARACTER.sphere_at(Vec3::ZERO));
        self.set_material(&gpu.queue, material);
    }

    /// What drawing `subject` needs: the normal-mapped pipelines if it has a normal map, the
    /// shadow map.
    fn prepare_for(&mut self, device: &wgpu::Device, subject: &CharacterGpu) {
        if subject.normal_mapped {
            self.pipelines
                .character
                .add_normal_mapped(&mut self.models, device);
        }
        if self.shadow_map.is_none() {
            self.ensure_shadow_map(device, SHADOW_MAP_SIZE);
        }
    }

    /// Uploads another subject beside the character (at load: the showroom's scanned head),
    /// drawn with the renderer's material; returns its slot for [`Renderer::select_subject`]
    /// (the character is slot 0). The character stays the one drawn.
    pub fn add_subject(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        model: &Model,
    ) -> Result<usize, String> {
        let subject = CharacterGpu::new(device, queue, &self.layouts, &self.sampler, model)?;
        self.prepare_for(device, &subject);
        if self.subjects.is_empty() {
            self.subjects.push(Subject::default());
        }
        self.subjects.push(Subject {
            gpu: Some(subject),
            bound: model_sphere(model).unwrap_or(CHARACTER.sphere_at(Vec3::ZERO)),
        });
        Ok(self.subjects.len() - 1)
    }

    /// Draws the subject in `slot` (0: the character) from now on; its pose comes from the
    /// next [`Renderer::update_character`]. An unknown slot leaves the one drawn. Creates
    /// nothing (the subjects' resources swap places).
    pub fn select_subject(&mut self, slot: usize) {
        let known = self.subjects.get(slot).is_some_and(|s| s.gpu.is_some());
        if slot == self.active_subject || !known {
            return;
        }
        let old = self.active_subject;
        self.subjects[old] = Subject {
            gpu: self.character.take(),
            bound: self.character_bound,
        };
        let new = std::mem::take(&mut self.subjects[slot]);
        self.character = new.gpu;
        self.character_bound = new.bound;
        self.active_subject = slot;
    }

    /// The subject drawn now (0: the character).
    pub fn subject(&self) -> usize {
        self.active_subject
    }

    /// Builds the key light's shadow map (once, or again at another size) and binds it to
    /// the frame group.
    fn ensure_shadow_map(&mut self, device: &wgpu::Device, size: u32) {
        if self.shadow_map.as_ref().map(|m| m.size) != Some(size) {
            let maps = shadow_maps(device, &self.layouts, size, &self.models.models());
            self.install_shadow_maps(device, maps);
        }
    }

    /// Draws shadows with `map` (and its penumbra map) from now on.
    fn install_shadow_maps(
        &mut self,
        device: &wgpu::Device,
        (map, penumbra): (ShadowMap, Option<Penumbra>),
    ) {
        self.penumbra = penumbra;
        let no_penumbra;
        let penumbra_view = match &self.penumbra {
            Some(p) => &p.result,
            None => {
                no_penumbra = penumbra::grid_texture(device, 1, "no penumbra map");
                &no_penumbra
            }
        };
        self.frame_group = frame_group(
            device,
            &self.layouts,
            &self.frame_buffer,
            (&map.view, &self.shadow_sampler, penumbra_view),
        );
        self.shadow_map = Some(map);
    }

    /// A measurement scene's shadows: whether the character (the measured medium) casts, a
    /// shadow-only occluder (world-space triangles; empty: none) and the sphere the light's
    /// frustum is fitted to (`None`: the character's bound).
    pub fn set_shadow_scene(
        &mut self,
        gpu: &Gpu,
        character_casts: bool,
        occluder: &[[f32; 3]],
        bound: Option<(Vec3, f32)>,
        size: u32,
    ) {
        self.ensure_shadow_map(&gpu.device, size);
        if let Some(map) = &mut self.shadow_map {
            map.character_casts = character_casts;
            map.set_occluder(&gpu.device, occluder);
        }
        self.shadow_bound = bound;
    }

    /// Whether this renderer has a shadow map (something that casts was loaded).
    pub fn has_shadow_map(&self) -> bool {
        self.shadow_map.is_some()
    }

    /// Uploads a scene: the character with `material`'s constants and every prop model (the
    /// one scene upload of stills, the demo and the game).
    pub fn load_scene(
        &mut self,
        gpu: &Gpu,
        character: &Model,
        props: &[(PropKind, Model)],
        material: &Material,
    ) -> Result<(), String> {
        self.load_character(gpu, character, material)?;
        for (kind, model) in props {
            self.load_prop(gpu, *kind, model);
        }
        Ok(())
    }

    /// Uploads a prop model for `kind`.
    pub fn load_prop(&mut self, gpu: &Gpu, kind: PropKind, model: &Model) {
        let prop = PropGpu::new(
            &gpu.device,
            &gpu.queue,
            &self.layouts,
            &self.sampler,
            kind,
            model,
        );
        self.install_prop(kind, model, prop);
    }

    /// Draws `prop`, uploaded from `model`, for `kind` (replacing any earlier one).
    fn install_prop(&mut self, kind: PropKind, model: &Model, prop: PropGpu) {
        self.props.retain(|p| p.kind != kind);
        self.casters.set_prop(kind, model);
        self.props.push(prop);
    }

    /// Recomputes every model's shading constants (and subsurface kernels) for `material`:
    /// every subject is drawn with it.
    pub fn set_material(&self, queue: &wgpu::Queue, material: &Material) {
        self.models.set_material(queue, material, self.clear);
    }

    /// Builds the blob shadows (at load) if anything loaded casts one; returns whether they
    /// exist. Load the scene first. The blobs are uploaded by [`Self::set_props`].
    pub fn enable_blob_shadows(&mut self, gpu: &Gpu) -> bool {
        if self.shadows.is_none() && self.casters.any() {
            self.shadows = Some(BlobShadows::new(
                &gpu.device,
                &self.layouts.frame,
                self.format,
                self.sss.is_some(),
            ));
        }
        self.shadows.is_some()
    }

    /// Switches built blob shadows on or off (the pipelines stay built).
    pub fn set_blob_shadows(&mut self, on: bool) {
        if let Some(s) = &mut self.shadows {
            s.enabled = on;
        }
    }

    /// Whether blob shadows are built and switched on.
    pub fn blob_shadows(&self) -> bool {
        self.shadows.as_ref().is_some_and(|s| s.enabled)
    }

    /// Whether this renderer has the screen-space subsurface pass.
    pub fn has_subsurface_pass(&self) -> bool {
        self.sss.is_some()
    }

    /// Places the props (their blob shadows uploaded now; [`Self::prepare`] draws those its
    /// view can see). Returns the number of buffer uploads made.
    pub fn set_props(&mut self, queue: &wgpu::Queue, instances: &[PropInstance]) -> u32 {
        self.placed.clear();
        self.placed.extend_from_slice(instances);
        match &mut self.shadows {
            Some(s) => s.set_props(queue, &self.casters, instances),
            None => 0,
        }
    }

    /// Uploads each kind's placed instances that may show in `frustum` (a kind whose visible
    /// instances did not change is not uploaded again). Returns the uploads made.
    fn cull_props(&mut self, queue: &wgpu::Queue, frustum: &Frustum) -> u32 {
        let mut uploads = 0;
        for prop in &mut self.props {
            self.scratch.clear();
            self.scratch.extend(
                self.placed
                    .iter()
                    .filter(|i| i.kind == prop.kind && prop.visible(frustum, &i.transform))
                    .map(|i| i.transform.to_cols_array_2d()),
            );
            uploads += u32::from(prop.set_instances(queue, &self.scratch));
        }
        uploads
    }

    /// Uploads the character's joint palettes for `pose`, placed at `world`.
    pub fn update_character(
        &mut self,
        queue: &wgpu::Queue,
        model: &Model,
        pose: &Pose,
        world: Mat4,
    ) {
        if let Some(c) = &mut self.character {
            c.update_pose(queue, model, pose, world);
        }
        self.character_world = world;
        if let Some(s) = &mut self.shadows {
            s.set_character(&CHARACTER, world);
        }
    }

    /// This frame's shadow view for `light` (nothing casts: [`ShadowView::NONE`]).
    fn shadow_view(&self, light: Vec3) -> ShadowView {
        let Some(map) = self
            .shadow_map
            .as_ref()
            .filter(|m| m.casts(self.character.is_some()))
        else {
            return ShadowView::NONE;
        };
        let (centre, radius) = self.shadow_bound.unwrap_or_else(|| {
            let (c, r) = self.character_bound;
            let w = self.character_world;
            let scale = w
                .x_axis
                .truncate()
                .length()
                .max(w.y_axis.truncate().length())
                .max(w.z_axis.truncate().length());
            (w.transform_point3(c), r * scale * POSE_MARGIN)
        });
        ShadowView::fit(light, centre, radius, map.size)
    }

    /// Writes the frame uniform (and the shadow map's light matrix) and the props this view
    /// can see. Returns the number of buffer uploads made.
    pub fn prepare(&mut self, queue: &wgpu::Queue, view: &FrameView) -> u32 {
        let prop_uploads = self.cull_props(queue, &Frustum::new(view.view_proj));
        let shadow = self.shadow_view(view.light.position);
        if let (Some(map), true) = (&self.shadow_map, shadow.drawn) {
            map.prepare(queue, &shadow);
        }
        let grid = self.penumbra.as_ref().map_or(0, |p| p.size);
        if let Some(p) = &self.penumbra {
            let params = shadow.penumbra_params(grid);
            p.prepare(queue, params[3], params[2]);
        }
        self.shadow_drawn.set(shadow.drawn);
        let raw = matches!(
            self.format,
            wgpu::TextureFormat::Rgba16Float | wgpu::TextureFormat::Rgba32Float
        );
        let manual_srgb = !raw && !self.format.is_srgb();
        let u = FrameUniform::new(
            view.view_proj,
            view.camera_pos,
            &view.light,
            (view.exposure, manual_srgb, raw),
            (&shadow, grid),
        );
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&u));
        1 + prop_uploads
    }

    /// The character pipelines that were built (or are being built).
    pub fn built_pipelines(&self) -> PipelineSet {
        PipelineSet {
            models: self.models.models(),
            unlit: self.pipelines.character.unlit.is_some(),
        }
    }

    pub fn character_triangles(&self) -> u32 {
        self.character.as_ref().map_or(0, |c| c.triangles)
    }

    /// Draws `draw` (no UI, untimed) into `target` and queues the copy its `read` methods
    /// return, in one submit.
    pub fn draw_offscreen(&self, gpu: &Gpu, target: &Offscreen, draw: DrawSet) -> RenderStats {
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let stats = self.encode(
            &mut encoder,
            &target.targets,
            &target.view,
            draw,
            None,
            None,
        );
        target.copy_out(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        stats
    }

    /// Records the frame into `encoder`, resolving into `output`: one render pass, or for a
    /// character drawn with a screen-space model the scene pass and the subsurface pass.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        output: &wgpu::TextureView,
        draw: DrawSet,
        ui: Option<&UiRenderer>,
        timer: Option<&PassTimer>,
    ) -> RenderStats {
        let shadow_draws = self.encode_shadow_map(encoder, draw);
        let mut stats = self.encode_scene(encoder, targets, output, draw, ui, timer);
        stats.draw_calls += shadow_draws;
        stats
    }

    /// The shadow map's depth-only pass, when this frame's uniform says one is drawn.
    fn encode_shadow_map(&self, encoder: &mut wgpu::CommandEncoder, draw: DrawSet) -> u32 {
        match &self.shadow_map {
            Some(map) if self.shadow_drawn.get() => {
                let character = self.character.as_ref().filter(|_| draw.character);
                let mut draws = map.encode(encoder, character);
                // Only a model that reads the penumbra map pays for it.
                let reads = draw.character && draw.shading.is_some_and(|m| m.effects().penumbra);
                if let (Some(p), true) = (&self.penumbra, reads) {
                    draws += p.encode(encoder);
                }
                draws
            }
            _ => 0,
        }
    }

    fn encode_scene(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        output: &wgpu::TextureView,
        draw: DrawSet,
        ui: Option<&UiRenderer>,
        timer: Option<&PassTimer>,
    ) -> RenderStats {
        let split_model = draw
            .shading
            .filter(|m| draw.character && m.effects().screen_space);
        if let Some(sss) = &self.sss {
            // The split targets exist from the first frame of each size, whichever model it
            // draws: switching to a screen-space model later creates nothing.
            let size = (targets.width, targets.height);
            let frame = sss.with_targets(size, &self.models, |split| {
                split_model.map(|model| {
                    self.encode_split(encoder, targets, output, draw, ui, timer, model, split)
                })
            });
            if let Some(stats) = frame {
                return stats;
            }
        }
        let mut stats = RenderStats::default();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[self.output_attachment(targets, output)],
            depth_stencil_attachment: Some(depth_attachment(targets)),
            timestamp_writes: timer.map(|t| t.writes()),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.frame_group, &[]);
        let shadow = self.shadows.as_ref().map(|s| &s.pipeline);
        self.draw_scene(&mut pass, draw, &self.pipelines.prop, shadow, &mut stats);
        // The UI goes last, inside the same pass: one draw call.
        if let Some(ui) = ui {
            stats.draw_calls += ui.draw(&mut pass);
        }
        stats
    }

    /// The frame's last pass draws into the MSAA target, cleared, and resolves into `output`.
    fn output_attachment<'a>(
        &self,
        targets: &'a Targets,
        output: &'a wgpu::TextureView,
    ) -> Option<wgpu::RenderPassColorAttachment<'a>> {
        Some(wgpu::RenderPassColorAttachment {
            view: &targets.msaa,
            depth_slice: None,
            resolve_target: Some(output),
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(self.clear),
                store: wgpu::StoreOp::Discard,
            },
        })
    }

    /// The character and props of `draw` into the open pass, opaque first and nearest first:
    /// the character (what the camera frames), then what stands on the floor, then the floor,
    /// most of which lies behind them, so its hidden texels fail the early depth test instead
    /// of being shaded and covered. With blob shadows on and props drawn the blobs go last,
    /// blended over the floor and depth-tested against everything, so what stands on a blob
    /// covers it.
    fn draw_scene<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        draw: DrawSet,
        prop_pipeline: &'p wgpu::RenderPipeline,
        shadow_pipeline: Option<&'p wgpu::RenderPipeline>,
        stats: &mut RenderStats,
    ) {
        if draw.character {
            // A model outside the built set is not drawn (and never compiled at run time).
            if let Some(c) = &self.character {
                let pipeline = match draw.shading {
                    Some(m) => self.models.pipeline((m, c.normal_mapped)),
                    None => self.pipelines.character.unlit.as_ref(),
                };
                let group = self.models.params_group(draw.shading);
                if let (Some(pipeline), Some(group)) = (pipeline, group) {
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(1, group, &[]);
                    stats.draw_calls += c.draw(pass);
                    stats.triangles += c.triangles;
                }
            }
        }
        if !draw.props {
            return;
        }
        pass.set_pipeline(prop_pipeline);
        let is_floor = |p: &&PropGpu| p.kind == PropKind::FloorTile;
        let standing = self.props.iter().filter(|p| !is_floor(p));
        for prop in standing.chain(self.props.iter().filter(is_floor)) {
            stats.draw_calls += prop.draw(pass);
            stats.triangles += prop.triangles * prop.count;
        }
        // The blobs lie on the floor: none in a frame without it.
        let shadows = self.shadows.as_ref().filter(|s| s.enabled);
        if let (Some(blobs), Some(pipeline)) = (shadows, shadow_pipeline) {
            let character = draw.character && self.character.is_some();
            stats.draw_calls += blobs.draw(pass, pipeline, character);
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn encode_split(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        targets: &Targets,
        output: &wgpu::TextureView,
        draw: DrawSet,
        ui: Option<&UiRenderer>,
        timer: Option<&PassTimer>,
        model: ShadingModel,
        split: &SplitTargets,
    ) -> RenderStats {
        let mut stats = RenderStats::default();
        let (Some(sss), Some(prop_split), Some(group)) =
            (&self.sss, &self.pipelines.prop_split, split.group(model))
        else {
            return stats;
        };
        // Background: alpha −1 tells the subsurface pass that nothing was drawn there.
        let clear = wgpu::Color {
            a: -1.0,
            ..self.clear
        };
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
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene (subsurface)"),
                color_attachments: &[
                    attachment(&split.colour_msaa, &split.colour),
                    attachment(&split.spread_msaa, &split.spread),
                ],
                depth_stencil_attachment: Some(depth_attachment(targets)),
                timestamp_writes: timer.map(|t| t.begin_writes()),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_group, &[]);
            let shadow = self.shadows.as_ref().and_then(|s| s.split.as_ref());
            self.draw_scene(&mut pass, draw, prop_split, shadow, &mut stats);
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("subsurface"),
            color_attachments: &[self.output_attachment(targets, output)],
            depth_stencil_attachment: Some(depth_attachment(targets)),
            timestamp_writes: timer.map(|t| t.end_writes()),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_pipeline(&sss.pipeline);
        pass.set_bind_group(1, group, &[]);
        pass.draw(0..3, 0..1);
        stats.draw_calls += 1;
        if let Some(ui) = ui {
            stats.draw_calls += ui.draw(&mut pass);
        }
        stats
    }
}

/// A subject's GPU resources and bounding sphere in its own space (centre, radius).
#[derive(Default)]
struct Subject {
    gpu: Option<CharacterGpu>,
    bound: (Vec3, f32),
}

/// How much a pose may reach beyond the bind pose's bounding sphere (arms, a jump's tuck).
const POSE_MARGIN: f32 = 1.25;

/// The bounding sphere of `model`'s meshes (their primitives' boxes), in its own space.
fn model_sphere(model: &Model) -> Option<(Vec3, f32)> {
    let mut boxes = model
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .map(|p| &p.bounds);
    let first = boxes.next()?;
    let (lo, hi) = boxes.fold((first.min, first.max), |(lo, hi), b| {
        (lo.min(b.min), hi.max(b.max))
    });
    let r = 0.5 * (hi - lo).length();
    (r.is_finite() && r > 0.0).then_some((0.5 * (lo + hi), r))
}

/// Group 0: the frame uniform, the shadow map with its comparison sampler, the penumbra map.
fn frame_group(
    device: &wgpu::Device,
    layouts: &Layouts,
    buffer: &wgpu::Buffer,
    (shadow_map, sampler, penumbra): (&wgpu::TextureView, &wgpu::Sampler, &wgpu::TextureView),
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout: &layouts.frame,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(shadow_map),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(penumbra),
            },
        ],
    })
}

fn depth_attachment(targets: &Targets) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view: &targets.depth,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Discard,
        }),
        stencil_ops: None,
    }
}

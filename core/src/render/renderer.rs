//! The frame: resources created at load, per-frame uniform writes, one render pass.

use glam::{Mat4, Vec3};

use super::character::CharacterGpu;
use super::frame::{FrameUniform, Light};
use super::layouts::Layouts;
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
use crate::shading::{Material, ShadingModel};

/// What the camera sees this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameView {
    pub view_proj: Mat4,
    pub camera_pos: Vec3,
    pub light: Light,
    pub exposure: f32,
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

    /// The same, building only `first`'s character pipeline now and the set's others on a
    /// background thread once [`Self::start_pipeline_builder`] is called (after the first
    /// frame: a quick first frame; see [`Self::receive_pipelines`]).
    pub fn with_first_pipeline(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        set: &PipelineSet,
        first: ShadingModel,
    ) -> Self {
        Self::build(gpu, format, set, Some(first))
    }

    /// Installs the character pipelines built in the background so far; blocks for the one
    /// that draws `need` on the character shown (the model about to be drawn) or, with `all`,
    /// for every one (before play, where nothing may be created).
    pub fn receive_pipelines(&mut self, need: Option<ShadingModel>, all: bool) {
        let mapped = self.character.as_ref().is_some_and(|c| c.normal_mapped);
        self.pipelines
            .character
            .receive(need.map(|m| (m, mapped)), all);
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
        let device = &gpu.device;
        let layouts = Layouts::new(device);
        let pipelines = Pipelines::new(device, &layouts, format, set, first);
        let sss = set
            .needs_subsurface_pass()
            .then(|| SssPass::new(device, &layouts, format, &set.models));
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("trilinear"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
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
        Self {
            layouts,
            pipelines,
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
            casters: Casters::default(),
            shadows: None,
            format,
            clear: wgpu::Color {
                r: 0.015,
                g: 0.017,
                b: 0.022,
                a: 1.0,
            },
        }
    }

    /// Uploads the character (replacing any previous one) with `material`'s constants.
    pub fn load_character(
        &mut self,
        gpu: &Gpu,
        model: &Model,
        material: &Material,
    ) -> Result<(), String> {
        let character = self.upload_subject(&gpu.device, &gpu.queue, model)?;
        self.select_subject(0);
        self.character = Some(character);
        self.casters.character = Some(CHARACTER);
        self.character_bound = model_sphere(model).unwrap_or(CHARACTER.sphere_at(Vec3::ZERO));
        self.set_material(&gpu.queue, material);
        Ok(())
    }

    /// A skinned model's GPU side (constants for the built models), with what drawing it
    /// needs: the normal-mapped pipelines if it has a normal map, the shadow map.
    fn upload_subject(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        model: &Model,
    ) -> Result<CharacterGpu, String> {
        let models = self.pipelines.character.built().models;
        let subject =
            CharacterGpu::new(device, queue, &self.layouts, &self.sampler, model, &models)?;
        if subject.normal_mapped {
            self.pipelines.character.add_normal_mapped(device);
        }
        if self.shadow_map.is_none() {
            self.ensure_shadow_map(device, SHADOW_MAP_SIZE);
        }
        Ok(subject)
    }

    /// Uploads another subject beside the character (at load: the showroom's scanned head)
    /// with `material`'s constants; returns its slot for [`Renderer::select_subject`] (the
    /// character is slot 0). The character stays the one drawn.
    pub fn add_subject(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        model: &Model,
        material: &Material,
    ) -> Result<usize, String> {
        let subject = self.upload_subject(device, queue, model)?;
        subject.set_material(queue, material);
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
            let map = ShadowMap::new(device, &self.layouts, size);
            let models = self.pipelines.character.built().models;
            self.penumbra = models
                .iter()
                .any(|m| m.effects().penumbra)
                .then(|| Penumbra::new(device, &map));
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
        self.props.retain(|p| p.kind != kind);
        self.casters.set_prop(kind, model);
        self.props.push(PropGpu::new(
            &gpu.device,
            &gpu.queue,
            &self.layouts,
            &self.sampler,
            kind,
            model,
        ));
    }

    /// Recomputes the character's shading constants (and subsurface kernels) for `material`.
    pub fn set_material(&self, queue: &wgpu::Queue, material: &Material) {
        if let Some(c) = &self.character {
            c.set_material(queue, material);
        }
        for c in self.subjects.iter().filter_map(|s| s.gpu.as_ref()) {
            c.set_material(queue, material);
        }
        if let Some(sss) = &self.sss {
            sss.set_material(queue, material, self.clear);
        }
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

    /// Replaces the placed props.
    /// Places the props; a kind whose instances did not change is not uploaded again.
    /// Returns the number of buffer uploads made.
    pub fn set_props(&mut self, queue: &wgpu::Queue, instances: &[PropInstance]) -> u32 {
        let mut uploads = 0;
        for prop in &mut self.props {
            self.scratch.clear();
            self.scratch.extend(
                instances
                    .iter()
                    .filter(|i| i.kind == prop.kind)
                    .map(|i| i.transform.to_cols_array_2d()),
            );
            uploads += u32::from(prop.set_instances(queue, &self.scratch));
        }
        if let Some(s) = &mut self.shadows {
            uploads += s.set_props(queue, &self.casters, instances);
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

    /// Writes the frame uniform (and the shadow map's light matrix).
    pub fn prepare(&self, queue: &wgpu::Queue, view: &FrameView) {
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
    }

    /// The character pipelines that were built (or are being built).
    pub fn built_pipelines(&self) -> PipelineSet {
        self.pipelines.character.built()
    }

    pub fn character_triangles(&self) -> u32 {
        self.character.as_ref().map_or(0, |c| c.triangles)
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
            let frame = sss.with_targets(targets.width, targets.height, |split| {
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

    /// The character and props of `draw` into the open pass. With blob shadows on and props
    /// drawn: the floor first, then the blobs (depth-tested against it), then what stands on
    /// it, which covers its own blob.
    fn draw_scene<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        draw: DrawSet,
        prop_pipeline: &'p wgpu::RenderPipeline,
        shadow_pipeline: Option<&'p wgpu::RenderPipeline>,
        stats: &mut RenderStats,
    ) {
        // The blobs lie on the floor: none in a frame without it.
        let shadows = self
            .shadows
            .as_ref()
            .filter(|s| s.enabled && draw.props)
            .zip(shadow_pipeline);
        let is_floor = |p: &PropGpu| p.kind == PropKind::FloorTile;
        if let Some((blobs, pipeline)) = shadows {
            pass.set_pipeline(prop_pipeline);
            for prop in self.props.iter().filter(|p| is_floor(p)) {
                stats.draw_calls += prop.draw(pass);
                stats.triangles += prop.triangles * prop.count;
            }
            let character = draw.character && self.character.is_some();
            stats.draw_calls += blobs.draw(pass, pipeline, character);
        }
        if draw.character {
            // A model outside the built set is not drawn (and never compiled at run time).
            if let Some(c) = &self.character {
                let pipeline = self.pipelines.character.get(draw.shading, c.normal_mapped);
                if let (Some(pipeline), Some(group)) = (pipeline, c.params_group(draw.shading)) {
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(1, group, &[]);
                    stats.draw_calls += c.draw(pass);
                    stats.triangles += c.triangles;
                }
            }
        }
        if draw.props {
            pass.set_pipeline(prop_pipeline);
            // The floor went first when the blobs were drawn.
            for prop in self
                .props
                .iter()
                .filter(|p| shadows.is_none() || !is_floor(p))
            {
                stats.draw_calls += prop.draw(pass);
                stats.triangles += prop.triangles * prop.count;
            }
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

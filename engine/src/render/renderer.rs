//! The renderer: a resource owner ([`Resources`]) plus its passes ([`Passes`], one module
//! each under `passes/`). A frame goes through three calls, as in wgpu's examples framework:
//! [`Renderer::resize`] when the target's size changes, [`Renderer::prepare`] with the
//! frame's packet (plain data from whoever runs the frame) — it writes the frame's buffers and
//! returns the [`PreparedFrame`], worked out once — and [`Renderer::encode`], which reads only
//! that value and the pass context. Loading and configuring the scene (subjects, props,
//! materials, shadows) happens between frames, through the methods here; construction is in
//! `build.rs`.

use glam::Vec3;

use super::light_maps::{LightMaps, Occluder, SHADOW_MAP_SIZE};
use super::material_gpu::standard_keys;
use super::model_gpu::PipelineKey;
use super::offscreen::Offscreen;
use super::passes::resolve::{self, Timed};
use super::passes::{BuildCtx, PassId, Passes, Stage, Target, PASS_COUNT};
use super::pipelines::{CharacterPipelines, PipelineSet};
use super::prepared::{PassCtx, PreparedFrame, RenderStats, SubjectDraw, FRAMES_PREPARED};
use super::prop_gpu::PropGpu;
use super::resources::{Resources, Subject};
use super::shadow_view::ShadowView;
use super::skinned::SkinnedGpu;
use super::targets::SplitTargets;
use super::{FrameUniform, Gpu, OutputMode};
use crate::asset::Model;
use crate::scene::{FramePacket, PropKind, Roles, SubjectId, CHARACTER};
use crate::shading::{Material, ShadingModel};

/// How much a pose may reach beyond the bind pose's bounding sphere (arms, a jump's tuck).
const POSE_MARGIN: f32 = 1.25;

pub struct Renderer {
    pub(super) res: Resources,
    pub(super) passes: Passes,
    pub(super) pipelines: CharacterPipelines,
    /// The shading models the scene can reach (and the unlit baseline, for benches).
    pub(super) set: PipelineSet,
    /// The optional passes asked for ([`Self::enable`]), table order.
    pub(super) wanted: [bool; PASS_COUNT],
    /// Passes switched off ([`Self::switch`]), table order.
    pub(super) off: [bool; PASS_COUNT],
    /// A frame asked for a size the renderer was not resized to (logged once).
    pub(super) warned_size: bool,
    /// Frames prepared so far (the next one's `seq`).
    pub(super) prepared: u64,
}

/// What the passes are built from, for the renderer's resources now.
pub(super) fn build_ctx<'a>(
    gpu: &'a Gpu,
    res: &'a Resources,
    set: &'a PipelineSet,
    wanted: [bool; PASS_COUNT],
) -> BuildCtx<'a> {
    BuildCtx {
        device: &gpu.device,
        cache: gpu.pipelines().cache,
        queue: &gpu.queue,
        layouts: &res.layouts,
        format: res.format,
        set,
        light_maps: res.light_maps.as_ref(),
        occluder: res.occluder.is_some(),
        character: res.subjects.iter().next().is_some(),
        props: PropKind::ALL.map(|k| res.props.iter().any(|p| p.kind == k)),
        wanted,
        standard: &res.standard,
    }
}

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

impl Renderer {
    // ---- the frame -------------------------------------------------------------------

    /// Makes the transient targets the built passes create (the frame graph's) at the
    /// frame's size; call when the output's size changes, before preparing a frame of it.
    pub fn resize(&mut self, gpu: &Gpu, (width, height): (u32, u32)) {
        let size = (width.max(1), height.max(1));
        let sized = self.res.split.as_ref().map(|t| t.size);
        if !self.passes.creates(Target::Split) || sized == Some(size) {
            return;
        }
        self.res.split = Some(SplitTargets::new(&gpu.device, size));
        for pass in self.passes.each_mut().into_iter().flatten() {
            pass.resize(&gpu.device, &self.res);
        }
    }

    /// Prepares the frame `packet` describes: installs the pipelines built so far (waiting
    /// for the one it draws, or for all of them when the packet is `settled`), poses the
    /// subject the packet names, fits the shadow map's frustum, lets every pass decide
    /// whether it runs and write its constants, and writes the frame uniform — all into this
    /// frame's copy of the per-frame buffers ([`FRAMES_PREPARED`]). The returned frame is
    /// everything `encode` reads besides what was loaded.
    pub fn prepare(&mut self, gpu: &Gpu, packet: &FramePacket) -> PreparedFrame {
        let queue = &gpu.queue;
        let draw = packet.draw;
        let seq = self.prepared;
        self.prepared += 1;
        let copy = (seq % FRAMES_PREPARED as u64) as usize;
        let slot = self.res.subjects.slot(packet.subject_id);
        self.receive_for(slot, draw, packet.settled);
        let mut uploads = 0;
        let mut subject = None;
        if let Some(s) = slot.and_then(|k| self.res.subjects.get_mut(k)) {
            if let Some(pose) = &packet.subject {
                s.gpu.pose(pose.model, pose.pose, pose.world);
                s.world = pose.world;
            }
            uploads += s.gpu.write_palettes(queue, copy);
            subject = draw.character.then_some(SubjectDraw {
                slot: slot.unwrap_or(0),
                shading: draw.shading,
                world: s.world,
            });
        }
        let mut split = draw
            .shading
            .filter(|m| subject.is_some() && m.effects().screen_space);
        if split.is_some() && self.res.split.as_ref().map(|t| t.size) != Some(packet.viewport) {
            if !self.warned_size {
                log::error!(
                    "a {}×{} frame before Renderer::resize to its size: its subject is not drawn",
                    packet.viewport.0,
                    packet.viewport.1
                );
                self.warned_size = true;
            }
            (split, subject) = (None, None);
        }
        let view = packet.view;
        let shadow = self.shadow_view(slot, view.light.position, view.view_proj);
        let output = OutputMode::for_format(self.res.format, view.exposure);
        let mut frame = PreparedFrame {
            seq,
            copy,
            size: packet.viewport,
            view,
            draw,
            subject,
            shadow,
            visible_props: [0; PropKind::ALL.len()],
            split,
            uniform: FrameUniform::new(&view, output, &shadow),
            passes: Default::default(),
            uploads,
        };
        self.passes.prepare(queue, packet, &mut frame, &self.res);
        for (pass, off) in frame.passes.iter_mut().zip(self.off) {
            pass.runs &= !off;
        }
        queue.write_buffer(
            &self.res.frame_buffers[copy],
            0,
            bytemuck::bytes_of(&frame.uniform),
        );
        frame.uploads += 1;
        frame
    }

    /// Installs the character pipelines built so far, waiting for those `draw` needs for the
    /// skin parts of the subject in `slot` (with and without a normal map), or with `all`
    /// for every one.
    fn receive_for(&mut self, slot: Option<usize>, draw: crate::scene::DrawSet, all: bool) {
        let gpu = slot.and_then(|k| self.res.subjects.get(k)).map(|s| &s.gpu);
        let (plain, mapped) = gpu.map_or((false, false), |g| (g.plain, g.normal_mapped));
        let mut need = [(ShadingModel::BASELINE, false); 2];
        let mut n = 0;
        if let Some(m) = draw.shading.filter(|_| draw.character) {
            for (wanted, key) in [(plain, (m, false)), (mapped, (m, true))] {
                if wanted {
                    need[n] = key;
                    n += 1;
                }
            }
        }
        self.pipelines
            .receive(&mut self.res.models, &need[..n], all);
    }

    /// This frame's shadow view for a light at `light` ([`ShadowView::NONE`] when nothing
    /// casts): fitted to the measurement scene's sphere, else to the sphere around the
    /// subject in `slot`'s posed box and cropped to the shadows the camera `camera` can see
    /// of it.
    fn shadow_view(&self, slot: Option<usize>, light: Vec3, camera: glam::Mat4) -> ShadowView {
        let res = &self.res;
        let Some(maps) = &res.light_maps else {
            return ShadowView::NONE;
        };
        let subject = slot.and_then(|k| res.subjects.get(k));
        if !(subject.is_some() && res.subject_casts || res.occluder.is_some()) {
            return ShadowView::NONE;
        }
        if let Some((centre, radius)) = res.shadow_fit {
            return ShadowView::fit(light, centre, radius, maps.size);
        }
        // The posed box where the subject has been posed, else its bind sphere and a margin.
        let (centre, radius, bounds) = match subject.and_then(|s| s.gpu.posed) {
            Some((lo, hi)) => (0.5 * (lo + hi), 0.5 * (hi - lo).length(), (lo, hi)),
            None => {
                let (c, r) = subject
                    .map(|s| s.world_sphere(POSE_MARGIN))
                    .unwrap_or(CHARACTER.sphere_at(Vec3::ZERO));
                (c, r, (c - Vec3::splat(r), c + Vec3::splat(r)))
            }
        };
        ShadowView::fit(light, centre, radius, maps.size).cropped_to(camera, light, bounds)
    }

    /// Records `frame` (see the module docs): the light's maps in passes of their own, then
    /// the scene's pass — into the output, or, ending with the subsurface pass, into its
    /// targets — and the frame's last pass, which resolves into the output. Reads only
    /// `frame`, what was loaded and `frame`'s copy of the per-frame buffers; refuses (one
    /// line) a frame whose copy a later frame has been prepared into.
    pub fn encode(&self, frame: &PreparedFrame, ctx: &mut PassCtx) -> Result<RenderStats, String> {
        let copies = FRAMES_PREPARED as u64;
        if frame.seq + copies < self.prepared || frame.seq >= self.prepared {
            return Err(format!(
                "frame {} is stale: {} frames were prepared after it and its buffers hold a later one's (at most {} may wait to be encoded)",
                frame.seq,
                self.prepared.saturating_sub(frame.seq + 1),
                FRAMES_PREPARED - 1
            ));
        }
        let mut stats = RenderStats::default();
        let res = &self.res;
        let group = &res.frame_groups[frame.copy];
        self.passes.encode(frame, res, ctx.encoder, &mut stats);
        let split = frame.split.and(res.split.as_ref());
        {
            let mut pass = match split {
                Some(targets) => targets.scene_pass(ctx, res.clear),
                None => resolve::output_pass(ctx, res.clear, Timed::Whole, "scene"),
            };
            pass.set_bind_group(0, group, &[]);
            self.passes
                .draw(Stage::Scene, frame, res, &mut pass, &mut stats);
            if split.is_none() {
                self.passes
                    .draw(Stage::Last, frame, res, &mut pass, &mut stats);
            }
        }
        if split.is_some() {
            let mut pass = resolve::output_pass(ctx, res.clear, Timed::End, "subsurface");
            pass.set_bind_group(0, group, &[]);
            self.passes
                .draw(Stage::Last, frame, res, &mut pass, &mut stats);
        }
        Ok(stats)
    }

    /// Encodes `frame` into `target` (untimed) and queues the copy its `read` methods
    /// return, in one submit.
    pub fn draw_offscreen(
        &self,
        gpu: &Gpu,
        target: &Offscreen,
        frame: &PreparedFrame,
    ) -> Result<RenderStats, String> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let stats = self.encode(
            frame,
            &mut PassCtx {
                encoder: &mut encoder,
                targets: &target.targets,
                output: &target.view,
                timer: None,
            },
        )?;
        target.copy_out(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        Ok(stats)
    }

    // ---- pipelines -------------------------------------------------------------------

    /// Installs the character pipelines built in the background so far; blocks for `need`'s
    /// or, with `all`, for every one (before play, where nothing may be created).
    pub fn receive_pipelines(&mut self, need: Option<PipelineKey>, all: bool) {
        let need: &[PipelineKey] = match &need {
            Some(k) => std::slice::from_ref(k),
            None => &[],
        };
        self.pipelines.receive(&mut self.res.models, need, all);
    }

    /// Starts building the other character pipelines in the background (after the first
    /// frame; a frame that needs one starts it too).
    pub fn start_pipeline_builder(&mut self) {
        self.pipelines.start_builder();
    }

    /// Whether some character pipeline is still being built in the background.
    pub fn pipelines_loading(&self) -> bool {
        self.pipelines.loading()
    }

    /// The character pipelines that were built (or are being built).
    pub fn built_pipelines(&self) -> PipelineSet {
        PipelineSet {
            models: self.res.models.models(),
            unlit: self.res.models.draws(None) || self.set.unlit,
        }
    }

    // ---- the scene -------------------------------------------------------------------

    /// Builds the passes the scene now needs (and again those it made stale), and sizes what
    /// they bind.
    pub(super) fn refresh_passes(&mut self, gpu: &Gpu) {
        let ctx = build_ctx(gpu, &self.res, &self.set, self.wanted);
        self.passes.refresh(&ctx);
        for pass in self.passes.each_mut().into_iter().flatten() {
            pass.resize(&gpu.device, &self.res);
        }
    }

    /// Uploads the character (replacing any previous one), its materials drawn as `roles`
    /// says and its skin with their optics.
    pub fn load_character(
        &mut self,
        gpu: &Gpu,
        model: &Model,
        roles: &Roles,
    ) -> Result<(), String> {
        let subject = self.upload_subject(gpu, model, roles)?;
        self.install_character(gpu, (model, roles), subject);
        Ok(())
    }

    fn upload_subject(
        &self,
        gpu: &Gpu,
        model: &Model,
        roles: &Roles,
    ) -> Result<SkinnedGpu, String> {
        let res = &self.res;
        SkinnedGpu::new(
            &gpu.device,
            &gpu.queue,
            (&res.layouts, &res.sampler),
            model,
            roles,
        )
    }

    /// Makes `subject`, uploaded from `model`, the character (slot 0), drawn.
    pub(super) fn install_character(
        &mut self,
        gpu: &Gpu,
        (model, roles): (&Model, &Roles),
        subject: SkinnedGpu,
    ) {
        self.prepare_for(gpu, (model, roles), &subject);
        let bound = model_sphere(model).unwrap_or(CHARACTER.sphere_at(Vec3::ZERO));
        self.res
            .subjects
            .set_character(Subject::new(subject, bound));
        self.set_material(gpu, &roles.optics);
        self.refresh_passes(gpu);
    }

    /// What drawing `subject` needs: the normal-mapped pipelines if a skin part has a normal
    /// map, its standard materials' pipelines, the light maps.
    fn prepare_for(&mut self, gpu: &Gpu, (model, roles): (&Model, &Roles), subject: &SkinnedGpu) {
        for key in standard_keys(model, roles) {
            if !self.res.standard.contains(&key) {
                self.res.standard.push(key);
            }
        }
        if subject.normal_mapped {
            self.pipelines
                .add_normal_mapped(&mut self.res.models, &gpu.device);
        }
        if self.res.light_maps.is_none() {
            self.make_light_maps(gpu, SHADOW_MAP_SIZE);
        }
    }

    /// Makes the light maps at `size` (once, or again at another size) and binds them.
    fn make_light_maps(&mut self, gpu: &Gpu, size: u32) {
        if self.res.light_maps.as_ref().map(|m| m.size) == Some(size) {
            return;
        }
        let penumbra = self.set.models.iter().any(|m| m.effects().penumbra);
        self.res.light_maps = Some(LightMaps::new(&gpu.device, size, penumbra));
        self.res.rebind_frame_group(&gpu.device);
        self.refresh_passes(gpu);
    }

    /// Uploads another subject beside the character under the scene's `id` for it (the
    /// showroom's scanned head; a frame packet naming `id` draws it), its materials drawn as
    /// `roles` says, its skin with the renderer's optics.
    pub fn add_subject(
        &mut self,
        gpu: &Gpu,
        id: SubjectId,
        model: &Model,
        roles: &Roles,
    ) -> Result<(), String> {
        if self.res.subjects.iter().next().is_none() {
            return Err(format!("{}: load the character first", model.source));
        }
        let subject = self.upload_subject(gpu, model, roles)?;
        self.prepare_for(gpu, (model, roles), &subject);
        self.refresh_passes(gpu);
        let bound = model_sphere(model).unwrap_or(CHARACTER.sphere_at(Vec3::ZERO));
        self.res.subjects.add(id, Subject::new(subject, bound));
        Ok(())
    }

    /// The world box of subject `id` as last posed (every vertex inside): what the shadow
    /// map is fitted to.
    pub fn subject_box(&self, id: SubjectId) -> Option<(Vec3, Vec3)> {
        let slot = self.res.subjects.slot(id)?;
        self.res.subjects.get(slot)?.gpu.posed
    }

    /// Triangles of the character.
    pub fn character_triangles(&self) -> u32 {
        self.res.subjects.get(0).map_or(0, |s| s.gpu.triangles)
    }

    /// Uploads a scene: the character, its materials drawn as `roles` says, and every prop
    /// model.
    pub fn load_scene(
        &mut self,
        gpu: &Gpu,
        (character, roles): (&Model, &Roles),
        props: &[(PropKind, Model)],
    ) -> Result<(), String> {
        self.load_character(gpu, character, roles)?;
        for (kind, model) in props {
            self.load_prop(gpu, *kind, model);
        }
        Ok(())
    }

    /// Uploads a prop model for `kind` (replacing any earlier one).
    pub fn load_prop(&mut self, gpu: &Gpu, kind: PropKind, model: &Model) {
        let layouts = &self.res.layouts;
        let prop = PropGpu::new(
            &gpu.device,
            &gpu.queue,
            layouts,
            &self.res.sampler,
            kind,
            model,
        );
        self.install_prop(kind, prop);
        self.refresh_passes(gpu);
    }

    /// Draws `prop`, uploaded from `model`, for `kind` (replacing any earlier one).
    pub(super) fn install_prop(&mut self, kind: PropKind, prop: PropGpu) {
        self.res.props.retain(|p| p.kind != kind);
        self.res.props.push(prop);
    }

    /// Recomputes every model's shading constants (and subsurface kernels) for `material`:
    /// every subject is drawn with it.
    pub fn set_material(&self, gpu: &Gpu, material: &Material) {
        self.res
            .models
            .set_material(&gpu.queue, material, self.res.clear);
    }

    /// A measurement scene's shadows: whether the subject (the measured medium) casts, a
    /// shadow-only occluder (world-space triangles; empty: none), the sphere the light's
    /// frustum is fitted to (`None`: the subject's bound) and the map's size.
    pub fn set_shadow_scene(
        &mut self,
        gpu: &Gpu,
        subject_casts: bool,
        occluder: &[[f32; 3]],
        fit: Option<(Vec3, f32)>,
        size: u32,
    ) {
        self.res.subject_casts = subject_casts;
        self.res.occluder = Occluder::new(&gpu.device, occluder);
        self.res.shadow_fit = fit;
        self.make_light_maps(gpu, size);
        self.refresh_passes(gpu);
    }

    /// Whether this renderer has a shadow map (something that casts was loaded).
    pub fn has_shadow_map(&self) -> bool {
        self.res.light_maps.is_some()
    }

    /// Asks for the optional pass `id` (the blob shadows, the UI) and builds it where the
    /// scene has what it draws for; returns whether it is built.
    pub fn enable(&mut self, gpu: &Gpu, PassId(slot): PassId) -> bool {
        self.wanted[slot] = true;
        self.refresh_passes(gpu);
        self.passes_built()[slot]
    }

    /// Switches pass `id` off or on (it stays built; off, it records nothing).
    pub fn switch(&mut self, PassId(slot): PassId, on: bool) {
        self.off[slot] = !on;
    }

    /// Whether pass `id` is built and switched on.
    pub fn is_on(&self, PassId(slot): PassId) -> bool {
        self.passes_built()[slot] && !self.off[slot]
    }

    /// Which passes are built ([`passes::NAMES`](super::passes::NAMES) order).
    pub fn passes_built(&self) -> [bool; PASS_COUNT] {
        self.passes.each().map(|p| p.is_some())
    }

    /// The output format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.res.format
    }

    /// The clear colour (the background).
    pub fn clear(&self) -> wgpu::Color {
        self.res.clear
    }

    /// Clears to `color` from now on (set before the material: the subsurface kernels keep
    /// it where nothing was drawn).
    pub fn set_clear(&mut self, color: wgpu::Color) {
        self.res.clear = color;
    }
}

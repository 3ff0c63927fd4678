//! What the renderer owns and its passes read: the bind group layouts and samplers, the frame
//! uniform and its bind group, the shading models' records, the scene as uploaded (subjects,
//! props, what casts), and the textures passes share — the light's maps, written by the
//! shadow and penumbra passes and read by the scene, and the transient split targets, written
//! by the scene and read by the pass that creates them. Passes hold only their own pipelines
//! and bind groups; everything two of them touch lives here, in types of its own (no pass's).

use glam::{Mat4, Vec3};

use super::layouts::Layouts;
use super::light_maps;
use super::material_gpu::StandardKey;
use super::model_gpu::ModelTable;
use super::prepared::{per_frame, FRAMES_PREPARED};
use super::prop_gpu::PropGpu;
use super::skinned::SkinnedGpu;
use super::targets::SplitTargets;
use crate::scene::SubjectId;

/// One subject's GPU side, its bounding sphere in its own space (centre, radius) and where
/// it was last placed (what `prepare` fits the shadow map to when it is not posed).
pub struct Subject {
    pub gpu: SkinnedGpu,
    pub bound: (Vec3, f32),
    pub world: Mat4,
}

impl Subject {
    pub fn new(gpu: SkinnedGpu, bound: (Vec3, f32)) -> Self {
        Self {
            gpu,
            bound,
            world: Mat4::IDENTITY,
        }
    }

    /// Its bounding sphere in the world where it was last placed, grown by `margin` for
    /// what a pose may reach beyond the bind pose.
    pub fn world_sphere(&self, margin: f32) -> (Vec3, f32) {
        let (c, r) = self.bound;
        let w = self.world;
        let scale = w
            .x_axis
            .truncate()
            .length()
            .max(w.y_axis.truncate().length())
            .max(w.z_axis.truncate().length());
        (w.transform_point3(c), r * scale * margin)
    }
}

/// The subjects uploaded, each under the scene's id for it: the character
/// ([`SubjectId::CHARACTER`], loaded first), then others shown instead of it (the showroom's
/// scanned head). A frame's packet names the one it draws; choosing another creates nothing
/// and changes nothing here.
#[derive(Default)]
pub struct Subjects {
    slots: Vec<(SubjectId, Subject)>,
}

impl Subjects {
    /// Puts `subject` first as the character (replacing the one before it).
    pub fn set_character(&mut self, subject: Subject) {
        match self.slots.first_mut() {
            Some(slot) => *slot = (SubjectId::CHARACTER, subject),
            None => self.slots.push((SubjectId::CHARACTER, subject)),
        }
    }

    /// Keeps `subject` under `id` (replacing one the id named before).
    pub fn add(&mut self, id: SubjectId, subject: Subject) {
        match self.slots.iter_mut().find(|(i, _)| *i == id) {
            Some(slot) => slot.1 = subject,
            None => self.slots.push((id, subject)),
        }
    }

    /// Where the subject the scene calls `id` is kept.
    pub fn slot(&self, id: SubjectId) -> Option<usize> {
        self.slots.iter().position(|(i, _)| *i == id)
    }

    pub fn get(&self, slot: usize) -> Option<&Subject> {
        self.slots.get(slot).map(|(_, s)| s)
    }

    pub fn get_mut(&mut self, slot: usize) -> Option<&mut Subject> {
        self.slots.get_mut(slot).map(|(_, s)| s)
    }

    pub fn iter(&self) -> impl Iterator<Item = &Subject> {
        self.slots.iter().map(|(_, s)| s)
    }
}

/// Everything the renderer's passes share (see the module docs).
pub struct Resources {
    pub layouts: Layouts,
    /// Trilinear and repeating: every mesh texture's.
    pub sampler: wgpu::Sampler,
    /// The frame uniform, one per prepared frame's copy.
    pub frame_buffers: [wgpu::Buffer; FRAMES_PREPARED],
    /// Group 0 (one per copy): the frame uniform, the shadow map, its comparison sampler, the
    /// penumbra map.
    pub frame_groups: [wgpu::BindGroup; FRAMES_PREPARED],
    /// One record per shading model the scene can reach.
    pub models: ModelTable,
    pub subjects: Subjects,
    /// The standard materials' pipelines the subjects loaded need.
    pub standard: Vec<StandardKey>,
    /// The prop kinds uploaded, one record each.
    pub props: Vec<PropGpu>,
    /// The shadow map and the penumbra grid, once something casts.
    pub light_maps: Option<light_maps::LightMaps>,
    /// A measurement scene's shadow-only occluder (world-space triangles).
    pub occluder: Option<light_maps::Occluder>,
    /// The sphere the light's frustum is fitted to; `None`: the drawn subject's.
    pub shadow_fit: Option<(Vec3, f32)>,
    /// Whether the drawn subject casts into the shadow map (measurement media do not).
    pub subject_casts: bool,
    /// The split targets at the frame's size, where a built pass creates them (the frame
    /// graph's transient `Target::Split`, made by `Renderer::resize`).
    pub split: Option<SplitTargets>,
    /// What group 0 binds where there are no light maps, and its comparison sampler.
    pub light_defaults: light_maps::Defaults,
    pub format: wgpu::TextureFormat,
    pub clear: wgpu::Color,
}

impl Resources {
    /// Rebinds group 0 to the current light maps (placeholders where there are none).
    pub fn rebind_frame_group(&mut self, device: &wgpu::Device) {
        self.frame_groups = per_frame(|k| {
            light_maps::frame_group(
                device,
                &self.layouts,
                &self.frame_buffers[k],
                self.light_maps.as_ref(),
                &self.light_defaults,
            )
        });
    }
}

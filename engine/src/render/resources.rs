//! What the renderer owns and its passes read: the bind group layouts and samplers, the frame
//! uniform and its bind group, the shading models' records, the scene as uploaded (subjects,
//! props, what casts), and the textures passes share — the light's maps, written by the
//! shadow and penumbra passes and read by the scene, and the subsurface targets, written by
//! the scene and read by the subsurface pass. Passes hold only their own pipelines and bind
//! groups; everything two of them touch lives here.

use glam::{Mat4, Vec3};

use super::layouts::Layouts;
use super::light_maps;
use super::model_gpu::ModelTable;
use super::passes::blobs::Casters;
use super::passes::subsurface::SplitTargets;
use super::prop_gpu::PropGpu;
use super::skinned::SkinnedGpu;

/// One subject's GPU side and its bounding sphere in its own space (centre, radius).
pub struct Subject {
    pub gpu: SkinnedGpu,
    pub bound: (Vec3, f32),
}

/// The subjects uploaded: slot 0 the character, then others shown instead of it (the
/// showroom's scanned head). One is drawn at a time; choosing another creates nothing.
#[derive(Default)]
pub struct Subjects {
    slots: Vec<Subject>,
    active: usize,
    /// Where the active subject was last placed.
    pub world: Mat4,
}

impl Subjects {
    /// Puts `subject` in slot 0 (replacing the character before it) and draws it.
    pub fn set_character(&mut self, subject: Subject) {
        match self.slots.first_mut() {
            Some(slot) => *slot = subject,
            None => self.slots.push(subject),
        }
        self.active = 0;
    }

    /// Adds a subject beside the character; returns its slot.
    pub fn add(&mut self, subject: Subject) -> usize {
        self.slots.push(subject);
        self.slots.len() - 1
    }

    /// Draws the subject in `slot` from now on (an unknown slot leaves the one drawn).
    pub fn select(&mut self, slot: usize) {
        if slot < self.slots.len() {
            self.active = slot;
        }
    }

    /// The slot drawn now.
    pub fn active_slot(&self) -> usize {
        self.active
    }

    /// The subject drawn now, if any is loaded.
    pub fn active(&self) -> Option<&Subject> {
        self.slots.get(self.active)
    }

    pub fn active_mut(&mut self) -> Option<&mut Subject> {
        self.slots.get_mut(self.active)
    }

    pub fn iter(&self) -> impl Iterator<Item = &Subject> {
        self.slots.iter()
    }

    /// The box (world) of the active subject as last posed: every vertex lies inside.
    pub fn posed_box(&self) -> Option<(Vec3, Vec3)> {
        self.active()?.gpu.posed
    }

    /// The active subject's bounding sphere in the world where it was last placed, grown by
    /// `margin` for what a pose may reach beyond the bind pose.
    pub fn world_sphere(&self, margin: f32) -> Option<(Vec3, f32)> {
        let (c, r) = self.active()?.bound;
        let w = self.world;
        let scale = w
            .x_axis
            .truncate()
            .length()
            .max(w.y_axis.truncate().length())
            .max(w.z_axis.truncate().length());
        Some((w.transform_point3(c), r * scale * margin))
    }
}

/// Everything the renderer's passes share (see the module docs).
pub struct Resources {
    pub layouts: Layouts,
    /// Trilinear and repeating: every mesh texture's.
    pub sampler: wgpu::Sampler,
    pub frame_buffer: wgpu::Buffer,
    /// Group 0: the frame uniform, the shadow map, its comparison sampler, the penumbra map.
    pub frame_group: wgpu::BindGroup,
    /// One record per shading model the scene can reach.
    pub models: ModelTable,
    pub subjects: Subjects,
    /// The standard materials' pipelines the subjects loaded need.
    pub standard: Vec<super::passes::character::StandardKey>,
    /// The prop kinds uploaded, one record each.
    pub props: Vec<PropGpu>,
    /// What casts a blob shadow (recorded at load).
    pub casters: Casters,
    /// The shadow map and the penumbra grid, once something casts.
    pub light_maps: Option<light_maps::LightMaps>,
    /// A measurement scene's shadow-only occluder (world-space triangles).
    pub occluder: Option<light_maps::Occluder>,
    /// The sphere the light's frustum is fitted to; `None`: the drawn subject's.
    pub shadow_fit: Option<(Vec3, f32)>,
    /// Whether the drawn subject casts into the shadow map (measurement media do not).
    pub subject_casts: bool,
    /// The subsurface pass's targets at the frame's size, where the scene can reach a
    /// screen-space model (made by `Renderer::resize`).
    pub split: Option<SplitTargets>,
    /// What group 0 binds where there are no light maps, and its comparison sampler.
    pub light_defaults: light_maps::Defaults,
    pub format: wgpu::TextureFormat,
    pub clear: wgpu::Color,
}

impl Resources {
    /// Rebinds group 0 to the current light maps (placeholders where there are none).
    pub fn rebind_frame_group(&mut self, device: &wgpu::Device) {
        self.frame_group = light_maps::frame_group(
            device,
            &self.layouts,
            &self.frame_buffer,
            self.light_maps.as_ref(),
            &self.light_defaults,
        );
    }
}

//! Blob (contact) shadows under the character and the props that stand on the ground
//! (`shaders/shadow.wgsl`): one instanced draw of ground quads, each a soft rounded footprint
//! computed in the fragment shader, multiplied into the ground's colour. Drawn after the floor
//! and before everything else, depth-tested against the floor (lifted [`LIFT`] above it),
//! never writing depth, so whatever stands on the ground covers its own shadow; alpha — the
//! subsurface pass's marker — and the spread target are write-masked off.
//!
//! The pass exists only in a renderer that asked for it (`Renderer::enable`) and has a caster
//! loaded (the character, or a prop of a kind that casts); the
//! split variant only where the scene can reach a screen-space model. Per frame the blobs are
//! staged into buffers reserved at load and uploaded into the frame's copy of the instance
//! buffer only when that copy holds others.

use crate::render::pipelines::{pipeline_layout, wgsl_module};
use glam::{Mat4, Vec3};

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::pipelines::PipelineDevice;
use crate::render::prepared::{per_frame, Drawn, PassFrame, PreparedFrame, FRAMES_PREPARED};
use crate::render::prop_gpu::{Footprint, PropGpu};
use crate::render::resources::Resources;
use crate::render::targets::{depth_state, multisample, scene_targets, MSAA_SAMPLES};
use crate::scene::{CharacterBound, FramePacket, PropInstance, PropKind, CHARACTER};
use crate::shader::{compose, ShaderDefs};

/// Height of the ground the track stands on (m).
pub const GROUND_Y: f32 = 0.0;
/// How far the blobs float above the ground, against z-fighting (m).
pub const LIFT: f32 = 0.02;
/// Height above the ground at which a caster's blob has faded out (m).
pub const FADE_HEIGHT: f32 = 1.6;
/// Darkness at a blob's centre: the character's, a prop's.
pub const CHARACTER_DARKNESS: f32 = 0.6;
pub const PROP_DARKNESS: f32 = 0.5;
/// Blobs one frame can draw (the character's included).
pub const MAX_BLOBS: usize = 256;

/// Whether props of `kind` cast a blob (the floor and the walls do not).
pub fn casts(kind: PropKind) -> bool {
    matches!(kind, PropKind::Table | PropKind::Chair | PropKind::Obstacle)
}

/// One blob as the shader reads it (see `BlobIn` in `shadow.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Blob {
    pub centre: [f32; 4],
    pub axes: [f32; 4],
    pub shape: [f32; 4],
}

/// A caster's fade with its height above the ground: (darkness factor, size factor), both 1
/// on the ground; a jumping runner's blob shrinks and lightens.
pub fn height_fade(height: f32) -> (f32, f32) {
    let k = (1.0 - height.max(0.0) / FADE_HEIGHT).clamp(0.0, 1.0);
    (k, 0.5 + 0.5 * k)
}

impl Blob {
    /// The character's blob for its world matrix (feet at the origin of the model): the
    /// bound is of a character at the runner's height, whatever scale fitted its file to it.
    pub fn character(bound: &CharacterBound, world: Mat4) -> Self {
        let feet = world.w_axis.truncate();
        let (dark, size) = height_fade(feet.y - GROUND_Y);
        let r = bound.radius * size;
        Self {
            centre: [feet.x, GROUND_Y + LIFT, feet.z, CHARACTER_DARKNESS * dark],
            axes: [1.0, 0.0, 0.0, 0.0],
            // Half dark at the body's radius, gone a soft width (0.2 r) beyond it.
            shape: [r, r * 0.6, 0.0, 0.0],
        }
    }

    /// A prop's blob: its model-space `footprint` placed by `transform`.
    pub fn prop(footprint: &Footprint, transform: Mat4) -> Self {
        let base = transform.transform_point3(Vec3::new(
            footprint.centre[0],
            footprint.min_y,
            footprint.centre[1],
        ));
        let x = transform.x_axis.truncate();
        let z = transform.z_axis.truncate();
        let axis = glam::Vec2::new(x.x, x.z).normalize_or(glam::Vec2::X);
        let half = [
            footprint.half[0] * x.length(),
            footprint.half[1] * z.length(),
        ];
        let (dark, size) = height_fade(base.y - GROUND_Y);
        let soft = 0.12 + 0.15 * half[0].min(half[1]);
        Self {
            centre: [base.x, GROUND_Y + LIFT, base.z, PROP_DARKNESS * dark],
            axes: [axis.x, axis.y, half[0] * size, half[1] * size],
            shape: [0.04, soft, 0.0, 0.0],
        }
    }
}

/// The footprint of the loaded props of `kind`, if that kind casts.
fn footprint(props: &[PropGpu], kind: PropKind) -> Option<&Footprint> {
    let prop = props.iter().find(|p| p.kind == kind && casts(kind))?;
    prop.footprint.as_ref()
}

/// The composed WGSL of the blob shader (`split`: the subsurface frame's two targets).
pub fn shader_source(split: bool) -> String {
    let defs = if split {
        ShaderDefs::new().flag("SCREEN_SPACE")
    } else {
        ShaderDefs::new()
    };
    compose("shadow", &defs).expect("the blob shader composes")
}

/// The GPU side: pipelines, the reserved instance buffer and the staged blobs.
pub struct BlobsPass {
    pipeline: wgpu::RenderPipeline,
    /// For frames with the subsurface pass.
    split: Option<wgpu::RenderPipeline>,
    /// One per prepared frame's copy, with what it holds.
    instances: [wgpu::Buffer; FRAMES_PREPARED],
    uploaded: [Vec<Blob>; FRAMES_PREPARED],
    /// Slot 0: the character's blob; then the props'. Capacity [`MAX_BLOBS`], never grown.
    staged: Vec<Blob>,
}

impl BlobsPass {
    fn new(ctx: &BuildCtx) -> Self {
        let device = ctx.device;
        let layout = pipeline_layout(device, "blob shadow", &[Some(&ctx.layouts.frame)]);
        let multiply = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::Src,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent::REPLACE,
        };
        // Colour only: alpha is the subsurface marker (and the output's coverage).
        let shade = wgpu::ColorTargetState {
            format: ctx.format,
            blend: Some(multiply),
            write_mask: wgpu::ColorWrites::COLOR,
        };
        let untouched = wgpu::ColorTargetState {
            format: ctx.format,
            blend: None,
            write_mask: wgpu::ColorWrites::empty(),
        };
        let build = |split: bool| {
            let module = wgsl_module(device, "blob shadow", shader_source(split));
            let targets = scene_targets(ctx.format, split, shade.clone(), untouched.clone());
            pipeline(ctx.pipelines(), &layout, &module, &targets)
        };
        let instances = per_frame(|_| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("blob shadows"),
                size: (MAX_BLOBS * std::mem::size_of::<Blob>()) as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let mut staged = Vec::with_capacity(MAX_BLOBS);
        staged.push(Blob::default());
        Self {
            pipeline: build(false),
            split: ctx.split().then(|| build(true)),
            instances,
            staged,
            uploaded: per_frame(|_| Vec::with_capacity(MAX_BLOBS)),
        }
    }

    /// Stages the blobs of `instances` whose kind casts (of the props loaded, `props`).
    fn stage_props(&mut self, props: &[PropGpu], instances: &[PropInstance]) {
        self.staged.truncate(1);
        for i in instances {
            if self.staged.len() == MAX_BLOBS {
                break;
            }
            if let Some(f) = footprint(props, i.kind) {
                self.staged.push(Blob::prop(f, i.transform));
            }
        }
    }

    /// Uploads the staged blobs into `copy` if it holds others; returns the uploads (0 or
    /// 1). A run moves the runner every frame but the props only now and then: then only the
    /// character's slot is written. No allocation: the buffers were reserved at load.
    fn upload(&mut self, queue: &wgpu::Queue, copy: usize) -> u32 {
        let uploaded = &mut self.uploaded[copy];
        if self.staged == *uploaded {
            return 0;
        }
        let props_same = uploaded.len() == self.staged.len() && uploaded[1..] == self.staged[1..];
        let upload = if props_same { 1 } else { self.staged.len() };
        uploaded.clear();
        uploaded.extend_from_slice(&self.staged);
        queue.write_buffer(
            &self.instances[copy],
            0,
            bytemuck::cast_slice(&self.staged[..upload]),
        );
        1
    }

    /// The blobs a frame draws: the props' and, when the subject is drawn, the character's.
    fn range(frame: &PreparedFrame) -> std::ops::Range<u32> {
        let first = if frame.subject.is_some() { 0 } else { 1 };
        let staged = frame.pass(<Self as super::Slot>::SLOT).steps;
        first..staged.max(first)
    }
}

/// The blobs, multiplied into the scene's floor.
impl Declared for BlobsPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[],
        writes: &[Target::Scene],
    };
}

impl Pass for BlobsPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        let something_casts = ctx.character || ctx.prop_kinds().any(casts);
        (ctx.wanted::<Self>() && something_casts).then(|| Self::new(ctx))
    }

    /// Stages the subject's blob where it is placed and the props' where the frame placed
    /// them; runs when switched on in a frame with props (the blobs lie on the floor);
    /// `steps`: the blobs staged.
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame {
        if let Some(subject) = &frame.subject {
            self.staged[0] = Blob::character(&CHARACTER, subject.world);
        }
        self.stage_props(&res.props, packet.props);
        frame.uploads += self.upload(queue, frame.copy);
        let staged = self.staged.len() as u32;
        let first = u32::from(frame.subject.is_none());
        PassFrame {
            runs: frame.draw.props && staged > first,
            steps: staged,
        }
    }

    /// The blobs, blended over the floor and depth-tested against everything.
    fn draw(
        &self,
        frame: &PreparedFrame,
        _res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let pipeline = match (frame.split, &self.split) {
            (Some(_), Some(split)) => split,
            (Some(_), None) => return Drawn::default(),
            (None, _) => &self.pipeline,
        };
        pass.set_pipeline(pipeline);
        pass.set_vertex_buffer(0, self.instances[frame.copy].slice(..));
        pass.draw(0..6, Self::range(frame));
        Drawn::calls(1)
    }
}

fn pipeline(
    dev: PipelineDevice,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let attributes = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4];
    dev.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("blob shadow"),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Blob>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                // A rotated quad may face either way.
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(depth_state(false, wgpu::CompareFunction::Less)),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_variants_parse_and_validate() {
        for split in [false, true] {
            let src = shader_source(split);
            let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{e}"));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{e:?}"));
        }
    }

    #[test]
    fn a_jumping_casters_blob_is_smaller_and_lighter() {
        let ground = Blob::character(&CHARACTER, Mat4::from_translation(Vec3::new(1.0, 0.0, 2.0)));
        let air = Blob::character(&CHARACTER, Mat4::from_translation(Vec3::new(1.0, 0.8, 2.0)));
        assert_eq!(ground.centre[..3], [1.0, GROUND_Y + LIFT, 2.0]);
        assert_eq!(air.centre[..3], ground.centre[..3]);
        assert!(air.centre[3] < ground.centre[3] && air.centre[3] > 0.0);
        assert!(air.shape[0] < ground.shape[0] && air.shape[1] < ground.shape[1]);
        assert_eq!(height_fade(10.0).0, 0.0);
    }

    #[test]
    fn a_props_blob_follows_its_transform() {
        let f = Footprint {
            centre: [0.0, 0.0],
            half: [0.5, 0.5],
            min_y: 0.0,
        };
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(0.9, 0.55, 0.6),
            glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            Vec3::new(-1.3, 0.0, 10.0),
        );
        let b = Blob::prop(&f, m);
        assert!((b.centre[0] + 1.3).abs() < 1e-5 && (b.centre[2] - 10.0).abs() < 1e-5);
        assert!((b.axes[2] - 0.45).abs() < 1e-5 && (b.axes[3] - 0.3).abs() < 1e-5);
        // The local x axis turned a quarter about +y: world (0, 0, −1) in (x, z).
        assert!(b.axes[0].abs() < 1e-5 && (b.axes[1] + 1.0).abs() < 1e-5);
        assert!(casts(PropKind::Obstacle) && !casts(PropKind::FloorTile));
    }
}

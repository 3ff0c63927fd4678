//! The props (floor tiles, walls, furniture, obstacles), instanced with the plain default-lit
//! shader (`shaders/prop.wgsl`): each frame the placements a view can see are uploaded per
//! kind into the frame's copy of its instance buffer (a copy that holds them already is not
//! written again) and drawn after
//! the subject — what stands on the floor first, then the floor, most of which lies behind
//! them, so its hidden texels fail the early depth test. Built when props are loaded; the
//! variant for frames with the subsurface pass (two linear targets) only where the scene can
//! reach a screen-space model.

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::camera::Frustum;
use crate::render::layouts::Layouts;
use crate::render::mesh::{instance_layout, vertex_layout};
use crate::render::pipelines::{pipeline, pipeline_layout, targets, wgsl_module, PipelineDevice};
use crate::render::prepared::{per_frame, Drawn, PassFrame, PreparedFrame, FRAMES_PREPARED};
use crate::render::prop_gpu::MAX_INSTANCES;
use crate::render::resources::Resources;
use crate::scene::{FramePacket, PropKind};
use crate::shader::{compose, ShaderDefs};

/// One kind's instances in one prepared frame's copy.
struct Instances {
    buffer: wgpu::Buffer,
    /// What the buffer holds now (capacity reserved once).
    uploaded: Vec<[[f32; 4]; 4]>,
}

pub struct PropsPass {
    pipeline: wgpu::RenderPipeline,
    /// For frames with the subsurface pass.
    split: Option<wgpu::RenderPipeline>,
    /// Per prepared frame's copy, one per kind in [`PropKind::ALL`] order.
    instances: [Vec<Instances>; FRAMES_PREPARED],
    /// Scratch for one kind's visible matrices.
    scratch: Vec<[[f32; 4]; 4]>,
}

/// The props' pipeline (`split`: the subsurface frame's two linear targets).
fn prop_pipeline(
    dev: PipelineDevice,
    layouts: &Layouts,
    format: wgpu::TextureFormat,
    split: bool,
) -> wgpu::RenderPipeline {
    let device = dev.device;
    let layout = pipeline_layout(
        device,
        "prop",
        &[Some(&layouts.frame), Some(&layouts.material)],
    );
    let defs = ShaderDefs::new().flag("INSTANCED");
    let defs = if split {
        defs.flag("SCREEN_SPACE")
    } else {
        defs
    };
    let source = compose("prop", &defs).expect("built-in shaders compose");
    let module = wgsl_module(device, "prop", source);
    pipeline(
        dev,
        &layout,
        &module,
        &targets(format, split),
        &[vertex_layout(), instance_layout()],
        "prop",
    )
}

/// The props, lit and shadowed, into the scene.
impl Declared for PropsPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[Target::ShadowMap],
        writes: &[Target::Scene],
    };
}

impl Pass for PropsPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.prop_kinds().next()?;
        let (device, layouts) = (ctx.device, ctx.layouts);
        let instances = per_frame(|_| {
            PropKind::ALL
                .iter()
                .map(|kind| Instances {
                    buffer: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(kind.file()),
                        size: MAX_INSTANCES as u64 * 64,
                        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    }),
                    uploaded: Vec::with_capacity(MAX_INSTANCES as usize),
                })
                .collect()
        });
        Some(Self {
            pipeline: prop_pipeline(ctx.pipelines(), layouts, ctx.format, false),
            split: ctx
                .split()
                .then(|| prop_pipeline(ctx.pipelines(), layouts, ctx.format, true)),
            instances,
            scratch: Vec::with_capacity(MAX_INSTANCES as usize),
        })
    }

    /// Uploads each kind's placements inside the view into the frame's copy; runs when the
    /// frame draws props and one is visible.
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame {
        let frustum = Frustum::new(frame.view.view_proj);
        for (k, kind) in PropKind::ALL.iter().enumerate() {
            self.scratch.clear();
            if let Some(prop) = res.props.iter().find(|p| p.kind == *kind) {
                self.scratch.extend(
                    packet
                        .props
                        .iter()
                        .filter(|i| i.kind == *kind && prop.visible(&frustum, &i.transform))
                        .take(MAX_INSTANCES as usize)
                        .map(|i| i.transform.to_cols_array_2d()),
                );
            }
            frame.visible_props[k] = self.scratch.len() as u32;
            let slot = &mut self.instances[frame.copy][k];
            // Written every frame it draws (a check against the copy, two frames old, would
            // make the writes per frame follow how often the view's props change).
            slot.uploaded.clear();
            slot.uploaded.extend_from_slice(&self.scratch);
            if !self.scratch.is_empty() {
                queue.write_buffer(&slot.buffer, 0, bytemuck::cast_slice(&self.scratch));
                frame.uploads += 1;
            }
        }
        let visible = frame.visible_props.iter().any(|&n| n > 0);
        PassFrame {
            runs: frame.draw.props && visible,
            steps: 0,
        }
    }

    fn draw(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let pipeline = match (frame.split, &self.split) {
            (Some(_), Some(split)) => split,
            (Some(_), None) => return Drawn::default(),
            (None, _) => &self.pipeline,
        };
        pass.set_pipeline(pipeline);
        let mut drawn = Drawn::default();
        let is_floor = |k: &PropKind| *k == PropKind::FloorTile;
        let standing = PropKind::ALL.iter().filter(|k| !is_floor(k));
        for kind in standing.chain(PropKind::ALL.iter().filter(|k| is_floor(k))) {
            let k = PropKind::ALL.iter().position(|x| x == kind).unwrap_or(0);
            let count = frame.visible_props[k];
            let Some(prop) = res.props.iter().find(|p| p.kind == *kind) else {
                continue;
            };
            if count == 0 {
                continue;
            }
            let buffer = &self.instances[frame.copy][k].buffer;
            pass.set_vertex_buffer(1, buffer.slice(..count as u64 * 64));
            drawn.draw_calls += prop.draw(pass, count);
            drawn.triangles += prop.triangles * count;
        }
        drawn
    }
}

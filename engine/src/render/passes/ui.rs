//! The UI's GPU side: one pipeline (premultiplied alpha blending, no depth write, depth test
//! Always), the skin atlas texture, fixed-capacity vertex buffers created once (one per
//! prepared frame's copy) and one draw call, last in the frame's last pass. The frame's
//! packet hands over the UI's vertices, written into the frame's copy; the screen size comes
//! from the frame.
//! Built where the renderer draws a UI (the game).

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::pipelines::PipelineDevice;
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{per_frame, Drawn, PassFrame, PreparedFrame, FRAMES_PREPARED};
use crate::render::resources::Resources;
use crate::render::targets::{depth_state, multisample, MSAA_SAMPLES};
use crate::scene::FramePacket;
use crate::shader::uniforms::UiUniform;
use crate::shader::{compose, ShaderDefs};
use crate::ui::{UiVertex, MAX_VERTICES};

/// The composed UI shader.
pub fn ui_shader_source() -> String {
    compose("ui", &ShaderDefs::new()).expect("built-in shaders compose (checked by tests)")
}

/// Vertex layout of [`UiVertex`]: position (pixels), uv, premultiplied colour (unorm8×4).
pub fn ui_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRS: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2, 2 => Unorm8x4];
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<UiVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRS,
    }
}

/// One prepared frame's copy of what the UI's draw reads.
struct UiCopy {
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    vertices: wgpu::Buffer,
    /// The screen size it holds.
    screen: [u32; 2],
}

pub struct UiPass {
    pipeline: wgpu::RenderPipeline,
    copies: [UiCopy; FRAMES_PREPARED],
    srgb: bool,
}

impl UiPass {
    /// Vertex capacity of the GPU buffer (matches the UI's own limit).
    pub const CAPACITY: usize = MAX_VERTICES;

    /// Creates every UI resource (once, at load), with the embedded skin atlas
    /// ([`crate::ui::atlas_rgba`]: RGBA8, straight alpha).
    fn new(dev: PipelineDevice, queue: &wgpu::Queue, format: wgpu::TextureFormat) -> Self {
        let device = dev.device;
        let (atlas_rgba, w, h) = crate::ui::atlas_rgba();
        let view = crate::render::texture::upload_single(
            device,
            queue,
            &atlas_rgba,
            (w, h),
            wgpu::TextureFormat::Rgba8Unorm,
            "ui atlas",
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("ui"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ui"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(16),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let copies = per_frame(|_| {
            let params = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ui params"),
                size: std::mem::size_of::<UiUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let vertices = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ui vertices"),
                size: (Self::CAPACITY * std::mem::size_of::<UiVertex>()) as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ui"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                ],
            });
            UiCopy {
                bind_group,
                params,
                vertices,
                screen: [0, 0],
            }
        });
        let pipeline_layout = pipeline_layout(device, "ui", &[Some(&layout)]);
        let module = wgsl_module(device, "ui", ui_shader_source());
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("ui"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(ui_vertex_layout())],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(depth_state(false, wgpu::CompareFunction::Always)),
            multisample: multisample(MSAA_SAMPLES),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: dev.cache,
        });
        Self {
            pipeline,
            copies,
            srgb: format.is_srgb(),
        }
    }

    /// Writes the surface size (pixels) the vertices are in into `copy`, unless it holds it
    /// (returns whether it wrote).
    fn set_screen(
        &mut self,
        queue: &wgpu::Queue,
        copy: usize,
        (width, height): (u32, u32),
    ) -> bool {
        let size = [width.max(1), height.max(1)];
        let c = &mut self.copies[copy];
        if size == c.screen {
            return false;
        }
        c.screen = size;
        let params = UiUniform {
            screen: [
                size[0] as f32,
                size[1] as f32,
                if self.srgb { 1.0 } else { 0.0 },
                0.0,
            ],
        };
        queue.write_buffer(&c.params, 0, bytemuck::bytes_of(&params));
        true
    }

    /// The vertices drawn of `vertices`: at most [`UiPass::CAPACITY`], whole triangles.
    fn count(vertices: &[UiVertex]) -> usize {
        let n = vertices.len().min(Self::CAPACITY);
        n - n % 3
    }

    /// Writes `vertices` into `copy`. Every frame that draws the UI writes its copy: a
    /// version check would write each change twice (once per copy) and make the writes per
    /// frame follow how often the UI changes.
    fn upload(&self, queue: &wgpu::Queue, copy: usize, vertices: &[UiVertex]) -> bool {
        let n = Self::count(vertices);
        if n > 0 {
            let c = &self.copies[copy];
            queue.write_buffer(&c.vertices, 0, bytemuck::cast_slice(&vertices[..n]));
        }
        n > 0
    }
}

/// The UI, over everything, into the output.
impl Declared for UiPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[],
        writes: &[Target::Output],
    };
}

impl Pass for UiPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.wanted::<Self>()
            .then(|| Self::new(ctx.pipelines(), ctx.queue, ctx.format))
    }

    /// Writes the frame's size and the UI's vertices into the frame's copy where it holds
    /// others; runs when there is anything to draw (`steps`: the vertices drawn).
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        _res: &Resources,
    ) -> PassFrame {
        if !frame.draw.ui {
            return PassFrame::default();
        }
        let copy = frame.copy;
        frame.uploads += u32::from(self.set_screen(queue, copy, frame.size));
        frame.uploads += u32::from(self.upload(queue, copy, packet.ui));
        let count = Self::count(packet.ui) as u32;
        PassFrame {
            runs: count > 0,
            steps: count,
        }
    }

    /// The whole UI with one draw call.
    fn draw(
        &self,
        frame: &PreparedFrame,
        _res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        let count = frame.pass(<Self as super::Slot>::SLOT).steps;
        let c = &self.copies[frame.copy];
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &c.bind_group, &[]);
        pass.set_vertex_buffer(
            0,
            c.vertices
                .slice(..count as u64 * std::mem::size_of::<UiVertex>() as u64),
        );
        pass.draw(0..count, 0..1);
        Drawn::calls(1)
    }
}

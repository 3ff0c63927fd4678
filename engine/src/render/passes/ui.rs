//! The UI's GPU side: one pipeline (premultiplied alpha blending, no depth write, depth test
//! Always), the skin atlas texture, a fixed-capacity vertex buffer created once and one draw
//! call, last in the frame's last pass. The frame's packet hands over the UI's vertices when
//! they changed (`crate::ui::Ui::needs_upload`); the screen size comes from the frame. Built
//! where the renderer draws a UI (the game).

use super::{BuildCtx, Pass, Stage};
use crate::render::pipelines::PipelineDevice;
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{Drawn, PassFrame, PreparedFrame};
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

pub struct UiPass {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    vertices: wgpu::Buffer,
    count: u32,
    screen: [u32; 2],
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
        let mut r = Self {
            pipeline,
            bind_group,
            params,
            vertices,
            count: 0,
            screen: [0, 0],
            srgb: format.is_srgb(),
        };
        r.set_screen(queue, (1, 1));
        r
    }

    /// Sets the surface size (pixels) the vertices are in; writes only when it changed
    /// (returns whether it wrote).
    fn set_screen(&mut self, queue: &wgpu::Queue, (width, height): (u32, u32)) -> bool {
        let size = [width.max(1), height.max(1)];
        if size == self.screen {
            return false;
        }
        self.screen = size;
        let params = UiUniform {
            screen: [
                size[0] as f32,
                size[1] as f32,
                if self.srgb { 1.0 } else { 0.0 },
                0.0,
            ],
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        true
    }

    /// Uploads the UI's vertices; at most [`UiPass::CAPACITY`] are kept.
    fn upload(&mut self, queue: &wgpu::Queue, vertices: &[UiVertex]) {
        let n = vertices.len().min(Self::CAPACITY);
        let n = n - n % 3;
        if n > 0 {
            queue.write_buffer(&self.vertices, 0, bytemuck::cast_slice(&vertices[..n]));
        }
        self.count = n as u32;
    }

    /// Vertices the next draw will issue.
    pub fn vertex_count(&self) -> u32 {
        self.count
    }
}

impl Pass for UiPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        ctx.ui
            .then(|| Self::new(ctx.pipelines(), ctx.queue, ctx.format))
    }

    fn stage(&self) -> Stage {
        Stage::Last
    }

    /// Takes the frame's size and the UI's vertices when they changed; runs when there is
    /// anything to draw.
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        _res: &Resources,
    ) -> PassFrame {
        frame.uploads += u32::from(self.set_screen(queue, frame.size));
        if let Some(vertices) = packet.ui {
            self.upload(queue, vertices);
            frame.uploads += 1;
        }
        PassFrame {
            runs: frame.draw.ui && self.count > 0,
            steps: 0,
        }
    }

    /// The whole UI with one draw call.
    fn draw(
        &self,
        _frame: &PreparedFrame,
        _res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_vertex_buffer(
            0,
            self.vertices
                .slice(..self.count as u64 * std::mem::size_of::<UiVertex>() as u64),
        );
        pass.draw(0..self.count, 0..1);
        Drawn::calls(1)
    }
}

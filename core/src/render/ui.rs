//! The UI's GPU side: one pipeline (premultiplied alpha blending, no depth write, depth test
//! Always), the skin atlas texture, a fixed-capacity vertex buffer created once and one draw
//! call. It is meant to be drawn last inside the frame's single MSAA pass.
//!
//! ```text
//! // load
//! let (rgba, w, h) = dermis_core::ui::atlas_rgba();
//! let mut ui_gpu = UiRenderer::new(&device, &queue, format, MSAA_SAMPLES, &rgba, w, h);
//! // every frame, after ui.end()
//! ui_gpu.resize(&queue, width, height);           // writes only when the size changed
//! if ui.needs_upload() { ui_gpu.upload(&queue, ui.vertices()); ui.mark_uploaded(); }
//! // inside the pass, after everything else
//! ui_gpu.draw(&mut pass);
//! ```

use super::targets::{depth_state, multisample};
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

pub struct UiRenderer {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    vertices: wgpu::Buffer,
    count: u32,
    screen: [u32; 2],
    srgb: bool,
}

impl UiRenderer {
    /// Vertex capacity of the GPU buffer (matches the UI's own limit).
    pub const CAPACITY: usize = MAX_VERTICES;

    /// Creates every UI resource (once, at load). `atlas_rgba` is `w`×`h` RGBA8, straight
    /// alpha, as [`crate::ui::atlas_rgba`] returns it.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
        msaa_samples: u32,
        atlas_rgba: &[u8],
        w: u32,
        h: u32,
    ) -> Self {
        assert_eq!(atlas_rgba.len(), (w * h * 4) as usize, "UI atlas size");
        let view = super::texture::upload_single(
            device,
            queue,
            atlas_rgba,
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
            size: 16,
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
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ui"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("ui"),
            source: wgpu::ShaderSource::Wgsl(ui_shader_source().into()),
        });
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
            multisample: multisample(msaa_samples),
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
            cache: super::pipeline_cache::for_device(device).as_ref(),
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
        r.resize(queue, 1, 1);
        r
    }

    /// Sets the surface size (pixels) the vertices are in; writes only when it changed.
    pub fn resize(&mut self, queue: &wgpu::Queue, width: u32, height: u32) {
        let size = [width.max(1), height.max(1)];
        if size == self.screen {
            return;
        }
        self.screen = size;
        let data = [
            size[0] as f32,
            size[1] as f32,
            if self.srgb { 1.0 } else { 0.0 },
            0.0,
        ];
        queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&data));
    }

    /// Uploads the UI's vertices (call only when [`crate::ui::Ui::needs_upload`]); at most
    /// [`UiRenderer::CAPACITY`] are kept.
    pub fn upload(&mut self, queue: &wgpu::Queue, vertices: &[UiVertex]) {
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

    /// Draws the whole UI with one draw call; returns the number of draw calls (0 or 1).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) -> u32 {
        if self.count == 0 {
            return 0;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_vertex_buffer(
            0,
            self.vertices
                .slice(..self.count as u64 * std::mem::size_of::<UiVertex>() as u64),
        );
        pass.draw(0..self.count, 0..1);
        1
    }
}

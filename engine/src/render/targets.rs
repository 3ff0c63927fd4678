//! Per-size render targets: a 4× MSAA colour buffer resolved into the output at the end of
//! the pass, and a transient depth buffer that is never stored.

pub const MSAA_SAMPLES: u32 = 4;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// How a pipeline uses the depth target: written or only read, compared with `compare`.
pub fn depth_state(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// `count` samples per pixel (the colour target's), no alpha to coverage.
pub fn multisample(count: u32) -> wgpu::MultisampleState {
    wgpu::MultisampleState {
        count,
        ..Default::default()
    }
}

pub struct Targets {
    pub width: u32,
    pub height: u32,
    pub format: wgpu::TextureFormat,
    pub msaa: wgpu::TextureView,
    pub depth: wgpu::TextureView,
}

impl Targets {
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        width: u32,
        height: u32,
    ) -> Self {
        let (width, height) = (width.max(1), height.max(1));
        let make = |label, format, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: MSAA_SAMPLES,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        Self {
            width,
            height,
            format,
            msaa: make("msaa colour", format, usage),
            depth: make("depth", DEPTH_FORMAT, usage),
        }
    }

    /// Recreates the targets if the size or format changed; returns whether it did.
    pub fn ensure(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        width: u32,
        height: u32,
    ) -> bool {
        if self.width == width.max(1) && self.height == height.max(1) && self.format == format {
            return false;
        }
        *self = Self::new(device, format, width, height);
        true
    }
}

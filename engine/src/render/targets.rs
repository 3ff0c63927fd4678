//! Per-size render targets: a 4× MSAA colour buffer resolved into the output at the end of
//! the pass, and a transient depth buffer that is never stored ([`Targets`]); and the split
//! targets a frame with the subsurface pass draws its scene into ([`SplitTargets`], the
//! frame graph's `Target::Split`), with the colour targets a pipeline drawing the scene has
//! in either frame ([`scene_targets`]).

use super::prepared::PassCtx;

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
            target_view(device, label, (width, height), format, MSAA_SAMPLES, usage)
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

/// Format of the split targets (linear radiance; irradiance and pixel size in mm).
pub const SPLIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// How many colour targets the split scene has.
pub const SPLIT_TARGETS: usize = 3;

/// The colour targets of a pipeline drawing the scene: `output` (the output's format), or in
/// a frame with the split targets (`split`) those, the first as `output` says and the others
/// as `rest` (their format filled in).
pub fn scene_targets(
    format: wgpu::TextureFormat,
    split: bool,
    output: wgpu::ColorTargetState,
    rest: wgpu::ColorTargetState,
) -> Vec<Option<wgpu::ColorTargetState>> {
    if !split {
        return vec![Some(wgpu::ColorTargetState { format, ..output })];
    }
    let first = wgpu::ColorTargetState {
        format: SPLIT_FORMAT,
        ..output
    };
    let rest = wgpu::ColorTargetState {
        format: SPLIT_FORMAT,
        ..rest
    };
    let mut targets = vec![Some(first)];
    targets.resize(SPLIT_TARGETS, Some(rest));
    targets
}

/// The scene's three targets in a frame with the subsurface pass (`Target::Split`), for one size: radiance that
/// stays (with the skin marker), irradiance to spread (with the pixel's size), the exit
/// factor per channel.
pub struct SplitTargets {
    pub size: (u32, u32),
    pub colour_msaa: wgpu::TextureView,
    pub spread_msaa: wgpu::TextureView,
    pub exit_msaa: wgpu::TextureView,
    pub colour: wgpu::TextureView,
    pub spread: wgpu::TextureView,
    pub exit: wgpu::TextureView,
}

impl SplitTargets {
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Self {
        let make = |label, samples, usage| {
            target_view(device, label, (width, height), SPLIT_FORMAT, samples, usage)
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = attach | wgpu::TextureUsages::TEXTURE_BINDING;
        Self {
            size: (width, height),
            colour_msaa: make("subsurface colour msaa", MSAA_SAMPLES, attach),
            spread_msaa: make("subsurface spread msaa", MSAA_SAMPLES, attach),
            exit_msaa: make("subsurface exit msaa", MSAA_SAMPLES, attach),
            colour: make("subsurface colour", 1, sampled),
            spread: make("subsurface spread", 1, sampled),
            exit: make("subsurface exit", 1, sampled),
        }
    }

    /// Opens the scene's pass into these targets: all cleared, alpha −1 in the colour target
    /// telling the gather that nothing was drawn there, resolved at its end.
    pub fn scene_pass<'e>(
        &self,
        ctx: &'e mut PassCtx<'_>,
        clear: wgpu::Color,
    ) -> wgpu::RenderPass<'e> {
        let clear = wgpu::Color { a: -1.0, ..clear };
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
        let timer = ctx.timer.map(|t| t.begin_writes());
        ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene (subsurface)"),
            color_attachments: &[
                attachment(&self.colour_msaa, &self.colour),
                attachment(&self.spread_msaa, &self.spread),
                attachment(&self.exit_msaa, &self.exit),
            ],
            depth_stencil_attachment: Some(depth_attachment(ctx.targets)),
            timestamp_writes: timer,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// The frame's depth target: cleared, never stored.
pub fn depth_attachment(targets: &Targets) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view: &targets.depth,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Discard,
        }),
        stencil_ops: None,
    }
}

/// A single-level 2D render target of `format` with `samples` samples, viewed whole: what every
/// target of the frame is.
fn target_view(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

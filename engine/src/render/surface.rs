//! The window surface, written once for every shell (the desktop window, `surfaces`, the
//! Android app): format choice, configuration, resize, recovery from an outdated or lost
//! swapchain, and the MSAA colour / depth [`Targets`] that follow its size. The shells own
//! their windows and event loops; this takes a `wgpu::Surface` and sizes.

use super::targets::Targets;
use super::Gpu;

/// Outcome of acquiring / presenting one frame (mirrors `wgpu::CurrentSurfaceTexture`); the
/// lifecycle (`crate::lifecycle`) and the shells read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameStatus {
    Presented,
    Suboptimal,
    Timeout,
    Occluded,
    Outdated,
    Lost,
    Validation,
}

/// How a surface is configured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceOptions {
    pub present_mode: wgpu::PresentMode,
    /// Whether frames can be copied from (screenshots).
    pub copy_src: bool,
    /// The format to keep when the surface offers it (pipelines already built for it);
    /// otherwise the first sRGB format, otherwise the first.
    pub keep_format: Option<wgpu::TextureFormat>,
    /// Whether the helper reconfigures itself on an outdated, lost or suboptimal swapchain
    /// (the desktop); `false` leaves that to the caller (Android's lifecycle, which may
    /// recreate the surface instead).
    pub self_heal: bool,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        Self {
            present_mode: wgpu::PresentMode::AutoVsync,
            copy_src: false,
            keep_format: None,
            self_heal: true,
        }
    }
}

/// The format a surface is configured with: `keep` when offered, else the first sRGB
/// format, else the first.
pub fn choose_format(
    formats: &[wgpu::TextureFormat],
    keep: Option<wgpu::TextureFormat>,
) -> Option<wgpu::TextureFormat> {
    keep.filter(|f| formats.contains(f))
        .or_else(|| formats.iter().copied().find(|f| f.is_srgb()))
        .or_else(|| formats.first().copied())
}

/// A configured window surface and the targets of its size.
pub struct SurfaceTarget {
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub targets: Targets,
    self_heal: bool,
    /// Called right before each present (winit's `pre_present_notify`).
    pre_present: Option<Box<dyn Fn()>>,
}

impl SurfaceTarget {
    /// Configures `surface` for `gpu` at `width` × `height` (at least 1 × 1).
    pub fn new(
        gpu: &Gpu,
        surface: wgpu::Surface<'static>,
        width: u32,
        height: u32,
        options: SurfaceOptions,
    ) -> Result<Self, String> {
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = choose_format(&caps.formats, options.keep_format)
            .ok_or("the surface is not supported by the adapter")?;
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if options.copy_src {
            if !caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
                return Err("this surface cannot be copied from".into());
            }
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            width: width.max(1),
            height: height.max(1),
            present_mode: options.present_mode,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&gpu.device, &config);
        let targets = Targets::new(&gpu.device, format, config.width, config.height);
        Ok(Self {
            surface,
            config,
            targets,
            self_heal: options.self_heal,
            pre_present: None,
        })
    }

    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Calls `f` right before each present.
    pub fn on_present(&mut self, f: impl Fn() + 'static) {
        self.pre_present = Some(Box::new(f));
    }

    /// Reconfigures for a new size (a zero size is ignored: a minimised window).
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.reconfigure(gpu);
    }

    /// Configures the surface again at its current size.
    pub fn reconfigure(&mut self, gpu: &Gpu) {
        self.surface.configure(&gpu.device, &self.config);
        self.targets.ensure(
            &gpu.device,
            self.config.format,
            self.config.width,
            self.config.height,
        );
    }

    /// The next swapchain image (with the targets sized to it), or why there is none this
    /// time. A self-healing surface reconfigures itself when it is outdated or lost.
    pub fn acquire(
        &mut self,
        gpu: &Gpu,
    ) -> Result<(wgpu::SurfaceTexture, FrameStatus), FrameStatus> {
        let (frame, status) = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => (f, FrameStatus::Presented),
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => (f, FrameStatus::Suboptimal),
            wgpu::CurrentSurfaceTexture::Timeout => return Err(FrameStatus::Timeout),
            wgpu::CurrentSurfaceTexture::Occluded => return Err(FrameStatus::Occluded),
            wgpu::CurrentSurfaceTexture::Outdated => {
                return Err(self.heal(gpu, FrameStatus::Outdated))
            }
            wgpu::CurrentSurfaceTexture::Lost => return Err(self.heal(gpu, FrameStatus::Lost)),
            wgpu::CurrentSurfaceTexture::Validation => return Err(FrameStatus::Validation),
        };
        let (w, h) = (frame.texture.width(), frame.texture.height());
        self.targets.ensure(&gpu.device, self.config.format, w, h);
        Ok((frame, status))
    }

    fn heal(&mut self, gpu: &Gpu, status: FrameStatus) -> FrameStatus {
        if self.self_heal {
            self.reconfigure(gpu);
        }
        status
    }

    /// Presents `frame` (acquired with `status`); a suboptimal swapchain is then configured
    /// again when self-healing.
    pub fn present(&mut self, gpu: &Gpu, frame: wgpu::SurfaceTexture, status: FrameStatus) {
        if let Some(f) = &self.pre_present {
            f();
        }
        gpu.queue.present(frame);
        if status == FrameStatus::Suboptimal {
            self.heal(gpu, status);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::choose_format;
    use wgpu::TextureFormat as F;

    #[test]
    fn the_kept_format_then_srgb_then_the_first() {
        let offered = [F::Bgra8Unorm, F::Rgba8UnormSrgb, F::Bgra8UnormSrgb];
        assert_eq!(
            choose_format(&offered, Some(F::Bgra8UnormSrgb)),
            Some(F::Bgra8UnormSrgb)
        );
        assert_eq!(
            choose_format(&offered, Some(F::Rgba16Float)),
            Some(F::Rgba8UnormSrgb)
        );
        assert_eq!(choose_format(&offered, None), Some(F::Rgba8UnormSrgb));
        assert_eq!(choose_format(&[F::Bgra8Unorm], None), Some(F::Bgra8Unorm));
        assert_eq!(choose_format(&[], None), None);
    }
}

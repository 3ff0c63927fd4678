//! GPU side of the Android app: wgpu instance/adapter/device (created once, on the first
//! window, kept across pause/resume), the window surface (created on InitWindow, dropped on
//! TermWindow), and the frame. For now a frame clears the screen with a slowly changing
//! colour; the real renderer replaces [`Renderer::draw`].

use crate::lifecycle::FrameStatus;
use android_activity::ndk::native_window::NativeWindow;
use std::time::Instant;
use wgpu::rwh::{
    AndroidDisplayHandle, AndroidNdkWindowHandle, DisplayHandle, HandleError, HasDisplayHandle,
    HasWindowHandle, RawDisplayHandle, RawWindowHandle, WindowHandle,
};

/// A native window that wgpu can own: the `NativeWindow` holds a reference
/// (`ANativeWindow_acquire`), so the pointer stays valid as long as the surface lives.
struct AndroidWindow(NativeWindow);

impl HasWindowHandle for AndroidWindow {
    fn window_handle(&self) -> Result<WindowHandle<'_>, HandleError> {
        let raw = RawWindowHandle::AndroidNdk(AndroidNdkWindowHandle::new(self.0.ptr().cast()));
        // SAFETY: the pointer is a live ANativeWindow referenced by `self.0` for `'_`.
        Ok(unsafe { WindowHandle::borrow_raw(raw) })
    }
}

impl HasDisplayHandle for AndroidWindow {
    fn display_handle(&self) -> Result<DisplayHandle<'_>, HandleError> {
        let raw = RawDisplayHandle::Android(AndroidDisplayHandle::new());
        // SAFETY: the Android display handle carries no data.
        Ok(unsafe { DisplayHandle::borrow_raw(raw) })
    }
}

struct Gpu {
    instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
}

struct Target {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
}

pub struct Renderer {
    gpu: Option<Gpu>,
    target: Option<Target>,
    start: Instant,
    frames: u64,
}

impl Default for Renderer {
    fn default() -> Self {
        Self::new()
    }
}

impl Renderer {
    pub fn new() -> Self {
        Renderer {
            gpu: None,
            target: None,
            start: Instant::now(),
            frames: 0,
        }
    }

    pub fn has_surface(&self) -> bool {
        self.target.is_some()
    }

    /// Creates the surface for `window` (and, the first time, the instance, adapter and
    /// device: Vulkan first, GLES when Vulkan gives no adapter that can present).
    pub fn create_surface(
        &mut self,
        window: NativeWindow,
        width: u32,
        height: u32,
    ) -> Result<(), String> {
        self.drop_surface();
        let surface = match &self.gpu {
            Some(gpu) => gpu
                .instance
                .create_surface(AndroidWindow(window))
                .map_err(|e| format!("create_surface: {e}"))?,
            None => {
                let (gpu, surface) = init_gpu(window)?;
                self.gpu = Some(gpu);
                surface
            }
        };
        let gpu = self.gpu.as_ref().expect("gpu initialised above");
        let mut config = surface
            .get_default_config(&gpu.adapter, width.max(1), height.max(1))
            .ok_or("the surface is not supported by the adapter")?;
        let caps = surface.get_capabilities(&gpu.adapter);
        if let Some(srgb) = caps.formats.iter().find(|f| f.is_srgb()) {
            config.format = *srgb;
        }
        config.present_mode = wgpu::PresentMode::Fifo;
        config.desired_maximum_frame_latency = 2;
        surface.configure(&gpu.device, &config);
        log::info!(
            "surface created: {}x{} {:?} {:?}",
            config.width,
            config.height,
            config.format,
            config.alpha_mode
        );
        self.target = Some(Target { surface, config });
        Ok(())
    }

    pub fn drop_surface(&mut self) {
        if self.target.take().is_some() {
            log::info!("surface dropped");
        }
    }

    pub fn reconfigure(&mut self, width: u32, height: u32) {
        let (Some(gpu), Some(t)) = (&self.gpu, &mut self.target) else {
            return;
        };
        if width == 0 || height == 0 {
            return;
        }
        t.config.width = width;
        t.config.height = height;
        t.surface.configure(&gpu.device, &t.config);
        log::info!("surface reconfigured: {width}x{height}");
    }

    /// Draws and presents one frame.
    pub fn draw(&mut self) -> FrameStatus {
        let (Some(gpu), Some(t)) = (&self.gpu, &self.target) else {
            return FrameStatus::Occluded;
        };
        let (frame, status) = match t.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => (f, FrameStatus::Presented),
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => (f, FrameStatus::Suboptimal),
            wgpu::CurrentSurfaceTexture::Timeout => return FrameStatus::Timeout,
            wgpu::CurrentSurfaceTexture::Occluded => return FrameStatus::Occluded,
            wgpu::CurrentSurfaceTexture::Outdated => return FrameStatus::Outdated,
            wgpu::CurrentSurfaceTexture::Lost => return FrameStatus::Lost,
            wgpu::CurrentSurfaceTexture::Validation => return FrameStatus::Validation,
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let t_s = self.start.elapsed().as_secs_f64();
        let c = |phase: f64| 0.25 + 0.2 * (t_s * 0.5 + phase).sin();
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("clear"),
            });
        {
            let _pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("clear"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: c(0.0),
                            g: c(2.1),
                            b: c(4.2),
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
        }
        gpu.queue.submit([enc.finish()]);
        gpu.queue.present(frame);
        self.frames += 1;
        if self.frames.is_multiple_of(600) {
            log::info!("{} frames presented", self.frames);
        }
        status
    }
}

fn init_gpu(window: NativeWindow) -> Result<(Gpu, wgpu::Surface<'static>), String> {
    let mut errors = Vec::new();
    for backends in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let surface = match instance.create_surface(AndroidWindow(window.clone())) {
            Ok(s) => s,
            Err(e) => {
                errors.push(format!("{backends:?}: create_surface: {e}"));
                continue;
            }
        };
        let adapter =
            match pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: Some(&surface),
                apply_limit_buckets: false,
            })) {
                Ok(a) => a,
                Err(e) => {
                    errors.push(format!("{backends:?}: request_adapter: {e}"));
                    continue;
                }
            };
        let info = adapter.get_info();
        log::info!(
            "adapter: {} ({:?}, {:?}) driver {} {}",
            info.name,
            info.backend,
            info.device_type,
            info.driver,
            info.driver_info
        );
        let device = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("dermis"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            ..Default::default()
        }));
        match device {
            Ok((device, queue)) => {
                device.on_uncaptured_error(std::sync::Arc::new(|e| {
                    log::error!("wgpu error: {e}");
                }));
                return Ok((
                    Gpu {
                        instance,
                        adapter,
                        device,
                        queue,
                    },
                    surface,
                ));
            }
            Err(e) => errors.push(format!("{backends:?}: request_device: {e}")),
        }
    }
    Err(format!("no usable GPU: {}", errors.join("; ")))
}

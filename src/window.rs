//! The desktop window (winit): the showroom demo with the follow camera.
//! Keys: M next shading model, N next material, C next clip, Esc quit.

use std::sync::Arc;
use std::time::Instant;

use dermis_core::render::{DrawSet, Gpu, Renderer, Targets};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::cli::WindowArgs;
use crate::demo::Demo;

struct Graphics {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    renderer: Renderer,
    targets: Targets,
}

struct App {
    args: WindowArgs,
    demo: Demo,
    graphics: Option<Graphics>,
    frames: u64,
    last: Option<Instant>,
    error: Option<String>,
}

pub fn run(args: WindowArgs) -> Result<(), String> {
    let demo = Demo::load(&crate::paths::assets_dir(), args.model.as_deref(), args.shading, args.material)?;
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { args, demo, graphics: None, frames: 0, last: None, error: None };
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl App {
    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let attrs = Window::default_attributes()
            .with_title(self.demo.title())
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| e.to_string())?);
        let instance = Gpu::instance();
        let surface = instance.create_surface(window.clone()).map_err(|e| e.to_string())?;
        let gpu = pollster::block_on(Gpu::from_instance(instance, Some(&surface))).map_err(|e| e.to_string())?;
        log::info!("rendering with {}", gpu.adapter_name());
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or("the surface offers no format")?;
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if self.args.screenshot.is_some() {
            if !caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
                return Err("this surface cannot be copied from, so --screenshot is unavailable".into());
            }
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&gpu.device, &config);
        let mut renderer = Renderer::new(&gpu, format);
        self.demo.upload(&gpu, &mut renderer)?;
        let targets = Targets::new(&gpu.device, format, config.width, config.height);
        self.graphics = Some(Graphics { window, surface, config, gpu, renderer, targets });
        Ok(())
    }

    fn key(&mut self, event: &KeyEvent, event_loop: &ActiveEventLoop) {
        if event.state != ElementState::Pressed {
            return;
        }
        let Some(g) = &mut self.graphics else { return };
        match &event.logical_key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Character(c) if c.eq_ignore_ascii_case("m") => self.demo.shading = self.demo.shading.next(),
            Key::Character(c) if c.eq_ignore_ascii_case("n") => {
                self.demo.next_material();
                g.renderer.set_material(&g.gpu.queue, &self.demo.material);
            }
            Key::Character(c) if c.eq_ignore_ascii_case("c") => {
                self.demo.clip = (self.demo.clip + 1) % self.demo.clip_count().max(1);
                self.demo.time = 0.0;
            }
            _ => return,
        }
        g.window.set_title(&self.demo.title());
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let now = Instant::now();
        let dt = self.last.map_or(1.0 / 60.0, |l| (now - l).as_secs_f32().min(0.1));
        self.last = Some(now);
        self.demo.update(dt);
        let Some(g) = &mut self.graphics else { return Ok(()) };
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => f,
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
                drop(f);
                g.surface.configure(&g.gpu.device, &g.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(&g.gpu.device, &g.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(()),
            wgpu::CurrentSurfaceTexture::Validation => return Err("surface validation error".into()),
        };
        let view = frame.texture.create_view(&wgpu::TextureViewDescriptor::default());
        let aspect = g.config.width as f32 / g.config.height as f32;
        self.demo.prepare(&g.gpu, &mut g.renderer, aspect);
        let mut encoder = g.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let draw = DrawSet { shading: Some(self.demo.shading), character: true, props: true };
        g.renderer.encode(&mut encoder, &g.targets, &view, draw, None);
        self.frames += 1;
        let last = self.args.frames.is_some_and(|n| self.frames >= n);
        let shot = match (&self.args.screenshot, last) {
            (Some(path), true) => Some((path.clone(), screenshot::record(&g.gpu, &mut encoder, &frame.texture))),
            _ => None,
        };
        g.gpu.queue.submit([encoder.finish()]);
        if let Some((path, buffer)) = shot {
            screenshot::save(&g.gpu, &buffer, &frame.texture, &path)?;
            println!("{}: frame {} ({})", path.display(), self.frames, self.demo.title());
        }
        g.window.pre_present_notify();
        g.gpu.queue.present(frame);
        if last {
            event_loop.exit();
        }
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.graphics.is_none() {
            if let Err(e) = self.init(event_loop) {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(g) = &mut self.graphics {
                    g.config.width = size.width.max(1);
                    g.config.height = size.height.max(1);
                    g.surface.configure(&g.gpu.device, &g.config);
                    g.targets.ensure(&g.gpu.device, g.config.format, g.config.width, g.config.height);
                }
            }
            WindowEvent::KeyboardInput { event, .. } => self.key(&event, event_loop),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.error = Some(e);
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.graphics {
            g.window.request_redraw();
        }
    }
}

mod screenshot {
    use dermis_core::render::Gpu;

    fn padded_row(width: u32) -> u32 {
        (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
    }

    /// Records a copy of the surface texture into a new readback buffer.
    pub fn record(gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) -> wgpu::Buffer {
        let (w, h) = (texture.width(), texture.height());
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("screenshot"),
            size: (padded_row(w) * h) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded_row(w)), rows_per_image: Some(h) },
            },
            texture.size(),
        );
        buffer
    }

    /// Waits for the copy and writes a PNG (BGRA surfaces are swizzled to RGBA).
    pub fn save(gpu: &Gpu, buffer: &wgpu::Buffer, texture: &wgpu::Texture, path: &std::path::Path) -> Result<(), String> {
        let (w, h) = (texture.width(), texture.height());
        let slice = buffer.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        gpu.wait();
        let bgra = matches!(texture.format(), wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
        let mut pixels = Vec::with_capacity((w * h * 4) as usize);
        {
            let data = slice.get_mapped_range().map_err(|e| format!("screenshot readback: {e}"))?;
            for row in 0..h {
                let start = (row * padded_row(w)) as usize;
                for px in data[start..start + (w * 4) as usize].chunks_exact(4) {
                    let (r, b) = if bgra { (px[2], px[0]) } else { (px[0], px[2]) };
                    pixels.extend_from_slice(&[r, px[1], b, 255]);
                }
            }
        }
        buffer.unmap();
        image::save_buffer(path, &pixels, w, h, image::ExtendedColorType::Rgba8).map_err(|e| format!("{}: {e}", path.display()))
    }
}

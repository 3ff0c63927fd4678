//! The desktop window (winit). Default: the runner game. `dermis demo`: the showroom.
//! Game keys: ←/→ (A/D) change lane, Space/↑ jump or start, M next shading model, Esc back to
//! the main screen (then quit). Demo keys: M next model, N next material, C next clip.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use dermis_core::game::{GameGpu, Key as GameKey, Session, Viewport};
use dermis_core::render::{DrawSet, Gpu, Renderer, Targets};
use dermis_core::scene::SceneAssets;
use dermis_core::ui::Insets;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::Key;
use winit::window::{Window, WindowId};

use crate::cli::WindowArgs;
use crate::demo::Demo;

/// What the window shows.
enum Mode {
    Game {
        session: Box<Session>,
        assets: Box<SceneAssets>,
        gpu: Option<Box<GameGpu>>,
    },
    Demo {
        demo: Box<Demo>,
        renderer: Option<Box<Renderer>>,
    },
}

struct Graphics {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    targets: Targets,
}

struct App {
    args: WindowArgs,
    mode: Mode,
    graphics: Option<Graphics>,
    frames: u64,
    last: Option<Instant>,
    cursor: (f32, f32),
    error: Option<String>,
}

/// Where the desktop game keeps the player's settings.
pub fn settings_path() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(base.join("dermis").join("settings.txt"))
}

pub fn run_game(args: WindowArgs) -> Result<(), String> {
    let assets = SceneAssets::load(&crate::paths::assets_dir(), args.model.as_deref())
        .map_err(|e| e.to_string())?;
    let path = args.settings.clone().or_else(settings_path);
    let mut session = Session::new(&assets.character, args.seed, path, args.autoplay);
    if let Some(m) = args.shading {
        session.settings.set_shading_model(m);
    }
    run(
        args,
        Mode::Game {
            session: Box::new(session),
            assets: Box::new(assets),
            gpu: None,
        },
    )
}

pub fn run_demo(args: WindowArgs) -> Result<(), String> {
    let shading = args
        .shading
        .unwrap_or(dermis_core::shading::ShadingModel::Oss);
    let demo = Demo::load(
        &crate::paths::assets_dir(),
        args.model.as_deref(),
        shading,
        args.material,
    )?;
    run(
        args,
        Mode::Demo {
            demo: Box::new(demo),
            renderer: None,
        },
    )
}

fn run(args: WindowArgs, mode: Mode) -> Result<(), String> {
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        args,
        mode,
        graphics: None,
        frames: 0,
        last: None,
        cursor: (0.0, 0.0),
        error: None,
    };
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    app.error.map_or(Ok(()), Err)
}

impl App {
    fn title(&self) -> String {
        match &self.mode {
            Mode::Game { session, .. } => {
                format!(
                    "dermis — {} ({})",
                    session.shading().label(),
                    session.shading().name()
                )
            }
            Mode::Demo { demo, .. } => demo.title(),
        }
    }

    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let attrs = Window::default_attributes()
            .with_title(self.title())
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| e.to_string())?);
        let instance = Gpu::instance();
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| e.to_string())?;
        let gpu = pollster::block_on(Gpu::from_instance(instance, Some(&surface)))
            .map_err(|e| e.to_string())?;
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
                return Err(
                    "this surface cannot be copied from, so --screenshot is unavailable".into(),
                );
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
        match &mut self.mode {
            Mode::Game {
                assets, gpu: slot, ..
            } => *slot = Some(Box::new(GameGpu::new(&gpu, format, assets)?)),
            Mode::Demo { demo, renderer } => {
                let mut r = Renderer::new(&gpu, format);
                demo.upload(&gpu, &mut r)?;
                *renderer = Some(Box::new(r));
            }
        }
        let targets = Targets::new(&gpu.device, format, config.width, config.height);
        self.graphics = Some(Graphics {
            window,
            surface,
            config,
            gpu,
            targets,
        });
        Ok(())
    }

    fn key(&mut self, event: &KeyEvent, event_loop: &ActiveEventLoop) {
        if event.state != ElementState::Pressed {
            return;
        }
        let key = match &event.logical_key {
            Key::Named(n) => format!("{n:?}"),
            Key::Character(c) => c.to_lowercase(),
            _ => return,
        };
        match &mut self.mode {
            Mode::Game { session, .. } => match key.as_str() {
                "ArrowLeft" | "a" => session.key(GameKey::Left),
                "ArrowRight" | "d" => session.key(GameKey::Right),
                "Space" | "ArrowUp" | "w" | "Enter" => session.key(GameKey::Jump),
                "m" => session.key(GameKey::NextModel),
                "Escape" => {
                    if session.game.screen() == dermis_core::game::Screen::Main {
                        event_loop.exit();
                    } else {
                        session.game.to_main();
                    }
                }
                _ => return,
            },
            Mode::Demo { demo, renderer } => match key.as_str() {
                "Escape" => event_loop.exit(),
                "m" => demo.shading = demo.shading.next(),
                "n" => {
                    demo.next_material();
                    if let (Some(r), Some(g)) = (renderer, &self.graphics) {
                        r.set_material(&g.gpu.queue, &demo.material);
                    }
                }
                "c" => {
                    demo.clip = (demo.clip + 1) % demo.clip_count().max(1);
                    demo.time = 0.0;
                }
                _ => return,
            },
        }
        let title = self.title();
        if let Some(g) = &self.graphics {
            g.window.set_title(&title);
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let now = Instant::now();
        let dt = self
            .last
            .map_or(1.0 / 60.0, |l| (now - l).as_secs_f32().min(0.1));
        self.last = Some(now);
        let Some(g) = &mut self.graphics else {
            return Ok(());
        };
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => f,
            wgpu::CurrentSurfaceTexture::Suboptimal(_)
            | wgpu::CurrentSurfaceTexture::Outdated
            | wgpu::CurrentSurfaceTexture::Lost => {
                g.surface.configure(&g.gpu.device, &g.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(())
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err("surface validation error".into())
            }
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = g
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let mut title_changed = false;
        match &mut self.mode {
            Mode::Game {
                session,
                assets,
                gpu: Some(gg),
            } => {
                let viewport = Viewport {
                    width: g.config.width,
                    height: g.config.height,
                    scale: g.window.scale_factor() as f32,
                    insets: Insets::default(),
                };
                let info = session.update(dt, &assets.character, viewport);
                title_changed = info.shading_changed;
                gg.upload(&g.gpu.queue, session, &assets.character);
                gg.encode(&mut encoder, &g.targets, &view, session);
            }
            Mode::Demo {
                demo,
                renderer: Some(r),
            } => {
                demo.update(dt);
                demo.prepare(&g.gpu, r, g.config.width as f32 / g.config.height as f32);
                let draw = DrawSet {
                    shading: Some(demo.shading),
                    character: true,
                    props: true,
                };
                r.encode(&mut encoder, &g.targets, &view, draw, None, None);
            }
            _ => return Ok(()),
        }
        self.frames += 1;
        let last = self.args.frames.is_some_and(|n| self.frames >= n);
        let shot = match (&self.args.screenshot, last) {
            (Some(path), true) => Some((
                path.clone(),
                screenshot::record(&g.gpu, &mut encoder, &frame.texture),
            )),
            _ => None,
        };
        g.gpu.queue.submit([encoder.finish()]);
        if let Some((path, buffer)) = shot {
            screenshot::save(&g.gpu, &buffer, &frame.texture, &path)?;
            println!("{}: frame {}", path.display(), self.frames);
        }
        g.window.pre_present_notify();
        g.gpu.queue.present(frame);
        if title_changed {
            let title = self.title();
            if let Some(g) = &self.graphics {
                g.window.set_title(&title);
            }
        }
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
                    g.targets.ensure(
                        &g.gpu.device,
                        g.config.format,
                        g.config.width,
                        g.config.height,
                    );
                }
            }
            WindowEvent::KeyboardInput { event, .. } => self.key(&event, event_loop),
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x as f32, position.y as f32)
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                if let Mode::Game { session, .. } = &mut self.mode {
                    let (x, y) = self.cursor;
                    match state {
                        ElementState::Pressed => session.pointer_down(x, y),
                        ElementState::Released => session.pointer_up(x, y),
                    }
                }
            }
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
        (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
    }

    /// Records a copy of the surface texture into a new readback buffer.
    pub fn record(
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) -> wgpu::Buffer {
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
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row(w)),
                    rows_per_image: Some(h),
                },
            },
            texture.size(),
        );
        buffer
    }

    /// Waits for the copy and writes a PNG (BGRA surfaces are swizzled to RGBA).
    pub fn save(
        gpu: &Gpu,
        buffer: &wgpu::Buffer,
        texture: &wgpu::Texture,
        path: &std::path::Path,
    ) -> Result<(), String> {
        let (w, h) = (texture.width(), texture.height());
        let slice = buffer.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        gpu.wait();
        let bgra = matches!(
            texture.format(),
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let mut pixels = Vec::with_capacity((w * h * 4) as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| format!("screenshot readback: {e}"))?;
            for row in 0..h {
                let start = (row * padded_row(w)) as usize;
                for px in data[start..start + (w * 4) as usize].chunks_exact(4) {
                    let (r, b) = if bgra { (px[2], px[0]) } else { (px[0], px[2]) };
                    pixels.extend_from_slice(&[r, px[1], b, 255]);
                }
            }
        }
        buffer.unmap();
        image::save_buffer(path, &pixels, w, h, image::ExtendedColorType::Rgba8)
            .map_err(|e| format!("{}: {e}", path.display()))
    }
}

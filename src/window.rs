//! The desktop window (winit). Default: the runner game. `dermis demo`: the showroom.
//! Game keys: ←/→ (A/D) change lane, Space/↑ jump or start, M next shading model, P pause /
//! resume, C close-up / wide play camera, F frame-time overlay, Esc pause a run (again: back
//! to the main screen; there: quit).
//! A run pauses by itself when the window loses focus. Demo keys: M next model, N next
//! material, C next clip.

use std::path::PathBuf;
use std::sync::Arc;

use dermis_engine::render::{
    FrameDriver, FrameOutput, Gpu, Output, Renderer, SurfaceOptions, SurfaceTarget,
};
use dermis_engine::scene::SceneAssets;
use dermis_game::app::{GameFrame, GameGpu, GameLoad, GameSetup, Key as GameKey, Session};
use dermis_game::lifecycle::FrameStatus;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::Key;
use winit::window::{Window, WindowId};

use crate::cli::{DemoArgs, GameArgs, WindowArgs};
use crate::demo::{Demo, DemoFrame};

/// What the window shows.
enum Mode {
    /// The game, its assets and session still on the loader thread (while the window and the
    /// device are made).
    Loading(Option<GameLoad>),
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
    target: SurfaceTarget,
    gpu: Gpu,
    driver: FrameDriver,
    /// The pipeline cache was saved once everything loaded (again at exit).
    cache_saved: bool,
}

struct App {
    args: WindowArgs,
    mode: Mode,
    graphics: Option<Graphics>,
    frames: u64,
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

/// The settings file a game window reads and writes: `--settings FILE`; else, for a player's
/// session, the user's ([`settings_path`]); a smoke-test run (`--frames N`) uses none, so it
/// starts from the default settings (model, best score) whatever the user saved, and saves
/// nothing.
pub fn game_settings_path(args: &GameArgs) -> Option<PathBuf> {
    match (&args.settings, args.window.frames) {
        (Some(path), _) => Some(path.clone()),
        (None, Some(_)) => None,
        (None, None) => settings_path(),
    }
}

pub fn run_game(args: GameArgs) -> Result<(), String> {
    // The assets load while the window and the device are made; the showroom's scanned head
    // after them (its subject option appears where it loads).
    let load = GameLoad::start(GameSetup {
        character: args.window.model.clone(),
        seed: args.seed,
        settings: game_settings_path(&args),
        autoplay: args.autoplay,
        shading: args.shading,
        skin: args.character.skin.clone(),
        clips: args.character.clips(),
        ..GameSetup::new(crate::paths::assets_dir())
    });
    run(args.window, Mode::Loading(Some(load)))
}

pub fn run_demo(args: DemoArgs) -> Result<(), String> {
    let demo = Demo::load(
        &crate::paths::assets_dir(),
        args.window.model.as_deref(),
        args.shading,
        args.material,
    )?;
    run(
        args.window,
        Mode::Demo {
            demo: Box::new(demo),
            renderer: None,
        },
    )
}

fn run(args: WindowArgs, mode: Mode) -> Result<(), String> {
    let mut app = App {
        args,
        mode,
        graphics: None,
        frames: 0,
        cursor: (0.0, 0.0),
        error: None,
    };
    let ran = EventLoop::new()
        .map_err(|e| format!("cannot open a window: {e}"))
        .and_then(|event_loop| {
            event_loop.set_control_flow(ControlFlow::Poll);
            event_loop.run_app(&mut app).map_err(|e| e.to_string())
        })
        .and(app.error.take().map_or(Ok(()), Err));
    // A game that never got its window: its loader's findings (a bad settings line, a broken
    // asset) come first, then the window's error.
    if let (Err(_), Mode::Loading(load)) = (&ran, &mut app.mode) {
        if let Some(load) = load.take() {
            load.wait()?;
        }
    }
    ran
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
            Mode::Loading(_) => "dermis".into(),
        }
    }

    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let attrs = Window::default_attributes()
            .with_title(self.title())
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| e.to_string())?);
        let (mut gpu, surface) = Gpu::with_surface(|| window.clone()).map_err(|e| e.to_string())?;
        log::info!("rendering with {}", gpu.adapter_name());
        // Last launch's pipelines ($XDG_CACHE_HOME/dermis), saved again at exit.
        if let Some(dir) = dermis_engine::render::pipeline_cache::desktop_dir() {
            gpu.use_pipeline_cache(&dir);
        }
        let size = window.inner_size();
        let copy_src = self.args.screenshot.is_some();
        let options = SurfaceOptions {
            copy_src,
            ..SurfaceOptions::default()
        };
        let mut target = SurfaceTarget::new(&gpu, surface, size.width, size.height, options)
            .map_err(|e| match copy_src {
                true if e.contains("copied") => format!("{e}, so --screenshot is unavailable"),
                _ => e,
            })?;
        let notify = window.clone();
        target.on_present(move || notify.pre_present_notify());
        let format = target.format();
        match &mut self.mode {
            Mode::Loading(load) => {
                let load = load.take().ok_or("the game was already loaded")?;
                let (assets, session) = load.wait()?;
                let gg = GameGpu::new(&gpu, format, &assets, session.shading())?;
                self.mode = Mode::Game {
                    session: Box::new(session),
                    assets: Box::new(assets),
                    gpu: Some(Box::new(gg)),
                };
                window.set_title(&self.title());
            }
            Mode::Game {
                assets,
                gpu: slot,
                session,
            } => {
                let gg = GameGpu::new(&gpu, format, assets, session.shading())?;
                *slot = Some(Box::new(gg));
            }
            Mode::Demo { demo, renderer } => {
                let mut r = Renderer::new(&gpu, format);
                demo.upload(&gpu, &mut r)?;
                *renderer = Some(Box::new(r));
            }
        }
        let driver = FrameDriver::interactive(&gpu);
        self.graphics = Some(Graphics {
            window,
            target,
            gpu,
            driver,
            cache_saved: false,
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
                "p" => session.key(GameKey::Pause),
                "f" => session.key(GameKey::FrameStats),
                "c" => session.key(GameKey::Camera),
                "h" => session.key(GameKey::Subject),
                "Escape" => match session.game.screen() {
                    dermis_game::rules::Screen::Main => event_loop.exit(),
                    dermis_game::rules::Screen::Play if !session.is_paused() => session.pause(),
                    _ => session.game.to_main(),
                },
                _ => return,
            },
            Mode::Demo { demo, renderer } => match key.as_str() {
                "Escape" => event_loop.exit(),
                "m" => demo.shading = demo.shading.next(),
                "n" => {
                    demo.next_material();
                    if let (Some(r), Some(g)) = (renderer, &self.graphics) {
                        r.set_material(&g.gpu, &demo.material);
                    }
                }
                "c" => {
                    demo.clip = (demo.clip + 1) % demo.clip_count().max(1);
                    demo.time = 0.0;
                }
                _ => return,
            },
            Mode::Loading(_) => return,
        }
        let title = self.title();
        if let Some(g) = &self.graphics {
            g.window.set_title(&title);
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let Some(g) = &mut self.graphics else {
            return Ok(());
        };
        let last = self.args.frames.is_some_and(|n| self.frames + 1 >= n);
        let want_shot = last && self.args.screenshot.is_some();
        let mut shot = None;
        let mut record = |encoder: &mut wgpu::CommandEncoder, output: &FrameOutput<'_>| {
            if want_shot {
                shot = Some(screenshot::record(&g.gpu, encoder, output.texture));
            }
        };
        let output = Output::Surface(&mut g.target);
        let mut title_changed = false;
        let drawn = match &mut self.mode {
            Mode::Game {
                session,
                assets,
                gpu: Some(gg),
            } => {
                let mut hook =
                    |e: &mut wgpu::CommandEncoder, _: &Session, o: &FrameOutput<'_>| record(e, o);
                let mut frame = GameFrame::new(session, gg, &assets.character);
                frame.scale = g.window.scale_factor() as f32;
                frame.after_encode = Some(&mut hook);
                let drawn = frame.run(&mut g.driver, &g.gpu, output);
                title_changed = frame.info.shading_changed;
                drawn
            }
            Mode::Demo {
                demo,
                renderer: Some(r),
            } => {
                let mut frame = DemoFrame::new(demo, r);
                frame.after_encode = Some(&mut record);
                frame.run(&mut g.driver, &g.gpu, output)
            }
            _ => return Ok(()),
        };
        match drawn {
            Ok(_) => {}
            Err(FrameStatus::Validation) => return Err("surface validation error".into()),
            // No image this time (the surface reconfigured itself where it had to).
            Err(_) => return Ok(()),
        }
        self.frames += 1;
        // Every pipeline built: their cache is saved now, not only at exit (a crash, a kill).
        if let Mode::Game { gpu: Some(gg), .. } = &self.mode {
            if !g.cache_saved && gg.loaded() {
                g.gpu.save_pipeline_cache();
                g.cache_saved = true;
            }
        }
        if let (Some(path), Some(pending)) = (&self.args.screenshot, shot) {
            screenshot::save(&g.gpu, &pending, path)?;
            println!("{}: frame {}", path.display(), self.frames);
        }
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
                    g.target.resize(&g.gpu, size.width, size.height);
                }
            }
            WindowEvent::KeyboardInput { event, .. } => self.key(&event, event_loop),
            WindowEvent::Focused(focused) => {
                if let Mode::Game { session, .. } = &mut self.mode {
                    if !focused {
                        session.auto_pause();
                    }
                    session.gui.reset_frame_clock();
                }
                // Frames may have stopped while away: the next one starts the clock afresh.
                if let Some(g) = &mut self.graphics {
                    g.driver.reset_clock();
                }
            }
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
    use dermis_engine::render::{read_mapped, Gpu};

    fn padded_row(width: u32) -> u32 {
        (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
    }

    /// A copy of a surface image on its way to a readback buffer.
    pub struct Pending {
        buffer: wgpu::Buffer,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    }

    /// Records a copy of the surface texture into a new readback buffer.
    pub fn record(
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) -> Pending {
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
        Pending {
            buffer,
            width: w,
            height: h,
            format: texture.format(),
        }
    }

    /// Waits for the copy and writes a PNG (BGRA surfaces are swizzled to RGBA).
    pub fn save(gpu: &Gpu, shot: &Pending, path: &std::path::Path) -> Result<(), String> {
        let (w, h) = (shot.width, shot.height);
        let bgra = matches!(
            shot.format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let pixels = read_mapped(&gpu.device, &shot.buffer, |data| {
            let mut pixels = Vec::with_capacity((w * h * 4) as usize);
            for row in 0..h {
                let start = (row * padded_row(w)) as usize;
                for px in data[start..start + (w * 4) as usize].chunks_exact(4) {
                    let (r, b) = if bgra { (px[2], px[0]) } else { (px[0], px[2]) };
                    pixels.extend_from_slice(&[r, px[1], b, 255]);
                }
            }
            pixels
        })
        .ok_or("screenshot readback: the buffer could not be mapped")?;
        image::save_buffer(path, &pixels, w, h, image::ExtendedColorType::Rgba8)
            .map_err(|e| format!("{}: {e}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    fn window_args(argv: &[&str]) -> GameArgs {
        let mut all = vec!["dermis"];
        all.extend_from_slice(argv);
        crate::cli::Cli::try_parse_from(all).unwrap().game
    }

    #[test]
    fn a_smoke_test_run_ignores_the_users_settings() {
        // `--frames N`: the default settings, nothing read or saved.
        assert_eq!(game_settings_path(&window_args(&["--frames", "1"])), None);
        // Unless a file is named.
        let named = window_args(&["--frames", "1", "--settings", "/tmp/s.txt"]);
        assert_eq!(
            game_settings_path(&named),
            Some(PathBuf::from("/tmp/s.txt"))
        );
        // A player's session: the user's file.
        assert_eq!(game_settings_path(&window_args(&[])), settings_path());
    }
}

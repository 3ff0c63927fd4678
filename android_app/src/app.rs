//! GPU side of the Android app: the wgpu context ([`dermis_core::render::Gpu`], created once
//! on the first window, kept across pause/resume, so limits and features match the desktop),
//! the game's GPU objects ([`GameGpu`]: every pipeline, the scene and the UI, created with the
//! first surface and kept), the window surface (created on InitWindow, dropped on TermWindow)
//! with its MSAA colour / depth [`Targets`], and the frame: the same
//! [`Session`] loop as the desktop window (update → upload → one pass → present).

use crate::lifecycle::FrameStatus;
use android_activity::ndk::native_window::NativeWindow;
use dermis_core::game::{GameGpu, Key, Screen, Session, Viewport};
use dermis_core::render::{Gpu, Targets};
use dermis_core::scene::SceneAssets;
use dermis_core::ui::Insets;
use std::path::PathBuf;
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

/// The window surface and what depends on its size.
struct Target {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    targets: Targets,
}

/// The game: assets (loaded once, at start), the session, and — once there is a GPU — its
/// pipelines for the surface format.
pub struct Game {
    pub assets: SceneAssets,
    pub session: Session,
    /// Where the session persists its settings (also written on SaveState).
    pub settings_path: Option<PathBuf>,
    /// Whether SaveState writes the settings: false when an intent extra overrode the
    /// shading model for this run only (the player's saved choice is kept).
    pub save_settings_on_save_state: bool,
    gpu: Option<(GameGpu, wgpu::TextureFormat)>,
}

impl Game {
    pub fn new(assets: SceneAssets, session: Session, settings_path: Option<PathBuf>) -> Self {
        Game {
            assets,
            session,
            settings_path,
            save_settings_on_save_state: true,
            gpu: None,
        }
    }

    /// Whether the game is anywhere but the main screen.
    pub fn in_play(&self) -> bool {
        self.session.game.screen() != Screen::Main
    }

    pub fn leave_play(&mut self) {
        self.session.game.to_main();
    }

    pub fn key(&mut self, key: Key) {
        self.session.key(key);
    }

    /// Writes the settings file now (SaveState); the session also saves on every change.
    pub fn save_settings(&self) {
        let Some(path) = &self.settings_path else {
            return;
        };
        if !self.save_settings_on_save_state {
            log::info!("SaveState: settings not rewritten (shading overridden by the intent)");
            return;
        }
        match self.session.settings.save(path) {
            Ok(()) => log::info!("SaveState: settings written to {}", path.display()),
            Err(e) => log::warn!("SaveState: cannot write {}: {e}", path.display()),
        }
    }
}

pub struct Renderer {
    gpu: Option<Gpu>,
    target: Option<Target>,
    game: Option<Game>,
    /// Display density / 160 (the UI's scale).
    scale: f32,
    last: Option<Instant>,
    frames: u64,
    /// The soak run in progress (intent extras or a Game Loop test), fed each frame.
    pub soak: Option<crate::soak::Soak>,
}

impl Renderer {
    /// `game` is `None` when the assets could not be loaded (the activity is finishing).
    pub fn new(game: Option<Game>, scale: f32) -> Self {
        Renderer {
            gpu: None,
            target: None,
            game,
            scale,
            last: None,
            frames: 0,
            soak: None,
        }
    }

    pub fn has_surface(&self) -> bool {
        self.target.is_some()
    }

    pub fn game(&self) -> Option<&Game> {
        self.game.as_ref()
    }

    pub fn game_mut(&mut self) -> Option<&mut Game> {
        self.game.as_mut()
    }

    pub fn set_scale(&mut self, scale: f32) {
        if scale != self.scale {
            log::info!("display scale {scale}");
            self.scale = scale;
        }
    }

    /// Forgets the last frame time (after a pause the game does not jump ahead).
    pub fn reset_clock(&mut self) {
        self.last = None;
    }

    /// Creates the surface for `window` (and, the first time, the GPU context — Vulkan first,
    /// GLES when Vulkan gives no adapter that can present — and the game's pipelines).
    pub fn create_surface(
        &mut self,
        window: NativeWindow,
        width: u32,
        height: u32,
    ) -> Result<(), String> {
        self.drop_surface();
        let Some(game) = &mut self.game else {
            return Err("no game (the assets did not load)".into());
        };
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
        // Keep the pipelines' format when this surface offers it; else prefer sRGB.
        let previous = game.gpu.as_ref().map(|(_, f)| *f);
        if let Some(format) = previous
            .filter(|f| caps.formats.contains(f))
            .or_else(|| caps.formats.iter().copied().find(|f| f.is_srgb()))
        {
            config.format = format;
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
        if previous != Some(config.format) {
            let t0 = Instant::now();
            let gg = GameGpu::new(gpu, config.format, &game.assets)
                .map_err(|e| format!("game GPU setup: {e}"))?;
            log::info!(
                "pipelines and scene uploaded for {:?} in {} ms",
                config.format,
                t0.elapsed().as_millis()
            );
            game.gpu = Some((gg, config.format));
        }
        let targets = Targets::new(&gpu.device, config.format, config.width, config.height);
        self.target = Some(Target {
            surface,
            config,
            targets,
        });
        Ok(())
    }

    /// Ends the soak run (if any) and returns its complete report.
    pub fn finish_soak(&mut self) -> Option<serde_json::Value> {
        let mut soak = self.soak.take()?;
        let gpu = self.gpu.as_ref()?;
        let runs = self.game.as_ref().map_or(0, |g| g.session.game.runs());
        Some(soak.finish(&gpu.device, runs))
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
        t.targets
            .ensure(&gpu.device, t.config.format, width, height);
        log::info!("surface reconfigured: {width}x{height}");
    }

    /// Advances the game and draws and presents one frame.
    pub fn draw(&mut self) -> FrameStatus {
        let (Some(gpu), Some(t), Some(game)) = (&self.gpu, &mut self.target, &mut self.game) else {
            return FrameStatus::Occluded;
        };
        let Some((gg, _)) = &mut game.gpu else {
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
        let now = Instant::now();
        let dt = self
            .last
            .map_or(1.0 / 60.0, |l| (now - l).as_secs_f32().min(0.1));
        self.last = Some(now);
        let (width, height) = (frame.texture.width(), frame.texture.height());
        t.targets
            .ensure(&gpu.device, t.config.format, width, height);
        let viewport = Viewport {
            width,
            height,
            scale: self.scale,
            insets: Insets::default(),
        };
        let info = game.session.update(dt, &game.assets.character, viewport);
        if info.shading_changed {
            log::info!("shading model: {}", game.session.shading().name());
        }
        gg.upload(&gpu.queue, &mut game.session, &game.assets.character);
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        gg.encode(&mut enc, &t.targets, &view, &game.session);
        let commands = enc.finish();
        let t_submit = Instant::now();
        gpu.queue.submit([commands]);
        gpu.queue.present(frame);
        let presented = Instant::now();
        if let Some(soak) = &mut self.soak {
            soak.frame(
                gpu,
                (width, height),
                now,
                (t_submit - now).as_secs_f64() * 1e3,
                (presented - t_submit).as_secs_f64() * 1e3,
                presented,
                game.session.shading(),
            );
        }
        self.frames += 1;
        if self.frames.is_multiple_of(3600) {
            log::info!(
                "{} frames presented; screen {:?}, score {}, best {}",
                self.frames,
                game.session.game.screen(),
                game.session.game.score(),
                game.session.game.best()
            );
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
        match pollster::block_on(Gpu::from_instance(instance, Some(&surface))) {
            Ok(gpu) => {
                let info = gpu.adapter.get_info();
                log::info!(
                    "GPU: {} ({:?}, {:?}) driver {} {}; timestamps {}",
                    info.name,
                    info.backend,
                    info.device_type,
                    info.driver,
                    info.driver_info,
                    gpu.timestamps
                );
                gpu.device.on_uncaptured_error(std::sync::Arc::new(|e| {
                    log::error!("wgpu error: {e}");
                }));
                return Ok((gpu, surface));
            }
            Err(e) => errors.push(format!("{backends:?}: {e}")),
        }
    }
    Err(format!("no usable GPU: {}", errors.join("; ")))
}

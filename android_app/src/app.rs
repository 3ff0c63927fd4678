//! GPU side of the Android app: the wgpu context ([`dermis_engine::render::Gpu`], created once
//! on the first window, kept across pause/resume, so limits and features match the desktop),
//! the game's GPU objects ([`GameGpu`]: every pipeline, the scene and the UI, created with the
//! first surface and kept), the window surface ([`SurfaceTarget`], the core's one surface
//! helper: created on InitWindow, dropped on TermWindow, with its MSAA colour / depth
//! targets), and the frame: the core's [`FrameDriver`] running the game ([`GameFrame`]: the
//! same [`Session`] loop as the desktop window, the governor choosing the shading tier).

use android_activity::ndk::native_window::NativeWindow;
use dermis_engine::heap::allocations;
use dermis_engine::render::{
    Clock, FrameDriver, FrameStatus, Gpu, Output, SurfaceOptions, SurfaceTarget,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::ui::Insets;
use dermis_game::app::{GameFrame, GameGpu, Key, Session};
use dermis_game::rules::Screen;
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
    target: Option<SurfaceTarget>,
    game: Option<Game>,
    /// Display density / 160 (the UI's scale).
    scale: f32,
    /// Safe-area insets (physical pixels): the UI stays out of cutouts and system bars.
    insets: Insets,
    driver: FrameDriver,
    frames: u64,
    /// The soak run in progress (intent extras or a Game Loop test), fed each frame.
    pub soak: Option<crate::soak::Soak>,
    /// The activity's cache directory: the pipeline cache lives there.
    pub cache_dir: Option<PathBuf>,
    /// The pipeline cache was saved once every pipeline was built.
    cache_saved: bool,
}

impl Renderer {
    /// `game` is `None` when the assets could not be loaded (the activity is finishing).
    pub fn new(game: Option<Game>, scale: f32) -> Self {
        Renderer {
            gpu: None,
            target: None,
            game,
            scale,
            insets: Insets::ZERO,
            driver: FrameDriver::new(Clock::INTERACTIVE).with_alloc_counter(allocations),
            frames: 0,
            soak: None,
            cache_dir: None,
            cache_saved: false,
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

    pub fn set_insets(&mut self, insets: Insets) {
        if insets != self.insets {
            log::info!("safe-area insets {insets:?}");
            self.insets = insets;
        }
    }

    /// Forgets the last frame time (after a pause the game does not jump ahead).
    pub fn reset_clock(&mut self) {
        self.driver.reset_clock();
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
                let (mut gpu, surface) = init_gpu(window)?;
                // Last launch's compiled pipelines, where the driver keeps them.
                if let Some(dir) = &self.cache_dir {
                    gpu.use_pipeline_cache(dir);
                }
                // The interactive driver: wall clock, every frame GPU-timed when it can be.
                self.driver = FrameDriver::interactive(&gpu).with_alloc_counter(allocations);
                self.gpu = Some(gpu);
                surface
            }
        };
        let gpu = self.gpu.as_ref().expect("gpu initialised above");
        // Keep the pipelines' format when this surface offers it; else prefer sRGB.
        let previous = game.gpu.as_ref().map(|(_, f)| *f);
        let options = SurfaceOptions {
            present_mode: wgpu::PresentMode::Fifo,
            keep_format: previous,
            // The lifecycle decides between reconfiguring and recreating the surface.
            self_heal: false,
            ..SurfaceOptions::default()
        };
        let target = SurfaceTarget::new(gpu, surface, width, height, options)?;
        log::info!(
            "surface created: {}x{} {:?} {:?}",
            target.config.width,
            target.config.height,
            target.config.format,
            target.config.alpha_mode
        );
        if previous != Some(target.format()) {
            let t0 = Instant::now();
            let gg = GameGpu::new(gpu, target.format(), &game.assets, game.session.shading())
                .map_err(|e| format!("game GPU setup: {e}"))?;
            log::info!(
                "pipelines and scene uploaded for {:?} in {} ms",
                target.format(),
                t0.elapsed().as_millis()
            );
            game.gpu = Some((gg, target.format()));
            // The first pipelines are in: kept for the next launch (again when the window
            // goes, with the rest).
            gpu.save_pipeline_cache();
        }
        self.target = Some(target);
        Ok(())
    }

    /// Ends the soak run (if any) and returns its complete report: the GPU drained first, so
    /// the last frames' GPU times are in.
    pub fn finish_soak(&mut self) -> Option<serde_json::Value> {
        let mut soak = self.soak.take()?;
        let gpu = self.gpu.as_ref()?;
        self.driver.drain(gpu, |f, ms| soak.gpu_time(f, ms));
        let runs = self.game.as_ref().map_or(0, |g| g.session.game.runs());
        soak.finish(&gpu.device, runs)
    }

    /// Stops the soak clock (pause, focus or window lost).
    pub fn pause_soak(&mut self) {
        if let Some(soak) = &mut self.soak {
            soak.pause();
        }
    }

    pub fn drop_surface(&mut self) {
        if self.target.take().is_some() {
            log::info!("surface dropped");
            // What was built since the last save: the next launch starts from it.
            if let Some(n) = self.gpu.as_ref().and_then(Gpu::save_pipeline_cache) {
                log::info!("pipeline cache saved ({n} bytes)");
            }
        }
    }

    pub fn reconfigure(&mut self, width: u32, height: u32) {
        let (Some(gpu), Some(t)) = (&self.gpu, &mut self.target) else {
            return;
        };
        if width == 0 || height == 0 {
            return;
        }
        t.resize(gpu, width, height);
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
        let mut frame = GameFrame::new(&mut game.session, gg, &game.assets.character);
        frame.scale = self.scale;
        frame.insets = self.insets;
        let times = match frame.run(&mut self.driver, gpu, Output::Surface(t)) {
            Ok(times) => times,
            Err(status) => return status,
        };
        if frame.info.shading_changed {
            log::info!("shading model: {}", game.session.shading().name());
        }
        if let Some(soak) = &mut self.soak {
            soak.frame(gpu, &times, self.driver.harvested(), &game.session);
        }
        // Every pipeline built (and the head uploaded): kept for the next launch now.
        if !self.cache_saved && gg.loaded() {
            gpu.save_pipeline_cache();
            self.cache_saved = true;
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
        times.status
    }
}

fn init_gpu(window: NativeWindow) -> Result<(Gpu, wgpu::Surface<'static>), String> {
    // Vulkan, else GLES (a phone without a usable Vulkan driver).
    let (gpu, surface) = Gpu::with_surface(|| AndroidWindow(window.clone()))
        .map_err(|e| format!("no usable GPU: {e}"))?;
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
    Ok((gpu, surface))
}

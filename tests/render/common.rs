//! The headless game rig the game-frame tests share: the real renderer on the headless
//! adapter, the project's assets, the game's GPU side, an offscreen target and a session —
//! the frame the shells render, without a window. Each test adds its own camera and shots.

use std::path::Path;

use dermis_engine::render::{Gpu, Offscreen, PreparedFrame, RgbaImage, OFFSCREEN_FORMAT};
use dermis_engine::scene::{FramePacket, FrameView, SceneAssets};
use dermis_engine::shading::ShadingModel;
use dermis_engine::ui::Insets;
use dermis_game::app::{GameGpu, Session, Viewport};
use dermis_game::rules::Screen;

pub struct Rig {
    pub gpu: Gpu,
    pub assets: SceneAssets,
    pub gg: GameGpu,
    pub target: Offscreen,
    pub session: Session,
    /// A test's own camera for every frame it prepares (`None`: the game's).
    pub camera: Option<FrameView>,
    /// The frame prepared last.
    pub frame: Option<PreparedFrame>,
}

impl Rig {
    /// A fresh game (3 lives, no save) rendering into a `width`×`height` target.
    #[allow(dead_code)] // Not every test binary that shares the rig uses the plain assets.
    pub fn new(width: u32, height: u32) -> Self {
        let assets = SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None)
            .unwrap_or_else(|e| panic!("{e}"));
        Self::with_assets(width, height, assets)
    }

    /// The same rig for `assets` (e.g. with the showroom's scanned head).
    pub fn with_assets(width: u32, height: u32, assets: SceneAssets) -> Self {
        let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
        let gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
        let target = Offscreen::new(&gpu, width, height);
        let session = Session::new(&assets.character, 3, None, false);
        Self {
            gpu,
            assets,
            gg,
            target,
            session,
            camera: None,
            frame: None,
        }
    }

    /// The target's size as the game's viewport (scale 1, no insets).
    pub fn viewport(&self) -> Viewport {
        Viewport {
            width: self.target.targets.width,
            height: self.target.targets.height,
            scale: 1.0,
            insets: Insets::ZERO,
        }
    }

    /// Advances the session by `dt` seconds and prepares the frame, as the shells do.
    #[allow(dead_code)] // Not every test binary that shares the rig advances the game.
    pub fn update(&mut self, dt: f32) {
        let viewport = self.viewport();
        // As the shells' game frame does: the head's option where the head was uploaded.
        self.session.gui.offer_head(self.gg.has_head());
        self.session.update(dt, &self.assets.character, viewport);
        self.prepare(|_| {});
    }

    /// Prepares the session's frame (the moment last updated) as the game frame does, after
    /// `edit` changed its packet (what a test leaves out).
    pub fn prepare(&mut self, edit: impl FnOnce(&mut FramePacket)) {
        self.gg.renderer.resize(
            &self.gpu,
            (self.target.targets.width, self.target.targets.height),
        );
        let settled = self.session.game.screen() == Screen::Play;
        let head = self.gg.head.clone();
        let mut packet = self
            .session
            .extract(&self.assets.character, head.as_deref(), settled);
        if let Some(view) = self.camera {
            packet.view = view;
        }
        edit(&mut packet);
        self.frame = Some(self.gg.prepare(&self.gpu, &packet));
    }

    /// The frame last updated without the UI, the character drawn or not, read back.
    #[allow(dead_code)] // Not every test binary that shares the rig shoots frames.
    pub fn shoot_frame(&mut self, character: bool) -> RgbaImage {
        self.prepare(|p| {
            p.draw.character = character;
            p.draw.ui = false;
        });
        self.draw()
    }

    /// Draws the frame prepared last (with the UI it says) and reads it back.
    #[allow(dead_code)] // Not every test binary that shares the rig draws frames.
    pub fn draw(&mut self) -> RgbaImage {
        let frame = self.frame.expect("a frame was prepared");
        self.gg
            .renderer
            .draw_offscreen(&self.gpu, &self.target, &frame)
            .unwrap_or_else(|e| panic!("{e}"));
        self.target.read(&self.gpu)
    }
}

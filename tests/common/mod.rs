//! The headless game rig the game-frame tests share: the real renderer on the headless
//! adapter, the project's assets, the game's GPU side, an offscreen target and a session —
//! the frame the shells render, without a window. Each test adds its own camera and shots.

use std::path::Path;

use dermis_core::app::{GameGpu, Session, Viewport};
use dermis_core::render::{DrawSet, Gpu, Offscreen, RgbaImage, OFFSCREEN_FORMAT};
use dermis_core::scene::SceneAssets;
use dermis_core::shading::ShadingModel;
use dermis_core::ui::Insets;

pub struct Rig {
    pub gpu: Gpu,
    pub assets: SceneAssets,
    pub gg: GameGpu,
    pub target: Offscreen,
    pub session: Session,
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

    /// Advances the session by `dt` seconds and uploads the frame, as the shells do.
    pub fn update(&mut self, dt: f32) {
        let viewport = self.viewport();
        // As the shells' game frame does: the head's option where the head was uploaded.
        self.session.gui.offer_head(self.gg.has_head());
        self.session.update(dt, &self.assets.character, viewport);
        self.gg
            .upload(&self.gpu.queue, &mut self.session, &self.assets.character);
    }

    /// The uploaded frame without the UI, the character drawn or not, read back.
    #[allow(dead_code)] // Not every test binary that shares the rig shoots frames.
    pub fn shoot_frame(&mut self, character: bool) -> RgbaImage {
        let draw = DrawSet {
            character,
            ..self.session.draw_set()
        };
        self.gg
            .renderer
            .draw_offscreen(&self.gpu, &self.target, draw);
        self.target.read(&self.gpu)
    }
}

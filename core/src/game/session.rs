//! One running game as the apps drive it: input → fixed-step simulation → animation, camera,
//! props and UI → GPU uploads → draw set. The desktop window, the headless `play` command,
//! the soak test and the Android app all run this same loop, and none of its per-frame steps
//! allocates in steady state.

use std::path::PathBuf;

use glam::Vec3;

use super::{Bot, Game, GameUi, Input, Screen, Settings, Swipe};
use crate::anim::Pose;
use crate::asset::Model;
use crate::camera::{Capsule, FollowCamera};
use crate::render::{DrawSet, FrameView, Light, PropInstance, Renderer, UiRenderer};
use crate::shading::ShadingModel;
use crate::ui::{Insets, Ui};

/// Exposure before tone mapping in the game.
pub const EXPOSURE: f32 = 1.6;

/// A discrete key the game understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Left,
    Right,
    Jump,
    /// Cycle the shading model (a developer shortcut; the menu button does the same).
    NextModel,
}

/// The screen the UI is laid out for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    pub width: u32,
    pub height: u32,
    /// Display density (1 on a desktop monitor, 2–4 on phones).
    pub scale: f32,
    pub insets: Insets,
}

/// What one frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameInfo {
    pub ticks: u32,
    pub ui_rebuilt: bool,
    pub shading_changed: bool,
}

pub struct Session {
    pub game: Game,
    pub bot: Option<Bot>,
    pub ui: Ui,
    pub gui: GameUi,
    pub settings: Settings,
    settings_path: Option<PathBuf>,
    pub pose: Pose,
    pub camera: FollowCamera,
    props: Vec<PropInstance>,
    pub light: Light,
    pending: Input,
    pointer_down: Option<(f32, f32)>,
    viewport: Viewport,
    /// Whether the character's bounding sphere is inside the view this frame; when it is not,
    /// it is neither animated nor uploaded.
    pub character_visible: bool,
    /// Buffer uploads (`write_buffer` calls) made by the last [`Session::upload`].
    pub uploads: u32,
}

impl Session {
    /// A session for `character`, with settings loaded from (and saved to) `settings_path`.
    pub fn new(
        character: &Model,
        seed: u64,
        settings_path: Option<PathBuf>,
        autoplay: bool,
    ) -> Self {
        let settings = settings_path
            .as_deref()
            .map(Settings::load)
            .unwrap_or_default();
        let mut game = Game::new(seed);
        game.set_best(settings.best);
        let mut camera = FollowCamera::new(Vec3::new(0.0, 2.2, -4.5), Vec3::new(0.0, 1.0, 4.0));
        camera.snap(game.camera_target().0, 0.0);
        Self {
            game,
            bot: autoplay.then(|| Bot::new(seed)),
            ui: Ui::with_embedded_atlas(),
            gui: GameUi::new(),
            settings,
            settings_path,
            pose: Pose::new(character),
            camera,
            props: Vec::with_capacity(Game::MAX_PROPS),
            light: Light::default(),
            pending: Input::NONE,
            pointer_down: None,
            viewport: Viewport {
                width: 1,
                height: 1,
                scale: 1.0,
                insets: Insets::default(),
            },
            character_visible: true,
            uploads: 0,
        }
    }

    /// Whether a sphere (centre, radius) is inside the camera's view for `aspect`.
    pub fn sphere_visible(&self, center: Vec3, radius: f32, aspect: f32) -> bool {
        let m = self.camera.view_proj(aspect);
        // Gribb–Hartmann planes from the rows of the clip matrix (depth 0..1).
        let r = [m.row(0), m.row(1), m.row(2), m.row(3)];
        let planes = [
            r[3] + r[0],
            r[3] - r[0],
            r[3] + r[1],
            r[3] - r[1],
            r[2],
            r[3] - r[2],
        ];
        planes.iter().all(|p| {
            let n = p.truncate();
            let len = n.length().max(1e-12);
            (n.dot(center) + p.w) / len >= -radius
        })
    }

    /// The shading model the player chose.
    pub fn shading(&self) -> ShadingModel {
        self.settings.shading_model()
    }

    pub fn key(&mut self, key: Key) {
        match key {
            Key::Left => self.pending.left = true,
            Key::Right => self.pending.right = true,
            Key::Jump => self.pending.jump = true,
            Key::NextModel => {
                let next = self.shading().next();
                self.settings.set_shading_model(next);
                self.save_settings();
            }
        }
    }

    /// Pointer (mouse or touch) in physical pixels.
    pub fn pointer_down(&mut self, x: f32, y: f32) {
        self.ui.pointer_down(x, y);
        self.pointer_down = Some((x, y));
    }

    pub fn pointer_up(&mut self, x: f32, y: f32) {
        self.ui.pointer_up(x, y);
        if let Some(down) = self.pointer_down.take() {
            if self.game.screen() == Screen::Play {
                let gesture = Input::from_gesture(down, (x, y), 24.0 * self.viewport.scale);
                self.pending.merge(&gesture);
            }
        }
    }

    /// A swipe from a platform gesture detector.
    pub fn swipe(&mut self, swipe: Swipe) {
        self.pending.swipe = Some(swipe);
    }

    fn save_settings(&self) {
        if let Some(path) = &self.settings_path {
            if let Err(e) = self.settings.save(path) {
                log::warn!("could not save settings to {}: {e}", path.display());
            }
        }
    }

    /// Advances the game by `dt` seconds and rebuilds what changed (CPU only).
    pub fn update(&mut self, dt: f32, character: &Model, viewport: Viewport) -> FrameInfo {
        self.viewport = viewport;
        let input = std::mem::replace(&mut self.pending, Input::NONE);
        let ticks = match &self.bot {
            Some(bot) => {
                let bot = *bot;
                self.game.update_with(dt, |g| bot.decide(g))
            }
            None => self.game.update(dt, &input),
        };
        let (target, yaw) = self.game.camera_target();
        let (feet, _) = self.game.player_transform();
        let capsule = Capsule {
            base: feet,
            height: 1.8,
            radius: 0.4,
        };
        self.camera.update(dt, target, yaw, &capsule);
        let aspect = viewport.width as f32 / viewport.height.max(1) as f32;
        self.character_visible = self.sphere_visible(feet + Vec3::Y * 0.9, 1.2, aspect);
        if self.character_visible {
            self.animate(character);
        }
        self.light.position = feet + Vec3::new(1.5, 3.0, 2.5);
        self.game.props(&mut self.props);
        // UI.
        let shading_before = self.shading();
        self.ui.begin(
            viewport.width as f32,
            viewport.height as f32,
            viewport.scale,
            viewport.insets,
        );
        let outcome = self
            .gui
            .draw(&mut self.ui, &mut self.game, &mut self.settings);
        self.ui.end();
        if outcome.settings_changed {
            self.save_settings();
        }
        FrameInfo {
            ticks,
            ui_rebuilt: self.ui.rebuilt_this_frame(),
            shading_changed: outcome.shading_changed || self.shading() != shading_before,
        }
    }

    /// Crossfades the two clips the game asks for into the pose.
    fn animate(&mut self, character: &Model) {
        self.pose.reset(character);
        let anim = self.game.anim_state();
        let mut first = true;
        for (k, &(clip, weight)) in anim.blend.iter().enumerate() {
            let Some(c) = character.animations.get(clip) else {
                continue;
            };
            let t = if c.duration > 0.0 {
                anim.time[k] % c.duration
            } else {
                0.0
            };
            if first {
                self.pose.apply_clip(c, t);
                first = false;
            } else if weight > 0.0 {
                self.pose.blend_clip(c, t, weight);
            }
        }
        self.pose.update_world(character);
    }

    /// Writes this frame's GPU data: joint palettes, frame uniform, props, UI (if changed).
    pub fn upload(
        &mut self,
        queue: &wgpu::Queue,
        renderer: &mut Renderer,
        ui: &mut UiRenderer,
        character: &Model,
    ) {
        let aspect = self.viewport.width as f32 / self.viewport.height.max(1) as f32;
        self.uploads = 1;
        if self.character_visible {
            renderer.update_character(queue, character, &self.pose, self.game.player_matrix());
            self.uploads += 1;
        }
        renderer.prepare(
            queue,
            &FrameView {
                view_proj: self.camera.view_proj(aspect),
                camera_pos: self.camera.eye.value,
                light: self.light,
                exposure: EXPOSURE,
            },
        );
        self.uploads += renderer.set_props(queue, &self.props);
        ui.resize(queue, self.viewport.width, self.viewport.height);
        if self.ui.needs_upload() {
            ui.upload(queue, self.ui.vertices());
            self.ui.mark_uploaded();
            self.uploads += 1;
        }
    }

    pub fn draw_set(&self) -> DrawSet {
        DrawSet {
            shading: Some(self.shading()),
            character: true,
            props: true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_player_is_visible_and_things_behind_the_camera_are_not() {
        let model = crate::probe::plane_model(0.5, 0.01);
        let mut s = Session::new(&model, 1, None, true);
        let vp = Viewport {
            width: 640,
            height: 360,
            scale: 1.0,
            insets: Insets::default(),
        };
        for _ in 0..30 {
            s.update(1.0 / 60.0, &model, vp);
        }
        assert!(s.character_visible);
        let (feet, _) = s.game.player_transform();
        assert!(s.sphere_visible(feet + Vec3::Y, 1.0, 16.0 / 9.0));
        // 50 m behind the camera, and far to the side: culled, so neither animated nor uploaded.
        let eye = s.camera.eye.value;
        assert!(!s.sphere_visible(eye - Vec3::Z * 50.0, 1.2, 16.0 / 9.0));
        assert!(!s.sphere_visible(eye + Vec3::X * 500.0, 1.2, 16.0 / 9.0));
    }
}

//! One running game as the apps drive it: input → fixed-step simulation → animation, camera,
//! props and UI → what the frame needs and the shading tier it gets ([`Governor`]) → GPU
//! uploads → draw set. The desktop window, the headless `play` command, the soak, `bench
//! effects` and the Android app all run this same loop (through
//! [`GameFrame`](super::GameFrame) and the core's frame driver), and none of its per-frame
//! steps allocates in steady state.

use std::path::PathBuf;

use glam::{Mat4, Vec3};

use super::gpu::HEAD;
use super::showroom::{head_matrix, is_showroom, Subject};
use super::{GameUi, Settings, Showroom, ShowroomHead};
use crate::governor::{Change, Governor, GovernorConfig, Needs, Tiers};
use crate::rules::{Bot, Clip, Game, Input, Screen, Swipe};
use dermis_engine::anim::{bind_pose_bounds, find_clips, fit_to_height, Clips, Pose};
use dermis_engine::asset::Model;
use dermis_engine::camera::{CameraPose, FollowCamera, Frustum};
use dermis_engine::scene::{
    DrawSet, FramePacket, FrameView, Light, PropInstance, SubjectId, SubjectPose, CHARACTER,
    EXPOSURE,
};
use dermis_engine::shading::ShadingModel;
use dermis_engine::ui::{Insets, Ui};

/// A discrete key the game understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Left,
    Right,
    Jump,
    /// Cycle the shading model (a developer shortcut; the menu button does the same).
    NextModel,
    /// Pause a run / resume it (the pause panel's Resume button does the same).
    Pause,
    /// Show / hide the frame-time overlay.
    FrameStats,
    /// Switch the play camera between the wide follow camera and its close-up (the play
    /// screen's "View" button does the same).
    Camera,
    /// Switch the showroom's subject runner ↔ scanned head where the head is offered (the
    /// menu's subject option does the same); nothing elsewhere.
    Subject,
}

/// The wide follow camera: eye offset and look-at point from the runner's feet (x right, y
/// up, z forward): the track far ahead, the runner small.
pub const FOLLOW_OFFSET: Vec3 = Vec3::new(0.0, 2.2, -4.5);
pub const FOLLOW_LOOK: Vec3 = Vec3::new(0.0, 1.0, 4.0);
/// The close-up follow camera: just behind and above the runner's head (centred, so the
/// runner stays in view on a narrow portrait screen), so the body from the hips up fills much
/// of the screen and its skin — shoulders, arms, neck, ears, lit by the key light from the
/// front right, so rims and ears are backlit — shows the chosen model, while the lane ahead
/// stays in view over the head.
pub const CLOSE_OFFSET: Vec3 = Vec3::new(0.0, 1.95, -1.3);
pub const CLOSE_LOOK: Vec3 = Vec3::new(0.0, 1.0, 3.5);
/// The close-up's stiffer springs (1/s): a spring trails a runner at speed u by 2u/ω, 4 m at
/// 12 m/s with the wide camera's; these keep the close-up within about a metre of its offset.
pub const CLOSE_EYE_OMEGA: f32 = 24.0;
pub const CLOSE_LOOK_OMEGA: f32 = 30.0;
/// Seconds the camera takes to glide between the two.
pub const CAMERA_SWITCH_S: f32 = 0.5;

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
    /// The follow camera (play); [`Session::view`] is the camera drawn.
    pub camera: FollowCamera,
    /// The menu's close-up camera and orbiting light, blended with the follow camera.
    pub showroom: Showroom,
    props: Vec<PropInstance>,
    pub light: Light,
    pending: Input,
    pointer_down: Option<(f32, f32)>,
    viewport: Viewport,
    /// Whether the character's bounding sphere is inside the view this frame; when it is not,
    /// it is neither animated nor uploaded.
    pub character_visible: bool,
    /// Chooses the character's shading tier each frame (tiers follow the player's choice).
    pub governor: Governor,
    /// What this frame needs (computed by [`Session::update`]).
    pub needs: Needs,
    /// 0: the wide follow camera, 1: the close-up; in between while switching.
    close: f32,
    /// The character's clip for each of the runner's [`Clip`]s (found by name).
    pub clips: Clips,
    /// Fits the character's file to the runner's height, feet on the ground
    /// ([`dermis_engine::anim::fit_to_height`]): a 4.6 m export and a 30 cm one run the same lanes.
    pub fit: Mat4,
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
        let close = if settings.close_camera { 1.0 } else { 0.0 };
        let mut camera = FollowCamera::new(
            FOLLOW_OFFSET.lerp(CLOSE_OFFSET, close),
            FOLLOW_LOOK.lerp(CLOSE_LOOK, close),
        );
        camera.snap(camera_target(&game, close).0, 0.0);
        let showroom = Showroom::new(game.screen(), &camera);
        Self {
            game,
            bot: autoplay.then(|| Bot::new(seed)),
            ui: Ui::with_embedded_atlas(),
            gui: GameUi::new(),
            settings_path,
            pose: Pose::new(character),
            showroom,
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
            governor: Governor::new(
                Tiers::for_choice(settings.shading_model()),
                GovernorConfig::for_fps(60.0),
            ),
            needs: Needs::default(),
            settings,
            close,
            clips: find_clips(character, &[], &[]).unwrap_or_default(),
            fit: bind_pose_bounds(character)
                .and_then(|b| fit_to_height(b, CHARACTER.height))
                .map_or(Mat4::IDENTITY, |f| f.matrix()),
        }
    }

    /// How far the play camera is into its close-up (0 wide, 1 close).
    pub fn close_up(&self) -> f32 {
        self.close
    }

    /// Switches the play camera (wide ↔ close-up) and saves the choice.
    pub fn toggle_camera(&mut self) {
        self.settings.close_camera = !self.settings.close_camera;
        self.save_settings();
    }

    /// Sets the governor's configuration (frame budget) and switches: `budget` the
    /// frame-time governor, `scheduling` the coverage / light tiers (both off: always the
    /// chosen model).
    pub fn configure_governor(&mut self, config: GovernorConfig, budget: bool, scheduling: bool) {
        self.governor = Governor::new(Tiers::for_choice(self.shading()), config);
        self.governor.enabled = budget && scheduling;
        self.governor.scheduling = scheduling;
    }

    /// The tier drawn this frame (index in the governor's tiers).
    pub fn tier(&self) -> usize {
        self.governor.drawn()
    }

    /// The model the character is drawn with this frame: the governor's tier.
    pub fn drawn_model(&self) -> ShadingModel {
        self.governor.tiers().model(self.governor.drawn())
    }

    /// Feeds the governor what the frame drawn last cost (ms; NaN when unknown) and the time
    /// it covered (s).
    pub fn record_frame(&mut self, cost_ms: f64, dt_s: f64) -> Option<Change> {
        self.governor.record(cost_ms, dt_s)
    }

    /// Whether a sphere (centre, radius) is inside the camera's view for `aspect`.
    pub fn sphere_visible(&self, center: Vec3, radius: f32, aspect: f32) -> bool {
        Frustum::new(self.view().view_proj(aspect)).sphere_visible(center, radius)
    }

    /// The camera drawn this frame: the showroom's on the menu, the follow camera in play.
    pub fn view(&self) -> CameraPose {
        self.showroom.view()
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
            Key::Pause => {
                self.game.toggle_pause();
                self.pending = Input::NONE;
            }
            Key::FrameStats => self.gui.show_frame_stats = !self.gui.show_frame_stats,
            Key::Camera => self.toggle_camera(),
            Key::Subject => self.gui.set_subject(self.gui.subject().other()),
        }
    }

    /// Pauses the run (focus lost, the app sent to the background); nothing outside a run.
    /// The run stays paused until the player resumes it.
    pub fn pause(&mut self) {
        self.game.pause();
        self.pending = Input::NONE;
        self.pointer_down = None;
    }

    /// The window lost focus / the app went to the background: pauses a player's run. An
    /// autoplayed session (the bot: `play`, the soak, tests) keeps running, so its clocks
    /// and reports never include a pause nobody asked for.
    pub fn auto_pause(&mut self) {
        if self.bot.is_none() {
            self.pause();
        }
    }

    pub fn is_paused(&self) -> bool {
        self.game.is_paused()
    }

    /// Pointer (mouse or touch) in physical pixels.
    pub fn pointer_down(&mut self, x: f32, y: f32) {
        self.ui.pointer_down(x, y);
        self.pointer_down = Some((x, y));
    }

    pub fn pointer_up(&mut self, x: f32, y: f32) {
        self.ui.pointer_up(x, y);
        if let Some(down) = self.pointer_down.take() {
            // A press on a button (the view switch) is the button's, not a jump.
            let s = self.viewport.scale.max(1e-3);
            let on_button = self
                .ui
                .button_rects()
                .any(|r| r.contains([down.0 / s, down.1 / s]));
            if self.game.screen() == Screen::Play && !self.game.is_paused() && !on_button {
                let gesture = Input::from_gesture(down, (x, y), 24.0 * self.viewport.scale);
                self.pending.merge(&gesture);
            }
        }
    }

    /// A swipe from a platform gesture detector.
    pub fn swipe(&mut self, swipe: Swipe) {
        self.pending.swipe = Some(swipe);
    }

    /// Writes the settings to their file, if the session has one (a failure is logged).
    pub fn save_settings(&self) {
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
        let (feet, _) = self.game.player_transform();
        // Paused: the camera holds still too.
        let camera_dt = if self.game.is_paused() { 0.0 } else { dt };
        let want = if self.settings.close_camera { 1.0 } else { 0.0 };
        let step = camera_dt.max(0.0) / CAMERA_SWITCH_S;
        self.close = if self.close < want {
            (self.close + step).min(want)
        } else {
            (self.close - step).max(want)
        };
        let k = self.close * self.close * (3.0 - 2.0 * self.close);
        self.camera.offset = FOLLOW_OFFSET.lerp(CLOSE_OFFSET, k);
        self.camera.look_offset = FOLLOW_LOOK.lerp(CLOSE_LOOK, k);
        let lerp = |a: f32, b: f32| a + (b - a) * k;
        self.camera.eye.omega = lerp(FollowCamera::EYE_OMEGA, CLOSE_EYE_OMEGA);
        self.camera.look.omega = lerp(FollowCamera::LOOK_OMEGA, CLOSE_LOOK_OMEGA);
        let (target, yaw) = camera_target(&self.game, k);
        self.camera
            .update(camera_dt, target, yaw, &CHARACTER.capsule_at(feet, 1.0));
        self.showroom.set_subject(self.shown_subject());
        self.showroom
            .update(camera_dt, &self.game, &self.camera, &self.ui, &viewport);
        let aspect = viewport.width as f32 / viewport.height.max(1) as f32;
        let (centre, radius) = CHARACTER.sphere_at(feet);
        self.character_visible = self.sphere_visible(centre, radius, aspect);
        if self.character_visible {
            self.animate(character);
        }
        self.light.position = self.showroom.light();
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
        if outcome.camera_toggled {
            self.toggle_camera();
        }
        if outcome.settings_changed {
            self.save_settings();
        }
        // The shading tier: what the frame needs and the frame budget.
        if self.governor.tiers().model(0) != self.shading() {
            self.governor.retier(Tiers::for_choice(self.shading()));
        }
        self.needs = Needs::of_character(
            self.view().view_proj(aspect),
            feet,
            self.light.position,
            self.light.intensity,
        );
        self.governor.select(self.needs);
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
            let Some(c) = self.clip(clip).and_then(|i| character.animations.get(i)) else {
                continue;
            };
            let t = if clip == Clip::Death as usize {
                // Played once, then held.
                anim.time[k].min(c.duration.max(0.0))
            } else if c.duration > 0.0 {
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

    /// The character's clip for the runner's clip `clip` ([`Clip`] as a number): the one found
    /// for it, else (a character without one) the run for a jump, the idle for a death, and
    /// the run's first frame for an idle.
    fn clip(&self, clip: usize) -> Option<usize> {
        use dermis_engine::anim::ClipRole as Role;
        let c = &self.clips;
        match clip {
            x if x == Clip::Idle as usize => c.get(Role::Idle).or(c.get(Role::Run)),
            x if x == Clip::Run as usize => c.get(Role::Run),
            x if x == Clip::Jump as usize => c.get(Role::Jump).or(c.get(Role::Run)),
            x if x == Clip::Death as usize => c.get(Role::Death).or(c.get(Role::Idle)),
            _ => None,
        }
    }

    /// What the showroom shows this frame: the head where it is offered, chosen and the
    /// menu is up; else the runner.
    pub fn shown_subject(&self) -> Subject {
        if is_showroom(self.game.screen()) {
            self.gui.subject()
        } else {
            Subject::Runner
        }
    }

    /// This frame's packet for the GPU side (the extract step: plain data, no GPU object).
    /// `head`: the showroom's scanned head, when the GPU side holds it; `settled`: every
    /// pipeline must be ready (play). It describes the whole frame (the UI's vertices with
    /// their version, every prop placed) and changes nothing here.
    pub fn extract<'a>(
        &'a self,
        character: &'a Model,
        head: Option<&'a ShowroomHead>,
        settled: bool,
    ) -> FramePacket<'a> {
        let aspect = self.viewport.width as f32 / self.viewport.height.max(1) as f32;
        let (id, subject) = match head.filter(|_| self.showroom.subject() == Subject::Head) {
            Some(head) => {
                let (feet, _) = self.game.player_transform();
                let pose = SubjectPose {
                    model: &head.model,
                    pose: &head.pose,
                    world: head_matrix(feet),
                };
                (HEAD, Some(pose))
            }
            None => {
                let pose = SubjectPose {
                    model: character,
                    pose: &self.pose,
                    world: self.game.player_matrix() * self.fit,
                };
                (SubjectId::CHARACTER, self.character_visible.then_some(pose))
            }
        };
        let view = self.view();
        FramePacket {
            viewport: (self.viewport.width, self.viewport.height),
            view: FrameView {
                view_proj: view.view_proj(aspect),
                camera_pos: view.eye,
                light: self.light,
                exposure: EXPOSURE,
            },
            draw: self.draw_set(),
            subject_id: id,
            subject,
            props: &self.props,
            ui: self.ui.vertices(),
            settled,
        }
    }

    /// What to draw: the character with this frame's tier ([`Session::drawn_model`]); the
    /// scanned head alone, on the clear background, while the showroom shows it.
    pub fn draw_set(&self) -> DrawSet {
        DrawSet {
            shading: Some(self.drawn_model()),
            character: true,
            props: self.showroom.subject() != Subject::Head,
            ui: true,
        }
    }
}

/// What the follow camera tracks, `close` (0..1) into the close-up: the wide camera follows
/// the runner's feet on the ground half-way towards its lane ([`Game::camera_target`]); the
/// close-up, whose view at the runner is narrow, follows it all the way, up into its jumps
/// too (so the head stays in the picture).
fn camera_target(game: &Game, close: f32) -> (Vec3, f32) {
    let (target, yaw) = game.camera_target();
    let (feet, _) = game.player_transform();
    (target + (feet - target) * close, yaw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_session_schedules_tiers_under_its_frame_budget() {
        let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
        let mut s = Session::new(&model, 1, None, true);
        // A screen-space model off the governor's front: its cheaper tiers are the front's
        // one-pass models.
        let front = crate::governor::front();
        let chosen = ShadingModel::ALL
            .into_iter()
            .find(|m| m.effects().screen_space && !front.contains(m))
            .expect("a screen-space model off the front");
        s.settings.set_shading_model(chosen);
        let vp = Viewport {
            width: 640,
            height: 360,
            scale: 1.0,
            insets: Insets::default(),
        };
        let dt = 1.0 / 60.0;
        let frames = |s: &mut Session, n: usize, cost_ms: f64| {
            for _ in 0..n {
                s.update(dt, &model, vp);
                s.record_frame(cost_ms, dt as f64);
            }
        };
        frames(&mut s, 30, 5.0);
        // The tiers follow the player's choice; in view and lit, the chosen model is drawn.
        let tiers = s.governor.tiers();
        let tiers = tiers.as_slice();
        assert!(tiers.len() >= 2 && tiers[0] == chosen, "{tiers:?}");
        assert!(tiers[1..].iter().all(|m| !m.effects().screen_space));
        let cheaper = tiers[1];
        assert!(s.needs.lit && s.needs.coverage > 0.0, "{:?}", s.needs);
        assert_eq!(s.tier(), 0, "{:?}", s.needs);
        // Over budget: one tier cheaper (and no other change within the window); the
        // choice itself is kept.
        frames(&mut s, 40, 40.0);
        assert_eq!((s.tier(), s.drawn_model()), (1, cheaper));
        assert_eq!(s.draw_set().shading, Some(cheaper));
        assert_eq!(s.shading(), chosen);
        // A new choice starts the governor over with its own tiers (switches kept).
        s.configure_governor(GovernorConfig::for_fps(60.0), false, true);
        s.key(Key::NextModel);
        frames(&mut s, 1, 40.0);
        assert_eq!(s.governor.tiers().model(0), s.shading());
        assert!(!s.governor.enabled && s.governor.scheduling);
        assert_eq!(s.tier(), 0);
    }

    #[test]
    fn the_player_is_visible_and_things_behind_the_camera_are_not() {
        let model = dermis_engine::asset::shapes::plane_model(0.5, 0.01);
        let mut s = Session::new(&model, 1, None, true);
        let vp = Viewport {
            width: 640,
            height: 360,
            scale: 1.0,
            insets: Insets::default(),
        };
        // The bot starts the run after half a second; the camera leaves the menu's showroom
        // for the follow camera within the blend: two seconds are well into play.
        for _ in 0..120 {
            s.update(1.0 / 60.0, &model, vp);
        }
        assert_eq!(s.game.screen(), Screen::Play);
        assert_eq!(s.view(), s.camera.pose());
        assert!(s.character_visible);
        let (feet, _) = s.game.player_transform();
        assert!(s.sphere_visible(feet + Vec3::Y, 1.0, 16.0 / 9.0));
        // 50 m behind the camera, and far to the side: culled, so neither animated nor uploaded.
        let eye = s.camera.eye.value;
        assert!(!s.sphere_visible(eye - Vec3::Z * 50.0, 1.2, 16.0 / 9.0));
        assert!(!s.sphere_visible(eye + Vec3::X * 500.0, 1.2, 16.0 / 9.0));
    }
}

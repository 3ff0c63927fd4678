//! Blob (contact) shadows in the game, rendered on the real renderer headless: the ground
//! just under the runner darkens and the ground far away does not; the character's own
//! pixels — the subsurface marker's path included — are untouched; a jumping runner's blob
//! is lighter than a standing one's. Each comparison renders the same uploaded frame twice,
//! shadows off and on.

use crate::common;
use dermis_engine::render::passes::PassId;

use std::path::Path;

use common::Rig;
use dermis_engine::camera::look_at;
use dermis_engine::render::{Gpu, RgbaImage, OFFSCREEN_FORMAT, SHADOW_MAP_SIZE};
use dermis_engine::scene::{key_light, FrameView, SceneAssets, EXPOSURE};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::Key;
use dermis_game::governor::GovernorConfig;
use glam::{Mat4, Vec3, Vec4Swizzles};

const W: u32 = 320;
const H: u32 = 180;

/// A game with the blob shadows on, always drawing `model`, rendering at W×H.
fn blob_rig(model: ShadingModel) -> Rig {
    let mut rig = Rig::new(W, H);
    assert!(
        rig.gg.renderer.is_on(PassId::blobs),
        "the game enables blob shadows"
    );
    rig.session.settings.set_shading_model(model);
    // The blobs alone: the key light's shadow map off (the character casts nothing), so the
    // character's pixels are told apart from the ground it would shadow.
    let (gpu, renderer) = (&rig.gpu, &mut rig.gg.renderer);
    renderer.set_shadow_scene(gpu, false, &[], None, SHADOW_MAP_SIZE);
    // Always the chosen model (no frame-budget or coverage tiers).
    rig.session
        .configure_governor(GovernorConfig::for_fps(60.0), false, false);
    rig
}

/// The blob tests' camera and shots on the shared rig.
impl Rig {
    /// The test's own camera, behind, beside and above the feet (whatever the game's screens
    /// do with theirs): (view-projection, eye).
    fn test_camera(&self) -> (Mat4, Vec3) {
        let feet = self.feet();
        let eye = feet + Vec3::new(0.8, 2.0, -2.8);
        let m = look_at(
            eye,
            feet + Vec3::new(0.0, 0.4, 0.8),
            0.9,
            W as f32 / H as f32,
        );
        (m, eye)
    }

    /// Advances one 60 Hz frame and prepares it, seen from [`Self::camera`].
    fn step(&mut self) {
        self.session
            .update(1.0 / 60.0, &self.assets.character, self.viewport());
        let (view_proj, camera_pos) = self.test_camera();
        self.camera = Some(FrameView {
            view_proj,
            camera_pos,
            light: key_light(self.feet()),
            exposure: EXPOSURE,
        });
        self.prepare(|_| {});
    }

    /// The prepared frame (without the UI), shadows on or off, the character drawn or not.
    fn shoot(&mut self, shadows: bool, character: bool) -> RgbaImage {
        self.gg.renderer.switch(PassId::blobs, shadows);
        let image = self.shoot_frame(character);
        self.gg.renderer.switch(PassId::blobs, true);
        image
    }

    /// The pixel where the world point `p` lands this frame.
    fn pixel(&self, p: Vec3) -> (u32, u32) {
        let clip = self.test_camera().0 * p.extend(1.0);
        let ndc = clip.xy() / clip.w;
        let x = ((ndc.x + 1.0) * 0.5 * W as f32) as u32;
        let y = ((1.0 - ndc.y) * 0.5 * H as f32) as u32;
        assert!(x < W && y < H, "{p} is off screen");
        (x, y)
    }

    /// The runner's feet on the ground.
    fn feet(&self) -> Vec3 {
        let (feet, _) = self.session.game.player_transform();
        Vec3::new(feet.x, 0.0, feet.z)
    }
}

fn luma(img: &RgbaImage, (x, y): (u32, u32)) -> f32 {
    let i = ((y * img.width + x) * 4) as usize;
    let p = &img.pixels[i..i + 3];
    0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32
}

/// Ground points around the feet: either side and behind (towards the camera).
const AROUND_FEET: [Vec3; 3] = [
    Vec3::new(0.3, 0.0, 0.0),
    Vec3::new(-0.3, 0.0, 0.0),
    Vec3::new(0.0, 0.0, -0.3),
];

/// Mean darkening (1 − on/off luma) at the ground points around the feet.
fn darkening(rig: &Rig, off: &RgbaImage, on: &RgbaImage) -> f32 {
    let feet = rig.feet();
    if std::env::var_os("BLOB_DUMP").is_some() {
        off.save_png(Path::new("/tmp/blob_off.png")).unwrap();
        on.save_png(Path::new("/tmp/blob_on.png")).unwrap();
        let n = off
            .pixels
            .iter()
            .zip(&on.pixels)
            .filter(|(a, b)| a != b)
            .count();
        println!("differing bytes {n}, feet at {:?}", rig.pixel(feet));
    }
    let mut sum = 0.0;
    for d in AROUND_FEET {
        let px = rig.pixel(feet + d);
        let (a, b) = (luma(off, px), luma(on, px));
        assert!(a > 5.0, "the ground at {px:?} is lit ({a})");
        sum += 1.0 - b / a;
    }
    sum / AROUND_FEET.len() as f32
}

/// The character's pixels: those that differ with it drawn, away from its edges.
fn character_pixels(with: &RgbaImage, without: &RgbaImage) -> Vec<usize> {
    let differs = |x: u32, y: u32| {
        let i = ((y * W + x) * 4) as usize;
        with.pixels[i..i + 3] != without.pixels[i..i + 3]
    };
    let mut out = Vec::new();
    for y in 2..H - 2 {
        for x in 2..W - 2 {
            if (-2i32..=2).all(|dy| {
                (-2i32..=2).all(|dx| differs((x as i32 + dx) as u32, (y as i32 + dy) as u32))
            }) {
                out.push((y * W + x) as usize);
            }
        }
    }
    out
}

/// (a) + (b) for one model: ground under the runner darker, far ground and the character
/// itself unchanged. Returns the darkening around the feet.
fn shadow_darkens_only_the_ground_under_the_runner(model: ShadingModel, split: bool) -> f32 {
    let mut rig = blob_rig(model);
    assert!(rig.gg.renderer.is_on(PassId::subsurface));
    assert_eq!(model.effects().screen_space, split);
    for _ in 0..5 {
        rig.step();
    }
    let off = rig.shoot(false, true);
    let on = rig.shoot(true, true);
    let bare = rig.shoot(false, false);
    let dark = darkening(&rig, &off, &on);
    println!("{}: darkening around the feet {dark:.3}", model.name());
    assert!(dark > 0.15, "{}: the blob darkens by {dark}", model.name());
    // Far ground (4 m to the side, 6 m ahead) and the sky-side top row: unchanged.
    let feet = rig.feet();
    for far in [
        rig.pixel(feet + Vec3::new(3.0, 0.0, 3.0)),
        rig.pixel(feet + Vec3::new(0.0, 0.0, 8.0)),
        (W / 2, 2),
    ] {
        assert_eq!(luma(&off, far), luma(&on, far), "{far:?} changed");
    }
    // The character's own pixels: identical with and without the blobs.
    let body = character_pixels(&off, &bare);
    assert!(
        body.len() > 200,
        "the character covers {} pixels",
        body.len()
    );
    let changed = body
        .iter()
        .filter(|&&i| off.pixels[i * 4..i * 4 + 4] != on.pixels[i * 4..i * 4 + 4])
        .count();
    assert_eq!(
        changed,
        0,
        "{}: {changed} character pixels changed",
        model.name()
    );
    dark
}

#[test]
fn the_blob_darkens_the_ground_under_the_runner_only() {
    shadow_darkens_only_the_ground_under_the_runner(ShadingModel::Ward, false);
}

/// (b) The subsurface frame (two targets, alpha the skin marker): the character's pixels —
/// gathered by the subsurface pass — are unchanged, and the blob darkens the ground as much
/// as in a one-pass frame, so a governor tier change does not make it jump.

#[test]
fn the_blob_keeps_the_subsurface_marker_intact() {
    let split = shadow_darkens_only_the_ground_under_the_runner(ShadingModel::Burley, true);
    let one_pass = shadow_darkens_only_the_ground_under_the_runner(ShadingModel::Ward, false);
    assert!(
        (split - one_pass).abs() < 0.05,
        "darkening {split} (subsurface frame) vs {one_pass} (one pass)"
    );
}

#[test]
fn a_jumping_runners_blob_is_lighter_than_a_standing_ones() {
    let mut rig = blob_rig(ShadingModel::Ward);
    // Start a run, with no obstacle in the way.
    rig.session.key(Key::Jump);
    rig.step();
    rig.session.game.debug_clear_obstacles_until(1e4);
    for _ in 0..30 {
        rig.step();
    }
    assert!(!rig.session.game.is_airborne());
    let (off, on) = (rig.shoot(false, true), rig.shoot(true, true));
    let standing = darkening(&rig, &off, &on);
    rig.session.key(Key::Jump);
    let mut frames = 0;
    while rig.session.game.player_position().y < 0.5 {
        rig.step();
        frames += 1;
        assert!(frames < 60, "the runner never got 0.5 m up");
    }
    let (off, on) = (rig.shoot(false, true), rig.shoot(true, true));
    let jumping = darkening(&rig, &off, &on);
    println!(
        "darkening standing {standing:.3}, jumping ({:.2} m up) {jumping:.3}",
        rig.session.game.player_position().y
    );
    assert!(standing > 0.15, "standing: {standing}");
    assert!(
        jumping < 0.7 * standing && jumping >= 0.0,
        "jumping {jumping} vs standing {standing}"
    );
}

/// The project rule: no pipeline for an effect nothing uses. Nothing casting (only the floor
/// and walls loaded): no blob pipeline. A scene with casters: one, plus the two-target
/// variant only in a renderer that has the subsurface pass.
#[test]
fn blob_pipelines_exist_only_when_something_casts() {
    use dermis_engine::render::{LiveObjects, PipelineSet, Renderer};
    use dermis_engine::scene::PropKind;
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets = SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None)
        .unwrap_or_else(|e| panic!("{e}"));
    let pipelines = || LiveObjects::read(&gpu.device).render_pipelines;
    // Floor and walls only: nothing casts.
    let mut bare = Renderer::with_pipelines(&gpu, OFFSCREEN_FORMAT, &PipelineSet::game());
    for (kind, model) in &assets.props {
        if matches!(kind, PropKind::FloorTile | PropKind::Wall) {
            bare.load_prop(&gpu, *kind, model);
        }
    }
    let before = pipelines();
    assert!(!bare.enable(&gpu, PassId::blobs) && !bare.is_on(PassId::blobs));
    assert_eq!(pipelines(), before);
    // The game's scene, with and without the subsurface pass.
    let one_pass = PipelineSet {
        models: vec![ShadingModel::Ward],
        unlit: false,
    };
    for (set, built) in [(PipelineSet::game(), 2), (one_pass, 1)] {
        let mut r = Renderer::with_pipelines(&gpu, OFFSCREEN_FORMAT, &set);
        r.load_scene(&gpu, (&assets.character, &assets.roles), &assets.props)
            .unwrap();
        let before = pipelines();
        assert!(r.enable(&gpu, PassId::blobs) && r.is_on(PassId::blobs));
        assert_eq!(pipelines() - before, built, "{set:?}");
        // Enabling again builds nothing more.
        assert!(r.enable(&gpu, PassId::blobs));
        assert_eq!(pipelines() - before, built);
    }
}

//! The key light's shadow map in the game, rendered on the real renderer headless: the
//! runner's shadow falls on the floor where the light puts it, the runner shadows itself, and
//! a shadow only ever darkens (the same uploaded frame rendered with the character casting and
//! with nothing casting). Then the pre-integrated tier's penumbra against the path-traced
//! shadow edges, which the measurement scenes cast through this same map with a real occluder.

use crate::common;

use common::Rig;
use dermis_engine::camera::look_at;
use dermis_engine::render::{Gpu, RgbaImage, SHADOW_MAP_SIZE};
use dermis_engine::scene::{key_light, FrameView, SubjectId, EXPOSURE};
use dermis_engine::shading::ShadingModel;
use dermis_game::governor::GovernorConfig;
use dermis_measure::ground_truth::{self as reference, metric, ReferenceSet, Scene};
use dermis_measure::scenes::SceneRenderer;
use glam::{Mat4, Vec3, Vec4Swizzles};

const W: u32 = 320;
const H: u32 = 240;

impl Rig {
    fn feet_on_ground(&self) -> Vec3 {
        let (feet, _) = self.session.game.player_transform();
        Vec3::new(feet.x, 0.0, feet.z)
    }

    /// A camera behind, left of and above the runner that sees the floor its shadow falls on.
    fn shadow_camera(&self) -> (Mat4, Vec3) {
        let feet = self.feet_on_ground();
        let eye = feet + Vec3::new(-1.2, 2.4, -3.6);
        let m = look_at(
            eye,
            feet + Vec3::new(-0.3, 0.5, -0.5),
            1.0,
            W as f32 / H as f32,
        );
        (m, eye)
    }

    /// This frame with the character casting or with nothing casting.
    fn shot(&mut self, casts: bool, character: bool) -> RgbaImage {
        let size = SHADOW_MAP_SIZE;
        self.gg
            .renderer
            .set_shadow_scene(&self.gpu, casts, &[], None, size);
        let (view_proj, camera_pos) = self.shadow_camera();
        self.camera = Some(FrameView {
            view_proj,
            camera_pos,
            light: key_light(self.feet_on_ground()),
            exposure: EXPOSURE,
        });
        self.shoot_frame(character)
    }

    fn pixel_of(&self, p: Vec3) -> (u32, u32) {
        let clip = self.shadow_camera().0 * p.extend(1.0);
        let ndc = clip.xy() / clip.w;
        let x = ((ndc.x + 1.0) * 0.5 * W as f32) as u32;
        let y = ((1.0 - ndc.y) * 0.5 * H as f32) as u32;
        assert!(x < W && y < H, "{p} is off screen");
        (x, y)
    }
}

fn luma(img: &RgbaImage, i: usize) -> f32 {
    let p = &img.pixels[4 * i..4 * i + 3];
    0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32
}

fn rig(model: ShadingModel) -> Rig {
    let mut rig = Rig::new(W, H);
    rig.session.settings.set_shading_model(model);
    rig.session
        .configure_governor(GovernorConfig::for_fps(60.0), false, false);
    rig.update(1.0 / 60.0);
    rig
}

#[test]
fn the_runner_casts_on_the_floor_and_on_itself_and_shadows_only_darken() {
    for model in [ShadingModel::Ward, ShadingModel::Preintegrated] {
        let mut rig = rig(model);
        let lit = rig.shot(false, true);
        let shadowed = rig.shot(true, true);
        let bare = rig.shot(false, false);
        // Where the light's ray through the chest meets the floor.
        let feet = rig.feet_on_ground();
        let light = key_light(feet).position;
        let chest = feet + Vec3::Y * 1.2;
        let ground = chest + (chest - light) * (chest.y / (light.y - chest.y));
        let (x, y) = rig.pixel_of(ground);
        let i = (y * W + x) as usize;
        let (before, after) = (luma(&lit, i), luma(&shadowed, i));
        println!("{model}: floor under the chest's shadow {before:.1} → {after:.1}");
        assert!(after < 0.8 * before, "{model}: {before} → {after}");
        // Nothing gets brighter; the character's own pixels darken somewhere (self-shadow).
        let n = (W * H) as usize;
        let brighter = (0..n)
            .filter(|&i| luma(&shadowed, i) > luma(&lit, i) + 1.5)
            .count();
        assert_eq!(brighter, 0, "{model}: pixels brightened by a shadow");
        let body =
            (0..n).filter(|&i| lit.pixels[4 * i..4 * i + 3] != bare.pixels[4 * i..4 * i + 3]);
        let (mut on_body, mut darker) = (0, 0);
        for i in body {
            on_body += 1;
            darker += usize::from(luma(&shadowed, i) < luma(&lit, i) - 8.0);
        }
        println!("{model}: {darker} of {on_body} character pixels in its own shadow");
        assert!(
            on_body > 500,
            "{model}: the runner is on screen ({on_body})"
        );
        assert!(darker > 0, "{model}: the runner shadows itself");
        assert!(darker < on_body / 2, "{model}: acne: {darker} of {on_body}");
    }
}

/// skin1, the darkest test material (skin-dark, A 0.185 / 0.083 / 0.046: its references'
/// scenes are smaller, so the edge's blade is ~6 mm above the medium — closer than the penumbra
/// map's 1 cm gap once was, which gave no penumbra at all: mean |ln| 3.76) and the widest
/// (marble, ℓ ≈ 10 mm: its scene is the largest, and the plane's box, flat, once lost every
/// crossing with the camera's frustum to rounding, so no penumbra map was drawn: 3.95).
fn edge_sets() -> Vec<(dermis_engine::shading::Material, ReferenceSet)> {
    dermis_measure::bake::install();
    let [skin1, _] = reference::acceptance_materials();
    let [dark, _, marble] = reference::test_materials();
    [skin1, dark, marble]
        .into_iter()
        .map(|m| {
            let set = ReferenceSet::load(&reference::file_for(&reference::default_dir(), &m.name))
                .unwrap_or_else(|e| panic!("{e}"));
            (m, set)
        })
        .collect()
}

#[test]
fn the_preintegrated_penumbra_bleeds_like_the_path_traced_shadow_edge() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let mut scenes = SceneRenderer::new(&gpu);
    for (m, set) in edge_sets() {
        for theta in [0.0, 45.0] {
            let entry = set
                .entry(&Scene::ShadowEdge { theta_deg: theta })
                .expect("reference has the edge");
            let pre = scenes
                .render(
                    &gpu,
                    ShadingModel::Preintegrated,
                    &m,
                    &entry.scene,
                    &entry.edges,
                )
                .unwrap();
            // Hard cases: the edge lies on a pixel boundary (the view is centred on it, an even
            // number of pixels wide); nothing is NaN or negative.
            assert!(pre.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
            let s = metric::score(&pre, entry);
            let ward = metric::score(
                &scenes
                    .render(&gpu, ShadingModel::Ward, &m, &entry.scene, &entry.edges)
                    .unwrap(),
                entry,
            );
            let noise = metric::score(&entry.values, entry).ref_rel_se_all;
            println!(
                "{} θ = {theta}°: preintegrated {:.3} (integrated {:.3}), ward {:.3}",
                m.name, s.mean_log_all, s.integrated_all, ward.mean_log_all
            );
            // The bound is 0.5; the shadow map's own tent and the oblique forward shift
            // the table leaves out cost ~0.1–0.2.
            assert!(
                s.mean_log_all <= 0.3 + 3.0 * noise,
                "{} θ {theta}: {s:?}",
                m.name
            );
            // No energy gain: what bleeds into the shadow is what the lit side loses.
            assert!(s.integrated_all <= 0.05, "{} θ {theta}: {s:?}", m.name);
            // A hard shadow cannot carry light across the edge: far worse on the same metric.
            assert!(
                ward.mean_log_all > 5.0 * s.mean_log_all,
                "{} θ {theta}: {ward:?}",
                m.name
            );
        }
    }
}

#[test]
fn shadowed_frames_stay_finite_and_non_negative_in_f16_under_every_model() {
    use dermis_engine::scene::SceneAssets;
    use dermis_engine::still::{Shot, StillRenderer};
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets = SceneAssets::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"),
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut still =
        StillRenderer::with_format(&gpu, &assets, 160, 180, wgpu::TextureFormat::Rgba16Float)
            .unwrap_or_else(|e| panic!("{e}"));
    // Lights from above the head (the face in its own shadow), grazing from the side (every
    // silhouette a shadow edge, the terminator across the body) and from behind and below
    // (translucency tested at the far side).
    let lights = [
        Vec3::new(0.05, 4.0, 0.05),
        Vec3::new(6.0, 1.0, 0.0),
        Vec3::new(-0.5, 0.3, -3.0),
    ];
    for model in ShadingModel::ALL {
        for light in lights {
            let shot = Shot {
                light: Some(light),
                clip: 1,
                time: 0.2,
                ..Shot::new(model, dermis_engine::shading::material::SKIN1)
            };
            let px = still.render_radiance(&gpu, &assets, &shot).unwrap();
            let bad = px
                .iter()
                .filter(|p| p[..3].iter().any(|v| !v.is_finite() || *v < 0.0))
                .count();
            assert_eq!(
                bad, 0,
                "{model} light {light}: {bad} NaN/inf/negative pixels"
            );
            assert!(px.iter().any(|p| p[0] > 0.0), "{model}: a black frame");
        }
    }
}

/// A ball of skin lit from the side, drawn through the real renderer with the ball casting
/// into the key light's shadow map and with nothing casting: a convex body shadows nothing
/// of itself, so where it faces the light the two frames agree. Near the terminator the
/// ball turns away from the light and its depth in the map steps by tens of texels' worth
/// between neighbours — the penumbra map must not take such a smooth, steep surface for a
/// caster's edge and bleed or darken around it (the head's false edges, issue 26).
#[test]
fn a_ball_lit_at_grazing_incidence_has_no_penumbra() {
    use dermis_engine::anim::Pose;
    use dermis_engine::asset::shapes::sphere_model;
    use dermis_engine::render::{Offscreen, Renderer};
    use dermis_engine::scene::{DrawSet, FramePacket, Light, Roles, SubjectPose};
    use dermis_engine::shading::material::SKIN1;
    const N: u32 = 256;
    let (r, far) = (0.05f32, 1000.0f32);
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let mut renderer = Renderer::new(&gpu, wgpu::TextureFormat::Rgba16Float);
    renderer.set_clear(wgpu::Color::BLACK);
    renderer.resize(&gpu, (N, N));
    let target = Offscreen::with_format(&gpu, N, N, wgpu::TextureFormat::Rgba16Float);
    // Thick enough that nothing shows through it from behind.
    let model = sphere_model(r, 2.0 * r);
    renderer
        .load_character(&gpu, &model, &Roles::medium(&SKIN1))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut pose = Pose::new(&model);
    pose.update_world(&model);
    // The light along +x (a little above), the camera along +z: the terminator runs down
    // the middle of the image, the lit half on the right.
    let to_light = Vec3::new(1.0, 0.15, 0.0).normalize();
    let view = glam::camera::rh::view::look_at_mat4(Vec3::Z, Vec3::ZERO, Vec3::Y);
    let h = 1.05 * r;
    let proj = glam::camera::rh::proj::directx::orthographic(-h, h, -h, h, 0.01, 10.0);
    let frame_view = FrameView {
        view_proj: proj * view,
        camera_pos: Vec3::Z,
        light: Light {
            position: to_light * far,
            intensity: far * far,
            color: Vec3::ONE,
            ambient: Vec3::ZERO,
        },
        exposure: 1.0,
    };
    let mut shot = |casts: bool| {
        renderer.set_shadow_scene(&gpu, casts, &[], None, SHADOW_MAP_SIZE);
        let packet = FramePacket {
            subject: Some(SubjectPose {
                model: &model,
                pose: &pose,
                world: Mat4::IDENTITY,
            }),
            ..FramePacket::new(
                (N, N),
                frame_view,
                DrawSet {
                    shading: Some(ShadingModel::Preintegrated),
                    character: true,
                    props: false,
                    ui: false,
                },
            )
        };
        let frame = renderer.prepare(&gpu, &packet);
        assert_eq!(frame.shadow.drawn, casts);
        renderer.draw_offscreen(&gpu, &target, &frame).unwrap();
        target.read_f16(&gpu)
    };
    let (cast, free) = (shot(true), shot(false));
    // Per band of n·l on the lit side seen at n·v ≥ 0.3: the largest change of the red
    // channel (the one the penumbra spreads furthest).
    let bands = [0.02f32, 0.05, 0.1, 0.2, 0.4, 1.01];
    let mut worst = [0.0f32; 5];
    let mut counts = [0usize; 5];
    for (i, (a, b)) in cast.iter().zip(&free).enumerate() {
        let x = ((i as u32 % N) as f32 + 0.5) / N as f32 * 2.0 * h - h;
        let y = h - ((i as u32 / N) as f32 + 0.5) / N as f32 * 2.0 * h;
        let q = r * r - x * x - y * y;
        if q <= 0.0 || q.sqrt() / r < 0.3 {
            continue;
        }
        let n = Vec3::new(x, y, q.sqrt()) / r;
        let nl = n.dot(to_light);
        let Some(k) = bands.windows(2).position(|w| nl >= w[0] && nl < w[1]) else {
            continue;
        };
        counts[k] += 1;
        worst[k] = worst[k].max((a[0] / b[0].max(1e-6) - 1.0).abs());
    }
    println!("n·l bands {bands:?}: pixels {counts:?}, largest |cast/free − 1| {worst:?}");
    assert!(counts.iter().all(|&c| c > 20), "{counts:?}");
    for (k, w) in worst.iter().enumerate() {
        assert!(
            *w < 0.05,
            "n·l {}–{}: the ball's own map changes its lit side by {w}",
            bands[k],
            bands[k + 1]
        );
    }
}

/// The showroom's close-up (the game's own camera and orbiting key light, the renderer's own
/// fit around the posed runner, prepared on the real renderer): the key light's map is
/// cropped to the shadows the camera can see — wherever the light is, its texel at the runner
/// is at most 0.7 of the uncropped 3 mm (the whole body in a sphere's margin) — and every point of the runner the camera sees, and of the floor
/// its shadow can fall on, that is shadowed stays inside the map.
#[test]
fn the_showroom_close_up_crops_the_shadow_map_to_what_it_sees() {
    use dermis_engine::render::ShadowView;
    use dermis_engine::scene::{Light, CHARACTER};
    use dermis_engine::ui::Rect;
    use dermis_game::app::showroom::{framing, orbit_light, LIGHT_PERIOD_S};
    let mut rig = rig(ShadingModel::DEFAULT);
    let feet = rig.feet_on_ground();
    let (centre, r) = CHARACTER.sphere_at(feet);
    // The uncropped fit: the character's sphere and the renderer's margin for a pose.
    let r = 1.25 * r;
    let aspect = W as f32 / H as f32;
    let pose = framing(feet, aspect, Rect::new(0.0, 0.0, 0.62, 1.0));
    let camera = pose.view_proj(aspect);
    let mut texels = Vec::new();
    for k in 0..16 {
        let light = orbit_light(feet, LIGHT_PERIOD_S * k as f32 / 16.0);
        rig.camera = Some(FrameView {
            view_proj: camera,
            camera_pos: pose.eye,
            light: Light {
                position: light,
                ..key_light(feet)
            },
            exposure: EXPOSURE,
        });
        rig.prepare(|_| {});
        let crop: ShadowView = rig.frame.expect("prepared").shadow;
        if k == 0 {
            let (lo, hi) = rig.gg.renderer.subject_box(SubjectId::CHARACTER).unwrap();
            println!("the posed runner's box: {lo} .. {hi}");
        }
        let fit = ShadowView::fit(light, centre, r, SHADOW_MAP_SIZE);
        assert!(
            crop.drawn && crop.texel_m <= fit.texel_m * 1.001,
            "light {light}"
        );
        texels.push((fit.texel_m * 1e3, crop.texel_m * 1e3));
        // Points on a grid of the sphere and of the floor around it, those the camera sees
        // whose segment to the light crosses the runner's box: inside the map.
        let (lo, hi) = rig
            .gg
            .renderer
            .subject_box(SubjectId::CHARACTER)
            .expect("the runner was posed");
        let n = 14;
        let f = |a: usize| (a as f32 + 0.5) / n as f32 * 2.0 - 1.0;
        let body =
            (0..n * n * n).map(|q| centre + Vec3::new(f(q % n), f(q / n % n), f(q / (n * n))) * r);
        let floor = (0..n * n).map(|q| feet + Vec3::new(f(q % n), 0.0, f(q / n)) * 3.0 * r);
        for p in body.chain(floor) {
            let seen = camera * p.extend(1.0);
            let s = seen.truncate() / seen.w;
            if seen.w <= 0.0 || s.x.abs() > 1.0 || s.y.abs() > 1.0 || !crosses(p, light, lo, hi) {
                continue;
            }
            let q = crop.view_proj * p.extend(1.0);
            let m = q.truncate() / q.w;
            assert!(
                m.x.abs() <= 1.0 && m.y.abs() <= 1.0,
                "light {light}: {p} off the map"
            );
        }
    }
    println!("showroom, texel at the runner over a turn of the light (mm, sphere fit → posed box crop): {texels:.2?}");
    // Everywhere on the turn (side and behind included, where the sphere's crop gained
    // nothing): at most 0.7 of the uncropped texel.
    assert!(texels.iter().all(|t| t.1 <= 0.7 * t.0), "{texels:?}");
}

/// Whether the segment from `p` to `light` crosses the box `lo..hi` (the slab test).
fn crosses(p: Vec3, light: Vec3, lo: Vec3, hi: Vec3) -> bool {
    let d = light - p;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for i in 0..3 {
        if d[i].abs() < 1e-9 {
            if p[i] < lo[i] || p[i] > hi[i] {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo[i] - p[i]) / d[i], (hi[i] - p[i]) / d[i]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

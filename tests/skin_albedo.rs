//! The albedo map through every skin tier (issue 28): a flat patch of skin whose albedo
//! texture has four quadrants of different albedo, rendered through the real renderer under
//! uniform light (a distant light over the hemisphere, cosine-weighted and stratified), gives
//! back each quadrant's albedo per channel within 2 %, in every spatial tier — the
//! pre-integrated LUT and the screen-space kernels alike. The skin's medium is skin1; the
//! quadrants' albedos are far from its own (0.4 / 0.19 / 0.10).

use dermis_core::asset::shapes::plane_model;
use dermis_core::asset::skin::srgb_to_linear;
use dermis_core::asset::{Model, TextureImage};
use dermis_core::render::{Gpu, Offscreen, Renderer};
use dermis_core::scene::{DrawSet, FramePacket, FrameView, Light, Role, Roles, SubjectPose};
use dermis_core::shading::material::SKIN1;
use dermis_core::shading::subsurface::exit_normalisation;
use dermis_core::shading::{fresnel, ShadingModel};
use glam::{Mat4, Vec3};

const PIXELS: u32 = 128;
/// Half the patch's width (m): 10 cm quadrants, each centre 5 cm from any albedo edge.
const HALF_M: f32 = 0.1;
/// The quadrants' albedos (sRGB bytes of the texture).
const QUADRANTS: [[u8; 3]; 4] = [
    [230, 120, 60],
    [60, 200, 140],
    [150, 90, 220],
    [200, 200, 200],
];

/// The patch: a flat medium with UVs across it and a 64² albedo texture of four quadrants.
fn patch() -> Model {
    let mut m = plane_model(HALF_M, 0.005);
    for prim in m.meshes.iter_mut().flat_map(|m| m.primitives.iter_mut()) {
        for v in &mut prim.vertices {
            v.uv = [
                (v.position[0] / HALF_M + 1.0) * 0.5,
                (v.position[2] / HALF_M + 1.0) * 0.5,
            ];
        }
    }
    let n = 64u32;
    let mut rgba8 = Vec::with_capacity((n * n * 4) as usize);
    for y in 0..n {
        for x in 0..n {
            let q = usize::from(x >= n / 2) + 2 * usize::from(y >= n / 2);
            rgba8.extend_from_slice(&QUADRANTS[q]);
            rgba8.push(255);
        }
    }
    m.textures = vec![TextureImage::rgba(n, n, rgba8, true)];
    m.materials[0].base_color_texture = Some(0);
    m.materials[0].base_color_factor = [1.0; 4];
    m
}

/// Radiance per pixel of the patch seen from straight above under a distant light at
/// incidence cosine `mu` with unit irradiance at normal incidence.
fn frame(
    gpu: &Gpu,
    r: &mut Renderer,
    target: &Offscreen,
    shading: ShadingModel,
    mu: f32,
) -> Vec<[f32; 4]> {
    let model = patch();
    let mut pose = dermis_core::anim::Pose::new(&model);
    pose.update_world(&model);
    let far = 100.0;
    let dir = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), mu, 0.0);
    let view = FrameView {
        view_proj: glam::camera::rh::proj::directx::orthographic(
            -HALF_M, HALF_M, -HALF_M, HALF_M, 0.01, 10.0,
        ) * glam::camera::rh::view::look_at_mat4(Vec3::Y, Vec3::ZERO, Vec3::Z),
        camera_pos: Vec3::Y,
        light: Light {
            position: dir * far,
            intensity: far * far,
            color: Vec3::ONE,
            ambient: Vec3::ZERO,
        },
        exposure: 1.0,
    };
    let draw = DrawSet {
        shading: Some(shading),
        character: true,
        props: false,
        ui: false,
    };
    let packet = FramePacket {
        subject: Some(SubjectPose {
            model: &model,
            pose: &pose,
            world: Mat4::IDENTITY,
        }),
        ..FramePacket::new((PIXELS, PIXELS), view, draw)
    };
    let prepared = r.prepare(gpu, &packet);
    r.draw_offscreen(gpu, target, &prepared);
    target.read_f16(gpu)
}

#[test]
fn a_textured_patch_gives_back_each_texels_albedo_under_uniform_light_in_every_tier() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let format = wgpu::TextureFormat::Rgba16Float;
    let mut r = Renderer::new(&gpu, format);
    r.set_clear(wgpu::Color::BLACK);
    let roles = Roles {
        materials: vec![Role::Skin { pigmented: true }],
        unassigned: Role::Standard,
        optics: SKIN1.clone(),
    };
    r.load_character(&gpu, &patch(), &roles).unwrap();
    // No self-shadow on the flat patch (the light grazes it at the first directions).
    r.set_shadow_scene(&gpu, false, &[], None, 64);
    r.resize(&gpu, (PIXELS, PIXELS));
    let target = Offscreen::with_format(&gpu, PIXELS, PIXELS, format);
    // Radiance toward the normal → exitance: L = M F_t(η, 1) / (π C(η)).
    let eta = SKIN1.eta;
    let to_exitance =
        (std::f64::consts::PI * exit_normalisation(eta)) / fresnel::transmittance_shader(eta, 1.0);
    // Cosine-weighted directions, stratified: μ² uniform.
    const DIRECTIONS: usize = 16;
    let spatial: Vec<ShadingModel> = ShadingModel::ALL
        .into_iter()
        .filter(|m| m.effects().screen_space || m.effects().lut)
        .collect();
    assert!(spatial.len() >= 3, "{spatial:?}");
    for model in spatial {
        let mut sum = [[0.0f64; 3]; 4];
        for i in 0..DIRECTIONS {
            let mu = (((i as f64 + 0.5) / DIRECTIONS as f64).sqrt()) as f32;
            let px = frame(&gpu, &mut r, &target, model, mu);
            for (q, s) in sum.iter_mut().enumerate() {
                // The quadrant's centre (texture x → world x → image column; y → z → row).
                let (qx, qy) = ((q % 2) as f32, (q / 2) as f32);
                let (cx, cy) = (
                    ((0.25 + 0.5 * qx) * PIXELS as f32) as u32,
                    ((0.25 + 0.5 * qy) * PIXELS as f32) as u32,
                );
                let mut mean = [0.0f64; 3];
                let mut n = 0.0;
                for y in cy - 4..cy + 4 {
                    for x in cx - 4..cx + 4 {
                        let p = px[(y * PIXELS + x) as usize];
                        for c in 0..3 {
                            mean[c] += p[c] as f64;
                        }
                        n += 1.0;
                    }
                }
                for c in 0..3 {
                    s[c] += mean[c] / n * to_exitance / mu as f64 / DIRECTIONS as f64;
                }
            }
        }
        for (q, measured) in sum.iter().enumerate() {
            // The image's quadrant q at (x, y) holds the texture's quadrant at (u, v), which
            // the top view may mirror: match by the closest albedo.
            let expected = QUADRANTS
                .iter()
                .map(|t| t.map(srgb_to_linear))
                .min_by(|a, b| {
                    let d = |t: &[f64; 3]| (0..3).map(|c| (t[c] - measured[c]).abs()).sum::<f64>();
                    d(a).total_cmp(&d(b))
                })
                .unwrap();
            for c in 0..3 {
                let rel = measured[c] / expected[c] - 1.0;
                assert!(
                    rel.abs() <= 0.02,
                    "{model}: quadrant {q} channel {c}: albedo {:.4}, texel's {:.4} ({:+.1} %)",
                    measured[c],
                    expected[c],
                    rel * 100.0
                );
            }
        }
    }
}

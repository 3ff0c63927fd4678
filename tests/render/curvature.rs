//! The per-vertex curvature (`asset::curvature`) reaches the pre-integrated shader and moves
//! the light as the physics says: a small ball lit from the side carries red light past its
//! terminator (the LUT's small-sphere rows), the same mesh told it is flat does not. Both are
//! told they are thick (1 m), so no translucency through them stands in for the wrap.

use dermis_engine::asset::curvature;
use dermis_engine::asset::shapes::sphere_model;
use dermis_engine::render::Gpu;
use dermis_engine::scene::face::Camera;
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_measure::face::render::HeadRenderer;
use glam::Vec3;

const R_M: f32 = 0.005;
const SIZE: u32 = 64;

/// The sphere's radiance seen from +z with the light along +x, and which pixels are past the
/// terminator (their point's x < −R/4).
fn render(gpu: &Gpu, flat: bool) -> (Vec<[f32; 3]>, Vec<bool>) {
    let mut model = sphere_model(R_M, 1.0);
    for v in &mut model.meshes[0].primitives[0].vertices {
        if flat {
            v.curvature = [0.0; 4];
        }
    }
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, 0.1),
        target: Vec3::ZERO,
        fov_y_deg: 2.0 * (1.2 * R_M / 0.1f32).atan().to_degrees(),
    };
    let mut renderer = HeadRenderer::new(gpu, &model, &SKIN1, SIZE, SIZE, true).unwrap();
    let light = Vec3::new(0.2, 0.0, 0.0);
    let pixels = renderer
        .radiance(gpu, ShadingModel::Preintegrated, &camera, light, 1.0)
        .unwrap();
    // Pixel columns map to x linearly enough here (a narrow field of view).
    let half = 1.2 * R_M;
    let dark = (0..SIZE * SIZE)
        .map(|i| {
            let x = ((i % SIZE) as f32 + 0.5) / SIZE as f32 * 2.0 * half - half;
            x < -0.25 * R_M
        })
        .collect();
    (pixels, dark)
}

#[test]
fn a_small_sphere_carries_red_past_its_terminator_and_a_flat_one_does_not() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    // The loader's curvature of the sphere is 1/R every way.
    let mut model = sphere_model(R_M, 2.0 * R_M);
    curvature::fill(&mut model.meshes[0].primitives);
    let k = curvature::mean(model.meshes[0].primitives[0].vertices[500].curvature);
    assert!((k * R_M - 1.0).abs() < 0.01, "{k}");

    let (curved, dark) = render(&gpu, false);
    let (flat, _) = render(&gpu, true);
    let sum = |img: &[[f32; 3]], c: usize| -> f32 {
        img.iter()
            .zip(&dark)
            .filter(|(_, d)| **d)
            .map(|(p, _)| p[c])
            .sum()
    };
    let (curved_red, flat_red) = (sum(&curved, 0), sum(&flat, 0));
    // Past the terminator of a 5 mm ball the red light that diffused round it shows; a flat
    // surface facing away from the light has none.
    assert!(
        curved_red > 2.0 * flat_red && curved_red > 0.0,
        "{curved_red} vs {flat_red}"
    );
    // And red leads: the curved sphere's dark side is redder than green there.
    assert!(
        curved_red > sum(&curved, 1),
        "{curved_red} {}",
        sum(&curved, 1)
    );
}

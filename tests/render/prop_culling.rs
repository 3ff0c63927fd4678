//! Props outside the camera's view are neither uploaded nor drawn, and culling them changes
//! no pixel: on the real renderer, a crate placed behind the camera (or far beyond the far
//! plane) adds no triangle and leaves the image byte for byte as it was; the same crate in
//! front of the camera adds its triangles and its pixels.

use std::path::Path;

use dermis_engine::camera::look_at;
use dermis_engine::render::{Gpu, Offscreen, RenderStats, Renderer, RgbaImage, OFFSCREEN_FORMAT};
use dermis_engine::scene::{
    key_light, showroom, DrawSet, FramePacket, FrameView, PropInstance, PropKind, SceneAssets,
    EXPOSURE,
};
use dermis_engine::shading::ShadingModel;
use glam::{Mat4, Vec3};

const W: u32 = 256;
const H: u32 = 144;

struct Scene {
    gpu: Gpu,
    renderer: Renderer,
    target: Offscreen,
}

impl Scene {
    fn new() -> Self {
        let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        let assets = SceneAssets::load(&root, None).unwrap_or_else(|e| panic!("{e}"));
        let mut renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT);
        renderer
            .load_scene(&gpu, (&assets.character, &assets.roles), &assets.props)
            .unwrap_or_else(|e| panic!("{e}"));
        renderer.resize(&gpu, (W, H));
        let target = Offscreen::new(&gpu, W, H);
        Self {
            gpu,
            renderer,
            target,
        }
    }

    /// The showroom plus `extra`, seen from in front of the back wall looking at it.
    fn shoot(&mut self, extra: &[PropInstance]) -> (RenderStats, RgbaImage) {
        let mut props = showroom();
        props.extend_from_slice(extra);
        let eye = Vec3::new(0.0, 1.6, 4.0);
        let view = FrameView {
            view_proj: look_at(eye, Vec3::new(0.0, 1.0, -6.0), 0.9, W as f32 / H as f32),
            camera_pos: eye,
            light: key_light(Vec3::ZERO),
            exposure: EXPOSURE,
        };
        let draw = DrawSet {
            shading: Some(ShadingModel::BASELINE),
            character: false,
            props: true,
            ui: false,
        };
        let packet = FramePacket {
            props: &props,
            ..FramePacket::new((W, H), view, draw)
        };
        let frame = self.renderer.prepare(&self.gpu, &packet);
        let stats = self
            .renderer
            .draw_offscreen(&self.gpu, &self.target, &frame)
            .unwrap();
        (stats, self.target.read(&self.gpu))
    }
}

fn crate_at(x: f32, z: f32) -> PropInstance {
    PropInstance {
        kind: PropKind::Obstacle,
        transform: Mat4::from_translation(Vec3::new(x, 0.0, z)),
    }
}

#[test]
fn props_out_of_view_cost_nothing_and_change_no_pixel() {
    let mut scene = Scene::new();
    let (stats, image) = scene.shoot(&[]);
    assert!(stats.triangles > 0, "the showroom drew nothing");
    // Behind the camera (it looks toward -z from z = 4), and far beyond the far plane.
    for hidden in [
        crate_at(0.0, 9.0),
        crate_at(0.0, -400.0),
        crate_at(300.0, -6.0),
    ] {
        let (s, img) = scene.shoot(&[hidden]);
        assert_eq!(s.triangles, stats.triangles, "{hidden:?} was drawn");
        assert!(img.pixels == image.pixels, "{hidden:?} changed the image");
    }
    // In front of the back wall, in view: its triangles and its pixels.
    let (s, img) = scene.shoot(&[crate_at(0.0, -2.0)]);
    assert!(s.triangles > stats.triangles, "a crate in view was culled");
    let changed = img
        .pixels
        .chunks_exact(4)
        .zip(image.pixels.chunks_exact(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > 200,
        "a crate in view changed only {changed} pixels"
    );
}

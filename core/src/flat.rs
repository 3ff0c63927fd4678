//! A flat semi-infinite medium seen from straight above and lit by a point light at height h:
//! the scene in which each shading model's *rendered* radial exitance is compared with the
//! Monte Carlo reference (`dermis bench shading`). It renders through the character pipeline
//! (a skinned plane with one joint), so the shaders measured are the ones the game runs.

use glam::{Mat4, Vec3};

use crate::anim::Pose;
use crate::asset::{
    Aabb, Material as AssetMaterial, Mesh, Model, Node, Primitive, Skin, Transform, Vertex,
};
use crate::render::{DrawSet, FrameView, Gpu, Light, Offscreen, Renderer};
use crate::shading::{units, Material, ShadingModel};

/// Rendered radiance target size (pixels per side).
pub const PIXELS: u32 = 256;

/// A plane of half-size `half_m` metres in x–z, facing +y, skinned to one joint.
pub fn plane_model(half_m: f32, thickness_m: f32) -> Model {
    let n = 32u32;
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            vertices.push(Vertex {
                position: [(u * 2.0 - 1.0) * half_m, 0.0, (v * 2.0 - 1.0) * half_m],
                normal: [0.0, 1.0, 0.0],
                tangent: [1.0, 0.0, 0.0, 1.0],
                uv: [u, v],
                joints: [0; 4],
                weights: [1.0, 0.0, 0.0, 0.0],
                thickness: thickness_m,
            });
        }
    }
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    let node = |mesh, skin, parent| Node {
        name: None,
        parent,
        children: Vec::new(),
        local: Transform::default(),
        mesh,
        skin,
    };
    Model {
        source: "flat medium".into(),
        nodes: vec![node(None, None, None), node(Some(0), Some(0), None)],
        roots: vec![0, 1],
        meshes: vec![Mesh {
            name: None,
            primitives: vec![Primitive {
                vertices,
                indices,
                material: Some(0),
                bounds: Aabb {
                    min: Vec3::new(-half_m, 0.0, -half_m),
                    max: Vec3::new(half_m, 0.0, half_m),
                },
            }],
        }],
        skins: vec![Skin {
            name: None,
            joints: vec![0],
            inverse_bind: vec![Mat4::IDENTITY],
        }],
        materials: vec![AssetMaterial {
            name: None,
            base_color_factor: [1.0; 4],
            base_color_texture: None,
        }],
        textures: Vec::new(),
        animations: Vec::new(),
    }
}

/// The flat-medium scene, created once and re-rendered per model and material.
pub struct FlatScene {
    pub model: Model,
    renderer: Renderer,
    target: Offscreen,
    pose: Pose,
    half_m: f32,
}

impl FlatScene {
    /// A plane `half_mm` millimetres from its centre to its edges. Its thickness attribute is
    /// set so OSS sees the depth it uses for a semi-infinite medium.
    pub fn new(gpu: &Gpu, half_mm: f64) -> Result<Self, String> {
        let half_m = (half_mm / units::MM_PER_M) as f32;
        let depth_mm = crate::shading::prediction::OSS_SEMI_INFINITE_MM;
        let thickness_m = (depth_mm / (units::MM_PER_M * units::OSS_DEPTH_SCALE)) as f32;
        let model = plane_model(half_m, thickness_m);
        let mut renderer = Renderer::new(gpu, wgpu::TextureFormat::Rgba16Float);
        renderer.load_character(gpu, &model, &crate::shading::material::SKIN1)?;
        renderer.clear = wgpu::Color::BLACK;
        let mut pose = Pose::new(&model);
        pose.update_world(&model);
        let target = Offscreen::with_format(gpu, PIXELS, PIXELS, wgpu::TextureFormat::Rgba16Float);
        Ok(Self {
            model,
            renderer,
            target,
            pose,
            half_m,
        })
    }

    /// Renders `shading` for `material` with a point light of intensity `intensity` at height
    /// `h_mm` over the centre, and returns the radiance averaged over annuli `edges_mm`
    /// (per channel).
    pub fn radial_radiance(
        &mut self,
        gpu: &Gpu,
        shading: ShadingModel,
        material: &Material,
        h_mm: f64,
        intensity: f32,
        edges_mm: &[f64],
    ) -> Vec<[f64; 3]> {
        self.renderer.set_material(&gpu.queue, material);
        self.renderer
            .update_character(&gpu.queue, &self.model, &self.pose, Mat4::IDENTITY);
        let h = self.half_m;
        let eye = Vec3::new(0.0, 1.0, 0.0);
        let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Z);
        let proj = glam::camera::rh::proj::directx::orthographic(-h, h, -h, h, 0.01, 10.0);
        let light = Light {
            position: Vec3::new(0.0, (h_mm / units::MM_PER_M) as f32, 0.0),
            intensity,
            color: Vec3::ONE,
            ambient: Vec3::ZERO,
        };
        self.renderer.prepare(
            &gpu.queue,
            &FrameView {
                view_proj: proj * view,
                camera_pos: eye,
                light,
                exposure: 1.0,
            },
        );
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let draw = DrawSet {
            shading: Some(shading),
            character: true,
            props: false,
        };
        self.renderer.encode(
            &mut encoder,
            &self.target.targets,
            &self.target.view,
            draw,
            None,
            None,
        );
        self.target.copy_out(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let pixels = self.target.read_f16(gpu);
        let mut sums = vec![[0.0f64; 3]; edges_mm.len().saturating_sub(1)];
        let mut counts = vec![0usize; sums.len()];
        let size_mm = 2.0 * self.half_m as f64 * units::MM_PER_M;
        for (i, p) in pixels.iter().enumerate() {
            let (x, y) = (
                (i as u32 % PIXELS) as f64 + 0.5,
                (i as u32 / PIXELS) as f64 + 0.5,
            );
            let r = ((x / PIXELS as f64 - 0.5).powi(2) + (y / PIXELS as f64 - 0.5).powi(2)).sqrt()
                * size_mm;
            if let Some(bin) = edges_mm.windows(2).position(|w| r >= w[0] && r < w[1]) {
                for c in 0..3 {
                    sums[bin][c] += p[c] as f64;
                }
                counts[bin] += 1;
            }
        }
        sums.iter()
            .zip(&counts)
            .map(|(s, &n)| s.map(|v| v / n.max(1) as f64))
            .collect()
    }
}

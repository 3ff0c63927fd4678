//! Measurement scenes: the reference scenes of [`crate::ground_truth`] rendered **through the
//! real renderer** (the character pipeline, the game's shaders and passes) and read back in
//! the Monte Carlo's units, so every shading model can be scored against path-traced ground
//! truth (`dermis profile`, `dermis bench shading`, the rendered-vs-reference tests).
//!
//! Geometry is built in millimetres-scaled metres: a flat plane (point light, shadow edge,
//! backlit slab) seen from straight above, or a sphere seen from the side with the light
//! along +z, so the terminator runs through the middle of the image. Each is a skinned mesh
//! with one joint, so it draws through the character pipeline like the game's character.
//!
//! **Radiance → exitance.** The renderer outputs radiance toward the camera; the references
//! are exitances. dermis' spatial models emit the exitance M with the radiance
//! M · F_t(η, n·v)/(π C(η)) (see `shading::subsurface`), so a pixel seen at n·v reads back as
//! M = π C(η) L / F_t(η, n·v) — the same conversion for every model (a Lambertian model's M is
//! then off by F_t/C, a few per cent at normal view: the boundary's exit distribution is part
//! of what a model gets right or wrong).

use glam::{Mat4, Vec3};

use dermis_engine::anim::Pose;
use dermis_engine::asset::shapes::{plane_model, sphere_model};
use dermis_engine::asset::Model;
use dermis_engine::render::{Gpu, Offscreen, Renderer};
use dermis_engine::scene::{DrawSet, FramePacket, FrameView, Light, Roles, SubjectPose};
use dermis_engine::shading::{fresnel, subsurface, units, Material, ShadingModel};

use crate::ground_truth::Scene;

/// The shadow map's size in these scenes: texels of 0.07 mm (white coat's edge view) or
/// finer, below the reference's narrowest strips (the game's map is 1024² over 2.3 m).
const SHADOW_MAP_SIZE: u32 = 4096;
/// Rendered target size (pixels per side).
pub const PIXELS: u32 = 512;
/// Distance of a directional light (m): far enough that its rays are parallel to f32 precision
/// over the scenes (≤ 0.2 m across).
const FAR_M: f32 = 1000.0;
/// Pixels whose surface is seen at n·v below this are not read (silhouette, MSAA edges).
const MIN_NV: f64 = 0.3;

/// The renderer and target the scenes are drawn with, reused across scenes and models.
pub struct SceneRenderer {
    renderer: Renderer,
    target: Offscreen,
    /// The geometry currently loaded (so consecutive renders of one scene upload it once).
    loaded: Option<(Geometry, Model, Pose)>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Geometry {
    Plane { half_mm: f64, thickness_mm: f64 },
    Sphere { radius_mm: f64 },
}

/// An orthographic camera at `eye` (unit vector, 1 m away) looking at the origin with `up`
/// up in the image, `half_mm` from the image centre to its edges.
#[derive(Clone, Copy, Debug)]
struct View {
    eye: Vec3,
    up: Vec3,
    half_mm: f64,
}

/// What one render returns: per bin and channel, the exitance in the reference's units.
pub type Exitance = Vec<[f64; 3]>;

impl SceneRenderer {
    pub fn new(gpu: &Gpu) -> Self {
        let mut renderer = Renderer::new(gpu, wgpu::TextureFormat::Rgba16Float);
        renderer.set_clear(wgpu::Color::BLACK);
        renderer.resize(gpu, (PIXELS, PIXELS));
        let target = Offscreen::with_format(gpu, PIXELS, PIXELS, wgpu::TextureFormat::Rgba16Float);
        Self {
            renderer,
            target,
            loaded: None,
        }
    }

    fn load(&mut self, gpu: &Gpu, geometry: Geometry, material: &Material) -> Result<(), String> {
        if self.loaded.as_ref().map(|(g, _, _)| *g) != Some(geometry) {
            let mm = |x: f64| (x / units::MM_PER_M) as f32;
            let model = match geometry {
                Geometry::Plane {
                    half_mm,
                    thickness_mm,
                } => plane_model(mm(half_mm), mm(thickness_mm)),
                Geometry::Sphere { radius_mm } => sphere_model(mm(radius_mm), mm(2.0 * radius_mm)),
            };
            self.renderer
                .load_character(gpu, &model, &Roles::medium(material))?;
            let mut pose = Pose::new(&model);
            pose.update_world(&model);
            self.loaded = Some((geometry, model, pose));
        } else {
            self.renderer.set_material(gpu, material);
        }
        Ok(())
    }

    /// Renders `scene` with `shading` for `material` and returns the exitance averaged over
    /// the bins `edges` (the reference's bins and units).
    pub fn render(
        &mut self,
        gpu: &Gpu,
        shading: ShadingModel,
        material: &Material,
        scene: &Scene,
        edges: &[f64],
    ) -> Result<Exitance, String> {
        scene.validate(edges)?;
        let last = edges[edges.len() - 1];
        let top = View {
            eye: Vec3::Y,
            up: Vec3::Z,
            half_mm: 0.0,
        };
        // (geometry, light, views, per-unit normalisation).
        let (geometry, light, views) = match *scene {
            Scene::PointLight { h_mm } => {
                // Intensity: the irradiance at the light's foot is 100 (f16's comfortable
                // range for the whole profile).
                let h_m = (h_mm / units::MM_PER_M) as f32;
                let half = last * 1.1 + 2.0;
                let light = (Vec3::new(0.0, h_m, 0.0), 100.0 * h_m * h_m, None);
                (
                    plane(half),
                    light,
                    vec![View {
                        half_mm: half,
                        ..top
                    }],
                )
            }
            Scene::ShadowEdge { theta_deg } => {
                let t = theta_deg.to_radians() as f32;
                let half = edges[0].abs().max(last.abs()) * 1.1 + 2.0;
                // Lit where x ≥ 0; the beam travels toward −x.
                let dir = Vec3::new(t.sin(), t.cos(), 0.0);
                let light = (dir * FAR_M, FAR_M * FAR_M, Some(edge_occluder(t, half)));
                (
                    plane(half),
                    light,
                    vec![View {
                        half_mm: half,
                        ..top
                    }],
                )
            }
            Scene::Sphere { radius_mm } => {
                let light = (Vec3::Z * FAR_M, FAR_M * FAR_M, None);
                let half = radius_mm * 1.05;
                // Toward the light, from the side (the terminator across the middle), from
                // behind: every band is seen somewhere at n·v ≥ MIN_NV.
                let views = vec![
                    View {
                        eye: Vec3::Z,
                        up: Vec3::Y,
                        half_mm: half,
                    },
                    View {
                        eye: Vec3::X,
                        up: Vec3::Z,
                        half_mm: half,
                    },
                    View {
                        eye: -Vec3::Z,
                        up: Vec3::Y,
                        half_mm: half,
                    },
                ];
                (Geometry::Sphere { radius_mm }, light, views)
            }
            Scene::SlabBacklit { thickness_mm } => {
                let geometry = Geometry::Plane {
                    half_mm: 20.0,
                    thickness_mm,
                };
                let light = (-Vec3::Y * FAR_M, FAR_M * FAR_M, None);
                (
                    geometry,
                    light,
                    vec![View {
                        half_mm: 10.0,
                        ..top
                    }],
                )
            }
        };
        self.load(gpu, geometry, material)?;
        // The measured medium casts nothing; the shadow edge's occluder casts through the
        // key light's shadow map, as the game's character does.
        match &light.2 {
            Some(occluder) => self.renderer.set_shadow_scene(
                gpu,
                false,
                &occluder.triangles,
                Some((occluder.centre, occluder.radius)),
                SHADOW_MAP_SIZE,
            ),
            None => self
                .renderer
                .set_shadow_scene(gpu, false, &[], None, SHADOW_MAP_SIZE),
        }
        let (position, intensity) = (light.0, light.1);
        // Per unit source power (point light: I = P/4π per m², M in mm⁻² = per m² × 1e-6) or
        // per unit irradiance (directional lights; the edge's on the surface).
        let per_unit = match *scene {
            Scene::PointLight { .. } => 1.0 / (4.0 * std::f64::consts::PI * intensity as f64 * 1e6),
            Scene::ShadowEdge { theta_deg } => {
                let d = position.length() as f64;
                d * d / (intensity as f64 * theta_deg.to_radians().cos())
            }
            _ => {
                let d = position.length() as f64;
                d * d / intensity as f64
            }
        };
        let eta = material.eta;
        let c_exit = subsurface::exit_normalisation(eta);
        let to_exitance = |nv: f64| {
            std::f64::consts::PI * c_exit / fresnel::transmittance_shader(eta, nv).max(1e-6)
                * per_unit
        };
        let nbins = edges.len() - 1;
        let mut sums = vec![[0.0f64; 3]; nbins];
        let mut counts = vec![0usize; nbins];
        for view in &views {
            let pixels = self.draw(gpu, shading, (position, intensity), view);
            let half = view.half_mm;
            let px_mm = 2.0 * half / PIXELS as f64;
            let right = (-view.eye).cross(view.up).as_dvec3();
            let (up, eye) = (view.up.as_dvec3(), view.eye.as_dvec3());
            if let Scene::ShadowEdge { .. } = scene {
                // Translation-invariant along z: average each column over the middle rows,
                // then each strip over the interpolated column profile (strips may be
                // narrower than a pixel).
                let mut columns = vec![[0.0f64; 3]; PIXELS as usize];
                let rows = (PIXELS / 4)..(3 * PIXELS / 4);
                for (i, col) in columns.iter_mut().enumerate() {
                    for row in rows.clone() {
                        let p = pixels[(row * PIXELS) as usize + i];
                        for c in 0..3 {
                            col[c] += p[c] as f64 / rows.len() as f64;
                        }
                    }
                }
                // World x of column i: image right is `right`; x = a · right.x.
                let col_at = |x: f64| {
                    let a = x / right.x;
                    ((a + half) / px_mm - 0.5).clamp(0.0, PIXELS as f64 - 1.0)
                };
                for (k, w) in edges.windows(2).enumerate() {
                    const N: usize = 16;
                    for j in 0..N {
                        let x = w[0] + (w[1] - w[0]) * (j as f64 + 0.5) / N as f64;
                        let f = col_at(x);
                        let (i0, t) = (f.floor() as usize, f.fract());
                        let i1 = (i0 + 1).min(PIXELS as usize - 1);
                        for c in 0..3 {
                            let v = columns[i0][c] * (1.0 - t) + columns[i1][c] * t;
                            sums[k][c] += v * to_exitance(1.0);
                        }
                        counts[k] += 1;
                    }
                }
                continue;
            }
            for (i, p) in pixels.iter().enumerate() {
                // Pixel centre in view coordinates (mm): a right, b up in the image.
                let a = ((i as u32 % PIXELS) as f64 + 0.5) * px_mm - half;
                let b = half - ((i as u32 / PIXELS) as f64 + 0.5) * px_mm;
                let (coord, nv) = match *scene {
                    Scene::Sphere { radius_mm } => {
                        let q = radius_mm * radius_mm - a * a - b * b;
                        if q <= 0.0 {
                            continue;
                        }
                        let depth = q.sqrt();
                        let world = right * a + up * b + eye * depth;
                        let cos_t = (world.z / radius_mm).clamp(-1.0, 1.0);
                        (cos_t.acos().to_degrees(), depth / radius_mm)
                    }
                    _ => ((a * a + b * b).sqrt(), 1.0),
                };
                if nv < MIN_NV {
                    continue;
                }
                let bin = match *scene {
                    Scene::SlabBacklit { .. } => (coord < 0.5 * half).then_some(0),
                    _ => edges.windows(2).position(|w| coord >= w[0] && coord < w[1]),
                };
                if let Some(k) = bin {
                    let f = to_exitance(nv);
                    for c in 0..3 {
                        sums[k][c] += p[c] as f64 * f;
                    }
                    counts[k] += 1;
                }
            }
        }
        for (k, n) in counts.iter().enumerate() {
            if *n == 0 {
                return Err(format!(
                    "{}: bin {} ({}–{}) has no pixel at {PIXELS}² — widen it",
                    scene.label(),
                    k,
                    edges[k],
                    edges[k + 1]
                ));
            }
        }
        Ok(sums
            .iter()
            .zip(&counts)
            .map(|(s, &n)| s.map(|v| v / n as f64))
            .collect())
    }

    /// Draws the loaded geometry through `view`; returns the raw radiance per pixel.
    fn draw(
        &mut self,
        gpu: &Gpu,
        shading: ShadingModel,
        (position, intensity): (Vec3, f32),
        view: &View,
    ) -> Vec<[f32; 4]> {
        let (eye, up) = (view.eye, view.up);
        let h = (view.half_mm / units::MM_PER_M) as f32;
        let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, up);
        let proj = glam::camera::rh::proj::directx::orthographic(-h, h, -h, h, 0.01, 10.0);
        let light = Light {
            position,
            intensity,
            color: Vec3::ONE,
            ambient: Vec3::ZERO,
        };
        let view = FrameView {
            view_proj: proj * view,
            camera_pos: eye,
            light,
            exposure: 1.0,
        };
        let draw = DrawSet {
            shading: Some(shading),
            character: true,
            props: false,
            ui: false,
        };
        let subject = self.loaded.as_ref().map(|(_, model, pose)| SubjectPose {
            model,
            pose,
            world: Mat4::IDENTITY,
        });
        let packet = FramePacket {
            subject,
            ..FramePacket::new((PIXELS, PIXELS), view, draw)
        };
        let frame = self.renderer.prepare(gpu, &packet);
        if let Err(e) = self.renderer.draw_offscreen(gpu, &self.target, &frame) {
            log::error!("{e}");
        }
        self.target.read_f16(gpu)
    }
}

/// A shadow-only occluder and the sphere the light's frustum is fitted to.
struct Occluder {
    triangles: Vec<[f32; 3]>,
    centre: Vec3,
    radius: f32,
}

/// The shadow edge's occluder: an opaque horizontal blade a quarter of the view's half-width
/// above the medium, its edge placed so that a light at incidence `theta` (rad, travelling
/// toward −x) shadows exactly x < 0; the map's frustum holds the viewed medium and the blade.
fn edge_occluder(theta: f32, half_mm: f64) -> Occluder {
    let half = (half_mm / units::MM_PER_M) as f32;
    let h = 0.25 * half;
    let x_edge = h * theta.tan();
    let (x0, z) = (-4.0 * half, 4.0 * half);
    let corner = |x: f32, z: f32| [x, h, z];
    let (a, b, c, d) = (
        corner(x0, -z),
        corner(x_edge, -z),
        corner(x_edge, z),
        corner(x0, z),
    );
    Occluder {
        triangles: vec![a, b, c, a, c, d],
        centre: Vec3::new(0.0, 0.5 * h, 0.0),
        radius: 1.05 * (2.0 * half * half + 0.25 * h * h).sqrt() + x_edge,
    }
}

/// The plane for a flat scene viewed `half_mm` from its centre: the plane reaches past the
/// view so nothing but the medium is seen; its thickness makes OSS see the depth it uses for
/// a semi-infinite medium.
fn plane(half_mm: f64) -> Geometry {
    let depth_mm = dermis_engine::shading::prediction::OSS_SEMI_INFINITE_MM;
    Geometry::Plane {
        half_mm: half_mm * 1.5,
        thickness_mm: depth_mm / units::OSS_DEPTH_SCALE,
    }
}

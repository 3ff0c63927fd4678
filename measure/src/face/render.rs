//! The scanned head drawn through the engine's character pipeline with one joint, under the
//! face scenes' camera and lights (`scene::face`), into its own target: linear radiance for
//! the face score, or a tone-mapped image. Measurement only (the game draws the head through
//! its own renderer).

use glam::{Mat4, Vec3};

use dermis_engine::anim::Pose;
use dermis_engine::asset::Model;
use dermis_engine::render::{Gpu, Offscreen, Renderer, RgbaImage};
use dermis_engine::scene::face::Camera;
use dermis_engine::scene::{DrawSet, FramePacket, FrameView, Light, Roles, SubjectPose, EXPOSURE};
use dermis_engine::shading::{Material, ShadingModel};

/// Draws a loaded head through the character pipeline into its own target.
pub struct HeadRenderer {
    renderer: Renderer,
    target: Offscreen,
    hdr: bool,
}

impl HeadRenderer {
    /// A renderer for `model` (from `asset::head::load`) at `width`×`height`; `hdr`: an `Rgba16Float`
    /// target holding linear radiance (no exposure, no tone mapping), else an sRGB image.
    pub fn new(
        gpu: &Gpu,
        model: &Model,
        material: &Material,
        width: u32,
        height: u32,
        hdr: bool,
    ) -> Result<Self, String> {
        let format = if hdr {
            wgpu::TextureFormat::Rgba16Float
        } else {
            dermis_engine::render::OFFSCREEN_FORMAT
        };
        let mut renderer = Renderer::new(gpu, format);
        if hdr {
            renderer.set_clear(wgpu::Color::BLACK);
        }
        // The albedo map is the skin's pigment; without it the head is the medium itself.
        let textured = model
            .materials
            .iter()
            .any(|m| m.base_color_texture.is_some());
        let roles = match textured {
            true => Roles {
                optics: material.clone(),
                ..Roles::of(model)
            },
            false => Roles::medium(material),
        };
        renderer.load_character(gpu, model, &roles)?;
        renderer.resize(gpu, (width, height));
        // Posed once, in its rest pose: a frame that poses it and draws nothing.
        let mut pose = Pose::new(model);
        pose.update_world(model);
        let view = FrameView {
            view_proj: Mat4::IDENTITY,
            camera_pos: Vec3::ZERO,
            light: Light::default(),
            exposure: EXPOSURE,
        };
        let nothing = DrawSet {
            shading: None,
            character: false,
            props: false,
            ui: false,
        };
        renderer.prepare(
            gpu,
            &FramePacket {
                subject: Some(SubjectPose {
                    model,
                    pose: &pose,
                    world: Mat4::IDENTITY,
                }),
                ..FramePacket::new((width, height), view, nothing)
            },
        );
        Ok(Self {
            renderer,
            target: Offscreen::with_format(gpu, width, height, format),
            hdr,
        })
    }

    /// Switches the material (the model keeps its geometry).
    pub fn set_material(&self, gpu: &Gpu, material: &Material) {
        self.renderer.set_material(gpu, material);
    }

    fn draw(&mut self, gpu: &Gpu, shading: Option<ShadingModel>, camera: &Camera, light: Light) {
        let (w, h) = (self.target.targets.width, self.target.targets.height);
        let aspect = w as f32 / h as f32;
        let view = FrameView {
            view_proj: dermis_engine::camera::look_at(
                camera.eye,
                camera.target,
                camera.fov_y_deg.to_radians(),
                aspect,
            ),
            camera_pos: camera.eye,
            light,
            exposure: EXPOSURE,
        };
        let draw = DrawSet {
            shading,
            character: true,
            props: false,
            ui: false,
        };
        let frame = self
            .renderer
            .prepare(gpu, &FramePacket::new((w, h), view, draw));
        if let Err(e) = self.renderer.draw_offscreen(gpu, &self.target, &frame) {
            log::error!("{e}");
        }
    }

    /// Linear radiance [W m⁻² sr⁻¹] per pixel (rows top to bottom) under a white point light
    /// of `intensity` W/sr at `position`, no ambient. Needs an `hdr` renderer.
    pub fn radiance(
        &mut self,
        gpu: &Gpu,
        shading: ShadingModel,
        camera: &Camera,
        position: Vec3,
        intensity: f32,
    ) -> Result<Vec<[f32; 3]>, String> {
        if !self.hdr {
            return Err("radiance needs an HDR head renderer".into());
        }
        let light = Light {
            position,
            intensity,
            color: Vec3::ONE,
            ambient: Vec3::ZERO,
        };
        self.draw(gpu, Some(shading), camera, light);
        Ok(self
            .target
            .read_f16(gpu)
            .into_iter()
            .map(|p| [p[0], p[1], p[2]])
            .collect())
    }

    /// The tone-mapped image under `light` (the game's exposure and ambient).
    pub fn image(
        &mut self,
        gpu: &Gpu,
        shading: ShadingModel,
        camera: &Camera,
        light: Light,
    ) -> Result<RgbaImage, String> {
        if self.hdr {
            return Err("image needs an sRGB head renderer".into());
        }
        self.draw(gpu, Some(shading), camera, light);
        Ok(self.target.read(gpu))
    }
}

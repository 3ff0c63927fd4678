//! One still frame rendered offscreen: the `render` command, the image tests and the benches.

use crate::render::passes::PassId;
use glam::{Mat4, Quat, Vec3};

use crate::anim::Pose;
use crate::camera::look_at;
use crate::render::{
    Gpu, Offscreen, PassCtx, PassTimer, PipelineSet, PreparedFrame, Renderer, RgbaImage,
    OFFSCREEN_FORMAT,
};
use crate::scene::{
    frame_bounds, posed_bounds, showroom, DrawSet, FramePacket, FrameView, Light, PropInstance,
    SceneAssets, SubjectPose, CHARACTER, EXPOSURE,
};
use crate::shading::{Material, ShadingModel};

#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    /// `None`: the unlit baseline.
    pub shading: Option<ShadingModel>,
    pub material: Material,
    pub clip: usize,
    pub time: f32,
    /// Light position; `None`: the key light ([`crate::scene::KEY_LIGHT_OFFSET`]).
    pub light: Option<Vec3>,
    /// Draw the showroom props around the character.
    pub props: bool,
    /// Fraction of the frame height the character's bounds fill.
    pub fill: f32,
}

impl Shot {
    pub fn new(shading: ShadingModel, material: Material) -> Self {
        Self {
            shading: Some(shading),
            material,
            clip: 0,
            time: 0.0,
            light: None,
            props: true,
            fill: 0.8,
        }
    }
}

/// Where a still places its character and camera ([`StillRenderer::framing`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framing {
    /// The character's placement in the world.
    pub world: Mat4,
    /// The camera and the light.
    pub view: FrameView,
}

/// A renderer with the scene uploaded and an offscreen target, reused across shots.
pub struct StillRenderer {
    pub renderer: Renderer,
    pub offscreen: Offscreen,
    pose: Pose,
    material: Option<Material>,
    timer: Option<PassTimer>,
    /// The showroom's props, placed with every shot (drawn in shots with props).
    props: Vec<PropInstance>,
}

impl StillRenderer {
    pub fn new(gpu: &Gpu, assets: &SceneAssets, width: u32, height: u32) -> Result<Self, String> {
        Self::with_format(gpu, assets, width, height, OFFSCREEN_FORMAT)
    }

    /// With an explicit target format (`Rgba16Float` renders raw radiance, no tone mapping).
    pub fn with_format(
        gpu: &Gpu,
        assets: &SceneAssets,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
    ) -> Result<Self, String> {
        Self::with_pipelines(
            gpu,
            assets,
            (width, height, format),
            &PipelineSet::everything(),
        )
    }

    /// Only the models in `set` (a shot of another model draws nothing): what one model's
    /// still needs, so a model that reads no table makes none (`render --shading ward`) and
    /// one that does makes only its own.
    pub fn with_pipelines(
        gpu: &Gpu,
        assets: &SceneAssets,
        (width, height, format): (u32, u32, wgpu::TextureFormat),
        set: &PipelineSet,
    ) -> Result<Self, String> {
        let mut renderer = Renderer::with_pipelines(gpu, format, set);
        renderer.load_scene(gpu, (&assets.character, &assets.roles), &assets.props)?;
        renderer.resize(gpu, (width, height));
        Ok(Self {
            renderer,
            offscreen: Offscreen::with_format(gpu, width, height, format),
            pose: Pose::new(&assets.character),
            material: None,
            timer: PassTimer::new(&gpu.device, &gpu.queue),
            props: showroom(),
        })
    }

    /// Builds and switches on the renderer's blob shadows under the character and the
    /// showroom props (drawn only in shots with props); returns whether they exist. Stills
    /// have none unless this is called; `renderer.switch(PassId::blobs, on)` switches them.
    pub fn enable_blob_shadows(&mut self, gpu: &Gpu) -> bool {
        self.renderer.enable(gpu, PassId::blobs)
    }

    /// Poses the character, places camera and light and prepares the frame of `shot`: the
    /// camera framed on this pose ([`Self::framing`]), then [`Self::frame_in`].
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        assets: &SceneAssets,
        shot: &Shot,
    ) -> Result<PreparedFrame, String> {
        let framing = self.framing(assets, shot)?;
        self.frame_in(gpu, assets, shot, &framing)
    }

    /// Where `shot` places the character and the camera: posed at the shot's moment, scaled
    /// to the one character height, standing at the origin, its posed bounds (every vertex
    /// skinned on the CPU) framed to fill `shot.fill` of the view; the light as the shot says.
    pub fn framing(&mut self, assets: &SceneAssets, shot: &Shot) -> Result<Framing, String> {
        let model = &assets.character;
        self.pose_at(assets, shot)?;
        let (lo, hi) = posed_bounds(model, &self.pose)
            .ok_or_else(|| format!("{}: no skinned mesh", model.source))?;
        // Normalise any character to the one character height, standing on the floor at the
        // origin.
        let scale = CHARACTER.normalising_scale(hi.y - lo.y);
        let center = (lo + hi) * 0.5;
        let world = Mat4::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::IDENTITY,
            Vec3::new(-center.x * scale, -lo.y * scale, -center.z * scale),
        );
        let (wlo, whi) = (world.transform_point3(lo), world.transform_point3(hi));
        let (w, h) = (self.offscreen.targets.width, self.offscreen.targets.height);
        let aspect = w as f32 / h as f32;
        let fov = 40f32.to_radians();
        let (eye, target) = frame_bounds(wlo.min(whi), wlo.max(whi), fov, shot.fill, aspect);
        // The key light of a character at the origin unless the shot places it.
        let light = shot.light.map_or_else(Light::default, |position| Light {
            position,
            ..Light::default()
        });
        let view = FrameView {
            view_proj: look_at(eye, target, fov, aspect),
            camera_pos: eye,
            light,
            exposure: EXPOSURE,
        };
        Ok(Framing { world, view })
    }

    /// Poses the character at `shot`'s moment.
    fn pose_at(&mut self, assets: &SceneAssets, shot: &Shot) -> Result<(), String> {
        let model = &assets.character;
        self.pose.reset(model);
        if !model.animations.is_empty() {
            let clip = model.animations.get(shot.clip).ok_or_else(|| {
                format!(
                    "{}: clip {} out of range (the model has {})",
                    model.source,
                    shot.clip,
                    model.animations.len()
                )
            })?;
            self.pose
                .apply_clip(clip, shot.time.clamp(0.0, clip.duration));
        }
        self.pose.update_world(model);
        Ok(())
    }

    /// Poses the character at `shot`'s moment and prepares its frame placed and seen as
    /// `framing` says (a camera that stays put while the character moves: what a game's
    /// frame does).
    pub fn frame_in(
        &mut self,
        gpu: &Gpu,
        assets: &SceneAssets,
        shot: &Shot,
        framing: &Framing,
    ) -> Result<PreparedFrame, String> {
        let model = &assets.character;
        if self.material.as_ref() != Some(&shot.material) {
            self.renderer.set_material(gpu, &shot.material);
            self.material = Some(shot.material.clone());
        }
        self.pose_at(assets, shot)?;
        let (w, h) = (self.offscreen.targets.width, self.offscreen.targets.height);
        let draw = DrawSet {
            shading: shot.shading,
            character: true,
            props: shot.props,
            ui: false,
        };
        let packet = FramePacket {
            subject: Some(SubjectPose {
                model,
                pose: &self.pose,
                world: framing.world,
            }),
            props: &self.props,
            ..FramePacket::new((w, h), framing.view, draw)
        };
        Ok(self.renderer.prepare(gpu, &packet))
    }

    /// Renders `shot` and reads the image back.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        assets: &SceneAssets,
        shot: &Shot,
    ) -> Result<RgbaImage, String> {
        let frame = self.frame(gpu, assets, shot)?;
        self.renderer.draw_offscreen(gpu, &self.offscreen, &frame)?;
        Ok(self.offscreen.read(gpu))
    }

    /// Renders `shot` into an `Rgba16Float` target and returns raw radiance per pixel.
    pub fn render_radiance(
        &mut self,
        gpu: &Gpu,
        assets: &SceneAssets,
        shot: &Shot,
    ) -> Result<Vec<[f32; 4]>, String> {
        let frame = self.frame(gpu, assets, shot)?;
        self.renderer.draw_offscreen(gpu, &self.offscreen, &frame)?;
        Ok(self.offscreen.read_f16(gpu))
    }

    /// Records `frame` into `encoder` (untimed), into the still's target.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &PreparedFrame,
    ) -> Result<(), String> {
        self.renderer.encode(
            frame,
            &mut PassCtx {
                encoder,
                targets: &self.offscreen.targets,
                output: &self.offscreen.view,
                timer: None,
            },
        )?;
        Ok(())
    }

    /// Renders `shot` with timestamps around its scene passes (the character, and the props
    /// and their blob shadows in a shot with props); returns GPU milliseconds.
    pub fn time_pass(&mut self, gpu: &Gpu, assets: &SceneAssets, shot: &Shot) -> Option<f64> {
        let frame = self.frame(gpu, assets, shot).ok()?;
        let timer = self.timer.as_ref()?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.renderer
            .encode(
                &frame,
                &mut PassCtx {
                    encoder: &mut encoder,
                    targets: &self.offscreen.targets,
                    output: &self.offscreen.view,
                    timer: Some(timer),
                },
            )
            .ok()?;
        timer.resolve(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        timer.read_ms(&gpu.device)
    }
}

impl RgbaImage {
    /// Saves as PNG.
    pub fn save_png(&self, path: &std::path::Path) -> Result<(), String> {
        image::save_buffer(
            path,
            &self.pixels,
            self.width,
            self.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| format!("{}: {e}", path.display()))
    }
}

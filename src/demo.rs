//! The showroom demo shared by the window and the `render` command: the character playing a
//! clip on a floor with props, lit by one point light, seen by the follow camera.

use std::path::Path;

use dermis_engine::anim::Pose;
use dermis_engine::camera::FollowCamera;
use dermis_engine::render::{
    FrameDriver, FrameOutput, FrameStatus, FrameTimes, Gpu, Output, RenderStats, Renderer,
};
use dermis_engine::scene::{
    posed_bounds, showroom, DrawSet, FramePacket, FrameView, Light, PropInstance, Roles,
    SceneAssets, SubjectPose, CHARACTER, EXPOSURE,
};
use dermis_engine::shading::{material::PRESETS, Material, ShadingModel};
use glam::{Mat4, Quat, Vec3};

pub struct Demo {
    pub assets: SceneAssets,
    pub pose: Pose,
    pub camera: FollowCamera,
    pub shading: ShadingModel,
    pub material: Material,
    pub clip: usize,
    pub time: f32,
    /// Where the character stands and which way it faces.
    pub position: Vec3,
    pub yaw: f32,
    /// Character height (m), from its bind-pose bounds.
    pub height: f32,
    /// Uniform scale applied to the character (external models come in other units).
    pub scale: f32,
    pub light: Light,
    /// The showroom's props around the character.
    pub props: Vec<PropInstance>,
}

impl Demo {
    pub fn load(
        assets_dir: &Path,
        model: Option<&Path>,
        shading: ShadingModel,
        material: Material,
    ) -> Result<Self, String> {
        let assets = SceneAssets::load(assets_dir, model).map_err(|e| e.to_string())?;
        let mut pose = Pose::new(&assets.character);
        pose.update_world(&assets.character);
        let (lo, hi) = posed_bounds(&assets.character, &pose)
            .ok_or_else(|| format!("{}: no skinned mesh", assets.character.source))?;
        let raw_height = (hi.y - lo.y).max(1e-6);
        // Bring any character to the one character height so the showroom and the light
        // fit it.
        let scale = if model.is_some() {
            CHARACTER.normalising_scale(raw_height)
        } else {
            1.0
        };
        let mut camera = FollowCamera::new(Vec3::new(0.0, 1.6, 3.2), Vec3::new(0.0, 1.0, 0.0));
        camera.snap(Vec3::ZERO, 0.0);
        Ok(Self {
            assets,
            pose,
            camera,
            shading,
            material,
            clip: 0,
            time: 0.0,
            position: Vec3::ZERO,
            yaw: 0.0,
            height: raw_height * scale,
            scale,
            light: Light::default(),
            props: showroom(),
        })
    }

    /// Uploads everything to the GPU (once).
    pub fn upload(&self, gpu: &Gpu, renderer: &mut Renderer) -> Result<(), String> {
        let roles = Roles {
            optics: self.material.clone(),
            ..self.assets.roles.clone()
        };
        renderer.load_scene(gpu, (&self.assets.character, &roles), &self.assets.props)
    }

    pub fn clip_count(&self) -> usize {
        self.assets.character.animations.len()
    }

    /// Advances the animation and the camera by `dt` seconds.
    pub fn update(&mut self, dt: f32) {
        self.time += dt;
        let model = &self.assets.character;
        self.pose.reset(model);
        if let Some(clip) = model.animations.get(self.clip) {
            let t = if clip.duration > 0.0 {
                self.time % clip.duration
            } else {
                0.0
            };
            self.pose.apply_clip(clip, t);
        }
        self.pose.update_world(model);
        let capsule = CHARACTER.capsule_at(self.position, self.height / CHARACTER.height);
        self.camera.update(dt, self.position, self.yaw, &capsule);
    }

    /// The character's placement in the world.
    pub fn world(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            Vec3::splat(self.scale),
            Quat::from_rotation_y(self.yaw),
            self.position,
        )
    }

    pub fn frame_view(&self, aspect: f32) -> FrameView {
        FrameView {
            view_proj: self.camera.view_proj(aspect),
            camera_pos: self.camera.eye.value,
            light: self.light,
            exposure: EXPOSURE,
        }
    }

    /// This frame's packet for a target of `viewport` pixels: the character posed and placed,
    /// the showroom's props, the follow camera.
    pub fn packet(&self, viewport: (u32, u32)) -> FramePacket<'_> {
        let aspect = viewport.0 as f32 / viewport.1.max(1) as f32;
        let draw = DrawSet {
            shading: Some(self.shading),
            character: true,
            props: true,
            ui: false,
        };
        FramePacket {
            subject: Some(SubjectPose {
                model: &self.assets.character,
                pose: &self.pose,
                world: self.world(),
            }),
            props: &self.props,
            ..FramePacket::new(viewport, self.frame_view(aspect), draw)
        }
    }

    pub fn next_material(&mut self) {
        let i = PRESETS
            .iter()
            .position(|m| m.name == self.material.name)
            .unwrap_or(0);
        self.material = PRESETS[(i + 1) % PRESETS.len()].clone();
    }

    pub fn title(&self) -> String {
        format!(
            "dermis — {} ({}) — {}",
            self.shading.label(),
            self.shading.name(),
            self.material.name
        )
    }
}

/// A hook run after a demo frame's passes are recorded (screenshots).
pub type AfterEncode<'h> = dyn FnMut(&mut wgpu::CommandEncoder, &FrameOutput<'_>) + 'h;

/// One demo frame, straight-line code between the frame helpers (as the game's frame):
/// begin → update → the demo's packet → prepare → encode → finish.
pub struct DemoFrame<'a> {
    pub demo: &'a mut Demo,
    pub renderer: &'a mut Renderer,
    pub after_encode: Option<&'a mut AfterEncode<'a>>,
}

impl<'a> DemoFrame<'a> {
    pub fn new(demo: &'a mut Demo, renderer: &'a mut Renderer) -> Self {
        Self {
            demo,
            renderer,
            after_encode: None,
        }
    }

    /// Runs one frame with `driver` into `output`.
    pub fn run(
        &mut self,
        driver: &mut FrameDriver,
        gpu: &Gpu,
        mut output: Output<'_>,
    ) -> Result<FrameTimes, FrameStatus> {
        let mut frame = driver.begin(gpu, &mut output)?;
        self.renderer.resize(gpu, frame.size);
        self.demo.update(frame.dt as f32);
        driver.updated(&mut frame);
        let packet = self.demo.packet(frame.size);
        let prepared = self.renderer.prepare(gpu, &packet);
        let stats = self
            .renderer
            .encode(&prepared, &mut frame.pass_ctx(&output))
            .unwrap_or_else(|e| {
                log::error!("{e}");
                RenderStats::default()
            });
        if let Some(hook) = &mut self.after_encode {
            let out = FrameOutput {
                targets: output.targets(),
                view: &frame.view,
                texture: &frame.texture,
            };
            hook(&mut frame.encoder, &out);
        }
        Ok(driver.finish(gpu, frame, &mut output, stats))
    }
}

//! The scanned head in the engine: loaded into metres (a real head's size), drawn through the
//! character pipeline with one joint, under the face scenes' camera and lights.
//!
//! The file is Lee Perry-Smith's head scan (`assets/head/`, CC BY 3.0): a bust in model units,
//! +y up, the face toward +z, 8.55 units across the shoulders and 3.8 across the ears. At
//! [`METRES_PER_UNIT`] the head is 15.2 cm across the ears and ~21 cm from chin to crown.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};

use crate::anim::Pose;
use crate::asset::compressed::{encoded_texture, sidecar_path};
use crate::asset::tangents::generate_tangents;
use crate::asset::{
    dir_reader, load_gltf_slice, Aabb, AssetError, Model, Node, Skin, TextureImage, TextureRole,
    Transform,
};
use crate::render::{Gpu, Offscreen, Renderer, RgbaImage};
use crate::scene::{DrawSet, FramePacket, FrameView, Light, Roles, SubjectPose, EXPOSURE};
use crate::shading::{Material, ShadingModel};

/// The head's folder under the assets root.
pub const DIR: &str = "head";
/// The mesh (Blender's glTF export, no textures bound).
pub const MESH_FILE: &str = "LeePerrySmith.glb";
/// The albedo (sRGB JPEG, 1024²) on TEXCOORD_0.
pub const ALBEDO_FILE: &str = "Map-COL.jpg";
/// The tangent-space normal map (linear JPEG, 1024², +y up: the OpenGL convention) on
/// TEXCOORD_0: the scan's pores and wrinkles the mesh does not carry.
pub const NORMAL_FILE: &str = "Infinite-Level_02_Tangent_SmoothUV.jpg";
/// Metres per model unit: 3.8 units across the ears → 15.2 cm.
pub const METRES_PER_UNIT: f32 = 0.04;
/// The credit the licence asks for wherever the head is shown or shipped.
pub const ATTRIBUTION: &str = "Head: \"Infinite, 3D Head Scan\" by Lee Perry-Smith / \
Infinite-Realities (ir-ltd.net), based on a work at triplegangers.com, CC BY 3.0";
/// The same credit in two short lines, for a screen that shows the head (the showroom).
pub const CREDIT_LINES: [&str; 2] = [
    "Head scan: Lee Perry-Smith / Infinite-Realities (ir-ltd.net)",
    "based on a work at triplegangers.com, CC BY 3.0",
];

/// The head's maps (files in [`DIR`]) in the roles the head's material reads them: what
/// [`load_from`] loads and `cargo xtask assets` encodes.
pub const MAPS: [(&str, TextureRole); 2] = [
    (ALBEDO_FILE, TextureRole::Colour),
    (NORMAL_FILE, TextureRole::Data),
];

/// Which of the head's maps [`load_with`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Maps {
    /// The albedo map as the base colour (all skin); else white (the homogeneous medium the
    /// path tracer renders).
    pub albedo: bool,
    /// The tangent-space normal map.
    pub normal: bool,
}

/// Loads the head in metres as a one-joint skinned model with its normal map; with
/// `textured`, its albedo map is the base colour (all skin), else the base colour is white
/// (the homogeneous medium the path tracer renders).
pub fn load(assets_dir: &Path, textured: bool) -> Result<Model, AssetError> {
    load_with(
        assets_dir,
        Maps {
            albedo: textured,
            normal: true,
        },
    )
}

/// The files of the head a build ships, relative to the assets root: the mesh, each map's
/// source image and the licence (its block encodings are beside each map, see
/// [`sidecar_path`]).
pub fn files() -> [String; 4] {
    [MESH_FILE, ALBEDO_FILE, NORMAL_FILE, LICENCE_FILE].map(|f| format!("{DIR}/{f}"))
}

/// The licence text that travels with the head.
pub const LICENCE_FILE: &str = "LeePerrySmith_License.txt";

/// One of the head's maps for `role`: its block encodings (`<map>.textures/<role>.<family>.ktx2`,
/// made by `cargo xtask assets`) where usable, else the JPEG decoded. Where the JPEG is not
/// there (the APK carries the encodings only) the encodings are all there is.
fn read_map(
    read: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    file: &str,
    role: TextureRole,
) -> Result<TextureImage, AssetError> {
    let path = format!("{DIR}/{file}");
    let source = read(&path).unwrap_or_default();
    let sidecar = |family| sidecar_path(&path, None, role, family);
    encoded_texture(&source, role, &sidecar, read, &path).map_err(|e| AssetError::new(&path, e))
}

/// Loads the head in metres from `assets_dir` (see [`load_from`]).
pub fn load_with(assets_dir: &Path, maps: Maps) -> Result<Model, AssetError> {
    load_from(&dir_reader(assets_dir), maps)
}

/// Loads the head in metres as a one-joint skinned model with the maps `maps` asks for,
/// reading its files through `read` (a path relative to the assets root to the file's bytes:
/// the file system, or the Android app's asset manager).
///
/// The file's UVs have v up (v = 0 at the images' bottom row, as the three.js example that
/// ships it samples them); the engine samples v down, so v is flipped here and the tangents
/// are generated again for the flipped UVs.
pub fn load_from(
    read: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    maps: Maps,
) -> Result<Model, AssetError> {
    let mesh_path = format!("{DIR}/{MESH_FILE}");
    let bytes = read(&mesh_path).map_err(|e| AssetError::new(&mesh_path, e))?;
    let resolve = |uri: &str| read(&format!("{DIR}/{uri}"));
    let file = load_gltf_slice(&bytes, &mesh_path, &resolve)?;
    let source = file.source.clone();
    let mut primitive = file
        .meshes
        .first()
        .and_then(|m| m.primitives.first())
        .cloned()
        .ok_or_else(|| AssetError::new(&source, "no mesh".to_string()))?;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for v in &mut primitive.vertices {
        let p = Vec3::from_array(v.position) * METRES_PER_UNIT;
        v.position = p.to_array();
        // Thickness (cast at load: the file gives none) and curvature in the file's units.
        v.thickness *= METRES_PER_UNIT;
        let a = METRES_PER_UNIT.sqrt();
        v.curvature = [
            v.curvature[0] / a,
            v.curvature[1] / a,
            v.curvature[2] / a,
            v.curvature[3] / METRES_PER_UNIT,
        ];
        v.uv[1] = 1.0 - v.uv[1];
        v.joints = [0; 4];
        v.weights = [1.0, 0.0, 0.0, 0.0];
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let vs = &primitive.vertices;
    let positions: Vec<Vec3> = vs.iter().map(|v| Vec3::from_array(v.position)).collect();
    let normals: Vec<Vec3> = vs.iter().map(|v| Vec3::from_array(v.normal)).collect();
    let uvs: Vec<Vec2> = vs.iter().map(|v| Vec2::from_array(v.uv)).collect();
    let tangents = generate_tangents(&positions, &normals, &uvs, &primitive.indices);
    for (v, t) in primitive.vertices.iter_mut().zip(tangents) {
        v.tangent = t;
    }
    primitive.bounds = Aabb { min: lo, max: hi };
    primitive.material = Some(0);
    let mut textures = Vec::new();
    let [(albedo, colour), (normal, data)] = MAPS;
    if maps.albedo {
        textures.push(read_map(read, albedo, colour)?);
    }
    if maps.normal {
        textures.push(read_map(read, normal, data)?);
    }
    let node = |mesh, skin| Node {
        name: None,
        parent: None,
        children: Vec::new(),
        local: Transform::default(),
        mesh,
        skin,
    };
    Ok(Model {
        source,
        nodes: vec![node(None, None), node(Some(0), Some(0))],
        roots: vec![0, 1],
        meshes: vec![crate::asset::Mesh {
            name: Some("head".into()),
            primitives: vec![primitive],
        }],
        skins: vec![Skin {
            name: None,
            joints: vec![0],
            inverse_bind: vec![Mat4::IDENTITY],
        }],
        materials: vec![crate::asset::Material {
            name: Some("skin".into()),
            base_color_texture: maps.albedo.then_some(0),
            metallic_factor: 0.0,
            normal_texture: maps.normal.then(|| textures.len() - 1),
            ..crate::asset::Material::default()
        }],
        textures,
        animations: Vec::new(),
        warnings: Vec::new(),
    })
}

/// The face scenes' camera: a three-quarter view from the front-right, so the right ear is
/// seen beside the face (metres, the head's own frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view (degrees).
    pub fov_y_deg: f32,
}

/// The middle of the head (between the ears, at the eyes' height).
pub const HEAD_CENTRE: Vec3 = Vec3::new(0.0, 0.048, 0.012);

pub fn camera() -> Camera {
    let dir = Vec3::new(0.45, 0.08, 0.89).normalize();
    Camera {
        eye: HEAD_CENTRE + dir * 0.75,
        target: HEAD_CENTRE,
        fov_y_deg: 24.0,
    }
}

/// Radiant intensity of the face scenes' point light [W/sr].
pub const LIGHT_INTENSITY: f32 = 1.0;
/// Distance of the face scenes' light from the head's centre [m].
pub const LIGHT_DISTANCE_M: f32 = 0.8;

/// The three lights of the face scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceLight {
    /// From the front, above and left of the camera.
    Front,
    /// From the right, level with the nose: the terminator runs along it.
    Side,
    /// From behind the head, right and a little above: through the right ear.
    Back,
}

impl FaceLight {
    pub const ALL: [FaceLight; 3] = [FaceLight::Front, FaceLight::Side, FaceLight::Back];

    pub fn name(self) -> &'static str {
        match self {
            FaceLight::Front => "front",
            FaceLight::Side => "side",
            FaceLight::Back => "back",
        }
    }

    /// Looks a light up by name.
    pub fn parse(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown face light `{s}` (known: front, side, back)"))
    }

    /// The light's position [m].
    pub fn position(self) -> Vec3 {
        let dir = match self {
            FaceLight::Front => Vec3::new(-0.2, 0.3, 1.0),
            FaceLight::Side => Vec3::new(1.0, 0.05, 0.1),
            FaceLight::Back => Vec3::new(0.35, 0.15, -1.0),
        };
        HEAD_CENTRE + dir.normalize() * LIGHT_DISTANCE_M
    }
}

/// Draws a loaded head through the character pipeline into its own target.
pub struct HeadRenderer {
    renderer: Renderer,
    target: Offscreen,
    hdr: bool,
}

impl HeadRenderer {
    /// A renderer for `model` (from [`load`]) at `width`×`height`; `hdr`: an `Rgba16Float`
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
            crate::render::OFFSCREEN_FORMAT
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
            view_proj: crate::camera::look_at(
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
        self.renderer.draw_offscreen(gpu, &self.target, &frame);
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

//! `dermis render`: one frame offscreen to a PNG.

use std::path::PathBuf;

use dermis_engine::render::pfm::FloatImage;
use dermis_engine::render::{Gpu, PipelineSet, OFFSCREEN_FORMAT};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::{Material, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};
use glam::Vec3;
use wgpu::TextureFormat::Rgba16Float;

use crate::cmd::args::{
    check_out_file, parse_index, parse_size, parse_time, parse_vec3, shading_help,
};
use crate::cmd::args::{parse_material, parse_model};
use crate::cmd::progress::Progress;

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    #[arg(
        long,
        default_value_t = ShadingModel::DEFAULT,
        value_parser = parse_model,
        help = shading_help("Shading model of the character")
    )]
    pub shading: ShadingModel,
    /// The skin's optics: a preset (skin1 | white-coat); default: what the character's file
    /// declares (KHR_materials_volume_scatter), else skin1.
    #[arg(long, value_parser = parse_material)]
    pub material: Option<Material>,
    /// glTF character (default: the project's own).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Which of the character's materials are skin: MATERIAL[=PRESET],… or `none` (default:
    /// what its file declares, else materials named like skin).
    #[arg(long, value_parser = crate::cmd::args::parse_skin)]
    pub skin: Option<dermis_engine::asset::skin::SkinChoice>,
    /// Animation clip index (checked against the model before any GPU work).
    #[arg(long, default_value_t = 0, value_parser = parse_index, allow_hyphen_values = true)]
    pub clip: usize,
    /// Time in the clip (seconds, ≥ 0; clamped to the clip).
    #[arg(long, default_value = "0", value_parser = parse_time, allow_hyphen_values = true)]
    pub time: f32,
    /// Image size, WxH.
    #[arg(long, default_value = "640x360", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Light position X,Y,Z in metres (the character stands at the origin, 1.75 m tall;
    /// negative coordinates as they are: `--light -0.5,2,1`).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light: Option<Vec3>,
    /// Leave out the props (character only).
    #[arg(long)]
    pub no_props: bool,
    /// Output PNG (checked before rendering: writable, `.png`).
    #[arg(long, required_unless_present_any = ["hdr", "export"])]
    pub out: Option<PathBuf>,
    /// What to draw: `character` (the game's, with props) or `head` (the scanned head,
    /// CC BY 3.0, in metres under the face scenes' camera; see `--face-light`).
    #[arg(long, default_value = "character", value_parser = ["character", "head"])]
    pub scene: String,
    /// Also (or only) write linear radiance, no exposure or tone mapping, as a `.pfm`
    /// (W m⁻² sr⁻¹ for a light of the given W/sr; the head: white light, no ambient).
    #[arg(long)]
    pub hdr: Option<PathBuf>,
    /// `--scene head`: the light of the face scenes (front | side | back) unless `--light`.
    #[arg(long, default_value = "front", value_parser = dermis_engine::scene::face::FaceLight::parse)]
    pub face_light: dermis_engine::scene::face::FaceLight,
    /// `--scene head`: leave the albedo map off (white: the path-traced reference's medium).
    #[arg(long)]
    pub plain: bool,
    /// `--scene head`: write the scene for the path tracer (head.ply in metres, scene.json)
    /// into this directory instead of rendering (`tools/mitsuba/render.py` reads it).
    #[arg(long)]
    pub export: Option<PathBuf>,
}

pub fn run(args: RenderArgs) -> Result<(), String> {
    if let Some(out) = &args.out {
        check_out_file(out, Some("png"))?;
    }
    if let Some(hdr) = &args.hdr {
        check_out_file(hdr, Some("pfm"))?;
    }
    if args.scene == "head" || args.export.is_some() {
        return super::render_head::run(&args);
    }
    let assets = SceneAssets::load_chosen(
        &crate::paths::assets_dir(),
        args.model.as_deref(),
        args.skin.as_ref(),
    )
    .map_err(|e| e.to_string())?;
    let material = args
        .material
        .clone()
        .unwrap_or_else(|| assets.roles.optics.clone());
    let clips = assets.character.animations.len();
    if args.clip >= clips.max(1) {
        return Err(format!(
            "{}: clip {} out of range (the model has {clips} clips)",
            assets.character.source, args.clip
        ));
    }
    // Steps: the GPU and pipelines, the frame, the PNG.
    let mut progress = Progress::new("render", 3);
    progress.begin("GPU device and pipelines");
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    // Only this model's pipelines and tables.
    let set = PipelineSet::only(args.shading);
    let mut still = StillRenderer::with_pipelines(&gpu, &assets, (w, h, OFFSCREEN_FORMAT), &set)?;
    progress.step("GPU device and pipelines");
    let shot = Shot {
        clip: args.clip,
        time: args.time,
        light: args.light,
        props: !args.no_props,
        ..Shot::new(args.shading, material.clone())
    };
    progress.begin("rendering");
    if let Some(out) = &args.out {
        still.render(&gpu, &assets, &shot)?.save_png(out)?;
    }
    if let Some(hdr) = &args.hdr {
        let mut raw = StillRenderer::with_pipelines(&gpu, &assets, (w, h, Rgba16Float), &set)?;
        let pixels = raw.render_radiance(&gpu, &assets, &shot)?;
        FloatImage::new(w, h, pixels.iter().map(|p| [p[0], p[1], p[2]]).collect())?.save(hdr)?;
    }
    progress.step("saved");
    progress.finish();
    println!(
        "{}: {} {} {}x{} on {}",
        super::render_head::outputs(&args),
        args.shading,
        material.name,
        w,
        h,
        gpu.adapter_name()
    );
    Ok(())
}

//! `dermis render --scene head`: the scanned head under the face scenes' camera and light, to
//! a PNG and/or linear radiance (`--hdr F.pfm`, the units and camera of the path-traced
//! references), or its scene exported for the path tracer (`--export DIR`).

use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::render::Gpu;
use dermis_engine::scene::face;
use dermis_engine::scene::Light;
use dermis_measure::face::export;
use dermis_measure::face::render::HeadRenderer;
use glam::Vec3;

use super::render::RenderArgs;

/// The files a render writes, for its one-line summary.
pub fn outputs(args: &RenderArgs) -> String {
    let files: Vec<String> = [&args.out, &args.hdr]
        .into_iter()
        .flatten()
        .map(|p| p.display().to_string())
        .collect();
    files.join(", ")
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    // The head declares no optics: skin1's unless a preset is named.
    let material = args
        .material
        .clone()
        .unwrap_or_else(|| dermis_engine::shading::material::DEFAULT_SKIN.clone());
    if args.scene != "head" {
        return Err("--export needs --scene head".into());
    }
    let assets = crate::paths::assets_dir();
    if let Some(dir) = &args.export {
        super::args::check_out_dir(dir)?;
        let model = head::load(&assets, false).map_err(|e| e.to_string())?;
        export::write(dir, &model, &material)?;
        println!(
            "{}: head.ply, scene.json ({}; {})",
            dir.display(),
            material.name,
            head::ATTRIBUTION
        );
        return Ok(());
    }
    let model = head::load(&assets, !args.plain).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let camera = face::camera();
    let position = args.light.unwrap_or_else(|| args.face_light.position());
    if let Some(out) = &args.out {
        let mut r = HeadRenderer::new(&gpu, &model, &material, w, h, false)?;
        let default = Light::default();
        let light = Light {
            position,
            // The face scenes' light, brighter for display, and a dim fill.
            intensity: 2.0 * face::LIGHT_INTENSITY,
            ambient: default.ambient * 0.3,
            ..default
        };
        r.image(&gpu, args.shading, &camera, light)?.save_png(out)?;
    }
    if let Some(hdr) = &args.hdr {
        let mut r = HeadRenderer::new(&gpu, &model, &material, w, h, true)?;
        let pixels = r.radiance(&gpu, args.shading, &camera, position, face::LIGHT_INTENSITY)?;
        FloatImage::new(w, h, pixels)?.save(hdr)?;
    }
    println!(
        "{}: {} {} head {}x{} light at {:.3?} on {}\n{}",
        outputs(args),
        args.shading,
        material.name,
        w,
        h,
        Vec3::to_array(&position),
        gpu.adapter_name(),
        head::ATTRIBUTION
    );
    Ok(())
}

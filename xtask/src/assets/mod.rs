//! `cargo xtask assets`: regenerates the project's own glTF assets, byte-for-byte reproducibly.
//!
//! * `assets/character.glb`: skinned humanoid with `_THICKNESS`, one primitive per material
//!   (skin declared by `KHR_materials_volume_scatter` with skin1's optics, tank top, shorts,
//!   hair, eyes: `outfit`), one base-colour atlas and the `idle`, `run`, `jump` clips.
//! * `assets/props/*.glb`: static props for the runner game.
//! * `<model>.textures/*.ktx2` (and the scanned head's `head/<map>.textures/`): the textures'
//!   GPU block encodings (`crate::textures`).

mod clips;
mod cut;
mod detmath;
mod export;
mod glb_writer;
mod humanoid;
mod mesh;
mod noise;
mod outfit;
mod props;
mod shapes;
mod skeleton;
mod texture;

use std::path::{Path, PathBuf};

use outfit::Mat;

/// Every generated file: (path relative to the output root, bytes, one-line summary).
pub fn generate() -> Vec<(String, Vec<u8>, String)> {
    let character = humanoid::build();
    let rgba = texture::bake(&character.mesh, &character.materials);
    let png = texture::encode_png(&rgba, texture::SIZE, texture::SIZE);
    let clips = clips::clips();
    let (lo, hi) = character.mesh.bounds();
    let thick = character
        .thickness
        .iter()
        .fold((f32::INFINITY, 0.0f32), |(a, b), &t| (a.min(t), b.max(t)));
    let clip_info: Vec<String> = clips
        .iter()
        .map(|c| {
            let kind = if c.looping { "loop" } else { "once" };
            format!(
                "{} {:.2}s {} keys {kind}",
                c.name,
                c.times.last().copied().unwrap_or(0.0),
                c.times.len()
            )
        })
        .collect();
    let summary = format!(
        "{} triangles, {} vertices, {} joints, height {:.3} m (feet at y={:.3}), thickness {:.4}..{:.3} m, {}x{} texture, clips: {}",
        character.mesh.triangle_count(),
        character.mesh.vertex_count(),
        character.skeleton.len(),
        hi.y - lo.y,
        lo.y,
        thick.0,
        thick.1,
        texture::SIZE,
        texture::SIZE,
        clip_info.join(", ")
    );
    // Two passes: the skin's multi-scatter factor needs the atlas mean over the skin's texels
    // as the engine measures it, on the file the engine loads.
    let first = export::character_glb(&character, &clips, &png, [1.0; 3]);
    let no_files = |uri: &str| -> Result<Vec<u8>, String> { Err(format!("no file {uri}")) };
    let model = dermis_engine::asset::load_gltf_slice(&first, "character.glb", &no_files)
        .expect("the generated character loads");
    let skin = Mat::ALL.iter().position(|&m| m == Mat::Skin).unwrap_or(0);
    let texture = model.materials[skin]
        .volume_scatter
        .and_then(|s| s.multiscatter_texture)
        .expect("the skin's multi-scatter texture");
    let mean = dermis_engine::asset::skin::texture_mean(&model, skin, texture)
        .expect("the atlas is in the file");
    let factor = outfit::skin_factor(mean);
    let summary = format!(
        "{summary}, skin atlas mean (linear) {:.3?}, multi-scatter factor {:.4?}",
        mean, factor
    );
    let mut out = vec![(
        "character.glb".to_string(),
        export::character_glb(&character, &clips, &png, factor),
        summary,
    )];
    for p in props::props() {
        let (lo, hi) = p.mesh.bounds();
        let size = hi - lo;
        let summary = format!(
            "{} triangles, {} vertices, {:.2} x {:.2} x {:.2} m",
            p.mesh.triangle_count(),
            p.mesh.vertex_count(),
            size.x,
            size.y,
            size.z
        );
        out.push((
            format!("props/{}.glb", p.name),
            export::static_glb(p.name, &p.mesh, &p.png, p.roughness),
            summary,
        ));
    }
    out
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Writes all assets under `dir`.
pub fn write_all(dir: &Path) -> Result<Vec<(PathBuf, String)>, String> {
    let mut written = Vec::new();
    for (rel, bytes, summary) in generate() {
        let path = dir.join(&rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("creating {}: {e}", parent.display()))?;
        }
        std::fs::write(&path, &bytes).map_err(|e| format!("writing {}: {e}", path.display()))?;
        written.push((path, summary));
    }
    Ok(written)
}

pub fn run(args: &[String]) -> Result<(), String> {
    let mut out_dir = repo_root().join("assets");
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--out" => out_dir = PathBuf::from(it.next().ok_or("--out needs a directory")?),
            "-h" | "--help" => {
                println!("usage: cargo xtask assets [--out DIR]   (default DIR: <repo>/assets)");
                return Ok(());
            }
            other => return Err(format!("assets: unknown argument `{other}` (try --help)")),
        }
    }
    for (p, summary) in write_all(&out_dir)? {
        let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
        println!("wrote {} ({len} bytes): {summary}", p.display());
    }
    // Their textures' GPU block encodings (and the scanned head's), beside each source.
    let t0 = std::time::Instant::now();
    let written = crate::textures::write_all(&out_dir, &repo_root().join("assets"))?;
    for (rel, len) in &written {
        println!("wrote {} ({len} bytes)", out_dir.join(rel).display());
    }
    println!(
        "{} texture encodings in {:.1} s",
        written.len(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed assets must be exactly what the generator produces.
    #[test]
    fn committed_assets_are_reproducible() {
        let tmp = std::env::temp_dir().join(format!("dermis-assets-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        let written = write_all(&tmp).expect("generate into a temp dir");
        let committed = repo_root().join("assets");
        for (path, _) in written {
            let rel = path.strip_prefix(&tmp).unwrap();
            let fresh = std::fs::read(&path).unwrap();
            let old = std::fs::read(committed.join(rel)).unwrap_or_else(|e| {
                panic!(
                    "assets/{} missing ({e}); run `cargo xtask assets`",
                    rel.display()
                )
            });
            assert!(
                fresh == old,
                "assets/{} differs from the generator output; run `cargo xtask assets`",
                rel.display()
            );
        }
        let _ = std::fs::remove_dir_all(&tmp);
    }
}

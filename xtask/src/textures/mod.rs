//! The GPU block encodings of every texture the project ships (part of `cargo xtask assets`):
//! every image a glTF file's materials reference — the character's, each prop's — in each
//! role the engine's loader reads it in (`dermis_engine::asset`: colour, sRGB, or data, linear;
//! the file is loaded by the engine to know which), and the scanned head's maps in theirs
//! (`face::head::MAPS`): the full mip chain the renderer builds (`dermis_texture::mip_chain`)
//! encoded as BC (BC1, or BC3 where the image has alpha: desktop GPUs) and ETC2 (RGB8 / RGBA8:
//! every Android GPU), each in a KTX2 file beside its source recording the source's hash
//! (`dermis_texture::sidecar_path`). Deterministic: the same sources give the same bytes.

pub mod etc2;

use std::path::Path;

use dermis_engine::asset::load_gltf_slice;
use dermis_texture::{
    fnv1a64, level_size, mip_chain, sidecar_path, BlockFormat, BlockImage, Family, TextureRole,
};

/// Every (image, role) the engine loads from a .glb, each once, with the image's bytes (the
/// project's files embed their images).
fn glb_textures(bytes: &[u8], file: &str) -> Result<Vec<(usize, TextureRole, Vec<u8>)>, String> {
    // The engine's own loader decides what is read in which role; with no files beside it,
    // it looks for no encoding and decodes every image.
    let no_files = |uri: &str| -> Result<Vec<u8>, String> { Err(format!("no file {uri}")) };
    let model = load_gltf_slice(bytes, file, &no_files).map_err(|e| e.to_string())?;
    if let Some(w) = model.warnings.first() {
        return Err(w.clone());
    }
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| format!("{file}: {e}"))?;
    let blob = gltf.blob.as_deref().unwrap_or_default();
    let mut out = Vec::new();
    for t in &model.textures {
        let index = t
            .image
            .ok_or_else(|| format!("{file}: a texture from no image"))?;
        let image = gltf
            .document
            .images()
            .nth(index)
            .ok_or_else(|| format!("{file}: no image {index}"))?;
        let gltf::image::Source::View { view, .. } = image.source() else {
            return Err(format!("{file}: image {index} is not embedded"));
        };
        let range = view.offset()..view.offset() + view.length();
        let data = blob
            .get(range)
            .ok_or_else(|| format!("{file}: image {index} outside the BIN chunk"))?;
        out.push((index, TextureRole::of_srgb(t.srgb), data.to_vec()));
    }
    Ok(out)
}

fn read(dir: &Path, rel: &str) -> Result<Vec<u8>, String> {
    let path = dir.join(rel);
    std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The families encoded (ASTC has no encoder here: see the report in `docs/`).
pub const FAMILIES: [Family; 2] = [Family::Bc, Family::Etc2];

/// One image to encode: where its source lives (relative to the assets root), its bytes,
/// its glTF image index (none for a standalone image) and its role.
pub struct Source {
    pub file: String,
    pub image: Option<usize>,
    pub role: TextureRole,
    pub bytes: Vec<u8>,
}

/// The glTF files whose textures are encoded: the character and every prop.
fn models(assets: &Path) -> Result<Vec<String>, String> {
    let mut out = vec!["character.glb".to_string()];
    let props = assets.join("props");
    let mut names: Vec<String> = std::fs::read_dir(&props)
        .map_err(|e| format!("{}: {e}", props.display()))?
        .flatten()
        .filter_map(|e| e.file_name().to_str().map(str::to_owned))
        .filter(|n| n.ends_with(".glb"))
        .map(|n| format!("props/{n}"))
        .collect();
    names.sort();
    out.extend(names);
    Ok(out)
}

/// Every image the project ships, with its role: the models' under `assets`, the head's
/// under `head_assets`.
pub fn sources(assets: &Path, head_assets: &Path) -> Result<Vec<Source>, String> {
    let mut out = Vec::new();
    for file in models(assets)? {
        let bytes = read(assets, &file)?;
        for (image, role, bytes) in glb_textures(&bytes, &file)? {
            out.push(Source {
                file: file.clone(),
                image: Some(image),
                role,
                bytes,
            });
        }
    }
    for (name, role) in dermis_engine::asset::head::MAPS {
        let file = format!("{}/{name}", dermis_engine::asset::head::DIR);
        out.push(Source {
            bytes: read(head_assets, &file)?,
            file,
            image: None,
            role,
        });
    }
    Ok(out)
}

/// The source decoded to RGBA8, as the engine decodes it (alpha as the file has it).
fn decode(source: &Source) -> Result<(Vec<u8>, u32, u32), String> {
    let img = image::load_from_memory(&source.bytes)
        .map_err(|e| format!("{}: {e}", source.file))?
        .into_rgba8();
    let (w, h) = img.dimensions();
    Ok((img.into_raw(), w, h))
}

/// One level in `format`.
fn encode_level(rgba: &[u8], w: u32, h: u32, format: BlockFormat, srgb: bool) -> Vec<u8> {
    match format {
        BlockFormat::Bc1 | BlockFormat::Bc3 => {
            let f = match format {
                BlockFormat::Bc1 => texpresso::Format::Bc1,
                _ => texpresso::Format::Bc3,
            };
            let params = texpresso::Params {
                weights: match srgb {
                    true => texpresso::COLOUR_WEIGHTS_PERCEPTUAL,
                    false => texpresso::COLOUR_WEIGHTS_UNIFORM,
                },
                ..Default::default()
            };
            let (w, h) = (w as usize, h as usize);
            let mut out = vec![0; f.compressed_size(w, h)];
            f.compress(rgba, w, h, params, &mut out);
            out
        }
        BlockFormat::Etc2Rgb8 | BlockFormat::Etc2Rgba8 => {
            let weights = match srgb {
                true => etc2::Weights::COLOUR,
                false => etc2::Weights::DATA,
            };
            etc2::encode(rgba, w, h, format == BlockFormat::Etc2Rgba8, weights)
        }
        BlockFormat::Bc7 | BlockFormat::Astc4x4 => {
            unreachable!("no encoder for {format:?} (FAMILIES)")
        }
    }
}

/// The encodings of one source: (path relative to the assets root, KTX2 bytes).
pub fn encode(source: &Source, families: &[Family]) -> Result<Vec<(String, Vec<u8>)>, String> {
    let (rgba, w, h) = decode(source)?;
    let srgb = source.role.srgb();
    // Alpha is kept (BC3, ETC2 RGBA8) only where a texel has some; else RGB, which reads 255.
    let alpha = rgba.chunks_exact(4).any(|px| px[3] < 255);
    let levels = mip_chain(&rgba, w, h, srgb);
    let mut out = Vec::new();
    for &family in families {
        let Some(format) = BlockFormat::for_image(family, alpha) else {
            continue;
        };
        let encoded = levels
            .iter()
            .enumerate()
            .map(|(i, level)| {
                let (lw, lh) = level_size(w, h, i);
                encode_level(level, lw, lh, format, srgb)
            })
            .collect();
        let img = BlockImage {
            format,
            srgb,
            width: w,
            height: h,
            levels: encoded,
            source_hash: Some(fnv1a64(&source.bytes)),
        };
        let path = sidecar_path(&source.file, source.image, source.role, family);
        out.push((path, img.write()));
    }
    Ok(out)
}

/// Encodes every shipped texture — the models' in `out`, the head's in `head_assets` — into
/// `out` (the assets root's layout); returns what it wrote. A `.ktx2` file left in those
/// folders from an earlier run that no source makes now is removed (the APK would ship it).
pub fn write_all(out: &Path, head_assets: &Path) -> Result<Vec<(String, usize)>, String> {
    let mut written = Vec::new();
    for source in sources(out, head_assets)? {
        for (rel, bytes) in encode(&source, &FAMILIES)? {
            let path = out.join(&rel);
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            }
            std::fs::write(&path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            written.push((rel, bytes.len()));
        }
    }
    let rels: Vec<&str> = written.iter().map(|(r, _)| r.as_str()).collect();
    for stale in stale_files(out, &rels) {
        let path = out.join(&stale);
        std::fs::remove_file(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("removed {} (no source makes it now)", path.display());
    }
    Ok(written)
}

/// The `.ktx2` files in the folders of `made` (paths relative to `root`) that are not in it.
fn stale_files(root: &Path, made: &[&str]) -> Vec<String> {
    let mut dirs: Vec<&str> = made
        .iter()
        .filter_map(|r| r.rsplit_once('/'))
        .map(|d| d.0)
        .collect();
    dirs.sort_unstable();
    dirs.dedup();
    let mut out = Vec::new();
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        for name in entries
            .flatten()
            .filter_map(|e| e.file_name().into_string().ok())
        {
            let rel = format!("{dir}/{name}");
            if name.ends_with(".ktx2") && !made.contains(&rel.as_str()) {
                out.push(rel);
            }
        }
    }
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assets() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
    }

    /// Every shipped texture has its committed encodings, made from the current source (its
    /// hash), of its size and role, and no other encoding is committed beside them; the
    /// smallest is encoded again and is byte-identical (the
    /// encoders are deterministic and unchanged). Encoding everything takes a minute: that is
    /// `cargo xtask assets`'s job, not the test's.
    #[test]
    fn committed_encodings_are_current() {
        let assets = assets();
        let sources = sources(&assets, &assets).unwrap();
        assert!(sources.len() >= 8, "{} sources", sources.len());
        for s in &sources {
            for family in FAMILIES {
                let rel = sidecar_path(&s.file, s.image, s.role, family);
                let bytes = std::fs::read(assets.join(&rel))
                    .unwrap_or_else(|e| panic!("{rel}: {e}; run `cargo xtask assets`"));
                let img = BlockImage::read(&bytes, (8192, 1 << 28)).unwrap();
                assert_eq!(
                    img.source_hash,
                    Some(fnv1a64(&s.bytes)),
                    "{rel} is stale; run `cargo xtask assets`"
                );
                img.check_role(s.role).unwrap();
                assert_eq!(img.format.family(), family);
            }
        }
        let made: Vec<String> = sources
            .iter()
            .flat_map(|s| FAMILIES.map(|f| sidecar_path(&s.file, s.image, s.role, f)))
            .collect();
        let made: Vec<&str> = made.iter().map(String::as_str).collect();
        let stale = stale_files(&assets, &made);
        assert!(
            stale.is_empty(),
            "{stale:?}: no source makes them; run `cargo xtask assets`"
        );
        let smallest = sources.iter().min_by_key(|s| s.bytes.len()).unwrap();
        for (rel, bytes) in encode(smallest, &FAMILIES).unwrap() {
            let committed = std::fs::read(assets.join(&rel)).unwrap();
            assert!(committed == bytes, "{rel}: a fresh encoding differs");
        }
    }
}

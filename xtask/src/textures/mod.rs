//! The GPU block encodings of every texture the project ships (part of `cargo xtask assets`):
//! for every image a glTF file's materials reference — the character's, each prop's — and the
//! scanned head's two maps, in the role the material gives it (its colour space, whether its
//! alpha is kept), the full mip chain the renderer builds (`dermis_texture::mip_chain`) encoded
//! as BC (BC1, BC3 where the alpha is the skin mask: desktop GPUs) and ETC2 (RGB8 / RGBA8:
//! every Android GPU), each in a KTX2 file beside its source
//! recording the source's hash (`dermis_texture::sidecar_path`). Deterministic: the same sources give the same bytes.

pub mod etc2;

use std::path::Path;

use dermis_texture::{
    fnv1a64, level_size, mip_chain, sidecar_path, BlockFormat, BlockImage, Family, TextureRole,
};

/// The scanned head's maps and their roles, under the assets root (as `face::head` reads
/// them; dermis-core's tests load the head from its encodings, so a rename shows there).
pub const HEAD_MAPS: [(&str, TextureRole); 2] = [
    ("head/Map-COL.jpg", TextureRole::BaseColor),
    (
        "head/Infinite-Level_02_Tangent_SmoothUV.jpg",
        TextureRole::Normal,
    ),
];

/// Every (image, role) the materials of a .glb reference, each once, with the image's bytes
/// (the project's files embed their images).
fn glb_textures(bytes: &[u8], file: &str) -> Result<Vec<(usize, TextureRole, Vec<u8>)>, String> {
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| format!("{file}: {e}"))?;
    let blob = gltf.blob.as_deref().unwrap_or_default();
    let mut out: Vec<(usize, TextureRole, Vec<u8>)> = Vec::new();
    for mat in gltf.document.materials() {
        for (role, ti) in TextureRole::of_material(&mat) {
            let Some(image) = gltf.document.textures().nth(ti).map(|t| t.source()) else {
                continue;
            };
            if out
                .iter()
                .any(|(i, r, _)| *i == image.index() && *r == role)
            {
                continue;
            }
            let gltf::image::Source::View { view, .. } = image.source() else {
                return Err(format!("{file}: image {} is not embedded", image.index()));
            };
            let range = view.offset()..view.offset() + view.length();
            let data = blob
                .get(range)
                .ok_or_else(|| format!("{file}: image {} outside the BIN chunk", image.index()))?;
            out.push((image.index(), role, data.to_vec()));
        }
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
    for (file, role) in HEAD_MAPS {
        out.push(Source {
            bytes: read(head_assets, file)?,
            file: file.to_string(),
            image: None,
            role,
        });
    }
    Ok(out)
}

/// The source decoded to RGBA8 as the role uses it (alpha 255 unless it is kept).
fn decode(source: &Source) -> Result<(Vec<u8>, u32, u32), String> {
    let img = image::load_from_memory(&source.bytes)
        .map_err(|e| format!("{}: {e}", source.file))?
        .into_rgba8();
    let (w, h) = img.dimensions();
    let mut rgba = img.into_raw();
    if !source.role.alpha() {
        for px in rgba.chunks_exact_mut(4) {
            px[3] = 255;
        }
    }
    Ok((rgba, w, h))
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
    let levels = mip_chain(&rgba, w, h, srgb);
    let mut out = Vec::new();
    for &family in families {
        let Some(format) = BlockFormat::for_role(family, source.role) else {
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
/// `out` (the assets root's layout); returns what it wrote.
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
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assets() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets")
    }

    /// Every shipped texture has its committed encodings, made from the current source (its
    /// hash), of its size and role; the smallest is encoded again and is byte-identical (the
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
        let smallest = sources.iter().min_by_key(|s| s.bytes.len()).unwrap();
        for (rel, bytes) in encode(smallest, &FAMILIES).unwrap() {
            let committed = std::fs::read(assets.join(&rel)).unwrap();
            assert!(committed == bytes, "{rel}: a fresh encoding differs");
        }
    }
}

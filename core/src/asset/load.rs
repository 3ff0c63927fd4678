//! Entry points: read a .glb/.gltf from disk or from memory, check it completely, and build a
//! [`Model`]. Buffers and images are loaded here (not by `gltf::import`) so that every size is
//! checked against [`limits`](super::limits) before anything is allocated.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use super::accessor::{view_bytes, Buffers};
use super::animation::load_animation;
use super::compressed::{declares_skin_mask, encoded_texture, sidecar_path};
use super::limits::{
    MAX_EXTERNAL_FILE_BYTES, MAX_FILE_BYTES, MAX_TOTAL_BUFFER_BYTES, MAX_TOTAL_IMAGE_BYTES,
};
use super::nodes::{load_nodes, load_skin, scene_roots};
use super::uri::{resolve_uri, UriRef};
use super::vertices::{load_mesh, Totals};
use super::{glb, AssetError, Family, Material, Model, Texels, TextureImage, TextureRole};

/// Loads a .glb or .gltf file; external buffers/images are read from the file's folder.
pub fn load_gltf(path: &Path) -> Result<Model, AssetError> {
    let file = path.display().to_string();
    let err = |p: String| AssetError::new(file.clone(), p);
    let meta = std::fs::metadata(path).map_err(|e| err(format!("cannot open: {e}")))?;
    if !meta.is_file() {
        return Err(err("not a regular file".into()));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(err(format!(
            "file too large: {} bytes (limit {MAX_FILE_BYTES})",
            meta.len()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| err(format!("cannot read: {e}")))?;
    let resolve = dir_reader(path.parent().unwrap_or(Path::new(".")));
    load_gltf_slice(&bytes, &file, &resolve)
}

/// Reads files under `dir` by their relative path (regular files up to the loader's size
/// limit): what a model's external files, and its textures' encodings, are read with.
pub fn dir_reader(dir: &Path) -> impl Fn(&str) -> Result<Vec<u8>, String> {
    let dir = dir.to_path_buf();
    move |uri: &str| -> Result<Vec<u8>, String> {
        let p = dir.join(uri);
        let m = std::fs::metadata(&p).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => format!("external file {uri:?} not found"),
            _ => format!("cannot open external file {uri:?}: {e}"),
        })?;
        if !m.is_file() {
            return Err(format!("external file {uri:?} is not a regular file"));
        }
        if m.len() > MAX_EXTERNAL_FILE_BYTES {
            return Err(format!(
                "external file {uri:?} too large: {} bytes (limit {MAX_EXTERNAL_FILE_BYTES})",
                m.len()
            ));
        }
        std::fs::read(&p).map_err(|e| format!("cannot read external file {uri:?}: {e}"))
    }
}

/// Loads a .glb or .gltf held in memory. `name` is used in errors and as [`Model::source`];
/// `resolve` fetches external URIs (already checked to be relative paths inside the model's
/// folder, percent-decoded, `/`-separated) relative to the model.
pub fn load_gltf_slice(
    bytes: &[u8],
    name: &str,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
) -> Result<Model, AssetError> {
    // One line per problem, whatever the underlying library printed.
    load(bytes, name, resolve).map_err(|p| AssetError::new(name, p.replace(['\n', '\r'], " ")))
}

fn map_gltf_error(e: gltf::Error) -> String {
    match e {
        gltf::Error::Deserialize(e) => format!("invalid JSON: {e}"),
        gltf::Error::Validation(errs) => {
            let list: Vec<String> = errs
                .iter()
                .take(4)
                .map(|(path, e)| format!("{path}: {e}"))
                .collect();
            let more = errs.len().saturating_sub(4);
            let more = if more > 0 {
                format!(" (+{more} more)")
            } else {
                String::new()
            };
            format!("invalid glTF: {}{more}", list.join("; "))
        }
        e => format!("invalid glTF: {e}"),
    }
}

/// Checks what gltf-json's own validation indexes without checking (it would panic).
fn precheck(root: &gltf::json::Root) -> Result<(), String> {
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            for (sem, acc) in &prim.attributes {
                if acc.value() >= root.accessors.len() {
                    return Err(format!(
                        "mesh {mi} primitive {pi}: attribute {} references missing accessor {}",
                        sem.to_string(),
                        acc.value()
                    ));
                }
            }
        }
    }
    Ok(())
}

fn extension_supported(ext: &str) -> bool {
    ext.starts_with("KHR_materials_")
        || matches!(
            ext,
            "KHR_texture_transform" | "KHR_mesh_quantization" | "KHR_lights_punctual"
        )
}

fn load(
    bytes: &[u8],
    name: &str,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
) -> Result<Model, String> {
    if bytes.is_empty() {
        return Err("empty file (0 bytes)".into());
    }
    let (json, bin) = if glb::is_glb(bytes) {
        let g = glb::parse(bytes)?;
        (g.json, g.bin)
    } else {
        (bytes, None)
    };
    let raw = gltf::Gltf::from_slice_without_validation(json).map_err(map_gltf_error)?;
    let raw = raw.document.into_json();
    precheck(&raw)?;
    // Known gltf-json validation panics are prechecked above; the guard is defence in depth
    // (it cannot help where panics abort, hence the precheck).
    let validated = std::panic::catch_unwind(move || gltf::Document::from_json(raw))
        .map_err(|_| "glTF validation failed on malformed input".to_string())?;
    let doc = validated.map_err(map_gltf_error)?;
    let root = doc.as_json();

    for ext in doc.extensions_required() {
        if !extension_supported(ext) {
            return Err(format!("requires unsupported extension {ext}"));
        }
    }

    let buffers = load_buffers(&doc, bin, resolve)?;

    let nodes = load_nodes(&doc)?;
    let roots = scene_roots(&doc, &nodes)?;

    let mut totals = Totals::default();
    let mut meshes = Vec::with_capacity(root.meshes.len());
    let mut infos = Vec::with_capacity(root.meshes.len());
    for mesh in doc.meshes() {
        let (m, info) = load_mesh(&buffers, &mesh, &mut totals)?;
        meshes.push(m);
        infos.push(info);
    }

    let mut skins = Vec::with_capacity(root.skins.len());
    for skin in doc.skins() {
        skins.push(load_skin(&buffers, &skin, nodes.len())?);
    }

    for (ni, node) in nodes.iter().enumerate() {
        let (Some(si), Some(mi)) = (node.skin, node.mesh) else {
            if node.skin.is_some() {
                log::warn!("node {ni} has a skin but no mesh; skin ignored");
            }
            continue;
        };
        let skin = skins
            .get(si)
            .ok_or_else(|| format!("node {ni} references missing skin {si}"))?;
        let info = infos
            .get(mi)
            .ok_or_else(|| format!("node {ni} references missing mesh {mi}"))?;
        if info.has_rigid_primitive {
            return Err(format!(
                "node {ni} has skin {si} but a primitive of mesh {mi} lacks JOINTS_0/WEIGHTS_0"
            ));
        }
        if let Some(j) = info.max_joint {
            if j as usize >= skin.joints.len() {
                return Err(format!(
                    "joint index {j} out of range: skin {si} has {} joints (node {ni}, mesh {mi})",
                    skin.joints.len()
                ));
            }
        }
    }

    let (materials, textures) = load_materials(&doc, &buffers, name, resolve)?;

    let mut animations = Vec::with_capacity(root.animations.len());
    for ai in 0..root.animations.len() {
        animations.push(load_animation(&doc, &buffers, ai, nodes.len())?);
    }

    Ok(Model {
        source: name.to_owned(),
        nodes,
        roots,
        meshes,
        skins,
        materials,
        textures,
        animations,
    })
}

fn load_buffers<'a>(
    doc: &gltf::Document,
    bin: Option<&'a [u8]>,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
) -> Result<Buffers<'a>, String> {
    let root = doc.as_json();
    // Check the declared sizes of all buffers before loading any.
    let mut total: u64 = 0;
    for (i, b) in root.buffers.iter().enumerate() {
        total = total.saturating_add(b.byte_length.0);
        if total > MAX_TOTAL_BUFFER_BYTES {
            return Err(format!(
                "buffer {i}: byteLength {} brings the total above the limit \
                 {MAX_TOTAL_BUFFER_BYTES} bytes",
                b.byte_length.0
            ));
        }
    }
    let mut data = Vec::with_capacity(root.buffers.len());
    for (i, b) in root.buffers.iter().enumerate() {
        let len = b.byte_length.0 as usize; // ≤ 256 MiB, checked above
        let short =
            |have: usize| format!("buffer {i}: byteLength {len} but only {have} bytes of data");
        let bytes: Cow<'a, [u8]> = match b.uri.as_deref() {
            None => {
                if i != 0 {
                    return Err(format!(
                        "buffer {i} has no uri (only buffer 0 may use the GLB BIN chunk)"
                    ));
                }
                let bin = bin.ok_or_else(|| {
                    format!("buffer {i} has no uri and there is no GLB BIN chunk")
                })?;
                if bin.len() < len {
                    return Err(short(bin.len()));
                }
                Cow::Borrowed(&bin[..len])
            }
            Some(uri) => {
                let mut v = match resolve_uri(uri).map_err(|e| format!("buffer {i}: {e}"))? {
                    UriRef::Data(d) => d,
                    UriRef::Relative(p) => resolve(&p).map_err(|e| format!("buffer {i}: {e}"))?,
                };
                if v.len() < len {
                    return Err(short(v.len()));
                }
                v.truncate(len);
                Cow::Owned(v)
            }
        };
        data.push(bytes);
    }
    Ok(Buffers { data })
}

/// Makes every texel opaque: the engine draws opaque, and the character shader reads the
/// base colour's alpha as the skin mask, so a texture without a declared mask is all skin.
fn opaque(mut tex: TextureImage) -> TextureImage {
    if let Texels::Rgba8(px) = &mut tex.texels {
        for px in px.chunks_exact_mut(4) {
            px[3] = 255;
        }
    }
    tex
}

fn load_materials(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    name: &str,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
) -> Result<(Vec<Material>, Vec<TextureImage>), String> {
    let root = doc.as_json();
    let mut materials = Vec::with_capacity(root.materials.len());
    let mut textures: Vec<TextureImage> = Vec::new();
    // (image, role) -> texture slot.
    let mut by_image: HashMap<(usize, TextureRole), usize> = HashMap::new();
    let mut image_bytes: u64 = 0;
    let file = name.rsplit(['/', '\\']).next().unwrap_or(name);
    for mat in doc.materials() {
        let mi = mat.index().unwrap_or(0);
        let pbr = mat.pbr_metallic_roughness();
        let factor = pbr.base_color_factor();
        if factor.iter().any(|f| !f.is_finite()) {
            return Err(format!("material {mi}: NaN/Inf baseColorFactor"));
        }
        let mut base_color_texture = None;
        if let Some(info) = pbr.base_color_texture() {
            if info.tex_coord() != 0 {
                log::warn!(
                    "material {mi}: base colour uses TEXCOORD_{}; TEXCOORD_0 is used",
                    info.tex_coord()
                );
            }
            let ti = info.texture().index();
            let ii = root
                .textures
                .get(ti)
                .map(|t| t.source.value())
                .filter(|&ii| ii < root.images.len())
                .ok_or_else(|| format!("material {mi}: texture {ti} has no valid image source"))?;
            let role = match declares_skin_mask(&mat, mi) {
                true => TextureRole::BaseColorMasked,
                false => TextureRole::BaseColor,
            };
            let slot = match by_image.get(&(ii, role)) {
                Some(&s) => s,
                None => {
                    let tex = load_image(doc, buffers, resolve, ii, role, file)?;
                    let tex = if role.alpha() { tex } else { opaque(tex) };
                    image_bytes = image_bytes.saturating_add(tex.bytes());
                    if image_bytes > MAX_TOTAL_IMAGE_BYTES {
                        return Err(format!(
                            "decoded images above the limit {MAX_TOTAL_IMAGE_BYTES} bytes"
                        ));
                    }
                    textures.push(tex);
                    by_image.insert((ii, role), textures.len() - 1);
                    textures.len() - 1
                }
            };
            base_color_texture = Some(slot);
        }
        materials.push(Material {
            name: mat.name().map(str::to_owned),
            base_color_factor: factor,
            base_color_texture,
            normal_texture: None,
        });
    }
    Ok((materials, textures))
}

/// Image `index`'s bytes as the file holds them (PNG, JPEG or KTX2).
fn image_source(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    index: usize,
) -> Result<Vec<u8>, String> {
    let what = format!("image {index}");
    let image = doc
        .images()
        .nth(index)
        .ok_or_else(|| format!("missing {what}"))?;
    match image.source() {
        gltf::image::Source::View { view, .. } => view_bytes(buffers, &view)
            .map(<[u8]>::to_vec)
            .map_err(|e| format!("{what}: {e}")),
        gltf::image::Source::Uri { uri, .. } => {
            match resolve_uri(uri).map_err(|e| format!("{what}: {e}"))? {
                UriRef::Data(d) => Ok(d),
                UriRef::Relative(p) => resolve(&p).map_err(|e| format!("{what}: {e}")),
            }
        }
    }
}

/// Image `index` for `role`: its block encodings where `cargo xtask assets` made them beside
/// the model file (checked against the source's
/// hash and size) or the image is a KTX2 file itself, else the image decoded. See
/// [`sidecar_path`].
fn load_image(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    index: usize,
    role: TextureRole,
    file: &str,
) -> Result<TextureImage, String> {
    let what = format!("image {index}");
    let source = image_source(doc, buffers, resolve, index)?;
    let sidecar = |family: Family| sidecar_path(file, Some(index), role, family);
    encoded_texture(&source, role, &sidecar, resolve, &what)
}

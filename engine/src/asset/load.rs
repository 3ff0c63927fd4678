//! Entry points: read a .glb/.gltf from disk or from memory, check it completely, and build a
//! [`Model`]. Buffers and images are loaded here (not by `gltf::import`) so that every size is
//! checked against [`limits`](super::limits) before anything is allocated.

use std::borrow::Cow;
use std::path::Path;

use super::accessor::Buffers;
use super::animation::load_animation;
use super::limits::{MAX_EXTERNAL_FILE_BYTES, MAX_FILE_BYTES, MAX_TOTAL_BUFFER_BYTES};
use super::materials::{load_materials, sanitize, Warnings};
use super::nodes::{load_nodes, load_skin, scene_roots};
use super::uri::{resolve_uri, UriRef};
use super::vertices::{load_mesh, Totals};
use super::{glb, AssetError, Model};

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
    let mut raw = raw.document.into_json();
    precheck(&raw)?;
    let mut warnings = Warnings::new(name);
    sanitize(&mut raw, &mut warnings);
    // Required extensions the engine reads pass; gltf-json's validation refuses the others.
    raw.extensions_required.retain(|e| !extension_supported(e));
    // Known gltf-json validation panics are prechecked above; the guard is defence in depth
    // (it cannot help where panics abort, hence the precheck).
    let validated = std::panic::catch_unwind(move || gltf::Document::from_json(raw))
        .map_err(|_| "glTF validation failed on malformed input".to_string())?;
    let doc = validated.map_err(map_gltf_error)?;
    let root = doc.as_json();

    if let Some(ext) = doc.extensions_required().next() {
        return Err(format!("requires unsupported extension {ext}"));
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

    let (materials, textures) = load_materials(&doc, &buffers, (name, resolve), &mut warnings)?;

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
        warnings: warnings.list,
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

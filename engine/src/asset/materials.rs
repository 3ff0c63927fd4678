//! Reads every material of a glTF file into [`Material`], loading each texture it uses once
//! per role ([`TextureRole`]: colour, sRGB; data, linear) — its GPU block encodings where
//! `cargo xtask assets` made them, else the image decoded (`images::gltf_image`).
//!
//! A bad value never refuses the file: it gets one warning line naming the file, the
//! material and the value, and a fallback. Scalars out of range take glTF's default;
//! colour and [0, 1] factors out of range are clamped (an exporter's 1.0000001 keeps its
//! intent); a value of the wrong JSON type takes the default; a texture reference to a
//! texture that does not exist, to `TEXCOORD_1`, or to an image that does not decode is
//! dropped (the factor alone remains). The extensions read here are listed in
//! [`MATERIAL_EXTENSIONS`]; others on a material are named in one warning per file.

use std::collections::{BTreeSet, HashMap};

use gltf::json::validation::Checked;
use serde_json::{Map, Value};

use super::accessor::Buffers;
use super::images::gltf_image;
use super::limits::MAX_TOTAL_IMAGE_BYTES;
use super::material::{
    AlphaMode, DiffuseTransmission, Material, Volume, VolumeScatter, DEFAULT_IOR,
};
use super::{TextureImage, TextureRole};

/// The material extensions the loader reads.
pub const MATERIAL_EXTENSIONS: [&str; 5] = [
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_volume",
    "KHR_materials_volume_scatter",
    "KHR_materials_diffuse_transmission",
];

/// Collects the loader's warnings (each logged as it is made).
pub(super) struct Warnings<'a> {
    file: &'a str,
    pub list: Vec<String>,
}

impl<'a> Warnings<'a> {
    pub fn new(file: &'a str) -> Self {
        Self {
            file,
            list: Vec::new(),
        }
    }

    pub fn push(&mut self, msg: impl std::fmt::Display) {
        let line = format!("{}: {msg}", self.file).replace(['\n', '\r'], " ");
        log::warn!("{line}");
        self.list.push(line);
    }
}

/// Before glTF validation (which would refuse the whole file): material texture references
/// to textures that do not exist are dropped and an unknown `alphaMode` becomes OPAQUE, each
/// with a warning.
pub(super) fn sanitize(root: &mut gltf::json::Root, w: &mut Warnings<'_>) {
    let textures = root.textures.len();
    for (mi, m) in root.materials.iter_mut().enumerate() {
        let label = label(m.name.as_deref(), mi);
        let mut check = |what: &str, index: Option<usize>| -> bool {
            match index {
                Some(i) if i >= textures => {
                    w.push(format!(
                        "{label}: {what} references texture {i}, but the file has {textures}; \
                         texture ignored"
                    ));
                    false
                }
                _ => true,
            }
        };
        let pbr = &mut m.pbr_metallic_roughness;
        if !check("baseColorTexture", info_index(&pbr.base_color_texture)) {
            pbr.base_color_texture = None;
        }
        let mr = info_index(&pbr.metallic_roughness_texture);
        if !check("metallicRoughnessTexture", mr) {
            pbr.metallic_roughness_texture = None;
        }
        if !check("emissiveTexture", info_index(&m.emissive_texture)) {
            m.emissive_texture = None;
        }
        let normal = m.normal_texture.as_ref().map(|t| t.index.value());
        if !check("normalTexture", normal) {
            m.normal_texture = None;
        }
        let occlusion = m.occlusion_texture.as_ref().map(|t| t.index.value());
        if !check("occlusionTexture", occlusion) {
            m.occlusion_texture = None;
        }
        if matches!(m.alpha_mode, Checked::Invalid) {
            w.push(format!("{label}: unknown alphaMode; OPAQUE is used"));
            m.alpha_mode = Checked::Valid(gltf::json::material::AlphaMode::Opaque);
        }
    }
}

fn info_index(info: &Option<gltf::json::texture::Info>) -> Option<usize> {
    info.as_ref().map(|t| t.index.value())
}

fn label(name: Option<&str>, index: usize) -> String {
    match name {
        Some(n) => format!("material {index} {n:?}"),
        None => format!("material {index}"),
    }
}

/// Loads each (image, role) once; a failed load is remembered (and warned about once).
struct Textures<'a, 'b> {
    doc: &'a gltf::Document,
    buffers: &'a Buffers<'b>,
    /// The file's name (its encodings are beside it: `<name>.textures/`).
    file: &'a str,
    resolve: &'a dyn Fn(&str) -> Result<Vec<u8>, String>,
    slots: HashMap<(usize, TextureRole), Option<usize>>,
    images: Vec<TextureImage>,
    bytes: u64,
}

impl Textures<'_, '_> {
    /// The texture slot of `texture` (an index already checked to exist) in `role`.
    fn slot(
        &mut self,
        texture: usize,
        role: TextureRole,
        what: &str,
        w: &mut Warnings<'_>,
    ) -> Result<Option<usize>, String> {
        let root = self.doc.as_json();
        let Some(image) = root.textures.get(texture).map(|t| t.source.value()) else {
            return Ok(None);
        };
        if let Some(slot) = self.slots.get(&(image, role)) {
            return Ok(*slot);
        }
        let (doc, buffers, resolve) = (self.doc, self.buffers, self.resolve);
        let slot = match gltf_image(doc, buffers, resolve, (image, role), self.file) {
            Ok(tex) => {
                self.bytes = self.bytes.saturating_add(tex.bytes());
                if self.bytes > MAX_TOTAL_IMAGE_BYTES {
                    return Err(format!(
                        "decoded images above the limit {MAX_TOTAL_IMAGE_BYTES} bytes"
                    ));
                }
                self.images.push(tex);
                Some(self.images.len() - 1)
            }
            Err(e) => {
                w.push(format!("{what} (texture {texture}): {e}; texture ignored"));
                None
            }
        };
        self.slots.insert((image, role), slot);
        Ok(slot)
    }
}

/// Reads a file's external files by URI (the loader's resolver).
type Resolve<'a> = &'a dyn Fn(&str) -> Result<Vec<u8>, String>;

/// Reads every material of the file `name` and loads the textures they use.
pub(super) fn load_materials(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    (name, resolve): (&str, Resolve<'_>),
    w: &mut Warnings<'_>,
) -> Result<(Vec<Material>, Vec<TextureImage>), String> {
    let root = doc.as_json();
    let mut tex = Textures {
        doc,
        buffers,
        file: name.rsplit(['/', '\\']).next().unwrap_or(name),
        resolve,
        slots: HashMap::new(),
        images: Vec::new(),
        bytes: 0,
    };
    let mut unknown: BTreeSet<String> = BTreeSet::new();
    let mut materials = Vec::with_capacity(root.materials.len());
    for (mi, m) in root.materials.iter().enumerate() {
        let mut r = Reader {
            label: label(m.name.as_deref(), mi),
            tex: &mut tex,
            w,
        };
        let mut out = Material {
            name: m.name.clone(),
            ..Material::default()
        };
        r.core(m, &mut out)?;
        if let Some(ext) = m.extensions.as_ref().map(|e| &e.others) {
            for key in ext.keys() {
                if !MATERIAL_EXTENSIONS.contains(&key.as_str()) {
                    unknown.insert(key.clone());
                }
            }
            r.extensions(ext, &mut out)?;
        }
        materials.push(out);
    }
    if !unknown.is_empty() {
        let list: Vec<&str> = unknown.iter().map(String::as_str).collect();
        w.push(format!(
            "material extensions not supported, ignored: {}",
            list.join(", ")
        ));
    }
    Ok((materials, tex.images))
}

/// Reads one material, warning under its label.
struct Reader<'r, 'a, 'b, 'w> {
    label: String,
    tex: &'r mut Textures<'a, 'b>,
    w: &'r mut Warnings<'w>,
}

impl Reader<'_, '_, '_, '_> {
    fn warn(&mut self, msg: impl std::fmt::Display) {
        let line = format!("{}: {msg}", self.label);
        self.w.push(line);
    }

    /// A [0, 1] factor: clamped, non-finite → `default`.
    fn unit(&mut self, what: &str, v: f32, default: f32) -> f32 {
        if !v.is_finite() {
            self.warn(format_args!(
                "{what} = {v} is not finite; {default} is used"
            ));
            default
        } else if !(0.0..=1.0).contains(&v) {
            let c = v.clamp(0.0, 1.0);
            self.warn(format_args!(
                "{what} = {v} is outside [0, 1]; clamped to {c}"
            ));
            c
        } else {
            v
        }
    }

    fn colour<const N: usize>(&mut self, what: &str, v: [f32; N], default: f32) -> [f32; N] {
        if v.iter().any(|x| !x.is_finite()) {
            self.warn(format_args!(
                "{what} = {v:?} is not finite; the default is used"
            ));
            return [default; N];
        }
        if v.iter().any(|x| !(0.0..=1.0).contains(x)) {
            let c = v.map(|x| x.clamp(0.0, 1.0));
            self.warn(format_args!(
                "{what} = {v:?} is outside [0, 1]; clamped to {c:?}"
            ));
            return c;
        }
        v
    }

    /// A texture reference `index`/`tex_coord` read as `role`.
    fn texture(
        &mut self,
        what: &str,
        index: usize,
        tex_coord: u64,
        transform: bool,
        role: TextureRole,
    ) -> Result<Option<usize>, String> {
        let count = self.tex.doc.as_json().textures.len();
        if index >= count {
            self.warn(format_args!(
                "{what} references texture {index}, but the file has {count}; texture ignored"
            ));
            return Ok(None);
        }
        if tex_coord != 0 {
            self.warn(format_args!(
                "{what} uses TEXCOORD_{tex_coord} (only TEXCOORD_0 is loaded); texture ignored"
            ));
            return Ok(None);
        }
        if transform {
            self.warn(format_args!("{what}: KHR_texture_transform is not applied"));
        }
        let what = format!("{}: {what}", self.label);
        self.tex.slot(index, role, &what, self.w)
    }

    fn info(
        &mut self,
        what: &str,
        info: &Option<gltf::json::texture::Info>,
        role: TextureRole,
    ) -> Result<Option<usize>, String> {
        let Some(i) = info else {
            return Ok(None);
        };
        let transform = i
            .extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key("KHR_texture_transform"));
        self.texture(what, i.index.value(), i.tex_coord as u64, transform, role)
    }

    /// The core glTF 2.0 material.
    fn core(&mut self, m: &gltf::json::Material, out: &mut Material) -> Result<(), String> {
        let pbr = &m.pbr_metallic_roughness;
        out.base_color_factor = self.colour("baseColorFactor", pbr.base_color_factor.0, 1.0);
        out.base_color_texture = self.info(
            "baseColorTexture",
            &pbr.base_color_texture,
            TextureRole::Colour,
        )?;
        out.metallic_factor = self.unit("metallicFactor", pbr.metallic_factor.0, 1.0);
        out.roughness_factor = self.unit("roughnessFactor", pbr.roughness_factor.0, 1.0);
        out.metallic_roughness_texture = self.info(
            "metallicRoughnessTexture",
            &pbr.metallic_roughness_texture,
            TextureRole::Data,
        )?;
        if let Some(n) = &m.normal_texture {
            let t = n.extensions.as_ref().is_some_and(|e| !e.others.is_empty());
            let idx = n.index.value();
            out.normal_texture = self.texture(
                "normalTexture",
                idx,
                n.tex_coord as u64,
                t,
                TextureRole::Data,
            )?;
            out.normal_scale = if n.scale.is_finite() {
                n.scale
            } else {
                self.warn(format_args!(
                    "normalTexture.scale = {} is not finite; 1 is used",
                    n.scale
                ));
                1.0
            };
        }
        if let Some(o) = &m.occlusion_texture {
            let t = o.extensions.as_ref().is_some_and(|e| !e.others.is_empty());
            let idx = o.index.value();
            out.occlusion_texture = self.texture(
                "occlusionTexture",
                idx,
                o.tex_coord as u64,
                t,
                TextureRole::Data,
            )?;
            out.occlusion_strength = self.unit("occlusionTexture.strength", o.strength.0, 1.0);
        }
        out.emissive_factor = self.colour("emissiveFactor", m.emissive_factor.0, 0.0);
        out.emissive_texture =
            self.info("emissiveTexture", &m.emissive_texture, TextureRole::Colour)?;
        out.alpha_mode = match m.alpha_mode {
            Checked::Valid(gltf::json::material::AlphaMode::Mask) => {
                let cutoff = m.alpha_cutoff.map_or(0.5, |c| c.0);
                let cutoff = if cutoff.is_finite() && cutoff >= 0.0 {
                    cutoff
                } else {
                    self.warn(format_args!(
                        "alphaCutoff = {cutoff} is not ≥ 0; 0.5 is used"
                    ));
                    0.5
                };
                AlphaMode::Mask { cutoff }
            }
            Checked::Valid(gltf::json::material::AlphaMode::Blend) => AlphaMode::Blend,
            _ => AlphaMode::Opaque,
        };
        out.double_sided = m.double_sided;
        Ok(())
    }

    /// The material extensions of [`MATERIAL_EXTENSIONS`], from their raw JSON.
    fn extensions(&mut self, ext: &Map<String, Value>, out: &mut Material) -> Result<(), String> {
        if let Some(e) = self.object(ext, "KHR_materials_emissive_strength") {
            let keys = ["emissiveStrength"];
            self.unknown_keys("KHR_materials_emissive_strength", e, &keys);
            let s = self.number(
                e,
                "KHR_materials_emissive_strength.emissiveStrength",
                1.0,
                |v| v >= 0.0,
                "≥ 0",
            );
            out.emissive_strength = s as f32;
        }
        if let Some(e) = self.object(ext, "KHR_materials_ior") {
            self.unknown_keys("KHR_materials_ior", e, &["ior"]);
            let ior = self.number(
                e,
                "KHR_materials_ior.ior",
                DEFAULT_IOR as f64,
                |v| v >= 1.0,
                "≥ 1",
            );
            out.ior = ior as f32;
        }
        if let Some(e) = self.object(ext, "KHR_materials_volume") {
            let name = "KHR_materials_volume";
            let keys = [
                "thicknessFactor",
                "thicknessTexture",
                "attenuationDistance",
                "attenuationColor",
            ];
            self.unknown_keys(name, e, &keys);
            let d = Volume::default();
            out.volume = Some(Volume {
                thickness_factor: self.number(
                    e,
                    "KHR_materials_volume.thicknessFactor",
                    0.0,
                    |v| v >= 0.0,
                    "≥ 0",
                ) as f32,
                thickness_texture: self.ext_texture(
                    e,
                    name,
                    "thicknessTexture",
                    TextureRole::Data,
                )?,
                attenuation_distance: self.number(
                    e,
                    "KHR_materials_volume.attenuationDistance",
                    f64::INFINITY,
                    |v| v > 0.0,
                    "> 0",
                ) as f32,
                attenuation_color: self.ext_colour(
                    e,
                    name,
                    "attenuationColor",
                    d.attenuation_color,
                ),
            });
        }
        if let Some(e) = self.object(ext, "KHR_materials_volume_scatter") {
            let name = "KHR_materials_volume_scatter";
            // The draft's README spells the factor `multiscatterColor` (earlier revisions:
            // `scatterAlbedo`, KhronosGroup/glTF commit a4531034); implementations and its
            // texture use `multiscatterColorFactor` / `multiscatterColorTexture`.
            let keys = [
                "multiscatterColor",
                "multiscatterColorFactor",
                "scatterAlbedo",
                "multiscatterColorTexture",
                "scatterAnisotropy",
            ];
            self.unknown_keys(name, e, &keys);
            let d = VolumeScatter::default();
            let spelling = [
                "multiscatterColor",
                "multiscatterColorFactor",
                "scatterAlbedo",
            ]
            .into_iter()
            .find(|k| e.contains_key(*k))
            .unwrap_or("multiscatterColor");
            let anisotropy = self.number(
                e,
                "KHR_materials_volume_scatter.scatterAnisotropy",
                0.0,
                |g| g > -1.0 && g < 1.0,
                "in (−1, 1)",
            );
            let texture =
                self.ext_texture(e, name, "multiscatterColorTexture", TextureRole::Colour)?;
            if texture.is_some() && !e.contains_key(spelling) {
                self.warn(format_args!(
                    "{name}.multiscatterColorTexture without multiscatterColor: the factor's \
                     default [0, 0, 0] makes it black"
                ));
            }
            out.volume_scatter = Some(VolumeScatter {
                multiscatter_color: self.ext_colour(e, name, spelling, d.multiscatter_color),
                multiscatter_texture: texture,
                anisotropy: anisotropy as f32,
            });
        }
        if let Some(e) = self.object(ext, "KHR_materials_diffuse_transmission") {
            let name = "KHR_materials_diffuse_transmission";
            let keys = [
                "diffuseTransmissionFactor",
                "diffuseTransmissionTexture",
                "diffuseTransmissionColorFactor",
                "diffuseTransmissionColorTexture",
            ];
            self.unknown_keys(name, e, &keys);
            let d = DiffuseTransmission::default();
            let factor = self.number(
                e,
                "KHR_materials_diffuse_transmission.diffuseTransmissionFactor",
                0.0,
                |v| (0.0..=1.0).contains(&v),
                "in [0, 1]",
            );
            out.diffuse_transmission = Some(DiffuseTransmission {
                factor: factor as f32,
                texture: self.ext_texture(
                    e,
                    name,
                    "diffuseTransmissionTexture",
                    TextureRole::Data,
                )?,
                color_factor: self.ext_colour(
                    e,
                    name,
                    "diffuseTransmissionColorFactor",
                    d.color_factor,
                ),
                color_texture: self.ext_texture(
                    e,
                    name,
                    "diffuseTransmissionColorTexture",
                    TextureRole::Colour,
                )?,
            });
        }
        Ok(())
    }

    /// The extension object `name`, if present (a non-object is warned about and ignored).
    fn object<'m>(
        &mut self,
        ext: &'m Map<String, Value>,
        name: &str,
    ) -> Option<&'m Map<String, Value>> {
        match ext.get(name)? {
            Value::Object(o) => Some(o),
            v => {
                self.warn(format_args!(
                    "{name} = {v} is not an object; extension ignored"
                ));
                None
            }
        }
    }

    fn unknown_keys(&mut self, name: &str, e: &Map<String, Value>, known: &[&str]) {
        for k in e.keys() {
            if !known.contains(&k.as_str()) && k != "extensions" && k != "extras" {
                self.warn(format_args!("{name}.{k} is not a known property; ignored"));
            }
        }
    }

    /// A number: absent → `default`; not a number, non-finite or failing `valid` → `default`.
    fn number(
        &mut self,
        e: &Map<String, Value>,
        what: &str,
        default: f64,
        valid: impl Fn(f64) -> bool,
        range: &str,
    ) -> f64 {
        let key = what.rsplit('.').next().unwrap_or(what);
        match e.get(key) {
            None => default,
            Some(v) => match v.as_f64() {
                Some(x) if x.is_finite() && valid(x) => x,
                Some(x) => {
                    self.warn(format_args!(
                        "{what} = {x} is not {range}; {default} is used"
                    ));
                    default
                }
                None => {
                    self.warn(format_args!(
                        "{what} = {v} is not a number; {default} is used"
                    ));
                    default
                }
            },
        }
    }

    /// An RGB colour in [0, 1] (clamped); anything but three numbers → `default`.
    fn ext_colour(
        &mut self,
        e: &Map<String, Value>,
        name: &str,
        key: &str,
        default: [f32; 3],
    ) -> [f32; 3] {
        let Some(v) = e.get(key) else {
            return default;
        };
        let what = format!("{name}.{key}");
        let nums: Option<Vec<f64>> = v
            .as_array()
            .map(|a| a.iter().filter_map(Value::as_f64).collect());
        match nums {
            Some(n) if n.len() == 3 && v.as_array().is_some_and(|a| a.len() == 3) => {
                self.colour(&what, [n[0] as f32, n[1] as f32, n[2] as f32], 0.0)
            }
            _ => {
                self.warn(format_args!(
                    "{what} = {v} is not three numbers; {default:?} is used"
                ));
                default
            }
        }
    }

    /// A texture reference (`{"index": i, "texCoord": k}`) inside an extension.
    fn ext_texture(
        &mut self,
        e: &Map<String, Value>,
        name: &str,
        key: &str,
        role: TextureRole,
    ) -> Result<Option<usize>, String> {
        let Some(v) = e.get(key) else {
            return Ok(None);
        };
        let what = format!("{name}.{key}");
        let index = v.get("index").and_then(Value::as_u64);
        let tex_coord = match v.get("texCoord") {
            None => Some(0),
            Some(t) => t.as_u64(),
        };
        let (Some(index), Some(tex_coord)) = (index, tex_coord) else {
            self.warn(format_args!(
                "{what} = {v} is not a texture reference; texture ignored"
            ));
            return Ok(None);
        };
        let transform = v
            .get("extensions")
            .and_then(|x| x.get("KHR_texture_transform"))
            .is_some();
        let index = usize::try_from(index).unwrap_or(usize::MAX);
        self.texture(&what, index, tex_coord, transform, role)
    }
}

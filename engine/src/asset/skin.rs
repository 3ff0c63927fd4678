//! Which materials of a model are skin, and with which optics ([`classify`]).
//!
//! In order:
//! 1. **The user's choice** ([`SkinChoice`], `MATERIAL[=preset],…` or `none`) decides alone:
//!    the materials it names are skin, no other is. A named material takes the preset's
//!    optics when one is given, else its own extensions' (below), else [`DEFAULT_SKIN`]'s.
//! 2. **The file's declaration**: a material with `KHR_materials_volume_scatter` is skin, with
//!    the optics its extensions give ([`skin_optics`]: `KHR_materials_volume`'s attenuation,
//!    the multi-scatter albedo, the anisotropy, `KHR_materials_ior`). When any
//!    material of the file declares it, no other material is skin. `KHR_materials_volume` with
//!    `KHR_materials_diffuse_transmission` alone is *not* skin: without the scatter extension
//!    the volume only absorbs (σ_s = 0 by `KHR_materials_volume`'s definition), so there is no
//!    scattering medium for the skin models; it is drawn as standard PBR.
//! 3. **The name rule**, for files that declare nothing: a material whose name has one of the
//!    words [`SKIN_WORDS`] and none of [`NOT_SKIN_WORDS`] is skin, with [`DEFAULT_SKIN`]'s
//!    optics. Words are the name split at non-alphanumerics, lower→upper case changes and
//!    letter↔digit changes, compared case-insensitively (`M_Skin_01`, `CharacterSkin`,
//!    `face` match; `Skinny`, `HairBase`, `Cesium_Man-effect`, `fox_material` do not).
//! 4. Otherwise **no material is skin**: every material is drawn as standard PBR and the skin
//!    models have nothing to shade (CesiumMan, the Fox, RiggedFigure, RiggedSimple).
//!
//! The albedo a skin material shows is [`Material::skin_albedo`](super::Material::skin_albedo).

use std::str::FromStr;

use super::Model;
use crate::shading::material::{Material as Optics, DEFAULT_SKIN, PRESETS};
use crate::shading::volume_optics::VolumeOptics;

/// Name words that make a material skin (rule 3).
pub const SKIN_WORDS: [&str; 5] = ["skin", "flesh", "face", "body", "head"];

/// Name words that keep a material from being skin by its name, whatever else it says.
pub const NOT_SKIN_WORDS: [&str; 28] = [
    "hair",
    "eye",
    "eyes",
    "eyelash",
    "eyelashes",
    "lash",
    "lashes",
    "brow",
    "brows",
    "eyebrow",
    "eyebrows",
    "teeth",
    "tooth",
    "tongue",
    "nail",
    "nails",
    "cloth",
    "clothes",
    "clothing",
    "shirt",
    "pants",
    "shoe",
    "shoes",
    "suit",
    "armor",
    "armour",
    "helmet",
    "hat",
];

/// The user's choice of skin materials: `none`, or `MATERIAL[=PRESET]` entries separated by
/// commas (a material by name, case-insensitive, or by index as `#N`).
#[derive(Clone, Debug, PartialEq)]
pub struct SkinChoice {
    pub entries: Vec<ChoiceEntry>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceEntry {
    pub material: String,
    /// The preset whose optics it takes (else its extensions', else the default skin's).
    pub preset: Option<&'static str>,
}

impl FromStr for SkinChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("none") {
            return Ok(SkinChoice {
                entries: Vec::new(),
            });
        }
        let mut entries = Vec::new();
        for item in s.split(',') {
            let (material, preset) = match item.split_once('=') {
                Some((m, p)) => (m.trim(), Some(p.trim())),
                None => (item.trim(), None),
            };
            if material.is_empty() {
                return Err(format!(
                    "skin choice {s:?}: an empty material name (MATERIAL[=PRESET],… or none)"
                ));
            }
            let preset = match preset {
                None => None,
                Some(p) => Some(
                    PRESETS
                        .iter()
                        .find(|m| m.name == p)
                        .and_then(Optics::preset_name)
                        .ok_or_else(|| {
                            let names: Vec<&str> = PRESETS.iter().map(|m| &*m.name).collect();
                            format!(
                                "skin choice {s:?}: unknown preset {p:?} (presets: {})",
                                names.join(", ")
                            )
                        })?,
                ),
            };
            entries.push(ChoiceEntry {
                material: material.to_owned(),
                preset,
            });
        }
        Ok(SkinChoice { entries })
    }
}

impl std::fmt::Display for SkinChoice {
    /// The choice as it is written (`none`, or `MATERIAL[=PRESET],…`): what parses back.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.entries.is_empty() {
            return f.write_str("none");
        }
        for (i, e) in self.entries.iter().enumerate() {
            if i > 0 {
                f.write_str(",")?;
            }
            f.write_str(&e.material)?;
            if let Some(p) = e.preset {
                write!(f, "={p}")?;
            }
        }
        Ok(())
    }
}

/// Why a material is, or is not, skin.
#[derive(Clone, Debug, PartialEq)]
pub enum Reason {
    /// Skin: it has `KHR_materials_volume_scatter`.
    Extensions,
    /// Skin: the user named it.
    Chosen,
    /// Skin: its name has this word ([`SKIN_WORDS`]).
    Name(&'static str),
    /// Not skin: the user chose other materials (or none).
    NotChosen,
    /// Not skin: other materials of the file declare skin by extension.
    NotDeclared,
    /// Not skin: its name has this word ([`NOT_SKIN_WORDS`]).
    NameExcluded(&'static str),
    /// Not skin: its name has no word of [`SKIN_WORDS`].
    NameDoesNotMatch,
}

/// One material's classification.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialClass {
    /// Index into [`Model::materials`].
    pub material: usize,
    /// The optics it is shaded with, when it is skin.
    pub skin: Option<Optics>,
    pub reason: Reason,
    /// What went wrong with its extensions' optics, if anything (also in the log).
    pub note: Option<String>,
}

/// Every material's classification, and the log line that says it.
#[derive(Clone, Debug, PartialEq)]
pub struct Classification {
    pub materials: Vec<MaterialClass>,
    /// The one line logged: which materials were taken for skin and why.
    pub summary: String,
}

impl Classification {
    /// Whether material `index` is skin.
    pub fn is_skin(&self, index: usize) -> bool {
        self.materials.get(index).is_some_and(|c| c.skin.is_some())
    }

    /// The skin materials' indices.
    pub fn skin_materials(&self) -> Vec<usize> {
        self.materials
            .iter()
            .filter(|c| c.skin.is_some())
            .map(|c| c.material)
            .collect()
    }
}

/// The words of a material name, lower-cased (see the module docs).
pub fn name_words(name: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut cur = String::new();
    let mut prev: Option<char> = None;
    for ch in name.chars() {
        if !ch.is_alphanumeric() {
            if !cur.is_empty() {
                words.push(std::mem::take(&mut cur));
            }
            prev = None;
            continue;
        }
        if let Some(p) = prev {
            let case_up = p.is_lowercase() && ch.is_uppercase();
            let digit = p.is_ascii_digit() != ch.is_ascii_digit();
            if (case_up || digit) && !cur.is_empty() {
                words.push(std::mem::take(&mut cur));
            }
        }
        cur.extend(ch.to_lowercase());
        prev = Some(ch);
    }
    if !cur.is_empty() {
        words.push(cur);
    }
    words
}

/// The name rule (rule 3) on one name.
pub fn name_rule(name: &str) -> Reason {
    let words = name_words(name);
    if let Some(w) = NOT_SKIN_WORDS
        .iter()
        .find(|w| words.iter().any(|x| x == *w))
    {
        return Reason::NameExcluded(w);
    }
    match SKIN_WORDS.iter().find(|w| words.iter().any(|x| x == *w)) {
        Some(w) => Reason::Name(w),
        None => Reason::NameDoesNotMatch,
    }
}

/// Classifies every material of `model` (the user's `choice` first, see the module docs),
/// logs the one line that says which are skin and why, and returns both. Errors (one line)
/// when the choice names a material the model does not have.
pub fn classify(model: &Model, choice: Option<&SkinChoice>) -> Result<Classification, String> {
    let n = model.materials.len();
    let name_of = |i: usize| model.materials[i].name.clone().unwrap_or_default();
    let mut chosen: Vec<Option<Option<&'static str>>> = vec![None; n];
    if let Some(c) = choice {
        for e in &c.entries {
            let found = match e.material.strip_prefix('#') {
                Some(k) => k.parse::<usize>().ok().filter(|&i| i < n),
                None => (0..n).find(|&i| name_of(i).eq_ignore_ascii_case(&e.material)),
            };
            let Some(i) = found else {
                let names: Vec<String> = (0..n).map(|i| format!("{:?}", name_of(i))).collect();
                return Err(format!(
                    "{}: no material {:?} to take for skin (its materials: {})",
                    model.source,
                    e.material,
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                ));
            };
            chosen[i] = Some(e.preset);
        }
    }
    let declared = model.materials.iter().any(|m| m.volume_scatter.is_some());
    let mut out = Vec::with_capacity(n);
    for (i, m) in model.materials.iter().enumerate() {
        let name = name_of(i);
        let from_extensions = |note: &mut Option<String>| {
            skin_optics(model, i).map(|v| {
                let (optics, why) = v.to_material(&name);
                *note = why;
                optics
            })
        };
        let mut note = None;
        let (skin, reason) = if choice.is_some() {
            match chosen[i] {
                Some(Some(preset)) => (
                    Optics::preset(preset).map(|p| p.for_file_material(&name)),
                    Reason::Chosen,
                ),
                Some(None) => (
                    from_extensions(&mut note)
                        .or_else(|| Some(DEFAULT_SKIN.for_file_material(&name))),
                    Reason::Chosen,
                ),
                None => (None, Reason::NotChosen),
            }
        } else if declared {
            match from_extensions(&mut note) {
                Some(o) => (Some(o), Reason::Extensions),
                None => (None, Reason::NotDeclared),
            }
        } else {
            match name_rule(&name) {
                Reason::Name(w) => (Some(DEFAULT_SKIN.for_file_material(&name)), Reason::Name(w)),
                r => (None, r),
            }
        };
        if let Some(note) = &note {
            log::warn!("{}: {}: {note}", model.source, m.label(i));
        }
        out.push(MaterialClass {
            material: i,
            skin,
            reason,
            note,
        });
    }
    let summary = summary(model, &out, choice.is_some(), declared);
    log::info!("{summary}");
    Ok(Classification {
        materials: out,
        summary,
    })
}

/// The volume optics material `mi`'s extensions declare (it has
/// `KHR_materials_volume_scatter`): σ_t from `KHR_materials_volume`'s attenuation (none
/// without it), η from `KHR_materials_ior`, g, and the multi-scatter albedo A of the material
/// as a whole: its factor × the mean of its texture ([`texture_mean`]) when it has one.
pub fn skin_optics(model: &Model, mi: usize) -> Option<VolumeOptics> {
    let m = model.materials.get(mi)?;
    let scatter = m.volume_scatter?;
    let volume = m.volume.unwrap_or_default();
    let factor = scatter.multiscatter_color.map(f64::from);
    let mean = scatter
        .multiscatter_texture
        .and_then(|t| texture_mean(model, mi, t))
        .unwrap_or([1.0; 3]);
    Some(VolumeOptics {
        attenuation_distance_m: volume.attenuation_distance as f64,
        attenuation_color: volume.attenuation_color.map(f64::from),
        multiscatter: std::array::from_fn(|c| factor[c] * mean[c]),
        anisotropy: scatter.anisotropy as f64,
        ior: m.ior as f64,
    })
}

/// An 8-bit sRGB value as linear [0, 1] (the sRGB transfer function).
pub fn srgb_to_linear(v: u8) -> f64 {
    let c = v as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The mean linear RGB of texture `t` over the texels material `mi` covers: every triangle of
/// its primitives sampled (nearest texel, UVs wrapped) at its UV centroid, weighted by its
/// area in UV space; sRGB textures decoded. `None` when the texture does not exist; the plain
/// mean of the texture when the material covers no UV area.
pub fn texture_mean(model: &Model, mi: usize, t: usize) -> Option<[f64; 3]> {
    let tex = model.textures.get(t)?;
    let (w, h) = (tex.width as usize, tex.height as usize);
    if w == 0 || h == 0 {
        return None;
    }
    // Level 0 (a block encoding's decoded: the texels the GPU samples).
    let px = tex.rgba8().ok()?;
    let decode = |v: u8| {
        if tex.srgb {
            srgb_to_linear(v)
        } else {
            v as f64 / 255.0
        }
    };
    let texel = |x: usize, y: usize| -> [f64; 3] {
        let i = 4 * (y * w + x);
        std::array::from_fn(|c| decode(px[i + c]))
    };
    let mut sum = [0.0f64; 3];
    let mut weight = 0.0f64;
    let prims = model.meshes.iter().flat_map(|m| &m.primitives);
    for p in prims.filter(|p| p.material == Some(mi)) {
        for tri in p.indices.chunks_exact(3) {
            let uv: [[f32; 2]; 3] =
                std::array::from_fn(|k| p.vertices.get(tri[k] as usize).map_or([0.0; 2], |v| v.uv));
            let [a, b, c] = uv.map(|t| [t[0] as f64, t[1] as f64]);
            let area = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() * 0.5;
            let (u, v) = ((a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0);
            if !(area > 0.0 && u.is_finite() && v.is_finite()) {
                continue;
            }
            let x = ((u.rem_euclid(1.0) * w as f64) as usize).min(w - 1);
            let y = ((v.rem_euclid(1.0) * h as f64) as usize).min(h - 1);
            let s = texel(x, y);
            for k in 0..3 {
                sum[k] += area * s[k];
            }
            weight += area;
        }
    }
    if weight > 0.0 {
        return Some(sum.map(|s| s / weight));
    }
    let n = (w * h) as f64;
    let mut all = [0.0f64; 3];
    for y in 0..h {
        for x in 0..w {
            let s = texel(x, y);
            for k in 0..3 {
                all[k] += s[k] / n;
            }
        }
    }
    Some(all)
}

fn summary(model: &Model, classes: &[MaterialClass], chosen: bool, declared: bool) -> String {
    let label = |c: &MaterialClass| model.materials[c.material].label(c.material);
    let skin: Vec<String> = classes
        .iter()
        .filter_map(|c| {
            let optics = c.skin.as_ref()?;
            let why = match &c.reason {
                Reason::Extensions => "KHR_materials_volume_scatter".to_string(),
                Reason::Chosen => "chosen by the user".to_string(),
                Reason::Name(w) => format!("its name has the word {w:?}"),
                _ => String::new(),
            };
            let of = match (&c.reason, optics.preset_name()) {
                (Reason::Extensions, Some(p)) => format!("its extensions' optics, equal to {p}'s"),
                (Reason::Extensions, None) => "its extensions' optics".to_string(),
                (_, Some(p)) => format!("{p}'s optics"),
                (_, None) => "its extensions' optics".to_string(),
            };
            Some(format!("{} ({why}; {of})", label(c)))
        })
        .collect();
    let rest: Vec<String> = classes
        .iter()
        .filter(|c| c.skin.is_none())
        .map(label)
        .collect();
    let basis = if chosen {
        "by the user's choice"
    } else if declared {
        "declared by KHR_materials_volume_scatter"
    } else {
        "by the name rule (no material declares KHR_materials_volume_scatter)"
    };
    if skin.is_empty() {
        let names = if rest.is_empty() {
            "the file has no materials".to_string()
        } else {
            format!("standard PBR: {}", rest.join(", "))
        };
        format!("{}: no skin material {basis}; {names}", model.source)
    } else if rest.is_empty() {
        format!("{}: skin {basis}: {}", model.source, skin.join(", "))
    } else {
        format!(
            "{}: skin {basis}: {}; standard PBR: {}",
            model.source,
            skin.join(", "),
            rest.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_of_names() {
        assert_eq!(name_words("M_Skin_01"), ["m", "skin", "01"]);
        assert_eq!(name_words("CharacterSkin"), ["character", "skin"]);
        assert_eq!(name_words("HairBase"), ["hair", "base"]);
        assert_eq!(name_words("Cesium_Man-effect"), ["cesium", "man", "effect"]);
        assert_eq!(name_words("Material.002"), ["material", "002"]);
        assert_eq!(name_words("HEAD"), ["head"]);
    }

    #[test]
    fn the_name_rule() {
        assert_eq!(name_rule("Skin"), Reason::Name("skin"));
        assert_eq!(name_rule("body_mat"), Reason::Name("body"));
        assert_eq!(name_rule("FaceSkin"), Reason::Name("skin"));
        assert_eq!(name_rule("Skinny"), Reason::NameDoesNotMatch);
        assert_eq!(name_rule("BodySuit"), Reason::NameExcluded("suit"));
        assert_eq!(name_rule("Eyes"), Reason::NameExcluded("eyes"));
        assert_eq!(name_rule("fox_material"), Reason::NameDoesNotMatch);
    }

    #[test]
    fn choices_parse() {
        let c: SkinChoice = "Skin=white-coat, Face".parse().unwrap();
        assert_eq!(c.entries.len(), 2);
        assert_eq!(c.entries[0].preset, Some("white-coat"));
        assert_eq!(c.entries[1].material, "Face");
        assert_eq!(c.entries[1].preset, None);
        assert!("none".parse::<SkinChoice>().unwrap().entries.is_empty());
        let e = "Skin=skin9".parse::<SkinChoice>().unwrap_err();
        assert!(
            e.contains("unknown preset \"skin9\"") && e.contains("skin1"),
            "{e}"
        );
        assert!("Skin,,Face".parse::<SkinChoice>().is_err());
    }
}

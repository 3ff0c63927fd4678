//! The character's materials: which part of the body each surface belongs to (skin, tank top,
//! shorts, hair, eyes), the fields whose zero sets bound them (the mesh is cut along those, see
//! `cut`), and each material's glTF description.

use super::texture::atlas;
use glam::Vec3;
use serde_json::{json, Value};

use dermis_engine::shading::material::SKIN1;
use dermis_engine::shading::volume_optics::VolumeOptics;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mat {
    Skin,
    TankTop,
    Shorts,
    Hair,
    Eyes,
}

impl Mat {
    /// Every material, in the file's material (and primitive) order.
    pub const ALL: [Mat; 5] = [Mat::Skin, Mat::TankTop, Mat::Shorts, Mat::Hair, Mat::Eyes];

    pub fn name(self) -> &'static str {
        match self {
            Mat::Skin => "Skin",
            Mat::TankTop => "TankTop",
            Mat::Shorts => "Shorts",
            Mat::Hair => "Hair",
            Mat::Eyes => "Eyes",
        }
    }

    /// Specular roughness: cotton and jersey are rough, hair less, the eyes' wet surface smooth.
    fn roughness(self) -> f64 {
        match self {
            Mat::Skin => 0.5,
            Mat::TankTop => 0.85,
            Mat::Shorts => 0.8,
            Mat::Hair => 0.6,
            Mat::Eyes => 0.1,
        }
    }
}

/// The attenuation distance the skin declares [m] (its colour follows from skin1's σ_t).
pub const SKIN_ATTENUATION_DISTANCE_M: f64 = 0.001;
/// The skin's volume thickness (`KHR_materials_volume.thicknessFactor`, metres): about a
/// limb's; the per-vertex `_THICKNESS` is the engine's own.
pub const SKIN_THICKNESS_M: f64 = 0.1;

/// A value rounded to 6 significant digits, so the file does not depend on the last bits of
/// the platform's `exp`.
fn round6(x: f64) -> f64 {
    format!("{x:.5e}").parse().unwrap_or(x)
}

/// The material's glTF JSON, its base colour from texture `texture`; the skin's multi-scatter
/// colour is `skin_factor` × that texture ([`skin_factor`]).
pub fn material_json(m: Mat, texture: usize, skin_factor: [f64; 3]) -> Value {
    let mut v = json!({
        "name": m.name(),
        "pbrMetallicRoughness": {
            "baseColorTexture": { "index": texture },
            "metallicFactor": 0.0,
            "roughnessFactor": m.roughness(),
        },
    });
    if m == Mat::Skin {
        // skin1 declared as an author would: the draft's volume scatter on a volume, with
        // diffuse transmission marking it dense (the draft's recommendation) and its IOR.
        let o = VolumeOptics::from_material(&SKIN1, SKIN_ATTENUATION_DISTANCE_M);
        v["extensions"] = json!({
            "KHR_materials_volume": {
                "thicknessFactor": SKIN_THICKNESS_M,
                "attenuationDistance": o.attenuation_distance_m,
                "attenuationColor": o.attenuation_color.map(round6),
            },
            "KHR_materials_volume_scatter": {
                "multiscatterColor": skin_factor.map(round6),
                "multiscatterColorTexture": { "index": texture },
                "scatterAnisotropy": o.anisotropy,
            },
            "KHR_materials_diffuse_transmission": { "diffuseTransmissionFactor": 1.0 },
            "KHR_materials_ior": { "ior": o.ior },
        });
    }
    v
}

/// The skin's multi-scatter colour factor: skin1's multi-scatter albedo A divided by the mean
/// of the atlas over the skin's texels as the engine measures it (`mean`, from
/// `asset::skin::texture_mean` on a first pass of the file), so the file's skin as a whole has
/// skin1's optics while each texel keeps the painted variation. Panics (the generator's bug)
/// if the paint is too dark for a factor ≤ 1.
pub fn skin_factor(mean: [f64; 3]) -> [f64; 3] {
    let target = VolumeOptics::from_material(&SKIN1, SKIN_ATTENUATION_DISTANCE_M).multiscatter;
    std::array::from_fn(|c| {
        let f = target[c] / mean[c];
        assert!(
            f > 0.0 && f <= 1.0,
            "skin paint mean {mean:?} darker than skin1's multi-scatter albedo {target:?}"
        );
        f
    })
}

/// The extensions the skin material uses.
pub const EXTENSIONS_USED: [&str; 4] = [
    "KHR_materials_diffuse_transmission",
    "KHR_materials_ior",
    "KHR_materials_volume",
    "KHR_materials_volume_scatter",
];

fn sq(x: f32) -> f32 {
    x * x
}

/// Mirror-symmetric coordinates (the outfit is symmetric).
fn mirror(p: Vec3) -> Vec3 {
    Vec3::new(p.x.abs(), p.y, p.z)
}

/// Waist of the shorts (y = 0.995 m; > 0 above).
fn waist(p: Vec3) -> f32 {
    p.y - 0.995
}

/// Hem of the shorts on the legs (y = 0.74 m; > 0 above).
fn hem(p: Vec3) -> f32 {
    p.y - 0.74
}

/// The tank top's armhole (< 0 inside the oval).
fn armhole(p: Vec3) -> f32 {
    let q = mirror(p);
    sq((q.x - 0.178) / 0.075) + sq((q.y - 1.43) / 0.15) - 1.0
}

/// The tank top's scooped neckline, deeper at the front (< 0 inside).
fn neckline(p: Vec3) -> f32 {
    let depth = 0.095 + 0.035 * (p.z / 0.03).clamp(-1.0, 1.0);
    sq(p.x / 0.088) + sq((p.y - 1.50) / depth) - 1.0
}

/// The hair cap's blend across its 6 mm edge: 0 on the skin side, 1 on the hair.
pub fn hair_cover(p: Vec3) -> f32 {
    let q = mirror(p);
    let front = (q.z / 0.08).clamp(-1.0, 1.0);
    let hairline = 1.680 - 0.006 * (1.0 - front) * 0.5 - 0.095 * (-front).max(0.0)
        + 0.012 * sq(q.x / 0.08) * front.max(0.0);
    ((q.y - hairline) / 0.006).clamp(0.0, 1.0)
}

/// Where the hair material begins: the middle of the blend (> 0: hair).
fn hairline(p: Vec3) -> f32 {
    hair_cover(p) - 0.5
}

/// The fields whose zero sets bound the materials of the part with atlas rect `rect`.
pub fn boundaries(rect: [f32; 4]) -> Vec<fn(Vec3) -> f32> {
    if rect == atlas::TORSO {
        vec![waist, armhole, neckline]
    } else if rect == atlas::LEG {
        vec![waist, hem]
    } else if rect == atlas::HEAD {
        vec![hairline]
    } else {
        Vec::new()
    }
}

/// The material of a triangle (bind-pose corners `tri`) of the part with atlas rect `rect`.
/// The mesh is cut along [`boundaries`], so each field keeps one sign over the triangle: it is
/// read at the corner where it is largest in magnitude (cut vertices sit on zero).
pub fn triangle_material(tri: [Vec3; 3], rect: [f32; 4]) -> Mat {
    let side = |f: fn(Vec3) -> f32| {
        tri.iter()
            .map(|&p| f(p))
            .fold(0.0f32, |a, v| if v.abs() > a.abs() { v } else { a })
    };
    if rect == atlas::EYE {
        Mat::Eyes
    } else if rect == atlas::TORSO && side(waist) < 0.0 {
        Mat::Shorts
    } else if rect == atlas::TORSO && side(armhole) > 0.0 && side(neckline) > 0.0 {
        Mat::TankTop
    } else if rect == atlas::LEG && side(waist) < 0.0 && side(hem) >= 0.0 {
        Mat::Shorts
    } else if rect == atlas::HEAD && side(hairline) > 0.0 {
        Mat::Hair
    } else {
        Mat::Skin
    }
}

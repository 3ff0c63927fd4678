//! The one registry of shading-model names.

use super::{burley, dipole, oss, ward, Material};
use crate::shader::ShaderDefs;

/// A selectable character shading model (and the paper's printed variants).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShadingModel {
    /// Ward anisotropic BRDF, standard half-vector form (Walter 2005).
    Ward,
    /// Ward as printed in eq. 1 (φ_i / φ_o in the exponent).
    WardPrinted,
    /// The paper's scaled Jensen dipole BSSRDF, standard form.
    Dipole,
    /// The dipole as printed in eq. 3 (extra 1/σ'_t on the virtual source).
    DipolePrinted,
    /// The authors' OSS colour model (eq. 5–6), as printed.
    Oss,
    /// OSS with eq. 5's terms replaced by positive, bounded, dimensionally consistent forms.
    OssStable,
    /// Christensen–Burley normalised diffusion with a transport-solved albedo (fourth model).
    Burley,
}

/// The effects a material shaded by a model calls for — what its shader computes. The
/// renderer composes a pipeline only for models a scene can reach, so an effect no material
/// uses has no code anywhere (props declare none and get the plain default-lit shader).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effects {
    /// Light transported under the surface (dipole/OSS/Burley terms).
    pub subsurface: bool,
    /// OSS's translucency term 20ρ_ts/d^2.5.
    pub translucency: bool,
    /// The Ward specular lobe.
    pub specular: bool,
    /// The base-colour texture tints the result.
    pub texture: bool,
}

/// The uniform block a model's shader reads at `@group(1) @binding(0)`: 16 vec4s, laid out
/// by each model's own `Params` struct (see `ward.rs`, `dipole.rs`, `oss.rs`).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ModelParams(pub [[f32; 4]; 16]);

impl ModelParams {
    pub const SIZE: u64 = std::mem::size_of::<Self>() as u64;

    /// Packs a model's vec4 rows, zero-filling the rest.
    pub fn from_rows(rows: &[[f32; 4]]) -> Self {
        let mut p = [[0.0; 4]; 16];
        p[..rows.len()].copy_from_slice(rows);
        Self(p)
    }
}

impl ShadingModel {
    /// Every model, in menu order.
    pub const ALL: [ShadingModel; 7] = [
        ShadingModel::Ward,
        ShadingModel::WardPrinted,
        ShadingModel::Dipole,
        ShadingModel::DipolePrinted,
        ShadingModel::Oss,
        ShadingModel::OssStable,
        ShadingModel::Burley,
    ];

    /// The paper's three, as the game's menu offers them by default.
    pub const PAPER: [ShadingModel; 3] =
        [ShadingModel::Ward, ShadingModel::Dipole, ShadingModel::Oss];

    /// The registry name (CLI, UI, JSON).
    pub fn name(self) -> &'static str {
        match self {
            Self::Ward => "ward",
            Self::WardPrinted => "ward-printed",
            Self::Dipole => "dipole",
            Self::DipolePrinted => "dipole-printed",
            Self::Oss => "oss",
            Self::OssStable => "oss-stable",
            Self::Burley => "burley",
        }
    }

    /// A short human label.
    pub fn label(self) -> &'static str {
        match self {
            Self::Ward => "Ward BRDF",
            Self::WardPrinted => "Ward BRDF (as printed)",
            Self::Dipole => "Scaled BSSRDF",
            Self::DipolePrinted => "Scaled BSSRDF (as printed)",
            Self::Oss => "OSS",
            Self::OssStable => "OSS (stable)",
            Self::Burley => "Burley diffusion",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|m| m.name() == name)
    }

    /// All names, comma-separated (for error messages and `--help`).
    pub fn names() -> String {
        Self::ALL.map(Self::name).join(", ")
    }

    /// The effects this model's shader computes.
    pub fn effects(self) -> Effects {
        let (subsurface, translucency, specular, texture) = match self {
            Self::Ward | Self::WardPrinted => (false, false, true, true),
            Self::Dipole | Self::DipolePrinted | Self::Burley => (true, false, false, false),
            Self::Oss | Self::OssStable => (true, true, true, true),
        };
        Effects {
            subsurface,
            translucency,
            specular,
            texture,
        }
    }

    /// The WGSL module (file in `shaders/`) implementing the model.
    pub fn module(self) -> &'static str {
        match self {
            Self::Ward | Self::WardPrinted => "ward",
            Self::Dipole | Self::DipolePrinted => "dipole",
            Self::Oss | Self::OssStable => "oss",
            Self::Burley => "burley",
        }
    }

    /// Composition flags selecting the variant inside the model's file.
    pub fn defs(self) -> ShaderDefs {
        let defs = ShaderDefs::new().alias("shading_model", self.module());
        match self {
            Self::WardPrinted => defs.flag("WARD_PRINTED"),
            Self::DipolePrinted => defs.flag("DIPOLE_PRINTED"),
            Self::OssStable => defs.flag("OSS_STABLE"),
            _ => defs,
        }
    }

    /// The next model in menu order (wrapping).
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|m| *m == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// CPU-side precompute of the model's constants for `material`.
    pub fn params(self, material: &Material) -> ModelParams {
        match self {
            Self::Ward | Self::WardPrinted => ward::Params::new(material, &ward::Lobe::SKIN).pack(),
            Self::Dipole | Self::DipolePrinted => dipole::Params::new(material).pack(),
            Self::Oss | Self::OssStable => oss::Params::new(material).pack(),
            Self::Burley => burley::Params::new(material).pack(),
        }
    }
}

impl std::fmt::Display for ShadingModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ShadingModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::from_name(s)
            .ok_or_else(|| format!("unknown shading model `{s}` (known: {})", Self::names()))
    }
}

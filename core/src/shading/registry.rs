//! The one registry of shading-model names.

use std::sync::Arc;

use super::preintegrated::{self, Lut};
use super::subsurface::Kernel;
use super::{bake, burley, dipole, oss, tabulated, ward, Material};
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
    /// Christensen–Burley normalised diffusion (transport-solved albedo, diffuse mean free
    /// path), spread in screen space.
    Burley,
    /// The Monte Carlo-measured diffusion profile with oblique incidence and translucency,
    /// spread in screen space.
    Tabulated,
    /// Pre-integrated skin: a LUT over (n·l, curvature) from the measured profile, one pass.
    Preintegrated,
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
    /// The screen-space subsurface pass spreads the model's irradiance (its frames render
    /// linear radiance into two targets and end with `sss_pass.wgsl`).
    pub screen_space: bool,
    /// The model samples a pre-integrated LUT (bound next to its uniform).
    pub lut: bool,
}

/// The uniform block a model's shader reads at `@group(1) @binding(0)`: 32 vec4s, laid out
/// by each model's own `Params` struct (see `ward.rs`, `dipole.rs`, `oss.rs`).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ModelParams(pub [[f32; 4]; MODEL_PARAM_ROWS]);

/// Rows (vec4) of [`ModelParams`].
pub const MODEL_PARAM_ROWS: usize = 32;

impl ModelParams {
    pub const SIZE: u64 = std::mem::size_of::<Self>() as u64;

    /// Packs a model's vec4 rows, zero-filling the rest.
    pub fn from_rows(rows: &[[f32; 4]]) -> Self {
        let mut p = [[0.0; 4]; MODEL_PARAM_ROWS];
        p[..rows.len()].copy_from_slice(rows);
        Self(p)
    }
}

impl ShadingModel {
    /// Every model, in menu order.
    pub const ALL: [ShadingModel; 9] = [
        ShadingModel::Ward,
        ShadingModel::WardPrinted,
        ShadingModel::Dipole,
        ShadingModel::DipolePrinted,
        ShadingModel::Oss,
        ShadingModel::OssStable,
        ShadingModel::Burley,
        ShadingModel::Tabulated,
        ShadingModel::Preintegrated,
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
            Self::Tabulated => "tabulated",
            Self::Preintegrated => "preintegrated",
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
            Self::Tabulated => "Measured profile",
            Self::Preintegrated => "Pre-integrated",
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
        let no = Effects {
            subsurface: false,
            translucency: false,
            specular: false,
            texture: false,
            screen_space: false,
            lut: false,
        };
        match self {
            Self::Ward | Self::WardPrinted => Effects {
                specular: true,
                texture: true,
                ..no
            },
            Self::Dipole | Self::DipolePrinted => Effects {
                subsurface: true,
                ..no
            },
            Self::Oss | Self::OssStable => Effects {
                subsurface: true,
                translucency: true,
                specular: true,
                texture: true,
                ..no
            },
            Self::Burley => Effects {
                subsurface: true,
                screen_space: true,
                ..no
            },
            Self::Tabulated => Effects {
                subsurface: true,
                translucency: true,
                screen_space: true,
                ..no
            },
            Self::Preintegrated => Effects {
                subsurface: true,
                translucency: true,
                lut: true,
                ..no
            },
        }
    }

    /// The WGSL module (file in `shaders/`) implementing the model.
    pub fn module(self) -> &'static str {
        match self {
            Self::Ward | Self::WardPrinted => "ward",
            Self::Dipole | Self::DipolePrinted => "dipole",
            Self::Oss | Self::OssStable => "oss",
            Self::Burley => "burley",
            Self::Tabulated => "tabulated",
            Self::Preintegrated => "preintegrated",
        }
    }

    /// Composition flags selecting the variant inside the model's file.
    pub fn defs(self) -> ShaderDefs {
        let defs = ShaderDefs::new().alias("shading_model", self.module());
        match self {
            Self::WardPrinted => defs.flag("WARD_PRINTED"),
            Self::DipolePrinted => defs.flag("DIPOLE_PRINTED"),
            Self::OssStable => defs.flag("OSS_STABLE"),
            _ => {
                let e = self.effects();
                let defs = if e.screen_space {
                    defs.flag("SCREEN_SPACE")
                } else {
                    defs
                };
                if e.subsurface && e.translucency {
                    defs.flag("TRANSLUCENCY")
                } else {
                    defs
                }
            }
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
            Self::Burley => burley::params(material).pack(),
            Self::Tabulated => tabulated::params(material).pack(),
            Self::Preintegrated => preintegrated::params(material).pack(),
        }
    }

    /// [`Self::params`] with the measured tables of `material` baked within `budget` (tests
    /// that run the per-pixel code over many materials use a quick one).
    pub fn params_with(self, material: &Material, budget: bake::Budget) -> ModelParams {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        match self {
            Self::Tabulated => {
                tabulated::params_from(&bake::measure(material, budget, threads), material).pack()
            }
            Self::Preintegrated => {
                preintegrated::params_from(&bake::measure(material, budget, threads), material)
                    .pack()
            }
            _ => self.params(material),
        }
    }

    /// The kernel the screen-space pass spreads this model's irradiance with.
    pub fn kernel(self, material: &Material) -> Option<Kernel> {
        match self {
            Self::Burley => Some(burley::kernel(material)),
            Self::Tabulated => Some(tabulated::kernel(material)),
            _ => None,
        }
    }

    /// The pre-integrated LUT this model samples.
    pub fn lut(self, material: &Material) -> Option<Arc<Lut>> {
        (self == Self::Preintegrated).then(|| preintegrated::lut(material))
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

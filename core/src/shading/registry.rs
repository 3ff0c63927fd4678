//! The one registry of shading-model names.

use std::sync::Arc;

use glam::DVec3;

use super::bake::Bake;
use super::pixel::Pixel;
use super::preintegrated::{self, Lut};
use super::subsurface::{self, Kernel};
use super::uniform::{Layout, ModelParams, Uniform};
use super::{burley, dipole, oss, prediction, tabulated, ward, Material};
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
    /// The model filters the key light's shadow by its diffusion profile, reading the
    /// distance to the nearest shadow edge from the penumbra map (its frames with a shadow
    /// map run the penumbra passes, `render/penumbra.rs`).
    pub penumbra: bool,
}

/// Everything the engine knows about one model: one row of [`TABLE`]. Adding a model is a
/// Rust file in `shading/` (its parameters, precompute and f64 reference), a WGSL file of the
/// same name in `shaders/`, a variant of [`ShadingModel`] and a row here.
pub struct Descriptor {
    pub model: ShadingModel,
    /// The registry name (CLI, UI, JSON).
    pub name: &'static str,
    /// A short human label.
    pub label: &'static str,
    /// The WGSL module (file in `shaders/`, and Rust file in `shading/`) implementing it.
    pub module: &'static str,
    /// The composition flag selecting this variant inside the module, if any.
    pub variant: Option<&'static str>,
    /// What its shader computes.
    pub effects: Effects,
    /// Its uniform struct, declared once with `model_uniform!` in its Rust file (the struct
    /// `params` packs and `shade`/`probe` read); the WGSL struct bound at `@group(1)
    /// @binding(0)` by its module (or a module it imports) declares the same members in the
    /// same order (`core/tests/uniform_layout.rs` compares the two with naga).
    pub uniform: Layout,
    /// CPU-side precompute of the uniform for a material.
    pub params: fn(&Material) -> ModelParams,
    /// The same from measured tables (models that read them).
    pub params_from: Option<fn(&Bake, &Material) -> ModelParams>,
    /// The kernel the screen-space pass spreads its irradiance with (screen-space models).
    pub kernel: Option<fn(&Material) -> Kernel>,
    /// The pre-integrated LUT it samples (LUT models).
    pub lut: Option<fn(&Material) -> Arc<Lut>>,
    /// f64 reference of the shader's `shade` (LUT models: the flat-ground limit without it).
    pub shade: fn(&ModelParams, &Pixel) -> DVec3,
    /// f64 reference of the probed sub-function at x (see `dermis_measure::conformance::reference_probe`).
    pub probe: fn(&ModelParams, &Pixel, f64) -> DVec3,
    /// Its prediction of the total diffuse reflectance, semi-infinite (None) or of a slab
    /// (mm) — `dermis sss`.
    pub total_reflectance: fn(&Material, Option<f64>) -> [f64; 3],
}

const NONE: Effects = Effects {
    subsurface: false,
    translucency: false,
    specular: false,
    texture: false,
    screen_space: false,
    lut: false,
    penumbra: false,
};
const WARD: Effects = Effects {
    specular: true,
    texture: true,
    ..NONE
};
const DIPOLE: Effects = Effects {
    subsurface: true,
    ..NONE
};
const OSS: Effects = Effects {
    subsurface: true,
    translucency: true,
    specular: true,
    texture: true,
    ..NONE
};

fn dipole_semi(m: &Material, _: Option<f64>) -> [f64; 3] {
    dipole::total_reflectance(m)
}

fn measured(m: &Material, _: Option<f64>) -> [f64; 3] {
    prediction::measured(m)
}

/// The spatial models' per-pixel part and its probed oblique table.
fn spatial_probe(p: &ModelParams, _: &Pixel, x: f64) -> DVec3 {
    subsurface::oblique_packed(p, x / (1.0 + x))
}

/// One row per model, in [`ShadingModel::ALL`] order.
pub static TABLE: [Descriptor; 9] = [
    Descriptor {
        model: ShadingModel::Ward,
        name: "ward",
        label: "Ward BRDF",
        module: "ward",
        variant: None,
        effects: WARD,
        uniform: ward::WardUniform::LAYOUT,
        params: |m| ward::Params::new(m, &ward::Lobe::SKIN).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| ward::shade(p, false, px),
        probe: |p, px, _| ward::probe(p, false, px),
        total_reflectance: dipole_semi,
    },
    Descriptor {
        model: ShadingModel::WardPrinted,
        name: "ward-printed",
        label: "Ward BRDF (as printed)",
        module: "ward",
        variant: Some("WARD_PRINTED"),
        effects: WARD,
        uniform: ward::WardUniform::LAYOUT,
        params: |m| ward::Params::new(m, &ward::Lobe::SKIN).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| ward::shade(p, true, px),
        probe: |p, px, _| ward::probe(p, true, px),
        total_reflectance: dipole_semi,
    },
    Descriptor {
        model: ShadingModel::Dipole,
        name: "dipole",
        label: "Scaled BSSRDF",
        module: "dipole",
        variant: None,
        effects: DIPOLE,
        uniform: dipole::DipoleUniform::LAYOUT,
        params: |m| dipole::Params::new(m).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| dipole::shade(p, false, px),
        probe: |p, _, x| dipole::profile_packed(p, false, x),
        total_reflectance: dipole_semi,
    },
    Descriptor {
        model: ShadingModel::DipolePrinted,
        name: "dipole-printed",
        label: "Scaled BSSRDF (as printed)",
        module: "dipole",
        variant: Some("DIPOLE_PRINTED"),
        effects: DIPOLE,
        uniform: dipole::DipoleUniform::LAYOUT,
        params: |m| dipole::Params::new(m).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| dipole::shade(p, true, px),
        probe: |p, _, x| dipole::profile_packed(p, true, x),
        total_reflectance: |m, _| prediction::dipole_printed(m),
    },
    Descriptor {
        model: ShadingModel::Oss,
        name: "oss",
        label: "OSS",
        module: "oss",
        variant: None,
        effects: OSS,
        uniform: oss::OssUniform::LAYOUT,
        params: |m| oss::Params::new(m).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| oss::shade(p, false, px),
        probe: |p, _, x| oss::colour_packed(p, false, x),
        total_reflectance: |m, slab| prediction::oss(m, slab, false),
    },
    Descriptor {
        model: ShadingModel::OssStable,
        name: "oss-stable",
        label: "OSS (stable)",
        module: "oss",
        variant: Some("OSS_STABLE"),
        effects: OSS,
        uniform: oss::OssUniform::LAYOUT,
        params: |m| oss::Params::new(m).pack(),
        params_from: None,
        kernel: None,
        lut: None,
        shade: |p, px| oss::shade(p, true, px),
        probe: |p, _, x| oss::colour_packed(p, true, x),
        total_reflectance: |m, slab| prediction::oss(m, slab, true),
    },
    Descriptor {
        model: ShadingModel::Burley,
        name: "burley",
        label: "Burley diffusion",
        module: "burley",
        variant: None,
        effects: Effects {
            subsurface: true,
            screen_space: true,
            ..NONE
        },
        uniform: subsurface::SubsurfaceUniform::LAYOUT,
        params: |m| burley::params(m).pack(),
        params_from: None,
        kernel: Some(burley::kernel),
        lut: None,
        shade: subsurface::local,
        probe: spatial_probe,
        total_reflectance: |m, _| burley::surface_albedo(m),
    },
    Descriptor {
        model: ShadingModel::Tabulated,
        name: "tabulated",
        label: "Measured profile",
        module: "tabulated",
        variant: None,
        effects: Effects {
            subsurface: true,
            translucency: true,
            screen_space: true,
            ..NONE
        },
        uniform: subsurface::SubsurfaceUniform::LAYOUT,
        params: |m| tabulated::params(m).pack(),
        params_from: Some(|b, m| tabulated::params_from(b, m).pack()),
        kernel: Some(tabulated::kernel),
        lut: None,
        shade: subsurface::local,
        probe: spatial_probe,
        total_reflectance: measured,
    },
    Descriptor {
        model: ShadingModel::Preintegrated,
        name: "preintegrated",
        label: "Pre-integrated",
        module: "preintegrated",
        variant: None,
        effects: Effects {
            subsurface: true,
            translucency: true,
            lut: true,
            penumbra: true,
            ..NONE
        },
        uniform: subsurface::SubsurfaceUniform::LAYOUT,
        params: |m| preintegrated::params(m).pack(),
        params_from: Some(|b, m| preintegrated::params_from(b, m).pack()),
        kernel: None,
        lut: Some(preintegrated::lut),
        shade: subsurface::local,
        probe: spatial_probe,
        total_reflectance: measured,
    },
];

impl ShadingModel {
    /// The one default, wherever no model is chosen (the game's first run and an unreadable
    /// saved choice, `render`, `demo`, `soak`, the benches, the phone): the mobile tier, the
    /// most accurate model without a screen-space pass (one LUT fetch per pixel).
    pub const DEFAULT: ShadingModel = ShadingModel::Preintegrated;

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

    /// This model's row of [`TABLE`].
    pub fn descriptor(self) -> &'static Descriptor {
        &TABLE[self as usize]
    }

    /// The registry name (CLI, UI, JSON).
    pub fn name(self) -> &'static str {
        self.descriptor().name
    }

    /// A short human label.
    pub fn label(self) -> &'static str {
        self.descriptor().label
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
        self.descriptor().effects
    }

    /// The WGSL module (file in `shaders/`) implementing the model.
    pub fn module(self) -> &'static str {
        self.descriptor().module
    }

    /// Composition flags selecting the variant inside the model's file: its own variant
    /// flag, else the flags its effects imply.
    pub fn defs(self) -> ShaderDefs {
        let d = self.descriptor();
        let defs = ShaderDefs::new().alias("shading_model", d.module);
        if let Some(flag) = d.variant {
            return defs.flag(flag);
        }
        let e = d.effects;
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

    /// The next model in menu order (wrapping).
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|m| *m == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// CPU-side precompute of the model's constants for `material`.
    pub fn params(self, material: &Material) -> ModelParams {
        (self.descriptor().params)(material)
    }

    /// [`Self::params`] from the given measured `tables` of `material` (tests that run the
    /// per-pixel code over many materials bake quick ones: `dermis_measure::bake::quick`).
    pub fn params_with(self, material: &Material, tables: &Bake) -> ModelParams {
        match self.descriptor().params_from {
            Some(from) => from(tables, material),
            None => self.params(material),
        }
    }

    /// The kernel the screen-space pass spreads this model's irradiance with.
    pub fn kernel(self, material: &Material) -> Option<Kernel> {
        self.descriptor().kernel.map(|k| k(material))
    }

    /// The pre-integrated LUT this model samples.
    pub fn lut(self, material: &Material) -> Option<Arc<Lut>> {
        self.descriptor().lut.map(|l| l(material))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::SKIN1;

    #[test]
    fn every_table_row_is_complete_and_in_order() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
        let mut names = std::collections::HashSet::new();
        for (i, m) in ShadingModel::ALL.iter().enumerate() {
            let d = m.descriptor();
            assert_eq!(d.model, *m, "row {i} is out of order");
            assert!(names.insert(d.name), "{} twice", d.name);
            assert_eq!(ShadingModel::from_name(d.name), Some(*m));
            assert!(!d.label.is_empty());
            // The WGSL and the Rust twin by name.
            let wgsl = format!("{root}/shaders/{}.wgsl", d.module);
            let rust = format!("{root}/core/src/shading/{}.rs", d.module);
            assert!(std::path::Path::new(&wgsl).is_file(), "{wgsl}");
            assert!(std::path::Path::new(&rust).is_file(), "{rust}");
            if let Some(flag) = d.variant {
                // The flag is read by the module or a module it imports.
                let shaders = std::fs::read_dir(format!("{root}/shaders")).expect("shaders/");
                let used = shaders.flatten().any(|e| {
                    std::fs::read_to_string(e.path())
                        .is_ok_and(|t| t.contains(&format!("#ifdef {flag}")))
                });
                assert!(used, "no shader reads {flag}");
            }
            // Each effect has what it needs.
            assert_eq!(d.effects.screen_space, d.kernel.is_some(), "{}", d.name);
            assert_eq!(d.effects.lut, d.lut.is_some(), "{}", d.name);
            // The functions run and give finite values.
            let p = (d.params)(&SKIN1);
            assert!(p.0.iter().flatten().all(|v| v.is_finite()), "{}", d.name);
            // `params` packs no more than the declared uniform struct.
            let past = &bytemuck::bytes_of(&p)[d.uniform.size..];
            assert!(past.iter().all(|b| *b == 0), "{}", d.name);
            let px = Pixel::new(DVec3::new(0.3, 0.2, 0.9).normalize(), DVec3::Z);
            assert!((d.shade)(&p, &px).is_finite(), "{}", d.name);
            assert!((d.probe)(&p, &px, 0.5).is_finite(), "{}", d.name);
            let r = (d.total_reflectance)(&SKIN1, None);
            // (OSS as printed predicts negative reflectances: finite is all that is asked.)
            assert!(r.iter().all(|v| v.is_finite()), "{}: {r:?}", d.name);
        }
    }
}

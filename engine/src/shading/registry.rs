//! The one registry of shading models: [`models!`] turns the rows of `shading/mod.rs` into
//! the [`ShadingModel`] enum, its [`ShadingModel::ALL`] order and the table of each model's
//! [`Descriptor`], which the model declares in its own Rust file. Everything else — the CLI,
//! the menu, the governor, the composer's modules, the renderer's per-model GPU records, the
//! conformance harness, the benches and the tests' lists — reads it from here.

use std::sync::Arc;

use glam::DVec3;

use super::bake::Bake;
use super::pixel::Pixel;
use super::subsurface::Kernel;
use super::uniform::{Layout, ModelParams, SharedConst};
use super::{Lut, Material, ShadingModel};

/// Declares the models: `default: Variant; baseline: Variant;` then one row per model,
/// `Variant => module::DESCRIPTOR,` (doc comments allowed), in menu order. Generates the
/// [`ShadingModel`] enum, `ShadingModel::{DEFAULT, BASELINE, ALL}` and the descriptor table.
macro_rules! models {
    (
        default: $default:ident;
        baseline: $baseline:ident;
        $( $(#[$doc:meta])* $variant:ident => $module:ident :: $row:ident, )+
    ) => {
        /// A selectable character shading model (and the paper's printed variants): one row of
        /// `shading/mod.rs`, its [`Descriptor`] declared in its own Rust file.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum ShadingModel {
            $( $(#[$doc])* $variant, )+
        }

        impl ShadingModel {
            /// The one default, wherever no model is chosen (the game's first run and an
            /// unreadable saved choice, `render`, `demo`, `soak`, the benches, the phone).
            pub const DEFAULT: ShadingModel = ShadingModel::$default;

            /// What costs and errors are compared against (benches' ratios, "× baseline").
            pub const BASELINE: ShadingModel = ShadingModel::$baseline;

            /// Every model, in menu order.
            pub const ALL: [ShadingModel; [$(ShadingModel::$variant),+].len()] =
                [$(ShadingModel::$variant),+];
        }

        /// One descriptor per model, in [`ShadingModel::ALL`] order.
        static TABLE: [&registry::Descriptor; ShadingModel::ALL.len()] = [$(&$module::$row),+];
    };
}
pub(super) use models;

/// The effects a material shaded by a model calls for — what its shader computes. The
/// renderer composes a pipeline only for models a scene can reach, so an effect no material
/// uses has no code anywhere (props declare none and get the plain default-lit shader).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effects {
    /// Light transported under the surface (dipole/OSS/Burley terms).
    pub subsurface: bool,
    /// OSS's translucency term 20ρ_ts/d^2.5.
    pub translucency: bool,
    /// The screen-space subsurface pass spreads the model's irradiance (its frames render
    /// linear radiance into two targets and end with `sss_pass.wgsl`).
    pub screen_space: bool,
    /// The model samples a LUT (bound next to its uniform).
    pub lut: bool,
    /// The model filters the key light's shadow by its diffusion profile, reading the
    /// distance to the nearest shadow edge from the penumbra map (its frames with a shadow
    /// map run the penumbra passes, `render/passes/penumbra.rs`).
    pub penumbra: bool,
}

impl Effects {
    /// No effect: the start of every model's `Effects { .., ..Effects::NONE }`.
    pub const NONE: Effects = Effects {
        subsurface: false,
        translucency: false,
        screen_space: false,
        lut: false,
        penumbra: false,
    };
}

/// Everything the engine knows about one model, declared as a `const` in the model's own
/// Rust file next to what it points at, and listed by one row of `shading/mod.rs`.
pub struct Descriptor {
    /// The registry name (CLI, UI, JSON).
    pub name: &'static str,
    /// A short human label.
    pub label: &'static str,
    /// The WGSL module (file in `shaders/`, and Rust file in `shading/`) implementing it.
    pub module: &'static str,
    /// That module's source (`include_str!` of `shaders/<module>.wgsl`): the composer's
    /// modules are the shared ones plus every model's.
    pub wgsl: &'static str,
    /// The composition flag selecting this variant inside the module, if any.
    pub variant: Option<&'static str>,
    /// What its shader computes.
    pub effects: Effects,
    /// Its uniform struct, declared once with `model_uniform!` in its Rust file (the struct
    /// `params` packs and `shade`/`probe` read); its module (or a module it imports) imports
    /// the generated WGSL struct of that name and binds it at `@group(1) @binding(0)`
    /// (`engine/tests/engine/uniform_layout.rs` checks both with naga).
    pub uniform: Layout,
    /// CPU-side precompute of the uniform for a material.
    pub params: fn(&Material) -> ModelParams,
    /// The same from measured tables (models that read them).
    pub params_from: Option<fn(&Bake, &Material) -> ModelParams>,
    /// The kernel the screen-space pass spreads its irradiance with (screen-space models).
    pub kernel: Option<fn(&Material) -> Kernel>,
    /// The LUT it samples (LUT models).
    pub lut: Option<fn(&Material) -> Arc<Lut>>,
    /// f64 reference of the shader's `shade` (LUT models: the flat-ground limit without it).
    pub shade: fn(&ModelParams, &Pixel) -> DVec3,
    /// f64 reference of the probed sub-function at x (see
    /// `dermis_measure::conformance::reference_probe`).
    pub probe: fn(&ModelParams, &Pixel, f64) -> DVec3,
    /// The same sub-function in the model's WGSL: an expression of `s: Surface` and `x: f32`
    /// giving a `vec3<f32>` (the conformance harness compiles it beside `shade`).
    pub probe_wgsl: &'static str,
    /// Its prediction of the total diffuse reflectance, semi-infinite (None) or of a slab
    /// (mm) — `dermis sss`.
    pub total_reflectance: fn(&Material, Option<f64>) -> [f64; 3],
    /// The constants its shader reads beyond the shared ones (a LUT's layout), declared in
    /// its Rust file: the composer's generated module `consts` holds them.
    pub consts: &'static [SharedConst],
}

impl ShadingModel {
    /// This model's descriptor.
    pub fn descriptor(self) -> &'static Descriptor {
        super::TABLE[self as usize]
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

    /// The LUT this model samples.
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
        for m in ShadingModel::ALL.iter() {
            let d = m.descriptor();
            assert!(names.insert(d.name), "{} twice", d.name);
            assert_eq!(ShadingModel::from_name(d.name), Some(*m));
            assert!(!d.label.is_empty());
            // The WGSL and the Rust twin by name.
            let wgsl = format!("{root}/shaders/{}.wgsl", d.module);
            let rust = format!("{root}/engine/src/shading/{}.rs", d.module);
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

//! Optical materials (σ in mm⁻¹): the presets, and what a glTF file's skin material becomes
//! (`volume_optics` maps its extensions; `asset::skin` decides which materials are skin).

use std::borrow::Cow;

/// A homogeneous scattering material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The preset's name (`skin1`, `white-coat`) or the glTF material's.
    pub name: Cow<'static, str>,
    /// Where the optics came from.
    pub origin: Origin,
    /// Absorption coefficient σ_a per RGB channel [mm⁻¹].
    pub sigma_a: [f64; 3],
    /// Reduced scattering coefficient σ'_s per RGB channel [mm⁻¹].
    pub sigma_s_prime: [f64; 3],
    /// Relative index of refraction η.
    pub eta: f64,
    /// Henyey–Greenstein anisotropy g (0: σ'_s already reduced, isotropic).
    pub g: f64,
    /// Whether the character's base-colour texture tints the models that use one
    /// (skin: yes; the paper's white-coat material is shown untextured).
    pub textured: bool,
}

/// Where a [`Material`]'s optics came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Made in code: one of the [`PRESETS`], or numbers a command or a test gives.
    Builtin,
    /// A glTF material's volume extensions (`KHR_materials_volume`,
    /// `KHR_materials_volume_scatter`, `KHR_materials_ior`; `volume_optics`). `preset`: the
    /// preset whose optics they equal within [`PRESET_MATCH`], whose exact values the material
    /// then takes (so the preset's shipped tables and LUTs serve it).
    Extensions { preset: Option<&'static str> },
    /// A glTF material given a preset's optics: by the user's choice or by the name rule
    /// (`asset::skin`).
    PresetFor(&'static str),
}

/// Relative tolerance within which optics read from a file are taken for a preset's. 1 %: a
/// multi-scatter colour's texture read from its GPU block encodings (`cargo xtask assets`)
/// moves the texture's mean, so the optics, by up to 0.64 % (the project's character: BC1
/// 6.4e-3, ETC2 5.1e-3, its PNG 1e-6), and desktop and phone then still take the same preset.
pub const PRESET_MATCH: f64 = 1e-2;

/// Skin, Jensen et al. 2001 (skin1).
pub const SKIN1: Material = Material {
    name: Cow::Borrowed("skin1"),
    origin: Origin::Builtin,
    sigma_a: [0.032, 0.17, 0.48],
    sigma_s_prime: [0.74, 0.88, 1.01],
    eta: 1.3,
    g: 0.0,
    textured: true,
};

/// The paper's white-coated material (§4.1, Fig. 1), fitted by Levenberg–Marquardt.
pub const WHITE_COAT: Material = Material {
    name: Cow::Borrowed("white-coat"),
    origin: Origin::Builtin,
    sigma_a: [0.000905, 0.001083, 0.002038],
    sigma_s_prime: [1.94, 1.94, 1.874],
    eta: 1.0936,
    g: 0.0,
    textured: false,
};

/// Every preset, in menu order.
pub const PRESETS: &[Material] = &[SKIN1, WHITE_COAT];

/// The preset a skin material without optics of its own takes.
pub const DEFAULT_SKIN: &Material = &SKIN1;

impl Material {
    /// Looks a preset up by name.
    pub fn preset(name: &str) -> Option<Material> {
        PRESETS.iter().find(|m| m.name == name).cloned()
    }

    /// The preset this is (same name and optics), or a file material's preset ([`Origin`]).
    pub fn preset_name(&self) -> Option<&'static str> {
        match self.origin {
            Origin::Builtin => PRESETS
                .iter()
                .find(|p| p.name == self.name && p.same_optics(self))
                .map(preset_str),
            Origin::Extensions { preset } => preset,
            Origin::PresetFor(p) => Some(p),
        }
    }

    /// This preset's optics for the glTF material `name` (the user's choice, the name rule).
    pub fn for_file_material(&self, name: &str) -> Material {
        Material {
            name: Cow::Owned(name.to_owned()),
            origin: self.preset_name().map_or(self.origin, Origin::PresetFor),
            textured: true,
            ..self.clone()
        }
    }

    /// Whether σ_a, σ'_s, η and g are equal (names and origins aside).
    pub fn same_optics(&self, other: &Material) -> bool {
        self.sigma_a == other.sigma_a
            && self.sigma_s_prime == other.sigma_s_prime
            && self.eta == other.eta
            && self.g == other.g
    }

    /// The preset whose σ_a, σ'_s, η and g all lie within [`PRESET_MATCH`] (relative) of
    /// these, if any.
    pub fn matching_preset(&self) -> Option<&'static Material> {
        let close = |a: f64, b: f64| (a - b).abs() <= PRESET_MATCH * b.abs().max(1e-9);
        PRESETS.iter().find(|p| {
            (0..3).all(|c| {
                close(self.sigma_a[c], p.sigma_a[c])
                    && close(self.sigma_s_prime[c], p.sigma_s_prime[c])
            }) && close(self.eta, p.eta)
                && (self.g - p.g).abs() <= PRESET_MATCH
        })
    }

    /// σ'_t = σ_a + σ'_s per channel.
    pub fn sigma_t_prime(&self) -> [f64; 3] {
        std::array::from_fn(|c| self.sigma_a[c] + self.sigma_s_prime[c])
    }

    /// Reduced albedo α' = σ'_s / σ'_t per channel.
    pub fn albedo(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| {
            if t[c] > 0.0 {
                self.sigma_s_prime[c] / t[c]
            } else {
                0.0
            }
        })
    }

    /// 1 − α' computed without cancellation, as σ_a / σ'_t.
    pub fn one_minus_albedo(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| {
            if t[c] > 0.0 {
                self.sigma_a[c] / t[c]
            } else {
                1.0
            }
        })
    }

    /// Effective transport coefficient σ_tr = √(3 σ_a σ'_t) [mm⁻¹].
    pub fn sigma_tr(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| (3.0 * self.sigma_a[c] * t[c]).sqrt())
    }
}

impl std::fmt::Display for Material {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name)
    }
}

/// A preset's name as a `'static` string (presets are named by literals).
fn preset_str(p: &'static Material) -> &'static str {
    match &p.name {
        Cow::Borrowed(s) => s,
        Cow::Owned(s) => s.as_str(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_by_name_and_origin() {
        assert_eq!(Material::preset("skin1"), Some(SKIN1));
        assert_eq!(Material::preset("nope"), None);
        assert_eq!(SKIN1.preset_name(), Some("skin1"));
        let file = WHITE_COAT.for_file_material("Body");
        assert_eq!(file.name, "Body");
        assert_eq!(file.origin, Origin::PresetFor("white-coat"));
        assert!(file.same_optics(&WHITE_COAT) && file.textured);
        assert_eq!(file.matching_preset(), Some(&WHITE_COAT));
    }

    #[test]
    fn matching_preset_tolerance() {
        let mut m = SKIN1.for_file_material("Skin");
        m.sigma_a[2] *= 1.0 + 0.5 * PRESET_MATCH;
        assert_eq!(m.matching_preset(), Some(&SKIN1));
        m.sigma_a[2] = SKIN1.sigma_a[2] * (1.0 + 2.0 * PRESET_MATCH);
        assert_eq!(m.matching_preset(), None);
    }
}

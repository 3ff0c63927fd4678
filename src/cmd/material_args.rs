//! The material a measurement command works on (`profile`, `sss`, `reference`, `bench
//! shading`): a named material, or any homogeneous medium given by its coefficients, by its
//! albedo and mean free path, or by a glTF file's skin material — one set of flags, checked
//! before any work (one line naming the flag and the bound).
//!
//! - `--material NAME`: a preset (skin1, white-coat) or, where the command has references for
//!   them, a test material (skin-dark, skin-pale, marble);
//! - `--sigma-a R,G,B --sigma-s R,G,B` [mm⁻¹]: the absorption and the scattering coefficient
//!   (σ_s, not reduced: σ'_s = σ_s (1 − g) with `--g`);
//! - `--albedo R,G,B --mfp-mm R,G,B`: the multi-scatter albedo A (what a user sees: the
//!   diffuse reflectance under uniform light, `shading::albedo`) and the reduced mean free path
//!   1/σ'_t [mm];
//! - `--model F.glb [--skin-material NAME]`: the optics the file's skin material declares
//!   (`KHR_materials_volume` + `_volume_scatter` + `_ior`), as the game reads them;
//! - `--eta X`, `--g G`: the boundary's relative index and the phase function's anisotropy,
//!   over whatever the source says.

use std::path::PathBuf;

use dermis_engine::asset::load_gltf;
use dermis_engine::asset::skin::{classify, skin_optics};
use dermis_engine::shading::albedo;
use dermis_engine::shading::material::{Material, Origin};
use dermis_engine::shading::subsurface::exit_normalisation;
use dermis_engine::shading::volume_optics::SIGMA_T_RANGE;

use crate::cmd::args::{float_in, parse_eta, parse_g};

/// Absorption coefficients accepted [mm⁻¹]: 0 (no absorption) up to the largest extinction
/// the engine's skin models are built for.
pub const SIGMA_A: (f64, f64) = (0.0, SIGMA_T_RANGE.1);
/// Scattering coefficients accepted [mm⁻¹] (a medium that scatters).
pub const SIGMA_S: (f64, f64) = (SIGMA_T_RANGE.0, SIGMA_T_RANGE.1);
/// Reduced mean free paths accepted [mm]: 1/σ'_t over the same range.
pub const MFP_MM: (f64, f64) = (1.0 / SIGMA_T_RANGE.1, 1.0 / SIGMA_T_RANGE.0);

/// Three numbers `R,G,B`, each checked by `one`.
fn rgb(s: &str, one: impl Fn(&str) -> Result<f64, String>) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [r, g, b] = parts[..] else {
        return Err(format!("`{s}` is not R,G,B"));
    };
    let c = |v: &str| one(v).map_err(|e| format!("in `{s}`: {e}"));
    Ok([c(r)?, c(g)?, c(b)?])
}

/// `--sigma-a R,G,B`, each in [`SIGMA_A`] mm⁻¹.
pub fn parse_sigma_a(s: &str) -> Result<[f64; 3], String> {
    rgb(s, |v| float_in(v, SIGMA_A.0, false, SIGMA_A.1, "mm⁻¹"))
}

/// `--sigma-s R,G,B`, each in [`SIGMA_S`] mm⁻¹.
pub fn parse_sigma_s(s: &str) -> Result<[f64; 3], String> {
    rgb(s, |v| float_in(v, SIGMA_S.0, false, SIGMA_S.1, "mm⁻¹"))
}

/// `--albedo R,G,B`, each in (0, 1) (the white limit is the boundary's C(η), checked with η).
pub fn parse_albedo(s: &str) -> Result<[f64; 3], String> {
    rgb(s, |v| {
        let a = float_in(v, 0.0, true, 1.0, "")?;
        if a >= 1.0 {
            return Err(format!(
                "{v} is not below 1 (no medium reflects all it receives)"
            ));
        }
        Ok(a)
    })
}

/// `--mfp-mm R,G,B`, each in [`MFP_MM`].
pub fn parse_mfp_mm(s: &str) -> Result<[f64; 3], String> {
    rgb(s, |v| float_in(v, MFP_MM.0, false, MFP_MM.1, "mm"))
}

/// Where a command's material comes from (see the module docs).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct MaterialArgs {
    /// A named material: skin1 | white-coat (and, in `reference` and `bench shading`,
    /// skin-dark | skin-pale | marble) (default: skin1, unless another source is given).
    #[arg(long, conflicts_with_all = ["sigma_a", "albedo", "model"])]
    pub material: Option<String>,
    /// Absorption coefficient σ_a per channel, R,G,B [mm⁻¹], 0..=1000 (with --sigma-s).
    #[arg(long, value_parser = parse_sigma_a, allow_hyphen_values = true, requires = "sigma_s", conflicts_with_all = ["albedo", "model"])]
    pub sigma_a: Option<[f64; 3]>,
    /// Scattering coefficient σ_s per channel, R,G,B [mm⁻¹], 0.001..=1000 (not reduced:
    /// σ'_s = σ_s (1 − g)) (with --sigma-a).
    #[arg(long, value_parser = parse_sigma_s, allow_hyphen_values = true, requires = "sigma_a")]
    pub sigma_s: Option<[f64; 3]>,
    /// Multi-scatter albedo A per channel, R,G,B in (0, 1): the medium's diffuse reflectance
    /// under uniform light (with --mfp-mm).
    #[arg(long, value_parser = parse_albedo, allow_hyphen_values = true, requires = "mfp_mm", conflicts_with = "model")]
    pub albedo: Option<[f64; 3]>,
    /// Reduced mean free path 1/σ'_t per channel, R,G,B [mm], 0.001..=1000 (with --albedo).
    #[arg(long, value_parser = parse_mfp_mm, allow_hyphen_values = true, requires = "albedo")]
    pub mfp_mm: Option<[f64; 3]>,
    /// A glTF file whose skin material's optics (KHR_materials_volume, _volume_scatter, _ior)
    /// are the material.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// With --model: which of its materials (by name; default: the first skin material that
    /// declares optics).
    #[arg(long, requires = "model")]
    pub skin_material: Option<String>,
    /// Relative index of refraction, 1..=3 (default: the source's; 1.4 for coefficients or
    /// albedos).
    #[arg(long, value_parser = parse_eta, allow_hyphen_values = true)]
    pub eta: Option<f64>,
    /// Henyey–Greenstein anisotropy g, -0.99..=0.99 (default: the source's; 0).
    #[arg(long, value_parser = parse_g, allow_hyphen_values = true)]
    pub g: Option<f64>,
}

/// η of a material given by numbers when `--eta` is not: skin's.
pub const DEFAULT_ETA: f64 = 1.4;

impl MaterialArgs {
    /// Whether the material is given by numbers or a file rather than by name.
    pub fn is_custom(&self) -> bool {
        self.sigma_a.is_some() || self.albedo.is_some() || self.model.is_some()
    }

    /// The material, with `named` resolving a `--material` name (each command knows its
    /// own names) and `default` the name used when no source is given. Every check is made
    /// here, before any work; the error is one line.
    pub fn resolve(
        &self,
        default: &str,
        named: impl Fn(&str) -> Result<Material, String>,
    ) -> Result<Material, String> {
        let mut m = if let (Some(a), Some(s)) = (self.sigma_a, self.sigma_s) {
            let g = self.g.unwrap_or(0.0);
            Material {
                name: "custom".into(),
                origin: Origin::Builtin,
                sigma_a: a,
                sigma_s_prime: s.map(|s| s * (1.0 - g)),
                eta: self.eta.unwrap_or(DEFAULT_ETA),
                g,
                textured: true,
            }
        } else if let (Some(a), Some(mfp)) = (self.albedo, self.mfp_mm) {
            let eta = self.eta.unwrap_or(DEFAULT_ETA);
            let white = exit_normalisation(eta);
            if let Some(c) = (0..3).find(|&c| a[c] >= white) {
                return Err(format!(
                    "--albedo: {} in channel {c} is not below {white:.4}, what a white medium \
                     reflects at η = {eta} (the rest is the boundary's specular reflection)",
                    a[c]
                ));
            }
            let mut m = albedo::material("custom", a, mfp, eta, self.g.unwrap_or(0.0));
            m.name = "custom".into();
            m
        } else if let Some(path) = &self.model {
            self.file_optics(path)?
        } else {
            let m = named(self.material.as_deref().unwrap_or(default))?;
            Material {
                eta: self.eta.unwrap_or(m.eta),
                ..m
            }
        };
        if let Some(g) = self.g {
            // Named and file materials keep their reduced coefficients; g sets σ_s.
            m.g = g;
        }
        if let Some(eta) = self.eta {
            m.eta = eta;
        }
        check(&m)?;
        Ok(m)
    }

    /// The optics of `path`'s skin material.
    fn file_optics(&self, path: &std::path::Path) -> Result<Material, String> {
        let shown = path.display();
        let model = load_gltf(path).map_err(|e| e.to_string())?;
        let index = match &self.skin_material {
            Some(name) => model
                .materials
                .iter()
                .position(|m| m.name.as_deref() == Some(name.as_str()))
                .ok_or_else(|| {
                    let names: Vec<&str> = model
                        .materials
                        .iter()
                        .filter_map(|m| m.name.as_deref())
                        .collect();
                    format!(
                        "{shown}: no material `{name}` (its materials: {})",
                        names.join(", ")
                    )
                })?,
            None => {
                let class = classify(&model, None)?;
                class
                    .skin_materials()
                    .into_iter()
                    .find(|&i| skin_optics(&model, i).is_some())
                    .ok_or_else(|| {
                        format!(
                            "{shown}: no skin material declares its optics \
                             (KHR_materials_volume_scatter); name one with --skin-material, or \
                             give --sigma-a/--sigma-s or --albedo/--mfp-mm"
                        )
                    })?
            }
        };
        let optics = skin_optics(&model, index).ok_or_else(|| {
            format!("{shown}: material #{index} declares no volume optics (KHR_materials_volume_scatter)")
        })?;
        let name = model.materials[index]
            .name
            .clone()
            .unwrap_or_else(|| format!("material-{index}"));
        let (m, note) = optics.to_material(&name);
        if let Some(note) = note {
            eprintln!("{shown}: {note}");
        }
        Ok(m)
    }
}

/// The bounds every material meets, whatever its source: finite coefficients, σ'_t within
/// [`SIGMA_T_RANGE`] per channel.
fn check(m: &Material) -> Result<(), String> {
    let (lo, hi) = SIGMA_T_RANGE;
    for (c, t) in m.sigma_t_prime().into_iter().enumerate() {
        let ok = m.sigma_a[c].is_finite()
            && m.sigma_a[c] >= 0.0
            && m.sigma_s_prime[c].is_finite()
            && m.sigma_s_prime[c] > 0.0
            && (lo..=hi).contains(&t);
        if !ok {
            return Err(format!(
                "material {}: channel {c} has σ_a = {}, σ'_s = {} mm⁻¹ (σ'_t must be in \
                 [{lo}, {hi}] mm⁻¹ and σ'_s > 0)",
                m.name, m.sigma_a[c], m.sigma_s_prime[c]
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use dermis_engine::shading::material::SKIN1;

    fn named(s: &str) -> Result<Material, String> {
        Material::preset(s).ok_or_else(|| format!("unknown material `{s}`"))
    }

    #[test]
    fn each_source_gives_the_medium_it_describes() {
        let by_name = MaterialArgs::default().resolve("skin1", named).unwrap();
        assert_eq!(by_name, SKIN1);
        let sigma = MaterialArgs {
            sigma_a: Some([0.1, 0.2, 0.3]),
            sigma_s: Some([2.0, 2.0, 2.0]),
            g: Some(0.5),
            ..Default::default()
        }
        .resolve("skin1", named)
        .unwrap();
        assert_eq!(sigma.sigma_s_prime, [1.0, 1.0, 1.0]);
        assert_eq!((sigma.eta, sigma.g), (DEFAULT_ETA, 0.5));
        // An albedo and a mean free path: the medium made reflects that albedo (the inversion
        // is the engine's measured table) with σ'_t = 1/mfp.
        let a = [0.6, 0.4, 0.25];
        let m = MaterialArgs {
            albedo: Some(a),
            mfp_mm: Some([2.0, 1.0, 0.5]),
            eta: Some(1.3),
            ..Default::default()
        }
        .resolve("skin1", named)
        .unwrap();
        for c in 0..3 {
            assert!((m.sigma_t_prime()[c] - [0.5, 1.0, 2.0][c]).abs() < 1e-9);
            let back = albedo::multi_scatter_albedo(m.albedo()[c], 1.3, 0.0);
            assert!((back - a[c]).abs() < 1e-6, "{back} vs {}", a[c]);
        }
    }

    #[test]
    fn absurd_values_are_one_line_before_any_work() {
        for bad in ["1,2", "a,b,c", "-1,0,0", "nan,1,1", "1e9,1,1", "inf,0,0"] {
            let e = parse_sigma_a(bad).unwrap_err();
            assert!(!e.contains('\n') && !e.is_empty(), "{bad}: {e}");
        }
        assert!(
            parse_sigma_s("0,1,1").is_err(),
            "a medium that does not scatter"
        );
        assert!(parse_albedo("1,0.5,0.5").is_err());
        assert!(parse_albedo("0,0.5,0.5").is_err());
        assert!(parse_mfp_mm("0,1,1").is_err());
        // An albedo above what a white medium reflects through the boundary.
        let e = MaterialArgs {
            albedo: Some([0.99, 0.5, 0.5]),
            mfp_mm: Some([1.0; 3]),
            eta: Some(1.6),
            ..Default::default()
        }
        .resolve("skin1", named)
        .unwrap_err();
        assert!(e.contains("white medium") && !e.contains('\n'), "{e}");
        let e = MaterialArgs {
            model: Some("/nonexistent/x.glb".into()),
            ..Default::default()
        }
        .resolve("skin1", named)
        .unwrap_err();
        assert!(e.contains("x.glb") && !e.contains('\n'), "{e}");
    }
}

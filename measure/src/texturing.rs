//! The albedo map through a subsurface medium, measured ([`mc::pigment`]): the two scenes
//! the texturing is judged on, and the cached reference of the second
//! (`tools/reference/albedo-step.json`, written by `dermis texturing --out tools/reference`),
//! which a renderer test compares the real renderer's step against.
//!
//! **The medium** (every scene): per channel σ'_t = skin1's (0.772, 1.05, 1.49) mm⁻¹, g = 0,
//! η = 1.4, multi-scatter albedo A₀ = [`base`] = 0.554 in every channel (α'₀ from the measured
//! inversion, `shading::albedo`), so the channels differ only in their length scale.
//!
//! **The patch** ([`patch`]): four texels of A = 0.15, 0.3, 0.45, 0.6 (every channel), each
//! [`PATCH_TEXEL_MM`] wide, repeating; uniform diffuse light of unit irradiance; the exitance
//! averaged over the central [`PATCH_CENTRE_MM`] of each texel (per incident power),
//! against the texel's A.
//!
//! **The step** ([`StepSet`]): A = [`dark`] for x < 0, [`base`] for x ≥ 0 (the edge along y at
//! x = 0); lit (1) by uniform diffuse light of unit irradiance over the whole plane — values
//! per unit irradiance, dimensionless: → A far from the edge on each side — and (2) by an
//! isotropic point light of unit power at height [`POINT_H_MM`] above the edge's origin —
//! values in mm⁻² per unit source power, the band |y| < [`BAND_MM`]/2 (the row of pixels
//! through the light's foot). Bins: strips of x (mm), [`step_edges`]. Specular reflection is
//! excluded everywhere, as in [`crate::ground_truth`].

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::mc::pigment::{self, Bins, Light, Stripes, Textured, Texturing};
use crate::mc::Estimate;
use dermis_engine::shading::albedo::single_scatter_albedo;
use dermis_engine::shading::subsurface::exit_normalisation;

/// Relative index of refraction of every scene.
pub const ETA: f64 = 1.4;
/// σ'_t per channel (mm⁻¹): skin1's.
pub const SIGMA_T: [f64; 3] = [0.772, 1.05, 1.49];
/// The fraction of the light that enters the medium which comes back out, for the medium
/// (A₀) and the step's dark side: the scenes' albedos are these × C(η) ([`base`], [`dark`]).
pub const BASE_ENTERED: f64 = 0.6;
pub const DARK_ENTERED: f64 = 0.2;

/// The medium's multi-scatter albedo A₀ (per incident power, as `shading::albedo`):
/// 0.6·C(1.4) = 0.554.
pub fn base() -> f64 {
    BASE_ENTERED * exit_normalisation(ETA)
}

/// The step's dark side's multi-scatter albedo: 0.2·C(1.4) = 0.185 (A₀/3).
pub fn dark() -> f64 {
    DARK_ENTERED * exit_normalisation(ETA)
}
/// The point light's height above the edge (mm) and the band of y it is read in (mm).
pub const POINT_H_MM: f64 = 5.0;
pub const BAND_MM: f64 = 1.0;
/// The patch's texels: albedos, width, and the centre span each is read over (mm).
pub const PATCH_ALBEDO: [f64; 4] = [0.15, 0.3, 0.45, 0.6];
pub const PATCH_TEXEL_MM: f64 = 80.0;
pub const PATCH_CENTRE_MM: f64 = 20.0;
/// Photons per channel and entry of the shipped step reference; its seed.
pub const STEP_PHOTONS: u64 = 8_000_000;
pub const SEED: u64 = 0x5EED_57E9;

/// Diffusion length 1/σ_tr (mm) of a medium of multi-scatter albedo `a` in channel `c`.
pub fn diffusion_length(a: f64, c: usize) -> f64 {
    let s = 1.0 - single_scatter_albedo(a, ETA, 0.0);
    1.0 / (SIGMA_T[c] * (3.0 * s).sqrt().max(1e-9))
}

/// The step's strip edges (mm): symmetric about the edge, 0.25 mm wide at it, out to ±48 mm.
pub fn step_edges() -> Vec<f64> {
    let side = [
        0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0,
    ];
    let mut e: Vec<f64> = side.iter().rev().map(|x| -x).collect();
    e.push(0.0);
    e.extend(side);
    e
}

/// Channel `c`'s medium with the map `map` entering it as `texturing`.
pub fn medium(c: usize, map: Stripes, texturing: Texturing) -> Textured {
    let single = map
        .albedo
        .iter()
        .map(|&a| single_scatter_albedo(a, ETA, 0.0))
        .collect();
    Textured {
        sigma_t: SIGMA_T[c],
        eta: ETA,
        base: base(),
        base_single: single_scatter_albedo(base(), ETA, 0.0),
        map,
        single,
        texturing,
    }
}

/// The step's map.
pub fn step_map() -> Stripes {
    Stripes {
        edges: vec![0.0],
        albedo: vec![dark(), base()],
        period: None,
    }
}

/// The patch's map (periodic).
pub fn patch_map() -> Stripes {
    let n = PATCH_ALBEDO.len();
    Stripes {
        edges: (1..n).map(|i| i as f64 * PATCH_TEXEL_MM).collect(),
        albedo: PATCH_ALBEDO.to_vec(),
        period: Some(n as f64 * PATCH_TEXEL_MM),
    }
}

/// Per texel: channel `c`'s exitance over the texel's centre under uniform light of unit
/// irradiance, to compare with the texel's A.
pub fn patch_channel(
    c: usize,
    texturing: Texturing,
    photons: u64,
    seed: u64,
    threads: usize,
) -> Vec<Estimate> {
    let mut edges = Vec::new();
    for i in 0..PATCH_ALBEDO.len() {
        let mid = (i as f64 + 0.5) * PATCH_TEXEL_MM;
        edges.extend([mid - 0.5 * PATCH_CENTRE_MM, mid + 0.5 * PATCH_CENTRE_MM]);
    }
    let bins = Bins { edges, band: 0.0 };
    let m = medium(c, patch_map(), texturing);
    let light = Light::Uniform {
        x_min: 0.0,
        x_max: 0.0,
    };
    let r = pigment::textured(&m, light, &bins, photons, seed + c as u64, threads);
    r.strips
        .values
        .iter()
        .zip(&r.strips.std_err)
        .step_by(2)
        .map(|(v, s)| Estimate {
            mean: *v,
            std_err: *s,
        })
        .collect()
}

/// [`patch_channel`] for every channel: per texel, R, G, B.
pub fn patch(texturing: Texturing, photons: u64, seed: u64, threads: usize) -> Vec<[Estimate; 3]> {
    let runs: Vec<Vec<Estimate>> = (0..3)
        .map(|c| patch_channel(c, texturing, photons, seed, threads))
        .collect();
    (0..PATCH_ALBEDO.len())
        .map(|i| std::array::from_fn(|c| runs[c][i]))
        .collect()
}

/// How the step is lit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StepLight {
    /// Uniform diffuse light of unit irradiance over the whole plane.
    Uniform,
    /// Isotropic unit-power point light at height `h_mm` above the edge's origin.
    Point { h_mm: f64 },
}

/// One profile: a texturing under a light, per strip and channel with standard errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepEntry {
    /// `pre-post`, `post-only` or `per-texel` ([`Texturing::name`]).
    pub texturing: String,
    pub light: StepLight,
    pub photons: u64,
    pub edges: Vec<f64>,
    pub values: Vec<[f64; 3]>,
    pub std_err: Vec<[f64; 3]>,
}

/// The step reference: the scene and one entry per texturing and light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepSet {
    pub sigma_t_prime: [f64; 3],
    pub eta: f64,
    pub g: f64,
    /// A₀ (x ≥ 0) and the dark side's A (x < 0); the edge is the line x = 0.
    pub base_albedo: f64,
    pub dark_albedo: f64,
    /// α' of A₀ and of the dark side (the measured inversion).
    pub base_single: f64,
    pub dark_single: f64,
    /// The point light's band |y| < band_mm/2.
    pub band_mm: f64,
    pub seed: u64,
    pub entries: Vec<StepEntry>,
}

/// The step's lights.
pub const STEP_LIGHTS: [StepLight; 2] = [StepLight::Uniform, StepLight::Point { h_mm: POINT_H_MM }];

/// One entry of the step: `texturing` under `light`, `photons` per channel.
pub fn step_entry(
    texturing: Texturing,
    light: StepLight,
    photons: u64,
    seed: u64,
    threads: usize,
) -> StepEntry {
    let edges = step_edges();
    let bins = Bins {
        edges: edges.clone(),
        band: BAND_MM,
    };
    let last = edges[edges.len() - 1];
    let mut values = vec![[0.0; 3]; edges.len() - 1];
    let mut std_err = values.clone();
    for c in 0..3 {
        let m = medium(c, step_map(), texturing);
        let light = match light {
            StepLight::Uniform => {
                // Beyond ten diffusion lengths of the wider side nothing reaches the strips.
                let reach =
                    last + 10.0 * diffusion_length(base(), c).max(diffusion_length(dark(), c));
                Light::Uniform {
                    x_min: -reach,
                    x_max: reach,
                }
            }
            StepLight::Point { h_mm } => Light::Point { h: h_mm },
        };
        let r = pigment::textured(&m, light, &bins, photons, seed + c as u64, threads);
        for k in 0..values.len() {
            values[k][c] = r.strips.values[k];
            std_err[k][c] = r.strips.std_err[k];
        }
    }
    StepEntry {
        texturing: texturing.name().to_string(),
        light,
        photons,
        edges,
        values,
        std_err,
    }
}

impl StepSet {
    /// Every texturing under every light; `progress(done, total)` after each entry.
    pub fn generate(
        photons: u64,
        seed: u64,
        threads: usize,
        mut progress: impl FnMut(usize, usize),
    ) -> StepSet {
        let total = Texturing::ALL.len() * STEP_LIGHTS.len();
        let mut entries = Vec::new();
        for (i, t) in Texturing::ALL.iter().enumerate() {
            for (j, light) in STEP_LIGHTS.iter().enumerate() {
                let k = (i * STEP_LIGHTS.len() + j) as u64;
                entries.push(step_entry(*t, *light, photons, seed + 10 * k, threads));
                progress(entries.len(), total);
            }
        }
        StepSet {
            sigma_t_prime: SIGMA_T,
            eta: ETA,
            g: 0.0,
            base_albedo: base(),
            dark_albedo: dark(),
            base_single: single_scatter_albedo(base(), ETA, 0.0),
            dark_single: single_scatter_albedo(dark(), ETA, 0.0),
            band_mm: BAND_MM,
            seed,
            entries,
        }
    }

    /// The entry of `texturing` under `light`.
    pub fn entry(&self, texturing: Texturing, light: StepLight) -> Option<&StepEntry> {
        self.entries
            .iter()
            .find(|e| e.texturing == texturing.name() && e.light == light)
    }

    pub fn load(path: &Path) -> Result<StepSet, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let set: StepSet = serde_json::from_str(&text)
            .map_err(|e| format!("{}: not an albedo-step reference: {e}", path.display()))?;
        for e in &set.entries {
            let n = e.edges.len().saturating_sub(1);
            if n == 0 || e.values.len() != n || e.std_err.len() != n {
                return Err(format!(
                    "{}: {} under {:?}: {} edges, {} values",
                    path.display(),
                    e.texturing,
                    e.light,
                    e.edges.len(),
                    e.values.len()
                ));
            }
        }
        Ok(set)
    }

    /// JSON, numbers to 6 significant digits, one entry per line.
    pub fn to_json(&self) -> String {
        let mut v = serde_json::to_value(self).expect("a step set serialises");
        crate::ground_truth::round_numbers(&mut v);
        let map = v.as_object().expect("an object");
        let mut s = String::from("{\n");
        for (k, val) in map.iter().filter(|(k, _)| *k != "entries") {
            s += &format!("  \"{k}\": {val},\n");
        }
        s += "  \"entries\": [\n";
        let entries = map["entries"].as_array().expect("an array");
        for (k, e) in entries.iter().enumerate() {
            let comma = if k + 1 < entries.len() { "," } else { "" };
            s += &format!("    {e}{comma}\n");
        }
        s += "  ]\n}\n";
        s
    }

    pub fn save(&self, path: &Path) -> Result<(), String> {
        std::fs::write(path, self.to_json())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }
}

/// The committed step reference: `tools/reference/albedo-step.json` (beside the scenes').
pub fn step_file(dir: &Path) -> PathBuf {
    dir.join("albedo-step.json")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn committed() -> StepSet {
        let dir = crate::ground_truth::source_dir();
        StepSet::load(&step_file(&dir)).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn uniform_light_on_a_textured_patch_returns_each_texels_albedo() {
        // Away from texel edges the chosen texturing gives the texel's A back within 2 %: red,
        // the longest diffusion length (every texturing and channel, 10⁶ photons:
        // `dermis texturing`).
        for t in [Texturing::PrePost] {
            for (i, e) in patch_channel(0, t, 400_000, 3, 2).iter().enumerate() {
                let a = PATCH_ALBEDO[i];
                let err = e.mean / a - 1.0;
                assert!(e.std_err < 0.008 * a, "{} texel {i}: noisy", t.name());
                assert!(
                    err.abs() < 0.02,
                    "{} texel {i} (A {a}): {:.4} ± {:.4}",
                    t.name(),
                    e.mean,
                    e.std_err
                );
            }
        }
    }

    #[test]
    fn a_map_equal_to_the_medium_is_the_homogeneous_medium() {
        // T ≡ 1: the textured walker is the plane walker; uniform light returns A₀.
        let map = Stripes {
            edges: vec![0.0],
            albedo: vec![base(), base()],
            period: None,
        };
        let bins = Bins {
            edges: vec![-5.0, 5.0],
            band: 0.0,
        };
        for t in Texturing::ALL {
            let m = medium(0, map.clone(), t);
            let light = Light::Uniform {
                x_min: -60.0,
                x_max: 60.0,
            };
            let r = pigment::textured(&m, light, &bins, 100_000, 5, 2);
            let want = base();
            let (v, se) = (r.strips.values[0], r.strips.std_err[0]);
            assert!(
                (v - want).abs() < 4.0 * se + 0.005 * want,
                "{}: {v} ± {se}",
                t.name()
            );
        }
    }

    #[test]
    fn the_committed_step_is_complete_and_reproducible() {
        let set = committed();
        // The file's 6 significant digits.
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-5 * b;
        assert_eq!(set.eta, ETA);
        assert!(
            same(set.base_albedo, base()) && same(set.dark_albedo, dark()),
            "{} {}",
            base(),
            dark()
        );
        assert!(same(
            set.base_single,
            single_scatter_albedo(base(), ETA, 0.0)
        ));
        assert!(same(
            set.dark_single,
            single_scatter_albedo(dark(), ETA, 0.0)
        ));
        assert_eq!(set.sigma_t_prime, SIGMA_T);
        for t in Texturing::ALL {
            for light in STEP_LIGHTS {
                let e = set
                    .entry(t, light)
                    .expect("every texturing under every light");
                assert_eq!(e.edges, step_edges());
                assert!(e.values.iter().flatten().all(|v| v.is_finite() && *v > 0.0));
                if light == StepLight::Uniform {
                    // Far from the edge each side reflects its own A.
                    let (far_dark, far_bright) = (e.values[0], e.values[e.values.len() - 1]);
                    for c in 0..3 {
                        assert!((far_dark[c] / dark() - 1.0).abs() < 0.03, "{e:?}");
                        assert!((far_bright[c] / base() - 1.0).abs() < 0.03);
                    }
                }
            }
        }
        // One entry again with another seed and fewer photons: within 4 combined SE.
        let again = step_entry(
            Texturing::PrePost,
            StepLight::Point { h_mm: POINT_H_MM },
            100_000,
            99,
            2,
        );
        let shipped = set
            .entry(Texturing::PrePost, StepLight::Point { h_mm: POINT_H_MM })
            .unwrap();
        for k in 0..again.values.len() {
            for c in 0..3 {
                let (a, b) = (again.values[k][c], shipped.values[k][c]);
                let se = (again.std_err[k][c].powi(2) + shipped.std_err[k][c].powi(2)).sqrt();
                assert!(
                    (a - b).abs() < 4.0 * se,
                    "strip {k} ch{c}: {a} vs {b} (SE {se})"
                );
            }
        }
    }
}

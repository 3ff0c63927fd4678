//! The path-traced reference data set: Monte Carlo ground truth of the scenes the shading
//! models are scored on (see `tools/reference/README.md`).
//!
//! One [`ReferenceSet`] per material holds one [`Entry`] per [`Scene`]: bin edges, and per
//! bin and RGB channel the Monte Carlo value and its standard error. All lengths in mm,
//! coefficients in mm⁻¹. The scenes and their units:
//! - [`Scene::PointLight`]: flat semi-infinite medium, isotropic unit-power point light at
//!   height h; bins are annuli (edges in mm); values are the diffuse exitance M(r) in mm⁻²
//!   per unit source power ([`mc::point_light_profile`]).
//! - [`Scene::ShadowEdge`]: flat semi-infinite medium, directional light at incidence angle
//!   θ_i (travelling toward −x) lighting x > 0, a straight edge along y shadowing x < 0;
//!   bins are strips in x (edges in mm); values are the strip-averaged exitance per unit
//!   irradiance on the surface in the lit region (→ the diffuse reflectance at θ_i far into
//!   the lit side, → 0 far into the shadow) ([`mc::shadow_edge`]).
//! - [`Scene::Sphere`]: a sphere of radius R lit by a directional beam; bins are bands of
//!   polar angle θ from the light direction (edges in degrees, θ = 0 faces the light);
//!   values are the exitance per unit area per unit beam irradiance ([`mc::sphere`]).
//! - [`Scene::SlabBacklit`]: a slab of thickness d lit at normal incidence from behind; one
//!   bin (edges `[0, d]`); the value is the diffuse transmittance per unit irradiance, the
//!   unscattered beam excluded ([`mc::slab_diffuse_transmittance`]).
//!
//! Specular (Fresnel) reflection at entry is excluded everywhere. The acceptance materials
//! are the presets with η = [`ETA`] and g = 0 ([`acceptance_material`]).

pub mod metric;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::mc::{self, Medium};
use dermis_engine::shading::albedo;
use dermis_engine::shading::material::{Material, SKIN1, WHITE_COAT};

/// Relative index of refraction of the acceptance case.
pub const ETA: f64 = 1.4;

/// One rendered scene (see the module docs for bins and units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Scene {
    /// Flat semi-infinite medium, isotropic unit-power point light at height `h_mm`.
    PointLight { h_mm: f64 },
    /// Flat semi-infinite medium, straight shadow edge, light at incidence `theta_deg`.
    ShadowEdge { theta_deg: f64 },
    /// Sphere of radius `radius_mm` lit by a directional beam.
    Sphere { radius_mm: f64 },
    /// Slab of thickness `thickness_mm` lit from behind at normal incidence.
    SlabBacklit { thickness_mm: f64 },
}

impl Scene {
    /// A short label for tables, e.g. `point h=5mm`.
    pub fn label(&self) -> String {
        match *self {
            Scene::PointLight { h_mm } => format!("point h={h_mm}mm"),
            Scene::ShadowEdge { theta_deg } => format!("edge θ={theta_deg}°"),
            Scene::Sphere { radius_mm } => format!("sphere R={radius_mm}mm"),
            Scene::SlabBacklit { thickness_mm } => format!("backlit slab d={thickness_mm}mm"),
        }
    }

    /// What a bin is, for table headers.
    pub fn bin_unit(&self) -> &'static str {
        match self {
            Scene::PointLight { .. } => "annulus r [mm]",
            Scene::ShadowEdge { .. } => "strip x [mm]",
            Scene::Sphere { .. } => "band θ [deg]",
            Scene::SlabBacklit { .. } => "slab",
        }
    }

    /// Checks the scene's parameter and its bin edges; the message names what is wrong.
    pub fn validate(&self, edges: &[f64]) -> Result<(), String> {
        let ok = |x: f64, lo: f64, hi: f64| x.is_finite() && x >= lo && x <= hi;
        match *self {
            Scene::PointLight { h_mm } if !ok(h_mm, 1e-3, 1e4) || h_mm <= 0.0 => {
                return Err(format!(
                    "point light height {h_mm} mm out of range (0, 1e4]"
                ));
            }
            Scene::ShadowEdge { theta_deg } if !ok(theta_deg, 0.0, 89.0) => {
                return Err(format!(
                    "shadow edge incidence {theta_deg}° out of range [0, 89]"
                ));
            }
            Scene::Sphere { radius_mm } if !ok(radius_mm, 1e-3, 1e4) => {
                return Err(format!(
                    "sphere radius {radius_mm} mm out of range [1e-3, 1e4]"
                ));
            }
            Scene::SlabBacklit { thickness_mm } if !ok(thickness_mm, 1e-3, 1e4) => {
                return Err(format!(
                    "slab thickness {thickness_mm} mm out of range [1e-3, 1e4]"
                ));
            }
            _ => {}
        }
        if edges.len() < 2 {
            return Err(format!("{}: needs at least one bin", self.label()));
        }
        if edges.iter().any(|e| !e.is_finite()) || edges.windows(2).any(|w| w[0] >= w[1]) {
            return Err(format!(
                "{}: bin edges must be finite and ascending",
                self.label()
            ));
        }
        let (lo, hi) = (edges[0], edges[edges.len() - 1]);
        match *self {
            Scene::PointLight { .. } if lo < 0.0 => {
                Err(format!("{}: annulus radii must be ≥ 0", self.label()))
            }
            Scene::Sphere { .. } if lo < 0.0 || hi > 180.0 => {
                Err(format!("{}: bands must lie within [0, 180]°", self.label()))
            }
            Scene::SlabBacklit { thickness_mm } if edges != [0.0, thickness_mm] => {
                Err(format!("{}: edges must be [0, thickness]", self.label()))
            }
            _ => Ok(()),
        }
    }

    /// The measure of each bin, for integrals over the scene: annulus areas π(b² − a²) (mm²)
    /// for the point light, strip widths b − a (mm) for the edge, band areas
    /// 2πR²(cos a − cos b) (mm²) for the sphere, 1 for the slab.
    pub fn bin_weights(&self, edges: &[f64]) -> Vec<f64> {
        use std::f64::consts::PI;
        edges
            .windows(2)
            .map(|w| match *self {
                Scene::PointLight { .. } => PI * (w[1] * w[1] - w[0] * w[0]),
                Scene::ShadowEdge { .. } => w[1] - w[0],
                Scene::Sphere { radius_mm } => {
                    2.0 * PI
                        * radius_mm
                        * radius_mm
                        * (w[0].to_radians().cos() - w[1].to_radians().cos())
                }
                Scene::SlabBacklit { .. } => 1.0,
            })
            .collect()
    }
}

/// One scene's reference: per bin and channel the Monte Carlo value and standard error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    pub scene: Scene,
    pub edges: Vec<f64>,
    pub values: Vec<[f64; 3]>,
    pub std_err: Vec<[f64; 3]>,
    /// Photons per channel.
    pub photons: u64,
}

impl Entry {
    /// [`Scene::bin_weights`] of this entry's bins.
    pub fn weights(&self) -> Vec<f64> {
        self.scene.bin_weights(&self.edges)
    }

    /// Bin midpoints (mm or degrees).
    pub fn mids(&self) -> Vec<f64> {
        self.edges.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
    }

    /// Largest relative standard error over the bins and channels whose value exceeds
    /// `floor` standard errors (the bins a comparison would use; see [`metric`]).
    pub fn max_rel_se(&self, floor: f64) -> f64 {
        let mut m: f64 = 0.0;
        for (v, s) in self.values.iter().zip(&self.std_err) {
            for c in 0..3 {
                if v[c] > 0.0 && v[c] > floor * s[c] {
                    m = m.max(s[c] / v[c]);
                }
            }
        }
        m
    }
}

/// The reference data set of one material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSet {
    pub material: String,
    pub sigma_a: [f64; 3],
    pub sigma_s_prime: [f64; 3],
    pub eta: f64,
    pub g: f64,
    pub seed: u64,
    pub entries: Vec<Entry>,
}

/// The preset `m` as the acceptance case: η = [`ETA`], g = 0.
pub fn acceptance_material(m: &Material) -> Material {
    Material {
        eta: ETA,
        g: 0.0,
        ..m.clone()
    }
}

/// The acceptance materials, in file order: skin1, white-coat.
pub fn acceptance_materials() -> [Material; 2] {
    [
        acceptance_material(&SKIN1),
        acceptance_material(&WHITE_COAT),
    ]
}

/// Materials that are not a preset, for `bench shading` (η = [`ETA`], g = 0), each made from
/// a multi-scatter albedo A and a reduced mean free path 1/σ'_t through the measured
/// inversion (`shading::albedo::material`): a darker skin and a paler one (skin1's mean free
/// paths, 1.30/0.95/0.67 mm), and marble (Jensen et al. 2001's σ'_t, 2.19/2.62/3.00 mm⁻¹).
/// Their albedos are [`TEST_ALBEDO_ENTERED`] × C(η) (per incident power, as
/// `shading::albedo` defines A; C(1.4) = 0.9232): skin-dark 0.185/0.083/0.046, skin-pale
/// 0.646/0.462/0.351, marble 0.812/0.794/0.757.
pub fn test_materials() -> [Material; 3] {
    let skin_mfp = [1.0 / 0.772, 1.0 / 1.05, 1.0 / 1.49];
    let marble_mfp = [1.0 / 2.19, 1.0 / 2.62, 1.0 / 3.00];
    let c = dermis_engine::shading::subsurface::exit_normalisation(ETA);
    let a = |i: usize| TEST_ALBEDO_ENTERED[i].map(|x| x * c);
    [
        albedo::material("skin-dark", a(0), skin_mfp, ETA, 0.0),
        albedo::material("skin-pale", a(1), skin_mfp, ETA, 0.0),
        albedo::material("marble", a(2), marble_mfp, ETA, 0.0),
    ]
}

/// The fraction of entered light each test material returns, per channel (their
/// multi-scatter albedo per incident power is this × C(η)).
pub const TEST_ALBEDO_ENTERED: [[f64; 3]; 3] =
    [[0.20, 0.09, 0.05], [0.70, 0.50, 0.38], [0.88, 0.86, 0.82]];

fn medium(m: &Material, c: usize) -> Medium {
    Medium::new(m.sigma_a[c], m.sigma_s_prime[c], m.g, m.eta)
}

/// Diffusion lengths 1/σ_tr per channel (mm); a large value where σ_a = 0.
fn diffusion_lengths(m: &Material) -> [f64; 3] {
    m.sigma_tr().map(|s| if s > 0.0 { 1.0 / s } else { 1e3 })
}

/// Edges 0, ±x0, ±x0·q, … ±x1 (symmetric, geometric away from 0), `n` per side.
fn symmetric_geometric(x0: f64, x1: f64, n: usize) -> Vec<f64> {
    let q = (x1 / x0).powf(1.0 / (n - 1) as f64);
    let side: Vec<f64> = (0..n).map(|k| round_edge(x0 * q.powi(k as i32))).collect();
    let mut e: Vec<f64> = side.iter().rev().map(|x| -x).collect();
    e.push(0.0);
    e.extend(side);
    e
}

/// `n + 1` edges from 0 to `r_max`, r_k = r_max sinh(a k/n)/sinh(a), with `a` chosen so the
/// first bin is `first` wide (equal widths, a = 0, if `first` ≥ r_max/n).
pub fn sinh_spaced(r_max: f64, n: usize, first: f64) -> Vec<f64> {
    let nf = n as f64;
    let width = |a: f64| {
        if a < 1e-9 {
            r_max / nf
        } else {
            r_max * (a / nf).sinh() / a.sinh()
        }
    };
    let a = if first >= r_max / nf {
        0.0
    } else {
        // width(a) decreases in a: bisect.
        let (mut lo, mut hi) = (0.0, 50.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if width(mid) > first {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    (0..=n)
        .map(|k| {
            if a < 1e-9 {
                r_max * k as f64 / nf
            } else {
                r_max * (a * k as f64 / nf).sinh() / a.sinh()
            }
        })
        .collect()
}

/// Rounds a bin edge to 3 significant digits (the files stay readable).
/// An edge rounded to 3 significant digits (readable tables).
pub fn round_edge(x: f64) -> f64 {
    round_sig(x, 3)
}

fn round_sig(x: f64, digits: usize) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{:.*e}", digits - 1, x).parse().unwrap_or(x)
}

/// The standard scenes and their bin edges for material `m`, scaled by its diffusion
/// lengths ℓ = 1/σ_tr (skin1 0.7–3.7 mm, white coat 9–14 mm) and mean free paths:
/// point light h = 2, 5, 20 mm; shadow edge θ_i = 0°, 45°; sphere R = 5, 20, 80 mm;
/// backlit slabs 0.5, 1, 2, 5 mm.
pub fn standard_scenes(m: &Material) -> Vec<(Scene, Vec<f64>)> {
    let ell = diffusion_lengths(m);
    let l_min = ell.iter().cloned().fold(f64::INFINITY, f64::min);
    let l_max = ell.iter().cloned().fold(0.0, f64::max).min(200.0);
    let mfp = m
        .sigma_t_prime()
        .iter()
        .map(|&t| 1.0 / t)
        .fold(f64::INFINITY, f64::min);
    let mut out = Vec::new();
    // Point light: 20 annuli out to where the irradiance has fallen to ~1 % of its peak (4h)
    // or the longest channel has diffused 3ℓ beyond the light's foot; at most h/4 wide at
    // the centre, widening outward (sinh spacing) when 3ℓ ≫ h.
    for h in [2.0f64, 5.0, 20.0] {
        let r_max = (4.0 * h).max(h + 3.0 * l_max);
        let n = 20;
        let edges = sinh_spaced(r_max, n, 0.25 * h)
            .into_iter()
            .map(round_edge)
            .collect();
        out.push((Scene::PointLight { h_mm: h }, edges));
    }
    // Shadow edge: strips from a quarter of the shortest scale (mean free path or ℓ) out to
    // 10ℓ of the longest channel on both sides (the last lit strip is the plateau, the
    // diffuse reflectance at θ_i, to ≲ 0.1 %), 13 per side.
    for theta in [0.0, 45.0] {
        let x0 = 0.25 * l_min.min(mfp);
        let edges = symmetric_geometric(x0, 10.0 * l_max, 13);
        out.push((Scene::ShadowEdge { theta_deg: theta }, edges));
    }
    // Sphere: 15° bands on the lit side, 30° on the smooth dark side (120°–180°); around
    // the terminator, bands on the angular scale of the shortest diffusion length
    // w = ℓ_min/R in degrees (within [1°, 5°]): edges at 90° ± {0, 1, 2, 4}·w, the 15° grid
    // kept only outside 90° ± (4w + 3°).
    for r in [5.0, 20.0, 80.0] {
        let w = (l_min / r).to_degrees().clamp(1.0, 5.0);
        let mut edges: Vec<f64> = [
            0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 105.0, 120.0, 150.0, 180.0,
        ]
        .into_iter()
        .filter(|e: &f64| (e - 90.0).abs() > 4.0 * w + 3.0)
        .collect();
        edges.push(90.0);
        for k in [1.0, 2.0, 4.0] {
            edges.push(round_sig(90.0 - k * w, 3));
            edges.push(round_sig(90.0 + k * w, 3));
        }
        edges.sort_by(f64::total_cmp);
        out.push((Scene::Sphere { radius_mm: r }, edges));
    }
    for d in [0.5, 1.0, 2.0, 5.0] {
        out.push((Scene::SlabBacklit { thickness_mm: d }, vec![0.0, d]));
    }
    out
}

fn mix_seed(seed: u64, k: u64) -> u64 {
    let mut s = seed ^ k.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    mc::rng::splitmix64(&mut s)
}

/// The seed of entry `index`, channel `channel` of a set generated with `seed`.
pub fn entry_seed(seed: u64, index: usize, channel: usize) -> u64 {
    mix_seed(mix_seed(seed, index as u64 + 1), channel as u64 + 1)
}

/// Simulates one scene for one channel's medium: (values, standard errors) per bin.
fn simulate_channel(
    med: &Medium,
    scene: &Scene,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> (Vec<f64>, Vec<f64>) {
    let p = match *scene {
        Scene::PointLight { h_mm } => {
            mc::point_light_profile(med, h_mm, edges, photons, seed, threads)
        }
        Scene::ShadowEdge { theta_deg } => {
            let mu = theta_deg.to_radians().cos().min(1.0);
            mc::shadow_edge(med, mu, edges, photons, seed, threads).strips
        }
        Scene::Sphere { radius_mm } => {
            mc::sphere(med, radius_mm, edges, photons, seed, threads).bands
        }
        Scene::SlabBacklit { thickness_mm } => {
            let e = mc::slab_diffuse_transmittance(med, thickness_mm, photons, seed, threads);
            return (vec![e.mean], vec![e.std_err]);
        }
    };
    (p.values, p.std_err)
}

/// One entry on its own: `photons` photons per channel, channel c seeded with a mix of
/// (`seed`, c); bit-identical for any `threads`.
/// Panics on an invalid scene (check [`Scene::validate`] first).
pub fn generate_entry(
    material: &Material,
    scene: &Scene,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> Entry {
    let mut entry = Entry {
        scene: *scene,
        edges: edges.to_vec(),
        values: vec![[0.0; 3]; edges.len() - 1],
        std_err: vec![[0.0; 3]; edges.len() - 1],
        photons,
    };
    for c in 0..3 {
        run_channel(
            material,
            &mut entry,
            c,
            mix_seed(seed, c as u64 + 1),
            threads,
        );
    }
    entry
}

fn run_channel(material: &Material, entry: &mut Entry, c: usize, seed: u64, threads: usize) {
    if let Err(e) = entry.scene.validate(&entry.edges) {
        panic!("reference: {e}");
    }
    let (v, s) = simulate_channel(
        &medium(material, c),
        &entry.scene,
        &entry.edges,
        entry.photons,
        seed,
        threads,
    );
    for k in 0..v.len() {
        entry.values[k][c] = v[k];
        entry.std_err[k][c] = s[k];
    }
}

impl ReferenceSet {
    /// Simulates every scene for `material` with `photons` photons per channel. Entry k,
    /// channel c is seeded with [`entry_seed`]`(seed, k, c)`; results are bit-identical for
    /// any `threads`. `progress(done, total)` is called before the first and after every
    /// (scene, channel) simulation, `total` = 3 × scenes.
    /// Panics on an invalid scene (check [`Scene::validate`] first).
    pub fn generate(
        material: &Material,
        scenes: &[(Scene, Vec<f64>)],
        photons: u64,
        seed: u64,
        threads: usize,
        mut progress: impl FnMut(usize, usize),
    ) -> ReferenceSet {
        assert!(photons > 0, "reference: photons must be positive");
        let total = 3 * scenes.len();
        progress(0, total);
        let mut entries = Vec::with_capacity(scenes.len());
        for (k, (scene, edges)) in scenes.iter().enumerate() {
            let mut entry = Entry {
                scene: *scene,
                edges: edges.clone(),
                values: vec![[0.0; 3]; edges.len().saturating_sub(1)],
                std_err: vec![[0.0; 3]; edges.len().saturating_sub(1)],
                photons,
            };
            for c in 0..3 {
                run_channel(material, &mut entry, c, entry_seed(seed, k, c), threads);
                progress(3 * k + c + 1, total);
            }
            entries.push(entry);
        }
        ReferenceSet {
            material: material.name.to_string(),
            sigma_a: material.sigma_a,
            sigma_s_prime: material.sigma_s_prime,
            eta: material.eta,
            g: material.g,
            seed,
            entries,
        }
    }

    /// The entry of `scene`, if present.
    pub fn entry(&self, scene: &Scene) -> Option<&Entry> {
        self.entries.iter().find(|e| e.scene == *scene)
    }

    /// Reads a set written by [`ReferenceSet::save`] (or any JSON of the same shape).
    pub fn load(path: &Path) -> Result<ReferenceSet, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let set: ReferenceSet = serde_json::from_str(&text)
            .map_err(|e| format!("{}: not a reference set: {e}", path.display()))?;
        for e in &set.entries {
            let n = e.edges.len().saturating_sub(1);
            if e.values.len() != n || e.std_err.len() != n {
                return Err(format!(
                    "{}: {} has {} edges but {} values and {} standard errors",
                    path.display(),
                    e.scene.label(),
                    e.edges.len(),
                    e.values.len(),
                    e.std_err.len()
                ));
            }
        }
        Ok(set)
    }

    /// Writes the set as JSON, numbers rounded to 6 significant digits, one entry per line.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        std::fs::write(path, self.to_json())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }

    /// The JSON text [`ReferenceSet::save`] writes.
    pub fn to_json(&self) -> String {
        let exact = serde_json::to_value(self).expect("reference set serialises");
        let mut v = exact.clone();
        round_numbers(&mut v);
        let map = v.as_object().expect("an object");
        // The optics as they are: a reference is matched to its material by them.
        let optics = ["eta", "g", "sigma_a", "sigma_s_prime"];
        let mut s = String::from("{\n");
        for key in ["material", "eta", "g", "sigma_a", "sigma_s_prime", "seed"] {
            let value = if optics.contains(&key) {
                &exact[key]
            } else {
                &map[key]
            };
            s += &format!("  \"{key}\": {value},\n");
        }
        s += "  \"entries\": [\n";
        let entries = map["entries"].as_array().expect("an array");
        for (k, e) in entries.iter().enumerate() {
            // Fields in declaration order (serde_json's map would sort them).
            let fields: Vec<String> = ["scene", "photons", "edges", "values", "std_err"]
                .iter()
                .map(|f| format!("\"{f}\":{}", e[*f]))
                .collect();
            let comma = if k + 1 < entries.len() { "," } else { "" };
            s += &format!("    {{{}}}{comma}\n", fields.join(","));
        }
        s += "  ]\n}\n";
        s
    }
}

/// Rounds every non-integer number in `v` to 6 significant digits.
pub(crate) fn round_numbers(v: &mut serde_json::Value) {
    use serde_json::Value;
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or(0.0);
            if let Some(r) = serde_json::Number::from_f64(round_sig(x, 6)) {
                *n = r;
            }
        }
        Value::Array(a) => a.iter_mut().for_each(round_numbers),
        Value::Object(o) => o.values_mut().for_each(round_numbers),
        _ => {}
    }
}

/// The directory holding the committed reference files: `$DERMIS_REFERENCE`, else
/// `./tools/reference` if it holds `skin1.json`, else the source tree's `tools/reference/`
/// (the same lookup as the desktop app's assets directory).
pub fn default_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("DERMIS_REFERENCE") {
        return PathBuf::from(dir);
    }
    let local = PathBuf::from("tools/reference");
    if local.join("skin1.json").is_file() {
        return local;
    }
    source_dir()
}

/// The source tree's `tools/reference/`.
pub fn source_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../tools/reference"))
}

/// `dir/<material>.json`.
pub fn file_for(dir: &Path, material: &str) -> PathBuf {
    dir.join(format!("{material}.json"))
}

#[cfg(test)]
mod tests;

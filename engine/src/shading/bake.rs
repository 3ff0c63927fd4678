//! Per-material tables of the spatial subsurface models (`tabulated`, `preintegrated`),
//! measured offline by the project's Monte Carlo (`dermis-measure`'s `bake`, written by
//! `dermis lut --out assets/sss`) and shipped in the binary like the pre-integration LUTs: the
//! runtime never runs a Monte Carlo.
//!
//! - **Kernel**: the normal-incidence pencil-beam exitance of the semi-infinite medium, as the
//!   power leaving through each ring [r_k, r_{k+1}) per unit incident power (specular
//!   excluded): `mass[k]`. The rings are geometric from [`R_FIRST_MM`] to a radius that holds
//!   the material's diffusion tail, plus the inner disk [0, r_1). Ring masses are exact
//!   integrals of the profile (the Monte Carlo bins them directly), so the screen-space pass,
//!   which spends each ring's mass at radii drawn inside it, conserves energy exactly.
//! - **Oblique incidence**: q(μ) = R(μ)/R(1), the diffuse reflectance of a collimated beam at
//!   incidence cosine μ relative to normal incidence (both per unit incident power, so q
//!   carries the Fresnel transmission at entry and the shallower deposition of oblique light:
//!   at low albedo R(μ) *rises* toward grazing before Fresnel takes it to 0), at μ = (k/6)².
//! - **Forward shift**: δ(μ), the mean forward displacement between entry and exit of that
//!   beam (the first moment of its line-spread function): obliquely entering light travels on
//!   before it leaves, so a point light's exitance is pushed outward.
//! - **Translucency**: the diffuse transmittance (unscattered part excluded) of a slab lit
//!   at normal incidence from behind, at thicknesses 0.25·2^k mm; past a diffusion length,
//!   where too few photons get through to measure it, diffusion's e^{−σ_tr d} carries on.
//!
//! A material no shipped file covers (any file's skin, the measurement commands' `--eta`,
//! `--g`) takes tables interpolated from the shipped nondimensional grid ([`super::grid`]), on
//! the desktop and the phone alike; a direct Monte Carlo bake ([`Baker`]) only where a command
//! or a test installs one.

use std::sync::{Arc, Mutex, OnceLock};

use super::Material;

/// Number of rings (besides the inner disk).
pub const RINGS: usize = 20;
/// Inner edge of the first ring (mm): below it the exitance is taken at the pixel itself.
pub const R_FIRST_MM: f64 = 0.05;
/// Oblique-incidence nodes μ_k = (k / (OBLIQUE_NODES − 1))²: dense toward grazing, where
/// Fresnel and q(μ) change fastest (tables are interpolated linearly in √μ).
pub const OBLIQUE_NODES: usize = 7;
/// Slab thickness nodes 0.25 · 2^k mm.
pub const SLAB_NODES: usize = 7;
pub const SLAB_FIRST_MM: f64 = 0.25;

/// Photons per channel for the kernel, for each oblique node and for each slab node, and a
/// cap on the events (free flights + boundary hits) each table may simulate: a material whose
/// photons walk long (albedo → 1) gets fewer photons, so a bake always ends in bounded time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub kernel: u64,
    pub oblique: u64,
    pub slab: u64,
    /// Event cap of the kernel's run …
    pub kernel_events: u64,
    /// … and of each oblique or slab run.
    pub events: u64,
    /// Events after which one photon is stopped (its weight counted as capped): at albedo
    /// → 1 and σ → ∞ a walk is otherwise unbounded.
    pub max_events: u64,
    /// Fewest photons a table is measured with, whatever the event caps.
    pub min_photons: u64,
    /// Photons per channel for each sphere row of the pre-integration LUT …
    pub sphere: u64,
    /// … and the event cap of each such run.
    pub sphere_events: u64,
}

/// What the shipped tables and LUTs are baked with.
pub const DEFAULT_BUDGET: Budget = Budget {
    kernel: 40_000,
    oblique: 10_000,
    slab: 1_000_000,
    kernel_events: 8_000_000,
    events: 1_500_000,
    max_events: 200_000,
    min_photons: 500,
    sphere: 200_000,
    sphere_events: 20_000_000,
};

#[derive(Clone, Debug, PartialEq)]
pub struct Bake {
    /// Ring edges r_0 = 0 < r_1 = R_FIRST_MM < … < r_RINGS+1 (mm): the inner disk, then the rings.
    pub edges: Vec<f64>,
    /// Power leaving through each ring per unit incident power, per channel (len = edges − 1).
    pub mass: Vec<[f64; 3]>,
    /// q(μ_k) per channel at [`oblique_node`] k; q(0) = 0, q(1) = 1.
    pub oblique: [[f64; 3]; OBLIQUE_NODES],
    /// δ(μ_k) per channel (mm): how far forward, along the light's horizontal direction,
    /// the exitance of a beam at incidence μ_k is centred from its entry point (0 at μ = 1).
    pub shift: [[f64; 3]; OBLIQUE_NODES],
    /// Diffuse transmittance at thickness SLAB_FIRST_MM · 2^k per channel.
    pub slab: [[f64; 3]; SLAB_NODES],
}

impl Bake {
    /// Total diffuse reflectance at normal incidence per unit incident power (Σ mass).
    pub fn reflectance(&self) -> [f64; 3] {
        std::array::from_fn(|c| self.mass.iter().map(|m| m[c]).sum())
    }

    /// The exitance density R(r) [mm⁻²] per unit incident power, piecewise constant per ring.
    pub fn profile(&self, c: usize, r: f64) -> f64 {
        let k = self.edges.partition_point(|&e| e <= r);
        if k == 0 || k >= self.edges.len() {
            return 0.0;
        }
        let (a, b) = (self.edges[k - 1], self.edges[k]);
        self.mass[k - 1][c] / (std::f64::consts::PI * (b * b - a * a))
    }

    /// δ(μ) by linear interpolation in √μ between the nodes.
    pub fn shift_at(&self, c: usize, mu: f64) -> f64 {
        let x = mu.clamp(0.0, 1.0).sqrt() * (OBLIQUE_NODES - 1) as f64;
        let i = (x.floor() as usize).min(OBLIQUE_NODES - 2);
        let f = x - i as f64;
        self.shift[i][c] * (1.0 - f) + self.shift[i + 1][c] * f
    }

    /// q(μ) by linear interpolation in √μ between the nodes.
    pub fn oblique_at(&self, c: usize, mu: f64) -> f64 {
        let x = mu.clamp(0.0, 1.0).sqrt() * (OBLIQUE_NODES - 1) as f64;
        let i = (x.floor() as usize).min(OBLIQUE_NODES - 2);
        let f = x - i as f64;
        self.oblique[i][c] * (1.0 - f) + self.oblique[i + 1][c] * f
    }

    /// Radius (mm) inside which half of the kernel's power leaves, per channel.
    pub fn median_radius(&self, c: usize) -> f64 {
        let total: f64 = self.mass.iter().map(|m| m[c]).sum();
        let mut acc = 0.0;
        for (k, m) in self.mass.iter().enumerate() {
            if acc + m[c] >= 0.5 * total {
                let f = (0.5 * total - acc) / m[c].max(f64::MIN_POSITIVE);
                return self.edges[k] + f * (self.edges[k + 1] - self.edges[k]);
            }
            acc += m[c];
        }
        *self.edges.last().unwrap_or(&0.0)
    }
}

/// Ring edges for `m`: the inner disk, then RINGS geometric rings out to about eight diffusion
/// lengths of the most translucent channel (at least 10 mm, at most 150 mm).
pub fn ring_edges(m: &Material) -> Vec<f64> {
    let tr = m.sigma_tr();
    let longest = (0..3)
        .map(|c| {
            if tr[c] > 0.0 {
                1.0 / tr[c]
            } else {
                f64::INFINITY
            }
        })
        .fold(0.0, f64::max);
    let r_max = (8.0 * longest).clamp(10.0, 150.0);
    let ratio = (r_max / R_FIRST_MM).powf(1.0 / RINGS as f64);
    let mut edges = vec![0.0];
    edges.extend((0..=RINGS).map(|k| R_FIRST_MM * ratio.powi(k as i32)));
    edges
}

/// The incidence cosine of oblique node k.
pub fn oblique_node(k: usize) -> f64 {
    let x = k as f64 / (OBLIQUE_NODES - 1) as f64;
    x * x
}

/// The shipped tables: baked at [`DEFAULT_BUDGET`] by `dermis lut --out assets/sss` for the
/// presets at their own η and at the reference scenes' η = 1.4. Each file records the material
/// and budget it was baked for; one that does not match is ignored.
pub const SHIPPED: &[&[u8]] = &[
    include_bytes!("../../../assets/sss/skin1-eta1.3.tables"),
    include_bytes!("../../../assets/sss/skin1-eta1.4.tables"),
    include_bytes!("../../../assets/sss/white-coat-eta1.0936.tables"),
    include_bytes!("../../../assets/sss/white-coat-eta1.4.tables"),
];

/// File name of the shipped tables of `m`.
pub fn file_name(m: &Material) -> String {
    format!("{}-eta{}.tables", m.name, m.eta)
}

const MAGIC: &[u8; 8] = b"DERMTAB1";

/// A budget's fields as the headers of the shipped files record them.
pub fn budget_values(budget: &Budget) -> [f64; 9] {
    [
        budget.kernel,
        budget.oblique,
        budget.slab,
        budget.kernel_events,
        budget.events,
        budget.max_events,
        budget.min_photons,
        budget.sphere,
        budget.sphere_events,
    ]
    .map(|v| v as f64)
}

/// What a shipped file was baked from: the material's optics and the budget (the start of
/// every shipped file's header: these tables' and the sphere LUTs').
pub fn baked_from(m: &Material, budget: &Budget) -> Vec<f64> {
    let mut h: Vec<f64> = Vec::new();
    h.extend(m.sigma_a);
    h.extend(m.sigma_s_prime);
    h.extend([m.eta, m.g]);
    h.extend(budget_values(budget));
    h
}

/// What tables were baked from: [`baked_from`] and the table sizes.
fn header(m: &Material, budget: &Budget) -> Vec<f64> {
    let mut h = baked_from(m, budget);
    h.extend([RINGS, OBLIQUE_NODES, SLAB_NODES].map(|v| v as f64));
    h
}

impl Bake {
    /// Little-endian f64: magic, the [`header`], the edges, masses, q(μ), δ(μ) and slabs.
    pub fn to_bytes(&self, m: &Material, budget: &Budget) -> Vec<u8> {
        let mut values = header(m, budget);
        values.extend(&self.edges);
        values.extend(self.mass.iter().flatten());
        values.extend(self.oblique.iter().flatten());
        values.extend(self.shift.iter().flatten());
        values.extend(self.slab.iter().flatten());
        let mut out = MAGIC.to_vec();
        for v in values {
            out.extend(v.to_le_bytes());
        }
        out
    }

    /// The tables in `bytes` if they were baked for `m` at `budget`.
    pub fn from_bytes(bytes: &[u8], m: &Material, budget: &Budget) -> Option<Bake> {
        let h = header(m, budget);
        let body = bytes.strip_prefix(MAGIC.as_slice())?;
        let values: Vec<f64> = body
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
            .collect();
        let rings = RINGS + 1;
        let want = h.len() + (rings + 1) + 3 * rings + 3 * (2 * OBLIQUE_NODES + SLAB_NODES);
        if body.len() % 8 != 0 || values.len() != want || values[..h.len()] != h[..] {
            return None;
        }
        let mut it = values[h.len()..].iter().copied();
        let mut next = || it.next().unwrap_or(0.0);
        let edges: Vec<f64> = (0..=rings).map(|_| next()).collect();
        let mut triple = || -> [f64; 3] { std::array::from_fn(|_| next()) };
        let mass = (0..rings).map(|_| triple()).collect();
        let oblique = std::array::from_fn(|_| triple());
        let shift = std::array::from_fn(|_| triple());
        let slab = std::array::from_fn(|_| triple());
        Some(Bake {
            edges,
            mass,
            oblique,
            shift,
            slab,
        })
    }
}

/// Bakes one material's tables directly by the Monte Carlo (installed by the measurement
/// crate, `dermis_measure::bake::install`, only where a command or a test asks for a direct
/// bake: the grid's yardstick).
pub type Baker = fn(&Material) -> Bake;
static BAKER: OnceLock<Baker> = OnceLock::new();

/// Installs the direct baker (the first installation wins).
pub fn install_baker(baker: Baker) {
    let _ = BAKER.set(baker);
}

/// Whether a direct baker is installed.
pub fn direct() -> bool {
    BAKER.get().is_some()
}

type Cache = Mutex<Vec<(Material, Arc<Bake>)>>;
static CACHE: Cache = Mutex::new(Vec::new());

/// The shipped tables baked for `m`, if any.
pub fn shipped(m: &Material) -> Option<Bake> {
    SHIPPED
        .iter()
        .find_map(|b| Bake::from_bytes(b, m, &DEFAULT_BUDGET))
}

/// Where a material's tables come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// A shipped file baked for exactly these optics (the presets).
    Shipped,
    /// The installed direct [`Baker`] (the Monte Carlo, where a command asked for it).
    Direct,
    /// Interpolated from the shipped nondimensional grid ([`super::grid`]).
    Grid,
}

/// Where [`for_material`] takes `m`'s tables from.
pub fn source(m: &Material) -> Source {
    if shipped(m).is_some() {
        Source::Shipped
    } else if direct() {
        Source::Direct
    } else {
        Source::Grid
    }
}

/// The tables for `m`, cached for the process: the shipped file baked for exactly these
/// optics, else the installed direct [`Baker`]'s (only where a command asked for a direct
/// bake), else interpolated from the shipped grid ([`super::grid`]: every material, well
/// under a millisecond, no Monte Carlo). Were the grid unreadable (a test rules it out) the
/// tables are empty (logged once by the grid): the spatial models render black, not wrong.
pub fn for_material(m: &Material) -> Arc<Bake> {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, b)) = cache.iter().find(|(k, _)| k == m) {
        return b.clone();
    }
    let bake = Arc::new(match (shipped(m), BAKER.get()) {
        (Some(b), _) => b,
        (None, Some(baker)) => baker(m),
        (None, None) => from_grid(m),
    });
    cache.push((m.clone(), bake.clone()));
    bake
}

/// `m`'s tables interpolated from the shipped grid (empty tables if it is unreadable).
pub fn from_grid(m: &Material) -> Bake {
    match super::grid::shipped() {
        Some(grid) => grid.bake(m),
        None => Bake {
            edges: ring_edges(m),
            mass: vec![[0.0; 3]; RINGS + 1],
            oblique: [[1.0; 3]; OBLIQUE_NODES],
            shift: [[0.0; 3]; OBLIQUE_NODES],
            slab: [[0.0; 3]; SLAB_NODES],
        },
    }
}

//! Per-material tables of the spatial subsurface models (`tabulated`, `preintegrated`),
//! measured once per material by the project's Monte Carlo ([`crate::mc`]) and cached.
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
//! Seeds are fixed and differ from every reference set's, photons in fixed batches, so a bake
//! is deterministic and independent of the thread count.

use std::sync::{Arc, Mutex};

use super::{fresnel, Material};
use crate::mc::{self, Medium};

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

/// What the renderer bakes at material load.
pub const DEFAULT_BUDGET: Budget = Budget {
    kernel: 40_000,
    oblique: 10_000,
    slab: 30_000,
    kernel_events: 8_000_000,
    events: 1_500_000,
    max_events: 200_000,
    min_photons: 500,
    sphere: 200_000,
    sphere_events: 20_000_000,
};

/// Strips on each side of the edge for the forward shift.
const STRIPS: usize = 48;

/// A quick bake for tests that run the per-pixel code over many materials (the tables are
/// noisier, the code paths the same).
pub const QUICK_BUDGET: Budget = Budget {
    kernel: 1_000,
    oblique: 100,
    slab: 100,
    kernel_events: 100_000,
    events: 10_000,
    max_events: 2_000,
    min_photons: 20,
    sphere: 200,
    sphere_events: 20_000,
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

pub fn medium(m: &Material, c: usize) -> Medium {
    Medium::new(m.sigma_a[c], m.sigma_s_prime[c], m.g, m.eta)
}

/// Photons for a run of `geom`/`source` within `events`: a pilot of a few photons measures
/// the events per photon.
fn photons_for(
    med: &Medium,
    (geom, source): (mc::Geometry, mc::Source),
    wanted: u64,
    events: u64,
    budget: &Budget,
    seed: u64,
) -> u64 {
    let pilot = 20.max(budget.min_photons.min(200));
    let r = mc::simulate(
        med,
        geom,
        source,
        &detectors(&[], budget),
        pilot,
        seed ^ 0xA5A5,
        1,
    );
    let per_photon = (r.events as f64 / pilot as f64).max(1.0);
    ((events as f64 / per_photon) as u64).clamp(budget.min_photons, wanted.max(budget.min_photons))
}

fn detectors(edges: &[f64], budget: &Budget) -> mc::Detectors {
    mc::Detectors {
        edges: edges.to_vec(),
        max_events: budget.max_events,
        ..Default::default()
    }
}

/// Measures the tables for `m` within `budget` on `threads` threads.
pub fn measure(m: &Material, budget: Budget, threads: usize) -> Bake {
    const SEED: u64 = 0x5EED_BA4E;
    let edges = ring_edges(m);
    let mut mass = vec![[0.0; 3]; edges.len() - 1];
    let mut oblique = [[0.0; 3]; OBLIQUE_NODES];
    let mut slab = [[0.0; 3]; SLAB_NODES];
    let mut shift = [[0.0; 3]; OBLIQUE_NODES];
    let semi = mc::Geometry::SemiInfinite;
    for c in 0..3 {
        let med = medium(m, c);
        let seed = SEED + 1000 * c as u64;
        let normal = (semi, mc::Source::Normal);
        let n = photons_for(
            &med,
            normal,
            budget.kernel,
            budget.kernel_events,
            &budget,
            seed,
        );
        let r = mc::simulate(
            &med,
            semi,
            mc::Source::Normal,
            &detectors(&edges, &budget),
            n,
            seed,
            threads,
        );
        for (k, w) in edges.windows(2).enumerate() {
            let area = std::f64::consts::PI * (w[1] * w[1] - w[0] * w[0]);
            mass[k][c] = r.reflectance_profile.values[k] * area;
        }
        // Oblique beams: reflectance and forward shift from the shadow-edge estimator over
        // symmetric strips (the cumulative exitance across the edge).
        let x_max = *edges.last().unwrap_or(&10.0);
        let strips: Vec<f64> = (0..=2 * STRIPS)
            .map(|i| x_max * (i as f64 / STRIPS as f64 - 1.0))
            .collect();
        let oblique_run = |mu: f64, seed: u64| {
            let source = mc::Source::Collimated { mu };
            let n = photons_for(
                &med,
                (semi, source),
                budget.oblique,
                budget.events,
                &budget,
                seed,
            );
            let cap = budget.max_events;
            let e = mc::edge::shadow_edge_with(&med, mu, &strips, cap, n, seed, threads);
            let r = e.reflectance.mean;
            // E[Δx]·R = ∫₀^∞ (R − M) dx − ∫_{−∞}^0 M dx; the beam travels toward −x.
            let moment: f64 = strips
                .windows(2)
                .zip(&e.strips.values)
                .map(|(w, m)| {
                    let width = w[1] - w[0];
                    if w[0] >= 0.0 {
                        (r - m) * width
                    } else {
                        -m * width
                    }
                })
                .sum();
            (r, -moment / r.max(f64::MIN_POSITIVE))
        };
        let (normal, _) = oblique_run(1.0, seed + 1);
        for k in 1..OBLIQUE_NODES - 1 {
            let mu = oblique_node(k);
            let (r, delta) = oblique_run(mu, seed + 10 + k as u64);
            // Where the medium reflects (next to) nothing the ratio is noise: Fresnel's
            // transmission ratio stands in; q stays within [0, 4] whatever the noise.
            oblique[k][c] = if normal > 1e-9 {
                (r / normal).clamp(0.0, 4.0)
            } else {
                fresnel::transmittance_shader(m.eta, mu)
                    / fresnel::transmittance_shader(m.eta, 1.0).max(1e-12)
            };
            shift[k][c] = if delta.is_finite() {
                delta.clamp(0.0, x_max)
            } else {
                0.0
            };
        }
        oblique[0][c] = 0.0;
        oblique[OBLIQUE_NODES - 1][c] = 1.0;
        shift[0][c] = shift[1][c];
        shift[OBLIQUE_NODES - 1][c] = 0.0;
        let mut extrapolating = false;
        for k in 0..SLAB_NODES {
            let d = SLAB_FIRST_MM * (1u32 << k) as f64;
            let geom = mc::Geometry::Slab { d };
            let seed = seed + 100 + k as u64;
            let source = mc::Source::Normal;
            let n = photons_for(
                &med,
                (geom, source),
                budget.slab,
                budget.events,
                &budget,
                seed,
            );
            let r = mc::simulate(
                &med,
                geom,
                source,
                &detectors(&[], &budget),
                n,
                seed,
                threads,
            );
            // Diffuse transmittance: the unscattered beam goes straight through (it is the
            // light source seen through the slab, not translucency).
            let diffuse = (r.transmittance.mean - r.unscattered.mean).max(0.0);
            let se = r.transmittance.std_err + r.unscattered.std_err;
            // Thick slabs transmit too few photons to measure: past the first node beyond a
            // diffusion length whose relative error exceeds 25 %, diffusion's asymptotic
            // e^{−σ_tr d} carries on from the last measured node.
            let thick = d * m.sigma_tr()[c] >= 1.0;
            let poor = diffuse <= 0.0 || se > 0.25 * diffuse;
            slab[k][c] = if k > 0 && (extrapolating || (thick && poor)) {
                extrapolating = true;
                let prev = slab[k - 1][c];
                let d_prev = SLAB_FIRST_MM * (1u32 << (k - 1)) as f64;
                prev * (-(m.sigma_tr()[c] * (d - d_prev))).exp()
            } else {
                diffuse
            };
        }
    }
    Bake {
        edges,
        mass,
        oblique,
        shift,
        slab,
    }
}

type Cache = Mutex<Vec<(Material, Arc<Bake>)>>;
static CACHE: Cache = Mutex::new(Vec::new());

/// The tables for `m`, measured on first use with [`DEFAULT_BUDGET`] and cached for the
/// process (a game switching models or materials measures each material once).
pub fn for_material(m: &Material) -> Arc<Bake> {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, b)) = cache.iter().find(|(k, _)| k == m) {
        return b.clone();
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let bake = Arc::new(measure(m, DEFAULT_BUDGET, threads));
    cache.push((*m, bake.clone()));
    bake
}

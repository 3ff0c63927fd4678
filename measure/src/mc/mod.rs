//! Monte Carlo photon-transport ground truth for the skin models (issue 4 §1).
//!
//! A pure-Rust, `f64`, CPU reference for light transport in a homogeneous, plane-parallel
//! medium with smooth (Fresnel) boundaries. It is the yardstick the shading models (Ward,
//! Jensen dipole, OSS, …) are measured against.
//!
//! # Units and conventions
//! - Lengths in **mm**, coefficients in **mm⁻¹**. [`Medium`] holds σ_a, the *reduced*
//!   scattering coefficient σ'_s, the Henyey–Greenstein anisotropy g and the relative index
//!   η = n_medium / n_outside. The walk uses the real σ_s = σ'_s/(1 − g) (σ_s = σ'_s when
//!   g = 0) and σ_t = σ_a + σ_s; single-scattering albedo σ_s/σ_t.
//! - The medium occupies z ≥ 0 ([`Geometry::SemiInfinite`]) or 0 ≤ z ≤ d
//!   ([`Geometry::Slab`]); z points *into* the medium. Light arrives from z < 0. For a slab the
//!   same outside medium (index 1 relative to η) is on both sides.
//! - Boundaries are smooth dielectrics: unpolarised Fresnel reflection with total internal
//!   reflection; a photon reaching a boundary is reflected with probability F (all-or-none),
//!   otherwise leaves. η = 1 means index-matched (F ≡ 0).
//! - Free paths are exponential with σ_t. Absorption is implicit (weight ×= albedo at each
//!   interaction); below weight [`walk::ROULETTE_THRESHOLD`] Russian roulette keeps a photon
//!   with probability [`walk::ROULETTE_SURVIVAL`]. Photons still alive after
//!   [`MAX_EVENTS`] events (free flights + boundary hits) are stopped and their weight is
//!   reported in [`Results::capped`] — an upper bound on the cap's bias.
//! - Phase function: Henyey–Greenstein; g = 0 is exactly isotropic.
//!
//! # Estimators (all per unit *incident* power unless stated)
//! Every photon carries unit incident power (½ for the point light: see below). For each
//! quantity the estimate is the mean over photons of that photon's contribution, and the
//! standard error is the per-photon one, sqrt((⟨x²⟩ − ⟨x⟩²)/(N − 1)).
//! - **Specular** reflectance [`Results::specular`]: Fresnel reflection at entry. It is
//!   *excluded* from the diffuse reflectance.
//! - **Diffuse reflectance** R_d = [`Results::reflectance`]: weight leaving through z = 0 after
//!   entering, per unit incident power. Jensen's dipole R_d is per unit power that *entered*
//!   (it equals 1 at α' = 1 for any η); compare it with
//!   [`Results::reflectance_per_entered`] = R_d / (1 − specular) (exact for normal incidence).
//! - **Transmittance** T (slab): weight leaving through z = d; `unscattered` is its
//!   never-scattered (collimated) part.
//! - **Radial profile** R(r) (pencil beam at normal incidence at the origin): the diffuse
//!   exitance per unit area per unit incident power in mm⁻², averaged over the annulus
//!   [r_k, r_{k+1}) — weight leaving in the annulus / (N · π(r_{k+1}² − r_k²)).
//!   [`Profile::r_mid`] is the midpoint (r_k + r_{k+1})/2. ∫ 2πr R(r) dr = R_d.
//! - **Point light** at height h above the surface (at (0, 0, −h)), isotropic, unit total
//!   power: only the half heading down matters, sampled uniformly in solid angle over the
//!   lower hemisphere (μ = cos θ uniform in (0, 1], weight ½), hitting the surface at
//!   r = h tan θ. This reproduces the irradiance E(r) = h / (4π (r² + h²)^{3/2})
//!   ([`point_light_irradiance`]) including the 1/(4π) normalisation and the inverse-square
//!   and cosine factors. Each photon enters with weight ½(1 − F(θ)), refracted, and the
//!   diffuse exitance M(r) per unit area per unit source power (mm⁻²) is binned in annuli as
//!   above. The Monte Carlo irradiance histogram (before Fresnel) is also returned, to check
//!   against the exact bin average [`point_light_irradiance_bins`].
//! - **Cone detector** (reciprocity checks): weight leaving the top with outside exit cosine
//!   ≥ `cone_mu`.
//! - **Oblique beam** ([`Source::Collimated`], [`oblique_reflectance`]): a pencil beam at the
//!   origin with incidence cosine μ travelling toward −x.
//! - **Shadow edge** ([`shadow_edge`], `edge.rs`): exitance per unit surface irradiance
//!   averaged over strips in x, for a directional light lighting x > 0 only; one oblique
//!   pencil beam gives it exactly by translation invariance.
//! - **Sphere** ([`sphere`], `sphere.rs`): a sphere under a directional beam, exitance per
//!   unit beam irradiance in bands of polar angle from the light.
//! - **Backlit slab** ([`slab_diffuse_transmittance`]): a slab's transmittance less its
//!   unscattered part.
//!
//! # One walk, many scenes
//! The photon walk itself (free flights, implicit absorption, roulette, HG scattering, the event
//! cap, the Fresnel boundary) is written once, `walk::Walk::follow`, generic over the scene's
//! geometry (`walk::Volume`: distance to the boundary along a flight and the incidence cosine
//! there, the mirror direction, what happens after an exit, the albedo at a point) and its
//! tallies (`walk::Scoring`). The scenes: `flat.rs` (the semi-infinite medium and the slab,
//! with [`Source`]'s sources and the radial, cone and shadow-edge detectors), `sphere.rs` (the
//! sphere under a beam, polar-angle bands), `mesh_walk.rs` (a closed triangle mesh, `mesh.rs`,
//! under a point light: BVH queries skipped within the safe distance of `mesh_grid.rs`,
//! overlapping sheets' layers, re-entry, the entry roulette; exits handed to the caller — the
//! face truth projects them into its camera) and `pigment.rs` (the flat medium under an albedo map, its albedo
//! varying over the surface). The white walk of `albedo.rs` is another algorithm (no
//! absorption, depth only, a length roulette) and has its own loop. `golden_tests.rs` pins
//! every entry point's results bit for bit.
//!
//! # Determinism
//! Photons run in fixed batches of [`estimate::BATCH_SIZE`]; batch b draws from its own
//! xoshiro256++ stream seeded from (seed, b). Threads take batches dynamically, but batch
//! tallies are summed in batch order, so results are bit-identical for any `threads`.

pub mod albedo;
pub mod edge;
pub mod estimate;
pub(crate) mod flat;
pub mod fresnel;
pub mod mesh;
pub mod mesh_grid;
pub mod mesh_walk;
pub mod phase;
pub mod pigment;
pub mod rng;
pub mod sphere;
pub mod walk;

pub mod chandrasekhar;
pub(crate) mod dipole_check;
#[cfg(test)]
mod golden_tests;
#[cfg(test)]
mod scene_tests;
#[cfg(test)]
mod tests;

pub use edge::{
    oblique_reflectance, shadow_edge, shadow_edge_with, slab_diffuse_transmittance, EdgeResults,
};
pub use estimate::{Estimate, BATCH_SIZE};
pub use sphere::{sphere, sphere_with, SphereResults};

use std::f64::consts::PI;

/// Default cap on events (free flights + boundary hits) per photon.
pub const MAX_EVENTS: u64 = 1_000_000;

/// A homogeneous medium. Units: mm⁻¹; η relative to the outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    pub sigma_a: f64,
    /// Reduced scattering coefficient σ'_s = σ_s (1 − g).
    pub sigma_s_prime: f64,
    /// Henyey–Greenstein anisotropy, in (−1, 1).
    pub g: f64,
    /// Relative index of refraction n_medium / n_outside.
    pub eta: f64,
}

impl Medium {
    pub fn new(sigma_a: f64, sigma_s_prime: f64, g: f64, eta: f64) -> Self {
        Medium {
            sigma_a,
            sigma_s_prime,
            g,
            eta,
        }
    }
    /// Scattering coefficient σ_s = σ'_s/(1 − g) (σ'_s exactly when g = 0).
    pub fn sigma_s(&self) -> f64 {
        if self.g == 0.0 {
            self.sigma_s_prime
        } else {
            self.sigma_s_prime / (1.0 - self.g)
        }
    }
    pub fn sigma_t(&self) -> f64 {
        self.sigma_a + self.sigma_s()
    }
    /// (σ_s, σ_t) after checking the medium can be walked: σ_t positive and finite, no
    /// negative coefficient, |g| < 1, η > 0 (panics otherwise, naming what is wrong).
    pub(crate) fn checked_sigmas(&self) -> (f64, f64) {
        let sigma_s = self.sigma_s();
        let sigma_t = self.sigma_a + sigma_s;
        assert!(
            sigma_t > 0.0 && sigma_t.is_finite(),
            "mc: σ_t must be positive and finite"
        );
        assert!(
            self.sigma_a >= 0.0 && sigma_s >= 0.0,
            "mc: negative coefficient"
        );
        assert!(self.g > -1.0 && self.g < 1.0, "mc: g must be in (-1, 1)");
        assert!(self.eta > 0.0, "mc: η must be positive");
        (sigma_s, sigma_t)
    }

    /// Reduced albedo α' = σ'_s / (σ_a + σ'_s).
    pub fn reduced_albedo(&self) -> f64 {
        self.sigma_s_prime / (self.sigma_a + self.sigma_s_prime)
    }
}

/// Plane-parallel geometry; z ≥ 0 is inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    SemiInfinite,
    /// 0 ≤ z ≤ d (mm).
    Slab {
        d: f64,
    },
}

/// How light arrives on the top surface (z = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// Collimated pencil beam at normal incidence at the origin.
    Normal,
    /// Diffuse (cosine-weighted, uniform-radiance) incidence at the origin.
    Diffuse,
    /// Cosine-weighted incidence restricted to cos θ ∈ [mu_min, 1] (for reciprocity checks).
    Cone { mu_min: f64 },
    /// Isotropic unit-power point light at (0, 0, −h), h > 0 in mm.
    PointLight { h: f64 },
    /// Collimated pencil beam at the origin with incidence cosine `mu` ∈ (0, 1]; its
    /// horizontal direction of travel is −x (`mu = 1` is [`Source::Normal`]).
    Collimated { mu: f64 },
}

/// What to detect besides the totals.
#[derive(Clone, Debug, PartialEq)]
pub struct Detectors {
    /// Annulus edges in mm (ascending); empty for no radial profile.
    pub edges: Vec<f64>,
    /// Exit-cosine threshold (outside) of the top cone detector; > 1 disables it.
    pub cone_mu: f64,
    /// Event cap per photon.
    pub max_events: u64,
}

impl Default for Detectors {
    fn default() -> Self {
        Detectors {
            edges: Vec::new(),
            cone_mu: 2.0,
            max_events: MAX_EVENTS,
        }
    }
}

/// A radial profile binned in annuli (see the module docs). Values in mm⁻².
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    pub edges: Vec<f64>,
    pub r_mid: Vec<f64>,
    pub values: Vec<f64>,
    pub std_err: Vec<f64>,
}

/// Everything one simulation measures (per unit incident power; see the module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Results {
    pub photons: u64,
    /// Total events (free flights + boundary hits) simulated, for performance reports.
    pub events: u64,
    pub specular: Estimate,
    /// Diffuse reflectance (top), specular excluded.
    pub reflectance: Estimate,
    /// Transmittance (bottom; 0 for the semi-infinite medium).
    pub transmittance: Estimate,
    /// Never-scattered part of the transmittance.
    pub unscattered: Estimate,
    pub absorbed: Estimate,
    /// Weight stopped by the event cap (bias bound).
    pub capped: Estimate,
    /// Top exits with outside exit cosine ≥ `cone_mu`.
    pub cone: Estimate,
    /// R(r) or M(r), top surface.
    pub reflectance_profile: Profile,
    /// T(r), bottom surface (slab).
    pub transmittance_profile: Profile,
    /// Monte Carlo irradiance histogram at the top (point light only).
    pub irradiance_profile: Profile,
}

impl Results {
    /// Diffuse reflectance per unit power that entered the medium, R_d / (1 − specular):
    /// the quantity Jensen's dipole R_d models. The standard error is scaled by the same
    /// factor (exact for normal incidence, where the specular part is deterministic).
    pub fn reflectance_per_entered(&self) -> Estimate {
        self.reflectance.scaled(1.0 / (1.0 - self.specular.mean))
    }
}

fn profile(edges: &[f64], bins: &[estimate::Acc], n: u64) -> Profile {
    if edges.len() < 2 {
        return Profile::default();
    }
    let mut p = Profile {
        edges: edges.to_vec(),
        ..Default::default()
    };
    for (k, acc) in bins.iter().enumerate() {
        let (a, b) = (edges[k], edges[k + 1]);
        let area = PI * (b * b - a * a);
        let e = acc.estimate(n).scaled(1.0 / area);
        p.r_mid.push(0.5 * (a + b));
        p.values.push(e.mean);
        p.std_err.push(e.std_err);
    }
    p
}

/// The general entry point: `photons` photons from `source` into `m` in `geom`, seeded
/// by `seed`, over `threads` threads (results independent of `threads`).
pub fn simulate(
    m: &Medium,
    geom: Geometry,
    source: Source,
    det: &Detectors,
    photons: u64,
    seed: u64,
    threads: usize,
) -> Results {
    if let Source::PointLight { h } = source {
        assert!(h > 0.0, "mc: point light height must be positive");
    }
    if let Source::Collimated { mu } = source {
        assert!(
            mu > 0.0 && mu <= 1.0,
            "mc: collimated incidence cosine must be in (0, 1]"
        );
    }
    for w in det.edges.windows(2) {
        assert!(
            w[0] < w[1] && w[0] >= 0.0,
            "mc: bin edges must be ascending and ≥ 0"
        );
    }
    let nbins = det.edges.len().saturating_sub(1);
    let walker = flat::FlatWalker::new(m, geom, source, &det.edges, det.cone_mu, det.max_events);
    let t = estimate::run_batches(photons, seed, threads, nbins, |rng, t| {
        walker.photon(rng, t)
    });
    let n = t.n;
    Results {
        photons: n,
        events: t.events,
        specular: t.specular.estimate(n),
        reflectance: t.refl.estimate(n),
        transmittance: t.trans.estimate(n),
        unscattered: t.unscattered.estimate(n),
        absorbed: t.absorbed.estimate(n),
        capped: t.capped.estimate(n),
        cone: t.cone.estimate(n),
        reflectance_profile: profile(&det.edges, &t.refl_bins, n),
        transmittance_profile: profile(&det.edges, &t.trans_bins, n),
        irradiance_profile: profile(&det.edges, &t.inc_bins, n),
    }
}

/// Total diffuse reflectance of the semi-infinite medium for a normally incident beam,
/// per unit incident power, specular reflection excluded. Divide by
/// `1 − fresnel(1, η).0` for the per-entered value (see [`Results::reflectance_per_entered`]).
pub fn total_reflectance(m: &Medium, photons: u64, seed: u64, threads: usize) -> Estimate {
    simulate(
        m,
        Geometry::SemiInfinite,
        Source::Normal,
        &Detectors::default(),
        photons,
        seed,
        threads,
    )
    .reflectance
}

/// Total diffuse reflectance of the semi-infinite medium under diffuse (uniform radiance)
/// incidence, per unit incident power, specular excluded.
pub fn total_reflectance_diffuse(m: &Medium, photons: u64, seed: u64, threads: usize) -> Estimate {
    simulate(
        m,
        Geometry::SemiInfinite,
        Source::Diffuse,
        &Detectors::default(),
        photons,
        seed,
        threads,
    )
    .reflectance
}

/// Diffuse reflectance and transmittance of a slab for normal incidence.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlabEstimate {
    /// Diffuse reflectance per unit incident power (specular excluded).
    pub r: Estimate,
    /// Total transmittance per unit incident power (including the unscattered part).
    pub t: Estimate,
    /// Specular reflectance at entry (deterministic for normal incidence).
    pub specular: f64,
    pub absorbed: Estimate,
    pub capped: Estimate,
}

/// Slab of thickness `d` mm, normal incidence.
pub fn slab(m: &Medium, d: f64, photons: u64, seed: u64, threads: usize) -> SlabEstimate {
    let r = simulate(
        m,
        Geometry::Slab { d },
        Source::Normal,
        &Detectors::default(),
        photons,
        seed,
        threads,
    );
    SlabEstimate {
        r: r.reflectance,
        t: r.transmittance,
        specular: r.specular.mean,
        absorbed: r.absorbed,
        capped: r.capped,
    }
}

/// Radial diffuse-reflectance profile R(r) (mm⁻²) of the semi-infinite medium for a
/// normally incident pencil beam; `edges` are annulus edges in mm.
pub fn radial_profile(
    m: &Medium,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> Profile {
    let det = Detectors {
        edges: edges.to_vec(),
        ..Default::default()
    };
    simulate(
        m,
        Geometry::SemiInfinite,
        Source::Normal,
        &det,
        photons,
        seed,
        threads,
    )
    .reflectance_profile
}

/// Radial reflectance and transmittance profiles of a slab (pencil beam, normal incidence).
pub fn slab_radial_profiles(
    m: &Medium,
    d: f64,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> (Profile, Profile) {
    let det = Detectors {
        edges: edges.to_vec(),
        ..Default::default()
    };
    let r = simulate(
        m,
        Geometry::Slab { d },
        Source::Normal,
        &det,
        photons,
        seed,
        threads,
    );
    (r.reflectance_profile, r.transmittance_profile)
}

/// Radial diffuse exitance M(r) (mm⁻² per unit source power) of the semi-infinite medium lit
/// by an isotropic unit-power point light at height `h` mm.
pub fn point_light_profile(
    m: &Medium,
    h: f64,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> Profile {
    point_light(m, Geometry::SemiInfinite, h, edges, photons, seed, threads).reflectance_profile
}

/// Point light over `geom`: full results (exitance profile, Monte Carlo irradiance, totals).
pub fn point_light(
    m: &Medium,
    geom: Geometry,
    h: f64,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> Results {
    let det = Detectors {
        edges: edges.to_vec(),
        ..Default::default()
    };
    simulate(
        m,
        geom,
        Source::PointLight { h },
        &det,
        photons,
        seed,
        threads,
    )
}

/// Irradiance (mm⁻² per unit source power) at distance `r` from the foot of an isotropic
/// unit-power point light at height `h`: E(r) = h / (4π (r² + h²)^{3/2}).
pub fn point_light_irradiance(h: f64, r: f64) -> f64 {
    h / (4.0 * PI * (r * r + h * h).powf(1.5))
}

/// Exact annulus averages of [`point_light_irradiance`] over the bins given by `edges`:
/// (h/2)(1/√(a²+h²) − 1/√(b²+h²)) / (π(b² − a²)).
pub fn point_light_irradiance_bins(h: f64, edges: &[f64]) -> Vec<f64> {
    edges
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let p = 0.5 * h * (1.0 / (a * a + h * h).sqrt() - 1.0 / (b * b + h * h).sqrt());
            p / (PI * (b * b - a * a))
        })
        .collect()
}
#[cfg(test)]
mod mesh_tests;

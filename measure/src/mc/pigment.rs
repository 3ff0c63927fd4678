//! A flat semi-infinite medium whose albedo varies over the surface: an albedo map A(x) of
//! texels (stripes in x, constant in y) on a medium of multi-scatter albedo A₀, under three
//! ways of making the map a subsurface medium ([`Texturing`]). The walk is the plane walker's
//! (σ_t = σ'_t, g = 0, exponential free paths, implicit absorption, Russian roulette, smooth
//! Fresnel boundary with all-or-none internal reflection).
//!
//! **How the pigment is modelled** ([`Texturing::PrePost`]): an infinitely thin, purely
//! absorbing layer lying on the boundary, over a homogeneous medium of the material's albedo
//! A₀; light crosses it once where it enters and once where it leaves, and not when the
//! boundary reflects it back inside (the Fresnel reflection happens beneath it), with a
//! transmittance T(x) = √(A(x)/A₀) that does not depend on direction (a real film's would be
//! T^{1/μ}). A photon entering at x_in with weight w carries w·T(x_in) into the medium and
//! leaves at x_out with its weight times T(x_out): the exitance is
//! T(x) ∫ R(x − y) T(y) E(y) dy, R the homogeneous medium's kernel, so where the map is
//! uniform over the kernel's reach uniform light returns T²A₀ = A. T > 1 (a texel brighter
//! than the medium) is a gain, not a film; the estimator is the same.
//!
//! [`Texturing::PostOnly`]: no weight on entry, A(x_out)/A₀ on exit (uniform light returns A
//! at every point). [`Texturing::PerTexel`]: no layer; the medium itself varies — under
//! texel x its reduced albedo is α'(x), the inversion of A(x) (σ'_t the same everywhere), so
//! each scattering event at x weighs α'(x).
//!
//! Sources: [`Light::Uniform`] (diffuse, cosine-weighted light of unit irradiance over the
//! whole plane; entry points uniform over a window wide enough that what lies beyond it does
//! not reach the bins, or over one period of a periodic map) and [`Light::Point`] (the
//! isotropic unit-power point light of [`super::walk`], at height h above x = y = 0). Exits
//! are binned in strips of x (all y for uniform light; |y| < band/2 for the point light).

use super::estimate::{run_batches, Acc};
use super::fresnel::fresnel;
use super::rng::Rng;
use super::walk::{ROULETTE_SURVIVAL, ROULETTE_THRESHOLD};
use super::{Estimate, Profile, MAX_EVENTS};
use std::f64::consts::PI;

/// How the albedo map enters the medium (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Texturing {
    /// Pigment crossed on entry and exit: T = √(A/A₀) at both.
    PrePost,
    /// A/A₀ on exit only.
    PostOnly,
    /// The medium's own reduced albedo follows the map.
    PerTexel,
}

impl Texturing {
    pub const ALL: [Texturing; 3] = [Texturing::PrePost, Texturing::PostOnly, Texturing::PerTexel];

    pub fn name(self) -> &'static str {
        match self {
            Texturing::PrePost => "pre-post",
            Texturing::PostOnly => "post-only",
            Texturing::PerTexel => "per-texel",
        }
    }
}

/// Texels: stripes in x with one albedo each, optionally repeating with a period.
#[derive(Clone, Debug, PartialEq)]
pub struct Stripes {
    /// Interior boundaries in x (mm, ascending; within [0, period) when periodic).
    pub edges: Vec<f64>,
    /// Albedo A of each stripe (one more than `edges`): x < edges[0], …, x ≥ edges[last].
    /// With a period the first stripe continues from the last.
    pub albedo: Vec<f64>,
    pub period: Option<f64>,
}

impl Stripes {
    /// Index of the stripe under x.
    pub fn index(&self, x: f64) -> usize {
        let x = self.period.map_or(x, |p| x.rem_euclid(p));
        self.edges.partition_point(|&e| e <= x)
    }
}

/// One channel's textured medium.
#[derive(Clone, Debug, PartialEq)]
pub struct Textured {
    /// σ'_t (mm⁻¹) = σ_t (g = 0).
    pub sigma_t: f64,
    pub eta: f64,
    /// The medium's multi-scatter albedo A₀ and its reduced albedo α'₀.
    pub base: f64,
    pub base_single: f64,
    pub map: Stripes,
    /// The reduced albedo under each stripe (used by [`Texturing::PerTexel`]).
    pub single: Vec<f64>,
    pub texturing: Texturing,
}

/// Where light comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Diffuse light of unit irradiance over the plane; photons enter uniformly over
    /// [x_min, x_max) (or over one period of a periodic map: then x_min, x_max are ignored).
    Uniform { x_min: f64, x_max: f64 },
    /// Isotropic unit-power point light at (0, 0, −h).
    Point { h: f64 },
}

/// Strips of x (ascending edges, mm) and, for the point light, the band |y| < band/2 (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Bins {
    pub edges: Vec<f64>,
    pub band: f64,
}

/// Exitance per strip: per unit irradiance (uniform light, dimensionless) or per unit source
/// power per mm² (point light).
#[derive(Clone, Debug, PartialEq)]
pub struct TexturedResults {
    pub photons: u64,
    pub events: u64,
    pub strips: Profile,
    /// Weight stopped by the event cap.
    pub capped: Estimate,
}

impl Textured {
    fn stripe_weights(&self, x: f64) -> (f64, f64, f64) {
        let i = self.map.index(x);
        let a = self.map.albedo[i];
        // (entry, exit, scattering albedo) under x.
        match self.texturing {
            Texturing::PrePost => {
                let t = (a / self.base).sqrt();
                (t, t, self.base_single)
            }
            Texturing::PostOnly => (1.0, a / self.base, self.base_single),
            Texturing::PerTexel => (1.0, 1.0, self.single[i]),
        }
    }

    fn photon(&self, light: Light, bins: &Bins, rng: &mut Rng, t: &mut super::estimate::Tally) {
        let (mu, x, y, w0) = match light {
            Light::Uniform { x_min, x_max } => {
                let (a, b) = self.map.period.map_or((x_min, x_max), |p| (0.0, p));
                (
                    rng.uniform_pos().sqrt(),
                    a + (b - a) * rng.uniform(),
                    0.0,
                    1.0,
                )
            }
            Light::Point { h } => {
                let mu = rng.uniform_pos();
                let r = h * (1.0 - mu * mu).max(0.0).sqrt() / mu;
                let phi = 2.0 * PI * rng.uniform();
                (mu, r * phi.cos(), r * phi.sin(), 0.5)
            }
        };
        let phi = 2.0 * PI * rng.uniform();
        let (f, cos_t) = fresnel(mu, self.eta);
        let (entry, _, _) = self.stripe_weights(x);
        let mut w = w0 * (1.0 - f) * entry;
        if w <= 0.0 {
            return;
        }
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let [mut px, mut py, mut pz] = [x, y, 0.0];
        let [mut ux, mut uy, mut uz] = [sin_t * phi.cos(), sin_t * phi.sin(), cos_t];
        let threshold = ROULETTE_THRESHOLD * w;
        let inv_eta = 1.0 / self.eta;
        let mut events = 0u64;
        loop {
            events += 1;
            if events > MAX_EVENTS {
                t.capped.add(w);
                break;
            }
            let s = -rng.uniform_pos().ln() / self.sigma_t;
            if uz < 0.0 && s >= -pz / uz {
                let d = -pz / uz;
                px += ux * d;
                py += uy * d;
                pz = 0.0;
                let (r, _) = fresnel(-uz, inv_eta);
                if r > 0.0 && (r >= 1.0 || rng.uniform() < r) {
                    uz = -uz;
                    continue;
                }
                let (_, exit, _) = self.stripe_weights(px);
                let out = w * exit;
                t.refl.add(out);
                let in_band = match light {
                    Light::Uniform { .. } => true,
                    Light::Point { .. } => py.abs() < 0.5 * bins.band,
                };
                let bx = self.map.period.map_or(px, |p| px.rem_euclid(p));
                let e = &bins.edges;
                if in_band && bx >= e[0] && bx < e[e.len() - 1] {
                    t.refl_bins[e.partition_point(|&v| v <= bx) - 1].add(out);
                }
                break;
            }
            px += ux * s;
            py += uy * s;
            pz += uz * s;
            let (_, _, albedo) = self.stripe_weights(px);
            w *= albedo;
            if w < threshold {
                if w == 0.0 || rng.uniform() >= ROULETTE_SURVIVAL {
                    break;
                }
                w /= ROULETTE_SURVIVAL;
            }
            let ct = 2.0 * rng.uniform() - 1.0;
            let az = 2.0 * PI * rng.uniform();
            [ux, uy, uz] = super::phase::rotate([ux, uy, uz], ct, az);
        }
        t.events += events.min(MAX_EVENTS);
    }
}

/// Exitance of the textured medium `m` under `light`, binned by `bins`; `photons` photons
/// seeded by `seed`, bit-identical for any `threads`.
pub fn textured(
    m: &Textured,
    light: Light,
    bins: &Bins,
    photons: u64,
    seed: u64,
    threads: usize,
) -> TexturedResults {
    assert!(
        m.sigma_t > 0.0 && m.sigma_t.is_finite(),
        "mc: σ_t must be positive"
    );
    assert!(m.base > 0.0, "mc: the medium's albedo must be positive");
    assert!(
        m.map.albedo.len() == m.map.edges.len() + 1 && m.single.len() == m.map.albedo.len(),
        "mc: one albedo per stripe"
    );
    assert!(
        bins.edges.len() >= 2 && bins.edges.windows(2).all(|w| w[0] < w[1]),
        "mc: strip edges must be ascending"
    );
    if let Light::Uniform { x_min, x_max } = light {
        assert!(
            x_min < x_max || m.map.period.is_some(),
            "mc: empty entry window"
        );
    }
    let nbins = bins.edges.len() - 1;
    let tally = run_batches(photons, seed, threads, nbins, |rng, t| {
        m.photon(light, bins, rng, t)
    });
    let n = tally.n;
    // Per unit irradiance: a photon stands for (entry window)/N of the plane's width per
    // unit length in y, so a strip's exitance is its weight / (N · width / window).
    let scale = |w: &[f64]| -> f64 {
        let width = w[1] - w[0];
        match light {
            Light::Uniform { x_min, x_max } => m.map.period.unwrap_or(x_max - x_min) / width,
            Light::Point { .. } => 1.0 / (width * bins.band),
        }
    };
    let mut strips = Profile {
        edges: bins.edges.clone(),
        ..Default::default()
    };
    for (w, acc) in bins.edges.windows(2).zip(&tally.refl_bins) {
        let e = Acc::estimate(acc, n).scaled(scale(w));
        strips.r_mid.push(0.5 * (w[0] + w[1]));
        strips.values.push(e.mean);
        strips.std_err.push(e.std_err);
    }
    TexturedResults {
        photons: n,
        events: tally.events,
        strips,
        capped: tally.capped.estimate(n),
    }
}

//! A flat semi-infinite medium whose albedo varies over the surface: an albedo map A(x) of
//! texels (stripes in x, constant in y) on a medium of multi-scatter albedo A₀, under three
//! ways of making the map a subsurface medium ([`Texturing`]). The walk is `walk.rs`'s in the
//! flat volume of `flat.rs` (σ_t = σ'_t, g = 0, Russian roulette relative to the entry
//! weight), its single-scattering albedo read from the map under [`Texturing::PerTexel`].
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
//! isotropic unit-power point light of [`super::Source::PointLight`], at height h above x = y = 0). Exits
//! are binned in strips of x (all y for uniform light; |y| < band/2 for the point light).

use glam::DVec3;
use std::f64::consts::PI;

use super::estimate::{run_batches, Acc, Tally};
use super::flat::{Face, Flat};
use super::fresnel::fresnel;
use super::rng::Rng;
use super::walk::{Flight, Photon, Scoring, Volume, Walk, ROULETTE_THRESHOLD};
use super::{Estimate, Profile, MAX_EVENTS};

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

    fn photon(&self, light: Light, bins: &Bins, rng: &mut Rng, t: &mut Tally) {
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
        let w = w0 * (1.0 - f) * entry;
        if w <= 0.0 {
            return;
        }
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let p = Photon::new(
            DVec3::new(x, y, 0.0),
            DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t),
            w,
        );
        let walk = Walk {
            sigma_t: self.sigma_t,
            albedo: self.base_single,
            g: 0.0,
            eta: self.eta,
            max_events: MAX_EVENTS,
        };
        let volume = Pigmented {
            flat: Flat { d: f64::INFINITY },
            medium: self,
        };
        let mut score = StripScore {
            medium: self,
            light,
            bins,
            t,
        };
        walk.follow(&volume, (), &mut score, rng, p, ROULETTE_THRESHOLD * w);
    }
}

/// The semi-infinite medium under the albedo map: the flat volume, whose single-scattering
/// albedo follows the map under [`Texturing::PerTexel`].
struct Pigmented<'a> {
    flat: Flat,
    medium: &'a Textured,
}

impl Volume for Pigmented<'_> {
    type State = ();
    type Hit = Face;

    #[inline]
    fn flight(&self, st: &mut (), p: &mut Photon, s: f64) -> Flight<Face> {
        self.flat.flight(st, p, s)
    }

    #[inline]
    fn reflect(&self, st: &mut (), p: &mut Photon, hit: &Face, cos_i: f64) {
        self.flat.reflect(st, p, hit, cos_i)
    }

    #[inline]
    fn albedo(&self, pos: DVec3, base: f64) -> f64 {
        match self.medium.texturing {
            Texturing::PerTexel => self.medium.single[self.medium.map.index(pos.x)],
            Texturing::PrePost | Texturing::PostOnly => base,
        }
    }
}

/// The strips' tallies of one photon: its exit weighted by the map where it leaves.
struct StripScore<'s> {
    medium: &'s Textured,
    light: Light,
    bins: &'s Bins,
    t: &'s mut Tally,
}

impl Scoring<Pigmented<'_>> for StripScore<'_> {
    #[inline]
    fn exit(&mut self, _: &Pigmented<'_>, p: &Photon, _: &Face, _: f64) {
        let (px, py) = (p.pos.x, p.pos.y);
        let (_, exit, _) = self.medium.stripe_weights(px);
        let out = p.weight * exit;
        self.t.refl.add(out);
        let in_band = match self.light {
            Light::Uniform { .. } => true,
            Light::Point { .. } => py.abs() < 0.5 * self.bins.band,
        };
        let bx = self.medium.map.period.map_or(px, |p| px.rem_euclid(p));
        let e = &self.bins.edges;
        if in_band && bx >= e[0] && bx < e[e.len() - 1] {
            self.t.refl_bins[e.partition_point(|&v| v <= bx) - 1].add(out);
        }
    }

    #[inline]
    fn capped(&mut self, w: f64) {
        self.t.capped.add(w);
    }

    #[inline]
    fn done(&mut self, events: u64, _absorbed: f64) {
        self.t.events += events;
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

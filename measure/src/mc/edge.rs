//! Oblique incidence and the shadow edge (flat semi-infinite medium).
//!
//! **Oblique pencil beam** ([`Source::Collimated`]): a collimated beam hits the origin with
//! incidence cosine μ, travelling toward −x. [`oblique_reflectance`] is its diffuse
//! reflectance per unit incident power (specular excluded).
//!
//! **Shadow edge** ([`shadow_edge`]): the same directional light lights the half-plane x > 0
//! and a straight edge along y shadows x < 0. The exitance M(x), per unit irradiance *on the
//! surface* in the lit region, is the line-spread function of the pencil beam integrated
//! over the lit sources: M(x) = P(Δx < x) weighted by exit weight, where Δx is the x offset
//! between a photon's entry and exit points. By translation invariance one pencil beam at
//! the origin gives it exactly: a photon leaving at Δx adds to strip [a, b) the fraction of
//! the strip whose points x have their source x − Δx in the lit half, clamp((b − Δx)/(b − a),
//! 0, 1). Far into the lit side M → [`oblique_reflectance`] at the same μ; far into the
//! shadow M → 0. Standard errors are the per-photon ones (every photon contributes once per
//! strip).

use super::estimate::{run_batches, Acc};
use super::flat::{ExitBinning, FlatWalker};
use super::{Detectors, Estimate, Geometry, Medium, Profile, Source};

/// Diffuse reflectance of the semi-infinite medium for a collimated beam with incidence
/// cosine `mu` ∈ (0, 1], per unit incident power, specular excluded.
pub fn oblique_reflectance(
    m: &Medium,
    mu: f64,
    photons: u64,
    seed: u64,
    threads: usize,
) -> Estimate {
    super::simulate(
        m,
        Geometry::SemiInfinite,
        Source::Collimated { mu },
        &Detectors::default(),
        photons,
        seed,
        threads,
    )
    .reflectance
}

/// What [`shadow_edge`] measures (per unit incident power of the pencil beam, i.e. per unit
/// surface irradiance for the strips).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeResults {
    pub photons: u64,
    pub events: u64,
    /// Fresnel reflection at entry.
    pub specular: Estimate,
    /// Total diffuse reflectance at this incidence (the far-lit limit of the strips).
    pub reflectance: Estimate,
    pub absorbed: Estimate,
    pub capped: Estimate,
    /// Strip averages of M(x) per unit surface irradiance in the lit region (dimensionless);
    /// `edges` are the strip edges in x (mm, ascending, may be negative), `r_mid` the strip
    /// midpoints.
    pub strips: Profile,
}

/// Shadow edge: exitance averaged over the strips `edges` (mm, ascending) for a directional
/// light with incidence cosine `mu`, travelling toward −x, lighting x > 0 (see the module
/// docs). Deterministic for any `threads`; `max_events` as in [`Detectors`].
pub fn shadow_edge_with(
    m: &Medium,
    mu: f64,
    edges: &[f64],
    max_events: u64,
    photons: u64,
    seed: u64,
    threads: usize,
) -> EdgeResults {
    assert!(
        mu > 0.0 && mu <= 1.0,
        "mc: incidence cosine must be in (0, 1]"
    );
    assert!(
        edges.len() >= 2,
        "mc: a shadow edge needs at least one strip"
    );
    for w in edges.windows(2) {
        assert!(
            w[0] < w[1] && w[0].is_finite() && w[1].is_finite(),
            "mc: strip edges must be finite and ascending"
        );
    }
    let mut walker = FlatWalker::new(
        m,
        Geometry::SemiInfinite,
        Source::Collimated { mu },
        edges,
        2.0,
        max_events,
    );
    walker.binning = ExitBinning::EdgeStrips;
    let nbins = edges.len() - 1;
    let t = run_batches(photons, seed, threads, nbins, |rng, t| {
        walker.photon(rng, t)
    });
    let n = t.n;
    EdgeResults {
        photons: n,
        events: t.events,
        specular: t.specular.estimate(n),
        reflectance: t.refl.estimate(n),
        absorbed: t.absorbed.estimate(n),
        capped: t.capped.estimate(n),
        strips: strip_profile(edges, &t.refl_bins, n),
    }
}

/// [`shadow_edge_with`] with the default event cap.
pub fn shadow_edge(
    m: &Medium,
    mu: f64,
    edges: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> EdgeResults {
    shadow_edge_with(m, mu, edges, super::MAX_EVENTS, photons, seed, threads)
}

fn strip_profile(edges: &[f64], bins: &[Acc], n: u64) -> Profile {
    let mut p = Profile {
        edges: edges.to_vec(),
        ..Default::default()
    };
    for (w, acc) in edges.windows(2).zip(bins) {
        let e = acc.estimate(n);
        p.r_mid.push(0.5 * (w[0] + w[1]));
        p.values.push(e.mean);
        p.std_err.push(e.std_err);
    }
    p
}

/// Diffuse transmittance of a slab of thickness `d` mm lit at normal incidence from the
/// other side, per unit incident power: everything leaving the far face except the
/// never-scattered (collimated) part. The standard error is the per-photon one (a photon
/// leaves once, scattered or not, so the scattered part's sums are the differences of the
/// two tallies' sums).
pub fn slab_diffuse_transmittance(
    m: &Medium,
    d: f64,
    photons: u64,
    seed: u64,
    threads: usize,
) -> Estimate {
    let walker = FlatWalker::new(
        m,
        Geometry::Slab { d },
        Source::Normal,
        &[],
        2.0,
        super::MAX_EVENTS,
    );
    let t = run_batches(photons, seed, threads, 0, |rng, t| walker.photon(rng, t));
    let diffuse = Acc {
        s1: (t.trans.s1 - t.unscattered.s1).max(0.0),
        s2: (t.trans.s2 - t.unscattered.s2).max(0.0),
    };
    diffuse.estimate(t.n)
}

//! The photon walk: sources, free paths, implicit absorption, Russian roulette, HG
//! scattering, Fresnel boundaries, and the per-photon tallies.

use super::estimate::Tally;
use super::fresnel::fresnel;
use super::phase::{rotate, sample_hg_cos};
use super::rng::Rng;
use super::{Geometry, Medium, Source};
use std::f64::consts::PI;

/// Roulette is played when the weight drops below this …
pub const ROULETTE_THRESHOLD: f64 = 1e-4;
/// … and the photon survives with this probability (its weight divided by it).
pub const ROULETTE_SURVIVAL: f64 = 0.1;

/// How top-surface exits are binned by `edges`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ExitBinning {
    /// Annuli in the distance r from the origin.
    Radial,
    /// Shadow-edge strips in x (see `edge.rs`): an exit at offset Δx adds to strip [a, b) the
    /// fraction of it lit by a half-plane x > 0 of sources, clamp((b − Δx)/(b − a), 0, 1).
    EdgeStrips,
}

pub(crate) struct Walker<'a> {
    pub sigma_t: f64,
    pub albedo: f64,
    pub g: f64,
    pub eta: f64,
    /// Slab thickness; `f64::INFINITY` for the semi-infinite medium.
    pub d: f64,
    pub source: Source,
    pub edges: &'a [f64],
    pub cone_mu: f64,
    pub max_events: u64,
    pub binning: ExitBinning,
}

impl<'a> Walker<'a> {
    pub fn new(
        m: &Medium,
        geom: Geometry,
        source: Source,
        edges: &'a [f64],
        cone_mu: f64,
        max_events: u64,
    ) -> Self {
        let (sigma_s, sigma_t) = m.checked_sigmas();
        let d = match geom {
            Geometry::SemiInfinite => f64::INFINITY,
            Geometry::Slab { d } => {
                assert!(d > 0.0, "mc: slab thickness must be positive");
                d
            }
        };
        Walker {
            sigma_t,
            albedo: sigma_s / sigma_t,
            g: m.g,
            eta: m.eta,
            d,
            source,
            edges,
            cone_mu,
            max_events,
            binning: ExitBinning::Radial,
        }
    }

    #[inline]
    fn bin(&self, r: f64) -> Option<usize> {
        let e = self.edges;
        if e.len() < 2 || r < e[0] || r >= e[e.len() - 1] {
            return None;
        }
        Some(e.partition_point(|&x| x <= r) - 1)
    }

    /// Adds an exit at offset `dx` with weight `w` to every shadow-edge strip it lights.
    fn add_edge_strips(&self, dx: f64, w: f64, t: &mut Tally) {
        for (k, e) in self.edges.windows(2).enumerate() {
            let frac = ((e[1] - dx) / (e[1] - e[0])).clamp(0.0, 1.0);
            if frac > 0.0 {
                t.refl_bins[k].add(w * frac);
            }
        }
    }

    /// Launches and follows one photon, adding its contributions to `t`.
    pub fn photon(&self, rng: &mut Rng, t: &mut Tally) {
        // Direction of incidence outside (cos θ toward +z), entry point, weight before Fresnel.
        let (mu, r0, w0, random_azimuth) = match self.source {
            Source::Normal => (1.0, 0.0, 1.0, false),
            Source::Collimated { mu } => (mu, 0.0, 1.0, false),
            Source::Diffuse => (rng.uniform_pos().sqrt(), 0.0, 1.0, true),
            Source::Cone { mu_min } => {
                let m2 = mu_min * mu_min;
                ((m2 + rng.uniform_pos() * (1.0 - m2)).sqrt(), 0.0, 1.0, true)
            }
            Source::PointLight { h } => {
                // Downward hemisphere, uniform in solid angle: μ uniform in (0, 1], weight ½
                // (the half of an isotropic unit-power source heading toward the surface).
                let mu = rng.uniform_pos();
                let r = h * (1.0 - mu * mu).max(0.0).sqrt() / mu;
                if let Some(b) = self.bin(r) {
                    t.inc_bins[b].add(0.5);
                }
                (mu, r, 0.5, true)
            }
        };
        // Azimuth of incidence: the incident direction's horizontal part points along
        // (cos φ, sin φ). For the point light, the entry point lies along that direction too
        // (at distance r0 from the origin).
        let (cphi, sphi) = if random_azimuth {
            let phi = 2.0 * PI * rng.uniform();
            let (s, c) = phi.sin_cos();
            (c, s)
        } else if let Source::Collimated { .. } = self.source {
            // The oblique beam travels toward −x.
            (-1.0, 0.0)
        } else {
            (1.0, 0.0)
        };
        let (x, y) = (r0 * cphi, r0 * sphi);
        let (f, cos_t) = fresnel(mu, self.eta);
        if f > 0.0 {
            t.specular.add(w0 * f);
        }
        let w = w0 * (1.0 - f);
        if w <= 0.0 {
            return;
        }
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let dir = [sin_t * cphi, sin_t * sphi, cos_t];
        self.follow(rng, t, [x, y, 0.0], dir, w);
    }

    /// Follows a photon that has just entered at `pos` (z = 0) with direction `dir` and
    /// weight `w` until it leaves, dies in roulette, or hits the event cap.
    fn follow(&self, rng: &mut Rng, t: &mut Tally, pos: [f64; 3], dir: [f64; 3], mut w: f64) {
        let [mut x, mut y, mut z] = pos;
        let [mut ux, mut uy, mut uz] = dir;
        let mut absorbed = 0.0;
        let mut scattered = false;
        let inv_eta = 1.0 / self.eta;
        let mut events: u64 = 0;
        loop {
            events += 1;
            if events > self.max_events {
                t.capped.add(w);
                break;
            }
            let s = -rng.uniform_pos().ln() / self.sigma_t;
            let db = if uz < 0.0 {
                -z / uz
            } else if uz > 0.0 {
                (self.d - z) / uz
            } else {
                f64::INFINITY
            };
            if s >= db {
                // Reaches a boundary: Fresnel reflect or leave (all-or-none).
                x += ux * db;
                y += uy * db;
                let top = uz < 0.0;
                z = if top { 0.0 } else { self.d };
                let (r, cos_out) = fresnel(uz.abs(), inv_eta);
                if r > 0.0 && (r >= 1.0 || rng.uniform() < r) {
                    uz = -uz;
                    continue;
                }
                let rr = (x * x + y * y).sqrt();
                if top {
                    t.refl.add(w);
                    if cos_out >= self.cone_mu {
                        t.cone.add(w);
                    }
                    if self.binning == ExitBinning::EdgeStrips {
                        self.add_edge_strips(x, w, t);
                    } else if let Some(b) = self.bin(rr) {
                        t.refl_bins[b].add(w);
                    }
                } else {
                    t.trans.add(w);
                    if !scattered {
                        t.unscattered.add(w);
                    }
                    if let Some(b) = self.bin(rr) {
                        t.trans_bins[b].add(w);
                    }
                }
                break;
            }
            x += ux * s;
            y += uy * s;
            z += uz * s;
            // Implicit absorption.
            absorbed += w * (1.0 - self.albedo);
            w *= self.albedo;
            if w < ROULETTE_THRESHOLD {
                if w == 0.0 || rng.uniform() >= ROULETTE_SURVIVAL {
                    absorbed += w;
                    break;
                }
                w /= ROULETTE_SURVIVAL;
            }
            scattered = true;
            let ct = sample_hg_cos(self.g, rng.uniform());
            let phi = 2.0 * PI * rng.uniform();
            [ux, uy, uz] = rotate([ux, uy, uz], ct, phi);
        }
        t.events += events.min(self.max_events);
        if absorbed != 0.0 {
            t.absorbed.add(absorbed);
        }
    }
}

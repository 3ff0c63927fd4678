//! The plane-parallel scenes: the semi-infinite medium z ≥ 0 and the slab 0 ≤ z ≤ d as a
//! [`Volume`] of the walk, their sources ([`Source`]) and their tallies (totals, the cone
//! detector, radial annuli or shadow-edge strips at the top, annuli at the bottom).

use glam::DVec3;
use std::f64::consts::PI;

use super::estimate::Tally;
use super::fresnel::fresnel;
use super::rng::Rng;
use super::walk::{Flight, Photon, Scoring, Volume, Walk, ROULETTE_THRESHOLD};
use super::{Geometry, Medium, Source};

/// The medium between the planes z = 0 (top, the lit side) and z = d (`f64::INFINITY`: none).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Flat {
    pub d: f64,
}

/// Which face a photon reached: the top (z = 0) or the bottom (z = d).
pub(crate) struct Face {
    pub top: bool,
}

impl Volume for Flat {
    type State = ();
    type Hit = Face;

    #[inline]
    fn flight(&self, _: &mut (), p: &mut Photon, s: f64) -> Flight<Face> {
        let (z, uz) = (p.pos.z, p.dir.z);
        let db = if uz < 0.0 {
            -z / uz
        } else if uz > 0.0 {
            (self.d - z) / uz
        } else {
            f64::INFINITY
        };
        if s >= db {
            p.pos.x += p.dir.x * db;
            p.pos.y += p.dir.y * db;
            let top = uz < 0.0;
            p.pos.z = if top { 0.0 } else { self.d };
            Flight::Boundary {
                hit: Face { top },
                cos_i: uz.abs(),
            }
        } else {
            Flight::Free
        }
    }

    #[inline]
    fn reflect(&self, _: &mut (), p: &mut Photon, _: &Face, _: f64) {
        p.dir.z = -p.dir.z;
    }
}

/// How top-surface exits are binned by `edges`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ExitBinning {
    /// Annuli in the distance r from the origin.
    Radial,
    /// Shadow-edge strips in x (see `edge.rs`): an exit at offset Δx adds to strip [a, b) the
    /// fraction of it lit by a half-plane x > 0 of sources, clamp((b − Δx)/(b − a), 0, 1).
    EdgeStrips,
}

/// A flat scene: the medium, its source and its detectors.
pub(crate) struct FlatWalker<'a> {
    pub walk: Walk,
    pub flat: Flat,
    pub source: Source,
    pub edges: &'a [f64],
    pub cone_mu: f64,
    pub binning: ExitBinning,
}

impl<'a> FlatWalker<'a> {
    pub fn new(
        m: &Medium,
        geom: Geometry,
        source: Source,
        edges: &'a [f64],
        cone_mu: f64,
        max_events: u64,
    ) -> Self {
        let walk = Walk::new(m, max_events);
        let d = match geom {
            Geometry::SemiInfinite => f64::INFINITY,
            Geometry::Slab { d } => {
                assert!(d > 0.0, "mc: slab thickness must be positive");
                d
            }
        };
        FlatWalker {
            walk,
            flat: Flat { d },
            source,
            edges,
            cone_mu,
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
        let (f, cos_t) = fresnel(mu, self.walk.eta);
        if f > 0.0 {
            t.specular.add(w0 * f);
        }
        let w = w0 * (1.0 - f);
        if w <= 0.0 {
            return;
        }
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let p = Photon::new(
            DVec3::new(r0 * cphi, r0 * sphi, 0.0),
            DVec3::new(sin_t * cphi, sin_t * sphi, cos_t),
            w,
        );
        let mut score = FlatScore { scene: self, t };
        self.walk
            .follow(&self.flat, (), &mut score, rng, p, ROULETTE_THRESHOLD);
    }
}

/// The flat scenes' tallies of one photon.
struct FlatScore<'s, 'a> {
    scene: &'s FlatWalker<'a>,
    t: &'s mut Tally,
}

impl Scoring<Flat> for FlatScore<'_, '_> {
    #[inline]
    fn exit(&mut self, _: &Flat, p: &Photon, face: &Face, cos_out: f64) {
        let (s, t, w) = (self.scene, &mut *self.t, p.weight);
        let (x, y) = (p.pos.x, p.pos.y);
        let rr = (x * x + y * y).sqrt();
        if face.top {
            t.refl.add(w);
            if cos_out >= s.cone_mu {
                t.cone.add(w);
            }
            if s.binning == ExitBinning::EdgeStrips {
                // Every strip this exit lights.
                for (k, e) in s.edges.windows(2).enumerate() {
                    let frac = ((e[1] - x) / (e[1] - e[0])).clamp(0.0, 1.0);
                    if frac > 0.0 {
                        t.refl_bins[k].add(w * frac);
                    }
                }
            } else if let Some(b) = s.bin(rr) {
                t.refl_bins[b].add(w);
            }
        } else {
            t.trans.add(w);
            if !p.scattered {
                t.unscattered.add(w);
            }
            if let Some(b) = s.bin(rr) {
                t.trans_bins[b].add(w);
            }
        }
    }

    #[inline]
    fn capped(&mut self, w: f64) {
        self.t.capped.add(w);
    }

    #[inline]
    fn done(&mut self, events: u64, absorbed: f64) {
        self.t.finish_photon(events, absorbed);
    }
}

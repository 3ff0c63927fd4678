//! The photon walk, once for every scene: free flights in σ_t, implicit absorption, Russian
//! roulette, Henyey–Greenstein scattering, the event cap, and the smooth Fresnel boundary
//! (reflected with probability F — always past the critical angle — else the photon leaves).
//!
//! What differs between the scenes is split in two, both static (generic) so the loop is
//! compiled once per scene with everything inlined:
//! - the **geometry**, `Volume`: how far a flight goes before it meets the boundary and what
//!   the boundary is there (its incidence cosine), the mirror direction, what happens after the
//!   photon leaves (by default nothing: it is gone; the mesh follows it outside and lets it
//!   re-enter where it meets the surface again), and the single-scattering albedo at a point
//!   (by default the medium's; the pigmented medium's varies over the surface). Per-photon
//!   geometric state (the mesh's current triangle and winding depth) is the volume's `State`.
//! - the **scoring**, `Scoring`: what is tallied when the photon leaves (radial bins, bands,
//!   strips, the camera's pixels…), when it is stopped by the event cap, lost, re-enters or
//!   escapes, and the photon's events and absorbed weight at the end.
//!
//! Sources (how photons are launched and enter) are the scenes' own: each scene draws its
//! entry point, direction and weight — the mesh's entry roulette included — and hands the
//! photon to `Walk::follow`. The random numbers are drawn in one fixed order: per event the
//! free path, then at a boundary the reflection test (only when 0 < F < 1), else the roulette
//! test (only below the threshold) and the scattering (cos θ, then the azimuth); what a volume
//! draws after an exit (the mesh's re-entry tests) comes before the next event's free path.

use glam::DVec3;
use std::f64::consts::PI;

use super::fresnel::fresnel;
use super::phase::{rotate, sample_hg_cos};
use super::rng::Rng;
use super::Medium;

/// Roulette is played when the weight drops below this (times the entry weight where the
/// scene's roulette is relative to it) …
pub const ROULETTE_THRESHOLD: f64 = 1e-4;
/// … and the photon survives with this probability (its weight divided by it).
pub const ROULETTE_SURVIVAL: f64 = 0.1;

/// A photon inside the medium.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Photon {
    pub pos: DVec3,
    /// Unit direction of travel.
    pub dir: DVec3,
    pub weight: f64,
    /// Whether it has scattered since it entered (a slab's collimated transmittance).
    pub scattered: bool,
}

impl Photon {
    pub fn new(pos: DVec3, dir: DVec3, weight: f64) -> Self {
        Photon {
            pos,
            dir,
            weight,
            scattered: false,
        }
    }
}

/// What a free flight of a given length meets (see [`Volume::flight`]).
pub(crate) enum Flight<H> {
    /// Nothing: the photon flies the whole length and interacts there.
    Free,
    /// The boundary, with incidence cosine `cos_i` (from inside); the photon is on it.
    Boundary { hit: H, cos_i: f64 },
    /// A surface that is not the boundary (an inner sheet of an overlapping mesh): the photon
    /// is on it, and the walk goes on with the next event (free paths are memoryless).
    Through,
    /// The photon is not inside the medium (a crack between triangles): it is stopped.
    Lost,
}

/// Where a photon that left goes (see [`Volume::leave`]).
pub(crate) enum Outside {
    /// Away for good.
    Escaped,
    /// Back into the medium (the volume has set its position, direction and state).
    Reentered,
    /// Into a surface from behind: stopped, like [`Flight::Lost`].
    Lost,
}

/// The geometry of a scene's medium (module docs).
pub(crate) trait Volume {
    /// What the volume remembers about a photon between events.
    type State;
    /// Where a flight met the boundary.
    type Hit;
    /// Whether a flight of length `s` from the photon meets a surface; if it does, the photon
    /// is moved onto it. [`Flight::Free`] leaves the photon where it is.
    fn flight(&self, st: &mut Self::State, p: &mut Photon, s: f64) -> Flight<Self::Hit>;
    /// Turns the photon at `hit` (incidence cosine `cos_i`) into the mirror direction.
    fn reflect(&self, st: &mut Self::State, p: &mut Photon, hit: &Self::Hit, cos_i: f64);
    /// Called once the photon has left through `hit` (refracted cosine `cos_out` outside, η the
    /// medium's relative index) and been scored: whether it comes back.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn leave(
        &self,
        _st: &mut Self::State,
        _p: &mut Photon,
        _hit: &Self::Hit,
        _cos_i: f64,
        _cos_out: f64,
        _eta: f64,
        _rng: &mut Rng,
    ) -> Outside {
        Outside::Escaped
    }
    /// The single-scattering albedo at `pos` (`base`: the medium's).
    #[inline]
    fn albedo(&self, _pos: DVec3, base: f64) -> f64 {
        base
    }
}

/// A scene's tallies (module docs). `exit` is called with the photon on the boundary, before
/// [`Volume::leave`]; `done` once per photon, last.
pub(crate) trait Scoring<V: Volume> {
    /// The photon leaves through `hit`, `cos_out` its refracted cosine outside.
    fn exit(&mut self, v: &V, p: &Photon, hit: &V::Hit, cos_out: f64);
    /// The event cap stopped a photon of weight `w`.
    fn capped(&mut self, w: f64);
    /// A photon of weight `w` was found outside the medium.
    #[inline]
    fn lost(&mut self, _w: f64) {}
    /// A photon of weight `w` that left came back in.
    #[inline]
    fn reentered(&mut self, _w: f64) {}
    /// A photon of weight `w` that left is gone for good.
    #[inline]
    fn escaped(&mut self, _w: f64) {}
    /// The photon's walk is over: its events (cap included) and the weight it lost to
    /// absorption (0 when none).
    fn done(&mut self, events: u64, absorbed: f64);
}

/// The medium's optics as the walk uses them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Walk {
    pub sigma_t: f64,
    /// Single-scattering albedo σ_s/σ_t (a [`Volume`] may vary it).
    pub albedo: f64,
    pub g: f64,
    /// Relative index of the medium to the outside.
    pub eta: f64,
    /// Events (free flights and boundary hits) after which a photon is stopped.
    pub max_events: u64,
}

impl Walk {
    /// The walk of `m` (checked: panics naming what is wrong) with an event cap.
    pub fn new(m: &Medium, max_events: u64) -> Self {
        let (sigma_s, sigma_t) = m.checked_sigmas();
        Walk {
            sigma_t,
            albedo: sigma_s / sigma_t,
            g: m.g,
            eta: m.eta,
            max_events,
        }
    }

    /// Follows photon `p`, just entered into `v` (volume state `st`), until it leaves for good,
    /// dies in the roulette (played below the weight `threshold`), is lost or hits the event
    /// cap, telling `score` what happens.
    #[inline]
    pub fn follow<V: Volume, S: Scoring<V>>(
        &self,
        v: &V,
        mut st: V::State,
        score: &mut S,
        rng: &mut Rng,
        mut p: Photon,
        threshold: f64,
    ) {
        let inv_eta = 1.0 / self.eta;
        let mut absorbed = 0.0;
        let mut events: u64 = 0;
        loop {
            events += 1;
            if events > self.max_events {
                score.capped(p.weight);
                break;
            }
            let s = -rng.uniform_pos().ln() / self.sigma_t;
            match v.flight(&mut st, &mut p, s) {
                Flight::Free => {}
                Flight::Through => continue,
                Flight::Lost => {
                    score.lost(p.weight);
                    break;
                }
                Flight::Boundary { hit, cos_i } => {
                    // Fresnel reflect or leave (all-or-none).
                    let (r, cos_out) = fresnel(cos_i, inv_eta);
                    if r > 0.0 && (r >= 1.0 || rng.uniform() < r) {
                        v.reflect(&mut st, &mut p, &hit, cos_i);
                        continue;
                    }
                    score.exit(v, &p, &hit, cos_out);
                    match v.leave(&mut st, &mut p, &hit, cos_i, cos_out, self.eta, rng) {
                        Outside::Escaped => {
                            score.escaped(p.weight);
                            break;
                        }
                        Outside::Lost => {
                            score.lost(p.weight);
                            break;
                        }
                        Outside::Reentered => {
                            score.reentered(p.weight);
                            continue;
                        }
                    }
                }
            }
            p.pos += p.dir * s;
            // Implicit absorption.
            let albedo = v.albedo(p.pos, self.albedo);
            absorbed += p.weight * (1.0 - albedo);
            p.weight *= albedo;
            if p.weight < threshold {
                if p.weight == 0.0 || rng.uniform() >= ROULETTE_SURVIVAL {
                    absorbed += p.weight;
                    break;
                }
                p.weight /= ROULETTE_SURVIVAL;
            }
            p.scattered = true;
            let ct = sample_hg_cos(self.g, rng.uniform());
            let phi = 2.0 * PI * rng.uniform();
            p.dir = DVec3::from_array(rotate(p.dir.to_array(), ct, phi));
        }
        score.done(events.min(self.max_events), absorbed);
    }
}

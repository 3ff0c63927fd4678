//! The closed triangle mesh ([`ClosedMesh`]) lit by an isotropic point light outside it: the
//! walk of `walk.rs` with the mesh as its geometry (`Inside`) and the caller's exit scorer.
//!
//! **Source.** A point light of unit radiant intensity at `light`. Only directions that can
//! reach the mesh matter: photons are sampled uniformly over the cone from the light that just
//! holds the mesh's bounding sphere (solid angle Ω), each carrying the power Ω of that cone
//! (the whole sphere, 4π, when the light is inside the bounding sphere). A photon that misses
//! the mesh carries nothing to it. The inverse-square and cosine factors come from the ray
//! geometry itself: equal solid angles land on areas growing as d²/cos θ.
//!
//! **Boundary.** The triangles' geometric normals, smooth dielectric of relative index η, as in
//! the probes: at entry from the light the Fresnel-reflected part is the specular reflection,
//! *excluded* (tallied on its own), the rest refracts in with weight (1 − F); from inside a
//! photon is reflected with probability F (total internal reflection past the critical angle),
//! else it leaves with its whole weight. Leaving, it is handed to the caller's exit scorer
//! (where it leaves, and through which triangle), then followed outside along the refracted
//! direction: if it meets the mesh again (a fold, the ear, the nose beside the cheek) it is
//! reflected with probability F there and re-enters otherwise — physical interreflection,
//! which counts again at its next exit. Light that leaves for good is `escaped`.
//!
//! **Inside.** The walk's (`walk.rs`), Russian roulette relative to the entry weight. A free
//! flight shorter than the mesh's safe distance needs no ray query. Where the mesh overlaps itself (a scan's eyelids and lips cross other
//! sheets) the medium is the region of positive winding number: the walk counts the layers it
//! is in and only the outermost face is a boundary. A photon found outside the mesh while
//! inside (a crack between triangles at f32/f64 precision, or a face seen from behind from
//! outside) is stopped and its weight tallied as `lost` (a bias bound, like `capped`).
//!
//! **Entry roulette** (optional): a photon entering far from where its exits can count (from
//! what the camera sees) goes on with a small probability and a weight divided by it, so the
//! walks are spent where they are seen — unbiased, like the walk's own roulette.
//!
//! **Energy.** Per unit source power sent toward the mesh: incident = specular + escaped +
//! absorbed + capped + lost in expectation (roulette is unbiased, not exact per photon).

use glam::DVec3;

use super::estimate::Acc;
use super::fresnel::fresnel;
use super::mesh::{ClosedMesh, DistanceField, Hit};
use super::rng::Rng;
use super::walk::{Flight, Outside, Photon, Scoring, Volume, Walk, ROULETTE_THRESHOLD};
use super::Medium;
use std::f64::consts::PI;

/// Scalar tallies of a mesh walk, per photon (the source's cone power not applied).
#[derive(Clone, Debug, Default)]
pub struct MeshTally {
    pub n: u64,
    pub events: u64,
    /// Power arriving on the mesh from the light (before Fresnel).
    pub incident: Acc,
    /// Fresnel reflection at entry (excluded from the exitance).
    pub specular: Acc,
    pub entered: Acc,
    /// Every exit, including light that re-enters later.
    pub exits: Acc,
    /// Light that left, met the mesh again and entered it.
    pub reentered: Acc,
    /// Light that left for good.
    pub escaped: Acc,
    pub absorbed: Acc,
    pub capped: Acc,
    pub lost: Acc,
    /// Entered weight stopped by the entry roulette (made up for by its survivors).
    pub culled: Acc,
}

impl MeshTally {
    pub fn merge(&mut self, o: &MeshTally) {
        self.n += o.n;
        self.events += o.events;
        for (a, b) in self.accs_mut().into_iter().zip(o.accs()) {
            a.merge(&b);
        }
    }
    fn accs(&self) -> [Acc; 10] {
        [
            self.incident,
            self.specular,
            self.entered,
            self.exits,
            self.reentered,
            self.escaped,
            self.absorbed,
            self.capped,
            self.lost,
            self.culled,
        ]
    }
    fn accs_mut(&mut self) -> [&mut Acc; 10] {
        [
            &mut self.incident,
            &mut self.specular,
            &mut self.entered,
            &mut self.exits,
            &mut self.reentered,
            &mut self.escaped,
            &mut self.absorbed,
            &mut self.capped,
            &mut self.lost,
            &mut self.culled,
        ]
    }
}

/// Where and how a photon left the mesh: handed to the exit scorer.
#[derive(Clone, Copy, Debug)]
pub struct Exit {
    /// Exit point.
    pub point: DVec3,
    /// The triangle it left through, with the point's barycentrics.
    pub hit: Hit,
    /// The photon's weight (per unit cone power).
    pub weight: f64,
}

/// One channel's walk in one mesh under one point light.
pub struct MeshWalker<'a> {
    pub mesh: &'a ClosedMesh,
    walk: Walk,
    light: DVec3,
    /// Cosine of the source cone's half-angle (−1: the whole sphere).
    cos_cone: f64,
    /// Frame of the cone: its axis and two perpendiculars.
    axis: [DVec3; 3],
    pub max_events: u64,
    /// Entry roulette: photons entering farther than `distance` from `field`'s points go on
    /// with probability `survival` (weight divided by it), the others stop.
    pub roulette: Option<EntryRoulette<'a>>,
}

/// Russian roulette at entry by distance from what matters (the camera's visible surface):
/// unbiased, it spends the walks where their exits can be seen.
#[derive(Clone, Copy)]
pub struct EntryRoulette<'a> {
    pub field: &'a DistanceField,
    pub distance: f64,
    pub survival: f64,
}

impl<'a> MeshWalker<'a> {
    /// A walker for medium `m` (lengths in the mesh's units) under a point light at `light`
    /// (outside the mesh).
    pub fn new(mesh: &'a ClosedMesh, m: &Medium, light: DVec3) -> Self {
        let walk = Walk::new(m, super::MAX_EVENTS);
        let to_centre = mesh.centre - light;
        let dist = to_centre.length();
        let cos_cone = if dist > mesh.radius * (1.0 + 1e-9) {
            (1.0 - (mesh.radius / dist).powi(2)).sqrt()
        } else {
            -1.0
        };
        let w = to_centre.try_normalize().unwrap_or(DVec3::Z);
        let (u, v) = w.any_orthonormal_pair();
        Self {
            mesh,
            walk,
            light,
            cos_cone,
            axis: [u, v, w],
            max_events: super::MAX_EVENTS,
            roulette: None,
        }
    }

    /// Solid angle of the source cone: the power each photon carries per unit intensity.
    pub fn cone_solid_angle(&self) -> f64 {
        2.0 * PI * (1.0 - self.cos_cone)
    }

    /// Launches one photon from the light and follows it; every exit goes to `score`.
    pub fn photon(&self, rng: &mut Rng, t: &mut MeshTally, score: &mut impl FnMut(&Exit)) {
        t.n += 1;
        let mu = 1.0 - rng.uniform() * (1.0 - self.cos_cone);
        let phi = 2.0 * PI * rng.uniform();
        let s = (1.0 - mu * mu).max(0.0).sqrt();
        let [u, v, w] = self.axis;
        let d = (u * (s * phi.cos()) + v * (s * phi.sin()) + w * mu).normalize();
        let Some(hit) = self.mesh.first_hit(self.light, d, f64::INFINITY, None) else {
            return;
        };
        t.incident.add(1.0);
        let n = self.mesh.normal(hit.tri);
        let cos_i = -d.dot(n);
        if cos_i <= 0.0 {
            // The light sees the inside of a triangle first: it is inside the mesh.
            t.lost.add(1.0);
            return;
        }
        let (f, cos_t) = fresnel(cos_i, self.walk.eta);
        if f > 0.0 {
            t.specular.add(f);
        }
        let mut w0 = 1.0 - f;
        if w0 <= 0.0 {
            return;
        }
        t.entered.add(w0);
        let x = self.light + d * hit.t;
        if let Some(r) = &self.roulette {
            if r.field.distance(x) > r.distance {
                if rng.uniform() >= r.survival {
                    t.culled.add(w0);
                    return;
                }
                w0 /= r.survival;
            }
        }
        let dir = refract_in(d, n, cos_i, cos_t, self.walk.eta);
        let walk = Walk {
            max_events: self.max_events,
            ..self.walk
        };
        let start = Layers {
            on: Some(hit.tri),
            depth: 1,
        };
        let mut exits = MeshScore { t, score };
        let threshold = ROULETTE_THRESHOLD * w0;
        walk.follow(
            &Inside(self.mesh),
            start,
            &mut exits,
            rng,
            Photon::new(x, dir, w0),
            threshold,
        );
    }
}

/// The closed mesh as a [`Volume`] of the walk (module docs: the safe distance, the layers of
/// overlapping sheets, re-entry).
pub(crate) struct Inside<'a>(pub &'a ClosedMesh);

/// Where a photon is with respect to the mesh's surfaces: the triangle it lies on (none after
/// a free flight) and the layers of the mesh around it (its winding number: 1 inside a simple
/// mesh).
pub(crate) struct Layers {
    on: Option<u32>,
    depth: u32,
}

/// The triangle a flight met and its outward normal.
pub(crate) struct Face {
    hit: Hit,
    n: DVec3,
}

impl Volume for Inside<'_> {
    type State = Layers;
    type Hit = Face;

    #[inline]
    fn flight(&self, st: &mut Layers, p: &mut Photon, s: f64) -> Flight<Face> {
        let mesh = self.0;
        let safe = if st.on.is_some() {
            0.0
        } else {
            match mesh.safe_distance(p.pos) {
                Some(d) => d,
                None => return Flight::Lost,
            }
        };
        if s >= safe {
            if let Some(hit) = mesh.first_hit(p.pos, p.dir, s, st.on) {
                p.pos += p.dir * hit.t;
                let n = mesh.normal(hit.tri);
                let cos_i = p.dir.dot(n);
                // Overlapping sheets (a scan's self-intersections: eyelids, lips): the medium
                // is where the winding number is positive, so a face crossed inward adds a
                // layer and one crossed outward with layers to spare removes it; only the last
                // layer's face is the boundary.
                if cos_i <= 0.0 || st.depth > 1 {
                    st.depth = if cos_i <= 0.0 {
                        st.depth + 1
                    } else {
                        st.depth - 1
                    };
                    st.on = Some(hit.tri);
                    return Flight::Through;
                }
                return Flight::Boundary {
                    hit: Face { hit, n },
                    cos_i,
                };
            }
        }
        st.on = None;
        Flight::Free
    }

    #[inline]
    fn reflect(&self, st: &mut Layers, p: &mut Photon, f: &Face, cos_i: f64) {
        p.dir = (p.dir - f.n * (2.0 * cos_i)).normalize();
        st.on = Some(f.hit.tri);
    }

    /// Outside: follows the refracted ray until it escapes or meets the mesh again, where it
    /// is reflected with probability F or re-enters.
    #[inline]
    fn leave(
        &self,
        st: &mut Layers,
        p: &mut Photon,
        f: &Face,
        cos_i: f64,
        cos_out: f64,
        eta: f64,
        rng: &mut Rng,
    ) -> Outside {
        let mesh = self.0;
        let n = f.n;
        let mut d = ((p.dir - n * cos_i) * eta + n * cos_out).normalize();
        let mut from = f.hit.tri;
        loop {
            let Some(h) = mesh.first_hit(p.pos, d, f64::INFINITY, Some(from)) else {
                return Outside::Escaped;
            };
            p.pos += d * h.t;
            let n = mesh.normal(h.tri);
            let cos_i = -d.dot(n);
            if cos_i <= 0.0 {
                return Outside::Lost;
            }
            let (f, cos_t) = fresnel(cos_i, eta);
            from = h.tri;
            if f > 0.0 && (f >= 1.0 || rng.uniform() < f) {
                d = (d + n * (2.0 * cos_i)).normalize();
                continue;
            }
            p.dir = refract_in(d, n, cos_i, cos_t, eta);
            *st = Layers {
                on: Some(h.tri),
                depth: 1,
            };
            return Outside::Reentered;
        }
    }
}

/// The mesh walk's books of one photon and the caller's exit scorer.
struct MeshScore<'s, F> {
    t: &'s mut MeshTally,
    score: &'s mut F,
}

impl<F: FnMut(&Exit)> Scoring<Inside<'_>> for MeshScore<'_, F> {
    #[inline]
    fn exit(&mut self, _: &Inside<'_>, p: &Photon, f: &Face, _: f64) {
        self.t.exits.add(p.weight);
        (self.score)(&Exit {
            point: p.pos,
            hit: f.hit,
            weight: p.weight,
        });
    }
    #[inline]
    fn capped(&mut self, w: f64) {
        self.t.capped.add(w);
    }
    #[inline]
    fn lost(&mut self, w: f64) {
        self.t.lost.add(w);
    }
    #[inline]
    fn reentered(&mut self, w: f64) {
        self.t.reentered.add(w);
    }
    #[inline]
    fn escaped(&mut self, w: f64) {
        self.t.escaped.add(w);
    }
    #[inline]
    fn done(&mut self, events: u64, absorbed: f64) {
        self.t.events += events;
        if absorbed != 0.0 {
            self.t.absorbed.add(absorbed);
        }
    }
}

/// The direction refracted into the medium (relative index η) of `d` arriving at outward normal
/// `n` with incidence cosine `cos_i` = −d·n and refracted cosine `cos_t`.
fn refract_in(d: DVec3, n: DVec3, cos_i: f64, cos_t: f64, eta: f64) -> DVec3 {
    let inv = 1.0 / eta;
    (d * inv + n * (cos_i * inv - cos_t)).normalize()
}

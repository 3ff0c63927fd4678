//! The photon walk inside a closed triangle mesh ([`ClosedMesh`]), lit by an isotropic point
//! light outside it: the probes' walk (`walk.rs`, `sphere.rs`) on arbitrary geometry.
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
//! **Inside.** Exponential free paths in σ_t, implicit absorption, Russian roulette relative
//! to the entry weight (`walk::ROULETTE_THRESHOLD`, `walk::ROULETTE_SURVIVAL`), Henyey–Greenstein
//! scattering (`phase.rs`), the event cap. A free flight shorter than the mesh's safe distance
//! needs no ray query. Where the mesh overlaps itself (a scan's eyelids and lips cross other
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
use super::phase::{rotate, sample_hg_cos};
use super::rng::Rng;
use super::walk::{ROULETTE_SURVIVAL, ROULETTE_THRESHOLD};
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
    sigma_t: f64,
    albedo: f64,
    g: f64,
    eta: f64,
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
        let (sigma_s, sigma_t) = m.checked_sigmas();
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
            sigma_t,
            albedo: sigma_s / sigma_t,
            g: m.g,
            eta: m.eta,
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
        let (f, cos_t) = fresnel(cos_i, self.eta);
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
        let dir = refract_in(d, n, cos_i, cos_t, self.eta);
        self.follow(rng, t, x, dir, w0, hit.tri, score);
    }

    /// Follows a photon that has just entered at `x` through triangle `tri`.
    #[allow(clippy::too_many_arguments)]
    fn follow(
        &self,
        rng: &mut Rng,
        t: &mut MeshTally,
        mut x: DVec3,
        mut u: DVec3,
        mut w: f64,
        tri: u32,
        score: &mut impl FnMut(&Exit),
    ) {
        let threshold = ROULETTE_THRESHOLD * w;
        let inv_eta = 1.0 / self.eta;
        let mut on: Option<u32> = Some(tri);
        // Layers of the mesh around the photon (its winding number): 1 inside a simple mesh.
        let mut depth: u32 = 1;
        let mut absorbed = 0.0;
        let mut events: u64 = 0;
        'walk: loop {
            events += 1;
            if events > self.max_events {
                t.capped.add(w);
                break;
            }
            let s = -rng.uniform_pos().ln() / self.sigma_t;
            let safe = if on.is_some() {
                0.0
            } else {
                match self.mesh.safe_distance(x) {
                    Some(d) => d,
                    None => {
                        t.lost.add(w);
                        break;
                    }
                }
            };
            if s >= safe {
                if let Some(hit) = self.mesh.first_hit(x, u, s, on) {
                    x += u * hit.t;
                    let n = self.mesh.normal(hit.tri);
                    let cos_i = u.dot(n);
                    // Overlapping sheets (a scan's self-intersections: eyelids, lips): the
                    // medium is where the winding number is positive, so a face crossed inward
                    // adds a layer and one crossed outward with layers to spare removes it; only
                    // the last layer's face is the boundary. Free paths are memoryless: the
                    // flight goes on from the crossing with a fresh length.
                    if cos_i <= 0.0 || depth > 1 {
                        depth = if cos_i <= 0.0 { depth + 1 } else { depth - 1 };
                        on = Some(hit.tri);
                        continue;
                    }
                    let (fr, cos_out) = fresnel(cos_i, inv_eta);
                    if fr > 0.0 && (fr >= 1.0 || rng.uniform() < fr) {
                        u = (u - n * (2.0 * cos_i)).normalize();
                        on = Some(hit.tri);
                        continue;
                    }
                    t.exits.add(w);
                    score(&Exit {
                        point: x,
                        hit,
                        weight: w,
                    });
                    // Outside: follow the refracted ray until it escapes or re-enters.
                    let mut d = (u - n * cos_i) * self.eta + n * cos_out;
                    d = d.normalize();
                    let mut from = hit.tri;
                    loop {
                        let Some(h) = self.mesh.first_hit(x, d, f64::INFINITY, Some(from)) else {
                            t.escaped.add(w);
                            break 'walk;
                        };
                        x += d * h.t;
                        let n = self.mesh.normal(h.tri);
                        let cos_i = -d.dot(n);
                        if cos_i <= 0.0 {
                            t.lost.add(w);
                            break 'walk;
                        }
                        let (f, cos_t) = fresnel(cos_i, self.eta);
                        from = h.tri;
                        if f > 0.0 && (f >= 1.0 || rng.uniform() < f) {
                            d = (d + n * (2.0 * cos_i)).normalize();
                            continue;
                        }
                        t.reentered.add(w);
                        u = refract_in(d, n, cos_i, cos_t, self.eta);
                        on = Some(h.tri);
                        depth = 1;
                        continue 'walk;
                    }
                }
            }
            x += u * s;
            on = None;
            absorbed += w * (1.0 - self.albedo);
            w *= self.albedo;
            if w < threshold {
                if w == 0.0 || rng.uniform() >= ROULETTE_SURVIVAL {
                    absorbed += w;
                    break;
                }
                w /= ROULETTE_SURVIVAL;
            }
            let ct = sample_hg_cos(self.g, rng.uniform());
            let phi = 2.0 * PI * rng.uniform();
            u = DVec3::from_array(rotate(u.to_array(), ct, phi));
        }
        t.events += events.min(self.max_events);
        if absorbed != 0.0 {
            t.absorbed.add(absorbed);
        }
    }
}

/// The direction refracted into the medium (relative index η) of `d` arriving at outward normal
/// `n` with incidence cosine `cos_i` = −d·n and refracted cosine `cos_t`.
fn refract_in(d: DVec3, n: DVec3, cos_i: f64, cos_t: f64, eta: f64) -> DVec3 {
    let inv = 1.0 / eta;
    (d * inv + n * (cos_i * inv - cos_t)).normalize()
}

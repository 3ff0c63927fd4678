//! The light a model returns to itself, per vertex: what of its own lit surface each vertex
//! sees. Light leaving the skin lands on the skin again — under the chin from the neck, in the
//! eye sockets from the cheeks and the nose, on the cheek beside the nose — and lights the
//! parts the key light's shadow leaves black (the face truth's energy books: a tenth of the
//! light that leaves the head comes back to it). A model that shades one point at a time adds
//! it as a dim fill (`returned_irradiance`, common.wgsl).
//!
//! A vertex sees, along a cosine-distributed ray, a point of the surface with normal n_h
//! (faced toward the vertex). Under a distant light along l of irradiance E, that point
//! leaves about A·E·max(n_h·l, 0) (A the medium's diffuse reflectance), so the vertex receives
//! A·E·g(l), g(l) = ⟨max(n_h·l, 0)⟩ over its rays (a ray that meets nothing gives 0). Stored
//! per vertex as g's first two spherical-harmonic bands over l, exact for max(x, 0) in the
//! mean over the sphere: g(l) ≈ max(¼·F + ½·s·l, 0), F the fraction of rays that meet the
//! model (its self view factor) and s the sum of the normals they meet over the ray count —
//! [`Vertex::bounce`] = (s, F); s turns with the skin.
//!
//! The seen point is taken as lit wherever it faces the light: its own shadow is not tested.
//! Tested (each seen point's sky cast again, its open fraction and mean open direction taken
//! into the bands) the face scored worse under every light of the sweep (the named back
//! light 0.138 against 0.129 on the strict bar, 0.257 against 0.225 on the wide; a second
//! bounce added to that changed 0.002): skin in its own shadow still glows — light diffuses
//! into the shadow and round the terminator — so the geometric shadow is too hard a cut.
//!
//! Cast at load through the thickness's BVH ([`Caster`]), over each mesh's primitives
//! together, on every core: [`RAYS`] rays per vertex in the same directions about every
//! vertex's normal (deterministic, and smooth across the mesh). Hits nearer than a few edge
//! lengths are the surface's own facets, not another part of it (light exchanged that close
//! is the diffusion's).

use glam::Vec3;

use super::thickness::Caster;
use super::Primitive;

/// Rays per vertex, cosine-distributed over the hemisphere (Malley: a Fibonacci spiral on
/// the unit disc lifted onto the hemisphere).
pub const RAYS: usize = 32;
/// Hits nearer than this many mean edge lengths are not counted.
const LOCAL_EDGES: f32 = 4.0;

/// Gives every vertex of `primitives` (one mesh, its own space) its [`Vertex::bounce`]
/// (module docs).
///
/// [`Vertex::bounce`]: super::Vertex::bounce
pub fn fill(primitives: &mut [Primitive]) {
    let (caster, diagonal) = Caster::of_mesh(primitives);
    if diagonal <= 0.0 {
        return;
    }
    let t_min = (LOCAL_EDGES * caster.mean_edge()).max(1e-4 * diagonal);
    let points: Vec<(Vec3, Vec3)> = primitives
        .iter()
        .flat_map(|p| &p.vertices)
        .map(|v| (Vec3::from_array(v.position), Vec3::from_array(v.normal)))
        .collect();
    let disc = cosine_directions();
    let bounces = in_parallel(&points, |&(at, n)| {
        n.try_normalize()
            .map_or([0.0; 4], |n| of_vertex(&caster, &disc, at, n, t_min))
    });
    let mut bounces = bounces.into_iter();
    for p in primitives.iter_mut() {
        for v in &mut p.vertices {
            v.bounce = bounces.next().unwrap_or_default();
        }
    }
}

/// `f` over `items` on the machine's cores, in order.
fn in_parallel<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = items.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        let parts: Vec<_> = items
            .chunks(chunk)
            .map(|part| scope.spawn(|| part.iter().map(&f).collect::<Vec<R>>()))
            .collect();
        parts
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    })
}

/// [`RAYS`] directions about +z, cosine-distributed.
fn cosine_directions() -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..RAYS)
        .map(|i| {
            let r = ((i as f32 + 0.5) / RAYS as f32).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt())
        })
        .collect()
}

/// (s, F) at the point `at` with unit normal `n` (module docs).
fn of_vertex(caster: &Caster, disc: &[Vec3], at: Vec3, n: Vec3, t_min: f32) -> [f32; 4] {
    let (u, w) = n.any_orthonormal_pair();
    let (mut sum, mut met) = (Vec3::ZERO, 0usize);
    for d in disc {
        let dir = (u * d.x + w * d.y + n * d.z).normalize();
        if let Some((_, t)) = caster.first(at, dir, t_min) {
            // The side of the surface the vertex sees faces it.
            let seen = caster.normal(t);
            sum += if seen.dot(dir) > 0.0 { -seen } else { seen };
            met += 1;
        }
    }
    let s = sum / RAYS as f32;
    [s.x, s.y, s.z, met as f32 / RAYS as f32]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::shapes::{plane_model, sphere_model};

    fn bounces(m: &mut crate::asset::Model) -> Vec<[f32; 4]> {
        let prims = &mut m.meshes[0].primitives;
        fill(prims);
        prims[0].vertices.iter().map(|v| v.bounce).collect()
    }

    #[test]
    fn a_convex_model_returns_nothing_to_itself() {
        for mut m in [sphere_model(0.05, 0.1), plane_model(0.1, 0.004)] {
            for b in bounces(&mut m) {
                assert!(b.iter().all(|c| c.abs() < 1e-6), "{b:?}");
            }
        }
    }

    #[test]
    fn a_vertex_in_a_fold_sees_the_other_side() {
        // Two squares at right angles (an open book, the spine along z): a vertex on one
        // page sees the other, whose normal faces it; rays toward the spine's far side miss.
        use crate::asset::{Aabb, Vertex};
        let a = 0.1f32;
        let v = |p: Vec3, n: Vec3| Vertex {
            position: p.to_array(),
            normal: n.to_array(),
            ..Default::default()
        };
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        // Page 1 in the plane y = 0 (x ≥ 0, normal +y); page 2 in x = 0 (y ≥ 0, normal +x).
        let n = 8;
        for page in 0..2 {
            let base = vertices.len() as u32;
            for i in 0..=n {
                for k in 0..=n {
                    let (s, t) = (a * i as f32 / n as f32, a * (k as f32 / n as f32 - 0.5));
                    let (p, nrm) = match page {
                        0 => (Vec3::new(s, 0.0, t), Vec3::Y),
                        _ => (Vec3::new(0.0, s, t), Vec3::X),
                    };
                    vertices.push(v(p, nrm));
                }
            }
            for i in 0..n {
                for k in 0..n {
                    let c = base + (i * (n + 1) + k) as u32;
                    let d = c + (n + 1) as u32;
                    indices.extend([c, d, c + 1, c + 1, d, d + 1]);
                }
            }
        }
        let mut prims = [Primitive {
            vertices,
            indices,
            material: None,
            bounds: Aabb {
                min: Vec3::new(0.0, 0.0, -a),
                max: Vec3::new(a, a, a),
            },
        }];
        fill(&mut prims);
        // A vertex in the middle of page 1, away from the spine: it sees page 2 (normal +x)
        // over part of its sky, none of its own page.
        let mid = prims[0]
            .vertices
            .iter()
            .find(|v| (v.position[0] - 0.5 * a).abs() < 1e-6 && v.position[2].abs() < 1e-6)
            .unwrap();
        let [sx, sy, sz, f] = mid.bounce;
        assert!(f > 0.1 && f < 0.6, "{:?}", mid.bounce);
        // What it sees faces +x: lit along +x, page 2 glows toward it; along −x, it is dark.
        assert!(
            sx > 0.9 * f && sy.abs() < 0.2 * f && sz.abs() < 0.2 * f,
            "{:?}",
            mid.bounce
        );
        let g = |l: Vec3| (0.25 * f + 0.5 * Vec3::new(sx, sy, sz).dot(l)).max(0.0);
        assert!(
            g(Vec3::X) > 0.5 * f && g(-Vec3::X) < 0.05 * f,
            "{:?}",
            mid.bounce
        );
    }
}

//! Thickness per vertex for meshes that do not give it (no `_THICKNESS` attribute): the
//! distance from the vertex along its inward normal to the mesh's other side, by one ray per
//! vertex cast at load through a bounding-volume hierarchy of the mesh's triangles (all its
//! primitives: an ear's other side may be another primitive; `obvhs`' compressed wide BVH, the
//! one the face truth walks). The shading models read it as
//! the material's thickness through the point (translucency's slab, the OSS depth).
//!
//! A ray that meets nothing (an open mesh, a single-sided sheet) takes the median of the
//! vertices whose rays did; a mesh where none did keeps [`DEFAULT_THICKNESS_M`]. Units are the
//! mesh's own (metres for a file in glTF's units; the vertex shader scales it with the skin).

use std::time::Duration;

use glam::{Vec3, Vec3A};
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;

use super::{Primitive, DEFAULT_THICKNESS_M};

/// Hits nearer than this fraction of the mesh's diagonal are the vertex's own triangles.
const SELF_HIT: f32 = 1e-5;
/// Barycentric tolerance: a ray through a shared edge hits one of its triangles rather than
/// slipping between them.
const EDGE_EPS: f32 = 1e-6;

/// Triangles in `obvhs`' compressed wide BVH with their outward normals, for where a ray
/// that starts inside the medium leaves it.
pub struct Caster {
    tris: Vec<[Vec3; 3]>,
    outward: Vec<Vec3>,
    bvh: Option<CwBvh>,
}

impl Caster {
    /// `tris` with, per triangle, a direction on its outward side (the sum of its vertices'
    /// normals): its winding may be either way.
    pub fn new(tris: Vec<[Vec3; 3]>, outward_hint: &[Vec3]) -> Self {
        let outward = tris
            .iter()
            .zip(outward_hint)
            .map(|(t, h)| {
                let n = (t[1] - t[0]).cross(t[2] - t[0]);
                if n.dot(*h) < 0.0 {
                    -n
                } else {
                    n
                }
            })
            .collect();
        let bvh = (!tris.is_empty()).then(|| {
            let prims: Vec<Triangle> = tris
                .iter()
                .map(|t| Triangle {
                    v0: t[0].into(),
                    v1: t[1].into(),
                    v2: t[2].into(),
                })
                .collect();
            build_cwbvh_from_tris(
                &prims,
                BvhBuildParams::fast_build(),
                &mut Duration::default(),
            )
        });
        Self { tris, outward, bvh }
    }

    /// The triangles of all of `primitives` (one mesh; each triangle's outward side by its
    /// vertices' normals), and the diagonal of their bounds.
    pub fn of_mesh(primitives: &[Primitive]) -> (Self, f32) {
        let (mut tris, mut outward) = (Vec::new(), Vec::new());
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in primitives {
            let at = |i: u32| Vec3::from_array(p.vertices[i as usize].position);
            let nrm = |i: u32| Vec3::from_array(p.vertices[i as usize].normal);
            for t in p.indices.chunks_exact(3) {
                tris.push([at(t[0]), at(t[1]), at(t[2])]);
                outward.push(nrm(t[0]) + nrm(t[1]) + nrm(t[2]));
            }
            lo = lo.min(p.bounds.min);
            hi = hi.max(p.bounds.max);
        }
        let diagonal = if tris.is_empty() {
            0.0
        } else {
            (hi - lo).length()
        };
        (Self::new(tris, &outward), diagonal)
    }

    /// The triangles' mean edge length (0 without triangles).
    pub fn mean_edge(&self) -> f32 {
        let sum: f32 = self
            .tris
            .iter()
            .map(|t| (t[1] - t[0]).length() + (t[2] - t[1]).length() + (t[0] - t[2]).length())
            .sum();
        sum / (3 * self.tris.len()).max(1) as f32
    }

    /// Where the ray `origin + t·dir` (unit `dir`, starting just inside the medium) leaves it,
    /// t > `t_min`: the medium is where the winding number is positive, so a layer the ray
    /// enters (a scan overlapping itself at an eyelid or a lip) must be left too. `None` where
    /// the ray meets nothing; the first face it leaves through where the count never closes
    /// (an open mesh).
    pub fn exit(&self, origin: Vec3, dir: Vec3, t_min: f32) -> Option<f32> {
        let bvh = self.bvh.as_ref()?;
        let ray = ray(origin, dir, t_min);
        let mut hits = Vec::new();
        let mut rh = RayHit::none();
        bvh.ray_traverse(ray, &mut rh, |_, id| {
            let i = bvh.primitive_indices[id] as usize;
            if let Some(d) = hit(&self.tris[i], origin, dir).filter(|d| *d > t_min) {
                hits.push((d, self.outward[i].dot(dir) > 0.0));
            }
            f32::INFINITY
        });
        hits.sort_by(|a, b| a.0.total_cmp(&b.0));
        // A ray through an edge or a vertex meets every triangle there at the same distance:
        // one crossing.
        hits.dedup_by(|b, a| a.1 == b.1 && b.0 - a.0 <= t_min);
        let mut depth = 1i32;
        for &(d, leaving) in &hits {
            depth += if leaving { -1 } else { 1 };
            if depth == 0 {
                return Some(d);
            }
        }
        hits.iter().find(|h| h.1).map(|h| h.0)
    }
}

impl Caster {
    /// The first triangle the ray `origin + t·dir` (unit `dir`) meets at t > `t_min`: its
    /// distance and its index (in the order given to [`Caster::new`]).
    pub fn first(&self, origin: Vec3, dir: Vec3, t_min: f32) -> Option<(f32, usize)> {
        let bvh = self.bvh.as_ref()?;
        let ray = ray(origin, dir, t_min);
        let mut rh = RayHit::none();
        let met = bvh.ray_traverse(ray, &mut rh, |_, id| {
            let i = bvh.primitive_indices[id] as usize;
            hit(&self.tris[i], origin, dir)
                .filter(|d| *d > t_min)
                .unwrap_or(f32::INFINITY)
        });
        met.then(|| {
            (
                rh.t,
                bvh.primitive_indices[rh.primitive_id as usize] as usize,
            )
        })
    }

    /// Triangle `i`'s unit normal on its outward side.
    pub fn normal(&self, i: usize) -> Vec3 {
        self.outward[i].normalize_or_zero()
    }
}

/// The ray `origin + t·dir`, t > `t_min`. (−0 components made +0: obvhs takes a direction's
/// octant from its sign bits, and an axis-aligned ray with a −0 missed the box it starts on.)
fn ray(origin: Vec3, dir: Vec3, t_min: f32) -> Ray {
    Ray::new(
        Vec3A::from(origin),
        Vec3A::from(dir + Vec3::ZERO),
        t_min,
        f32::INFINITY,
    )
}

/// Möller–Trumbore, both faces: the distance along `dir` to the triangle, if the line meets it.
fn hit(t: &[Vec3; 3], origin: Vec3, dir: Vec3) -> Option<f32> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    // A sliver (its corner angles below ~1e-6 rad) or a ray along its plane: f32 cannot
    // place the hit.
    let area = e1.cross(e2).length();
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if area <= 1e-6 * e1.length() * e2.length() || det.abs() <= 1e-6 * area {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - t[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if u < -EDGE_EPS || v < -EDGE_EPS || u + v > 1.0 + EDGE_EPS {
        return None;
    }
    Some(e2.dot(q) * inv)
}

/// The thickness at each of `points` (with unit outward `normals`) through the triangles
/// `bvh` holds: the distance along −normal to where the medium ends ([`Caster::exit`]).
pub fn cast(bvh: &Caster, points: &[Vec3], normals: &[Vec3], diagonal: f32) -> Vec<Option<f32>> {
    let t_min = SELF_HIT * diagonal;
    points
        .iter()
        .zip(normals)
        .map(|(&p, &n)| {
            let dir = -n.try_normalize()?;
            bvh.exit(p, dir, t_min)
        })
        .collect()
}

/// Gives every vertex of the primitives whose `given[i]` is false a thickness cast through
/// all of `primitives`' triangles (module docs).
pub fn fill(primitives: &mut [Primitive], given: &[bool]) {
    if primitives.iter().zip(given).all(|(_, g)| *g) {
        return;
    }
    let (bvh, diagonal) = Caster::of_mesh(primitives);
    let mut cast_all = Vec::new();
    for (p, _) in primitives.iter().zip(given).filter(|(_, g)| !**g) {
        let points: Vec<Vec3> = p
            .vertices
            .iter()
            .map(|v| Vec3::from_array(v.position))
            .collect();
        let normals: Vec<Vec3> = p
            .vertices
            .iter()
            .map(|v| Vec3::from_array(v.normal))
            .collect();
        cast_all.push(cast(&bvh, &points, &normals, diagonal));
    }
    let mut hits: Vec<f32> = cast_all.iter().flatten().flatten().copied().collect();
    let fallback = if hits.is_empty() {
        DEFAULT_THICKNESS_M
    } else {
        let mid = hits.len() / 2;
        *hits.select_nth_unstable_by(mid, f32::total_cmp).1
    };
    let missing = primitives.iter_mut().zip(given).filter(|(_, g)| !**g);
    for ((p, _), cast) in missing.zip(cast_all) {
        for (v, t) in p.vertices.iter_mut().zip(cast) {
            v.thickness = t.unwrap_or(fallback);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::shapes::{plane_model, sphere_model};

    /// The closed box [−a, a] × [−b, b] × [−c, c] as twelve triangles.
    fn slab(a: f32, b: f32, c: f32) -> Vec<[Vec3; 3]> {
        let corner = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { -a } else { a },
                if i & 2 == 0 { -b } else { b },
                if i & 4 == 0 { -c } else { c },
            )
        };
        let faces = [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ];
        faces
            .iter()
            .flat_map(|f| {
                [
                    [corner(f[0]), corner(f[1]), corner(f[2])],
                    [corner(f[0]), corner(f[2]), corner(f[3])],
                ]
            })
            .collect()
    }

    #[test]
    fn a_slab_is_as_thick_as_it_is_and_a_ray_out_of_it_meets_nothing() {
        let tris = slab(0.05, 0.003, 0.04);
        // The box's faces point away from its centre.
        let outward: Vec<Vec3> = tris.iter().map(|t| t[0] + t[1] + t[2]).collect();
        let bvh = Caster::new(tris, &outward);
        // Through the 6 mm face, from the top and from the bottom (away from the edges).
        let t = cast(
            &bvh,
            &[Vec3::new(0.01, 0.003, 0.02), Vec3::new(-0.02, -0.003, 0.0)],
            &[Vec3::Y, -Vec3::Y],
            0.13,
        );
        for got in t {
            let got = got.expect("the other face");
            assert!((got - 0.006).abs() < 1e-6, "{got}");
        }
        // Across its 10 cm length; and outward from a face nothing is met.
        let across = bvh.exit(Vec3::new(0.05, 0.0, 0.0), -Vec3::X, 1e-6);
        assert!((across.unwrap() - 0.1).abs() < 1e-6);
        assert_eq!(bvh.exit(Vec3::new(0.0, 0.003, 0.0), Vec3::Y, 1e-6), None);
    }

    #[test]
    fn a_spheres_thickness_is_its_diameter_at_every_vertex() {
        let r = 0.03;
        let mut model = sphere_model(r, 1.0);
        let prims = &mut model.meshes[0].primitives;
        fill(prims, &[false]);
        for v in &prims[0].vertices {
            // The tessellated sphere's chord through the centre: within its facets' sag.
            assert!(
                (v.thickness - 2.0 * r).abs() < 0.01 * r,
                "{} at {:?} n {:?}",
                v.thickness,
                v.position,
                v.normal
            );
        }
    }

    #[test]
    fn a_layer_the_ray_enters_is_left_too() {
        // Two spheres of radius r overlapping, centres r apart along x (one mesh in two
        // primitives, as a scan overlapping itself): from the first's leftmost point inward
        // the ray enters the second at x = 0 and leaves the union at x = 2r, not at x = r.
        let r = 0.02;
        let mut model = sphere_model(r, 1.0);
        let first = model.meshes[0].primitives.remove(0);
        let mut second = first.clone();
        for v in &mut second.vertices {
            v.position[0] += r;
        }
        second.bounds.min.x += r;
        second.bounds.max.x += r;
        let mut prims = [first, second];
        fill(&mut prims, &[false, false]);
        let left = prims[0]
            .vertices
            .iter()
            .min_by(|a, b| a.position[0].total_cmp(&b.position[0]))
            .unwrap();
        assert!(
            (left.thickness - 3.0 * r).abs() < 0.01 * r,
            "{}",
            left.thickness
        );
    }

    #[test]
    fn given_thickness_is_kept_and_a_sheet_keeps_the_default() {
        let mut model = sphere_model(0.03, 0.123);
        let prims = &mut model.meshes[0].primitives;
        fill(prims, &[true]);
        assert!(prims[0].vertices.iter().all(|v| v.thickness == 0.123));
        // A single-sided sheet: no ray meets another side.
        let mut sheet = plane_model(0.1, 0.5);
        let sheets = &mut sheet.meshes[0].primitives;
        fill(sheets, &[false]);
        assert!(sheets[0]
            .vertices
            .iter()
            .all(|v| v.thickness == DEFAULT_THICKNESS_M));
    }
}

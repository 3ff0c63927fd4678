//! Thickness per vertex for meshes that do not give it (no `_THICKNESS` attribute): the
//! distance from the vertex along its inward normal to the mesh's other side, by one ray per
//! vertex cast at load through a bounding-volume hierarchy of the mesh's triangles (all its
//! primitives: an ear's other side may be another primitive). The shading models read it as
//! the material's thickness through the point (translucency's slab, the OSS depth).
//!
//! A ray that meets nothing (an open mesh, a single-sided sheet) takes the median of the
//! vertices whose rays did; a mesh where none did keeps [`DEFAULT_THICKNESS_M`]. Units are the
//! mesh's own (metres for a file in glTF's units; the vertex shader scales it with the skin).

use glam::Vec3;

use super::{Primitive, DEFAULT_THICKNESS_M};

/// Triangles per leaf of the hierarchy.
const LEAF: usize = 4;
/// Hits nearer than this fraction of the mesh's diagonal are the vertex's own triangles.
const SELF_HIT: f32 = 1e-5;
/// Barycentric tolerance: a ray through a shared edge hits one of its triangles rather than
/// slipping between them.
const EDGE_EPS: f32 = 1e-6;

/// A node of the hierarchy: its box and either two children (`count == 0`: the left one
/// follows it, `right` is the other) or `count` triangles of the order from `start`.
#[derive(Clone, Copy)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    start: u32,
    count: u32,
    right: u32,
}

/// A bounding-volume hierarchy over triangles, median split on the longest axis.
pub struct Bvh {
    tris: Vec<[Vec3; 3]>,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    pub fn new(tris: Vec<[Vec3; 3]>) -> Self {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * tris.len() / LEAF + 1),
            order: (0..tris.len() as u32).collect(),
            tris,
        };
        if !bvh.tris.is_empty() {
            let centroids: Vec<Vec3> = bvh.tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
            bvh.build(0, bvh.tris.len(), &centroids);
        }
        bvh
    }

    fn build(&mut self, start: usize, end: usize, centroids: &[Vec3]) -> usize {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &t in &self.order[start..end] {
            for p in self.tris[t as usize] {
                lo = lo.min(p);
                hi = hi.max(p);
            }
            clo = clo.min(centroids[t as usize]);
            chi = chi.max(centroids[t as usize]);
        }
        let index = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            start: start as u32,
            count: (end - start) as u32,
            right: 0,
        });
        let extent = chi - clo;
        if end - start <= LEAF || extent.max_element() <= 0.0 {
            return index;
        }
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = start + (end - start) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |a, b| {
            centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis])
        });
        self.build(start, mid, centroids);
        let right = self.build(mid, end, centroids);
        let node = &mut self.nodes[index];
        node.count = 0;
        node.right = right as u32;
        index
    }

    /// The distance to the nearest triangle the ray `origin + t·dir` (unit `dir`) meets with
    /// `t > t_min`, if any.
    pub fn nearest(&self, origin: Vec3, dir: Vec3, t_min: f32) -> Option<f32> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best = f32::INFINITY;
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            let node = self.nodes[i as usize];
            // Slab test (an infinite `inv` component gives ±inf or NaN, which min/max drop).
            let a = (node.lo - origin) * inv;
            let b = (node.hi - origin) * inv;
            let near = a.min(b).max_element().max(t_min);
            let far = a.max(b).min_element().min(best);
            if near > far {
                continue;
            }
            if node.count == 0 {
                stack.push(node.right);
                stack.push(i + 1);
                continue;
            }
            let (s, n) = (node.start as usize, node.count as usize);
            for &t in &self.order[s..s + n] {
                if let Some(d) = hit(&self.tris[t as usize], origin, dir) {
                    if d > t_min && d < best {
                        best = d;
                    }
                }
            }
        }
        best.is_finite().then_some(best)
    }
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
/// `bvh` holds: the distance to the first triangle along −normal, `None` where there is none.
pub fn cast(bvh: &Bvh, points: &[Vec3], normals: &[Vec3], diagonal: f32) -> Vec<Option<f32>> {
    let t_min = SELF_HIT * diagonal;
    points
        .iter()
        .zip(normals)
        .map(|(&p, &n)| {
            let dir = -n.try_normalize()?;
            bvh.nearest(p, dir, t_min)
        })
        .collect()
}

/// Gives every vertex of the primitives whose `given[i]` is false a thickness cast through
/// all of `primitives`' triangles (module docs).
pub fn fill(primitives: &mut [Primitive], given: &[bool]) {
    if primitives.iter().zip(given).all(|(_, g)| *g) {
        return;
    }
    let mut tris = Vec::new();
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in primitives.iter() {
        let at = |i: u32| Vec3::from_array(p.vertices[i as usize].position);
        for t in p.indices.chunks_exact(3) {
            tris.push([at(t[0]), at(t[1]), at(t[2])]);
        }
        lo = lo.min(p.bounds.min);
        hi = hi.max(p.bounds.max);
    }
    let bvh = Bvh::new(tris);
    let diagonal = (hi - lo).length();
    let mut cast_all = Vec::new();
    for (p, _) in primitives.iter().zip(given).filter(|(_, g)| !**g) {
        let points: Vec<Vec3> = p.vertices.iter().map(|v| Vec3::from_array(v.position)).collect();
        let normals: Vec<Vec3> = p.vertices.iter().map(|v| Vec3::from_array(v.normal)).collect();
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
        let bvh = Bvh::new(slab(0.05, 0.003, 0.04));
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
        let across = bvh.nearest(Vec3::new(0.05, 0.0, 0.0), -Vec3::X, 1e-6);
        assert!((across.unwrap() - 0.1).abs() < 1e-6);
        assert_eq!(bvh.nearest(Vec3::new(0.0, 0.003, 0.0), Vec3::Y, 1e-6), None);
    }

    #[test]
    fn a_spheres_thickness_is_its_diameter_at_every_vertex() {
        let r = 0.03;
        let mut model = sphere_model(r, 1.0);
        let prims = &mut model.meshes[0].primitives;
        fill(prims, &[false]);
        for v in &prims[0].vertices {
            // The tessellated sphere's chord through the centre: within its facets' sag.
            assert!((v.thickness - 2.0 * r).abs() < 0.01 * r, "{} at {:?} n {:?}", v.thickness, v.position, v.normal);
        }
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
        assert!(sheets[0].vertices.iter().all(|v| v.thickness == DEFAULT_THICKNESS_M));
    }
}

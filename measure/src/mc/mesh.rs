//! A closed triangle mesh as the boundary of a Monte Carlo medium: ray queries through a BVH
//! (`obvhs`' compressed wide BVH, f32 boxes) with the triangle tests in f64, and a voxel grid
//! of safe distances (`mesh_grid.rs`) so that most free flights deep inside need no ray query.
//!
//! **Units.** Whatever the caller gives; the Monte Carlo passes millimetres (σ in mm⁻¹).

use std::time::Duration;

use glam::{DVec3, Vec3A};
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;

use super::mesh_grid::SafeGrid;
pub use super::mesh_grid::{DistanceField, MAX_SAFE_VOXELS};

/// Edge tolerance of the f64 triangle test (barycentric units): rays through a shared edge hit
/// both triangles rather than slipping between them.
const EDGE_EPS: f64 = 1e-10;

/// A ray's first crossing of the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f64,
    /// Triangle index.
    pub tri: u32,
    /// Barycentric weights of the triangle's second and third vertices.
    pub b1: f64,
    pub b2: f64,
}

/// A closed, outward-wound triangle mesh ready for ray queries (see the module docs).
pub struct ClosedMesh {
    positions: Vec<DVec3>,
    vertex_normals: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Unit outward geometric normal per triangle.
    normals: Vec<DVec3>,
    bvh: CwBvh,
    grid: SafeGrid,
    /// Bounding box of the vertices.
    pub lo: DVec3,
    pub hi: DVec3,
    /// Bounding sphere (centre, radius) of the vertices.
    pub centre: DVec3,
    pub radius: f64,
    /// Surface area.
    pub area: f64,
}

impl ClosedMesh {
    /// The mesh from vertex positions, vertex normals (for shading only) and triangles wound
    /// counter-clockwise seen from outside; `voxel` is the safe grid's cell side (same units).
    /// Refuses degenerate input (no triangles, an index out of range, a non-finite position).
    pub fn new(
        positions: Vec<DVec3>,
        vertex_normals: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        voxel: f64,
    ) -> Result<Self, String> {
        if triangles.is_empty() || positions.len() != vertex_normals.len() {
            return Err("mesh: no triangles, or normals and positions differ in count".into());
        }
        if positions.iter().any(|p| !p.is_finite()) || !(voxel > 0.0 && voxel.is_finite()) {
            return Err("mesh: a position or the voxel size is not finite".into());
        }
        if triangles
            .iter()
            .flatten()
            .any(|&i| i as usize >= positions.len())
        {
            return Err("mesh: a triangle's vertex index is out of range".into());
        }
        let mut area = 0.0;
        let normals = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                let n = (b - a).cross(c - a);
                area += 0.5 * n.length();
                n.normalize_or_zero()
            })
            .collect();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let centre = 0.5 * (lo + hi);
        let radius = positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0, f64::max);
        let tris: Vec<Triangle> = triangles
            .iter()
            .map(|t| {
                let [v0, v1, v2] = t.map(|i| Vec3A::from(positions[i as usize].as_vec3()));
                Triangle { v0, v1, v2 }
            })
            .collect();
        let bvh = build_cwbvh_from_tris(
            &tris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let grid = SafeGrid::build(&positions, &triangles, lo, hi, voxel);
        Ok(Self {
            positions,
            vertex_normals: vertex_normals
                .into_iter()
                .map(|n| n.normalize_or_zero())
                .collect(),
            triangles,
            normals,
            bvh,
            grid,
            lo,
            hi,
            centre,
            radius,
            area,
        })
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Unit outward geometric normal of triangle `tri`.
    pub fn normal(&self, tri: u32) -> DVec3 {
        self.normals[tri as usize]
    }

    /// The vertex normals interpolated at a hit (unit; the geometric normal where they cancel).
    pub fn shading_normal(&self, hit: &Hit) -> DVec3 {
        let [a, b, c] = self.triangles[hit.tri as usize].map(|i| self.vertex_normals[i as usize]);
        let n = a * (1.0 - hit.b1 - hit.b2) + b * hit.b1 + c * hit.b2;
        n.try_normalize().unwrap_or(self.normals[hit.tri as usize])
    }

    /// Möller–Trumbore in f64: (t, b1, b2) when `d` crosses triangle `tri` at t > 0.
    #[inline]
    fn intersect(&self, tri: usize, o: DVec3, d: DVec3) -> Option<(f64, f64, f64)> {
        let [a, b, c] = self.triangles[tri].map(|i| self.positions[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let s = o - a;
        let b1 = s.dot(p) * inv;
        if !(-EDGE_EPS..=1.0 + EDGE_EPS).contains(&b1) {
            return None;
        }
        let q = s.cross(e1);
        let b2 = d.dot(q) * inv;
        if b2 < -EDGE_EPS || b1 + b2 > 1.0 + EDGE_EPS {
            return None;
        }
        let t = e2.dot(q) * inv;
        (t > 0.0).then_some((t, b1, b2))
    }

    /// The first crossing of the ray `o + t·d` (d unit) with 0 < t ≤ `tmax`, ignoring triangle
    /// `skip` (the one the ray starts on, if any).
    pub fn first_hit(&self, o: DVec3, d: DVec3, tmax: f64, skip: Option<u32>) -> Option<Hit> {
        let ray = Ray::new(
            Vec3A::from(o.as_vec3()),
            Vec3A::from(d.as_vec3()),
            0.0,
            if tmax.is_finite() {
                (tmax * (1.0 + 1e-5) + 1e-5) as f32
            } else {
                f32::INFINITY
            },
        );
        let mut best: Option<Hit> = None;
        let mut rh = RayHit::none();
        self.bvh.ray_traverse(ray, &mut rh, |_, id| {
            let tri = self.bvh.primitive_indices[id];
            if Some(tri) == skip {
                return f32::INFINITY;
            }
            match self.intersect(tri as usize, o, d) {
                Some((t, b1, b2)) if t <= tmax && best.is_none_or(|h| t < h.t) => {
                    best = Some(Hit { t, tri, b1, b2 });
                    t as f32
                }
                _ => f32::INFINITY,
            }
        });
        best
    }

    /// Whether anything but triangle `skip` lies on the ray within 0 < t < `tmax`.
    pub fn occluded(&self, o: DVec3, d: DVec3, tmax: f64, skip: Option<u32>) -> bool {
        let ray = Ray::new(
            Vec3A::from(o.as_vec3()),
            Vec3A::from(d.as_vec3()),
            0.0,
            tmax as f32,
        );
        !self.bvh.ray_traverse_miss(ray, |_, id| {
            let tri = self.bvh.primitive_indices[id];
            if Some(tri) == skip {
                return f32::INFINITY;
            }
            match self.intersect(tri as usize, o, d) {
                Some((t, _, _)) if t < tmax => t as f32,
                _ => f32::INFINITY,
            }
        })
    }

    /// A distance from `p` within which the surface certainly is not (0 near the surface);
    /// `None` when `p` is outside the mesh (or its grid).
    #[inline]
    pub fn safe_distance(&self, p: DVec3) -> Option<f64> {
        self.grid.safe_distance(p)
    }

    /// Whether `p` is inside the mesh: the first crossing along a fixed direction leaves it.
    pub fn contains(&self, p: DVec3) -> bool {
        if self.grid.outside(p) {
            return false;
        }
        let d = DVec3::new(0.267, 0.534, 0.802).normalize();
        self.first_hit(p, d, f64::INFINITY, None)
            .is_some_and(|h| d.dot(self.normals[h.tri as usize]) > 0.0)
    }

    /// Enclosed volume (positive for outward winding).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Fractions of the grid's voxels that are (outside, surface, inside) — a build check.
    pub fn grid_fractions(&self) -> (f64, f64, f64) {
        self.grid.fractions()
    }
}

/// A closed UV sphere of radius `r` centred at the origin (`rings` ≥ 2 latitude bands,
/// `segments` ≥ 3 longitudes), outward wound, with its exact normals: the test mesh of the walk.
pub fn uv_sphere(r: f64, rings: u32, segments: u32) -> (Vec<DVec3>, Vec<DVec3>, Vec<[u32; 3]>) {
    let mut normals = vec![DVec3::Z];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            normals.push(DVec3::new(
                th.sin() * ph.cos(),
                th.sin() * ph.sin(),
                th.cos(),
            ));
        }
    }
    normals.push(-DVec3::Z);
    let south = normals.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut tris = Vec::new();
    for j in 0..segments {
        tris.push([0, ring(1, j), ring(1, j + 1)]);
        tris.push([south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            tris.push([a, c, d]);
            tris.push([a, d, b]);
        }
    }
    (normals.iter().map(|n| *n * r).collect(), normals, tris)
}

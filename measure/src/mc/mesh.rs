//! A closed triangle mesh as the boundary of a Monte Carlo medium: ray queries through a BVH
//! (`obvhs`' compressed wide BVH, f32 boxes) with the triangle tests in f64, and a voxel grid
//! of safe distances so that most free flights deep inside need no ray query at all.
//!
//! **Units.** Whatever the caller gives; the Monte Carlo passes millimetres (σ in mm⁻¹).
//!
//! **The safe-distance grid.** Voxels of side `h` over the mesh's bounds: every voxel a
//! triangle's (slightly grown) bounding box touches is a *surface* voxel; the others are flood
//! filled from the grid's border (6-connected, through non-surface voxels) as *outside*, the
//! rest are *inside*. Each inside voxel holds its L∞ distance k (in voxels, capped at
//! [`MAX_SAFE_VOXELS`]) to the nearest surface voxel: every surface point lies in a surface
//! voxel, so every point of the voxel is at least (k − 1)·h from the surface, and a free flight
//! shorter than that cannot reach it. A point in an outside voxel is outside the mesh (a photon
//! found there leaked through a crack: the walk reports it as lost).

use std::collections::VecDeque;
use std::time::Duration;

use glam::{DVec3, Vec3A};
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;

/// The largest L∞ voxel distance the grid records (a flight of up to (k − 1)·h needs no query).
pub const MAX_SAFE_VOXELS: u8 = 8;
/// Grid value of a voxel outside the mesh.
const OUTSIDE: u8 = u8::MAX;
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

/// Voxel grid of safe distances (module docs).
struct SafeGrid {
    origin: DVec3,
    h: f64,
    dims: [usize; 3],
    cells: Vec<u8>,
}

/// The index of the voxel (side `h`, grid `dims` from `origin`) holding `p`, if any.
#[inline]
fn voxel_index(origin: DVec3, h: f64, dims: [usize; 3], p: DVec3) -> Option<usize> {
    let q = (p - origin) / h;
    if !(q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0) {
        return None;
    }
    let (i, j, k) = (q.x as usize, q.y as usize, q.z as usize);
    let [nx, ny, nz] = dims;
    (i < nx && j < ny && k < nz).then(|| (k * ny + j) * nx + i)
}

impl SafeGrid {
    #[inline]
    fn index(&self, p: DVec3) -> Option<usize> {
        voxel_index(self.origin, self.h, self.dims, p)
    }

    fn build(positions: &[DVec3], triangles: &[[u32; 3]], lo: DVec3, hi: DVec3, h: f64) -> Self {
        let margin = 2.0 * h;
        let origin = lo - DVec3::splat(margin);
        let span = (hi - lo) + DVec3::splat(2.0 * margin);
        let dims = [
            (span.x / h).ceil() as usize + 1,
            (span.y / h).ceil() as usize + 1,
            (span.z / h).ceil() as usize + 1,
        ];
        let [nx, ny, nz] = dims;
        const UNSET: u8 = OUTSIDE - 1;
        let mut cells = vec![UNSET; nx * ny * nz];
        let at = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let grow = 1e-6 * h;
        for t in triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let (tlo, thi) = (a.min(b).min(c) - grow, a.max(b).max(c) + grow);
            let i0 = ((tlo - origin) / h).floor().max(DVec3::ZERO);
            let i1 = ((thi - origin) / h).floor();
            for k in i0.z as usize..=(i1.z as usize).min(nz - 1) {
                for j in i0.y as usize..=(i1.y as usize).min(ny - 1) {
                    for i in i0.x as usize..=(i1.x as usize).min(nx - 1) {
                        cells[at(i, j, k)] = 0;
                    }
                }
            }
        }
        // Flood the outside from the border through non-surface voxels.
        let mut queue = VecDeque::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let border = i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny;
                    if (border || k + 1 == nz) && cells[at(i, j, k)] == UNSET {
                        cells[at(i, j, k)] = OUTSIDE;
                        queue.push_back((i, j, k));
                    }
                }
            }
        }
        while let Some((i, j, k)) = queue.pop_front() {
            let mut visit = |i: usize, j: usize, k: usize| {
                let c = &mut cells[at(i, j, k)];
                if *c == UNSET {
                    *c = OUTSIDE;
                    queue.push_back((i, j, k));
                }
            };
            if i > 0 {
                visit(i - 1, j, k);
            }
            if i + 1 < nx {
                visit(i + 1, j, k);
            }
            if j > 0 {
                visit(i, j - 1, k);
            }
            if j + 1 < ny {
                visit(i, j + 1, k);
            }
            if k > 0 {
                visit(i, j, k - 1);
            }
            if k + 1 < nz {
                visit(i, j, k + 1);
            }
        }
        let dist = linf_distance(&cells, dims, MAX_SAFE_VOXELS);
        for (c, d) in cells.iter_mut().zip(dist) {
            if *c != OUTSIDE {
                *c = d;
            }
        }
        Self {
            origin,
            h,
            dims,
            cells,
        }
    }
}

/// L∞ distance (in voxels, capped at `cap`) of each voxel to the nearest voxel whose value is
/// 0: separable, one axis at a time (min over the window of max(|offset|, distance so far)).
fn linf_distance(cells: &[u8], dims: [usize; 3], cap: u8) -> Vec<u8> {
    let [nx, ny, _] = dims;
    let mut dist: Vec<u8> = cells
        .iter()
        .map(|&c| if c == 0 { 0 } else { cap })
        .collect();
    let strides = [1, nx, nx * ny];
    for (axis, &stride) in strides.iter().enumerate() {
        let n = dims[axis];
        let prev = dist.clone();
        for (idx, d) in dist.iter_mut().enumerate() {
            if *d == 0 {
                continue;
            }
            let pos = (idx / stride) % n;
            let mut best = *d;
            for off in 1..cap as usize {
                if off as u8 >= best {
                    break;
                }
                for p in [pos.checked_sub(off), Some(pos + off).filter(|&p| p < n)]
                    .into_iter()
                    .flatten()
                {
                    let other = prev[idx + p * stride - pos * stride];
                    best = best.min(other.max(off as u8));
                }
            }
            *d = best;
        }
    }
    dist
}

/// A coarse voxel field of the L∞ distance (voxels of side `h`, capped) to a set of points:
/// how far a point is from, say, what the camera sees.
pub struct DistanceField {
    origin: DVec3,
    h: f64,
    dims: [usize; 3],
    cap: u8,
    cells: Vec<u8>,
}

impl DistanceField {
    /// The field over the box [lo, hi] (points outside it count as `cap` voxels away).
    pub fn new(points: &[DVec3], lo: DVec3, hi: DVec3, h: f64, cap: u8) -> Self {
        let origin = lo - DVec3::splat(h);
        let span = hi - lo + DVec3::splat(2.0 * h);
        let dims = [
            (span.x / h).ceil() as usize + 1,
            (span.y / h).ceil() as usize + 1,
            (span.z / h).ceil() as usize + 1,
        ];
        let mut marks = vec![1u8; dims[0] * dims[1] * dims[2]];
        for p in points {
            if let Some(i) = voxel_index(origin, h, dims, *p) {
                marks[i] = 0;
            }
        }
        Self {
            origin,
            h,
            dims,
            cap,
            cells: linf_distance(&marks, dims, cap),
        }
    }

    /// The distance from `p` to the nearest point's voxel, in voxels times h (≥ the true
    /// distance less one voxel; `cap`·h when far or outside the field).
    pub fn distance(&self, p: DVec3) -> f64 {
        voxel_index(self.origin, self.h, self.dims, p).map_or(self.cap, |i| self.cells[i]) as f64
            * self.h
    }
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
        let c = self.grid.cells[self.grid.index(p)?];
        if c == OUTSIDE {
            return None;
        }
        Some((c.max(1) - 1) as f64 * self.grid.h)
    }

    /// Whether `p` is inside the mesh: the first crossing along a fixed direction leaves it.
    pub fn contains(&self, p: DVec3) -> bool {
        if self
            .grid
            .index(p)
            .is_none_or(|i| self.grid.cells[i] == OUTSIDE)
        {
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
        let n = self.grid.cells.len() as f64;
        let count = |f: &dyn Fn(u8) -> bool| self.grid.cells.iter().filter(|&&c| f(c)).count();
        (
            count(&|c| c == OUTSIDE) as f64 / n,
            count(&|c| c == 0) as f64 / n,
            count(&|c| c != OUTSIDE && c != 0) as f64 / n,
        )
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

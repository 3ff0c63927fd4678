//! The voxel grids of the mesh walk: the safe-distance grid of a [`ClosedMesh`] (how far a
//! free flight may go without a ray query, and which points are certainly outside) and the
//! [`DistanceField`] of the entry roulette.
//!
//! **The safe-distance grid.** Voxels of side `h` over the mesh's bounds: every voxel a
//! triangle's (slightly grown) bounding box touches is a *surface* voxel; the others are flood
//! filled from the grid's border (6-connected, through non-surface voxels) as *outside*, the
//! rest are *inside*. Each inside voxel holds its L∞ distance k (in voxels, capped at
//! [`MAX_SAFE_VOXELS`]) to the nearest surface voxel: every surface point lies in a surface
//! voxel, so every point of the voxel is at least (k − 1)·h from the surface, and a free flight
//! shorter than that cannot reach it. A point in an outside voxel is outside the mesh (a photon
//! found there leaked through a crack: the walk reports it as lost).
//!
//! That bound is loose where triangles are large (their bounding boxes mark voxels far from
//! the surface) and is 0 within a voxel or two of it, where most of a skin walk's flights
//! start. So each voxel within [`NEAR_VOXELS`] of the surface also keeps the exact distance d
//! from its centre c to the nearest triangle (rounded down to h/[`NEAR_STEPS`]), and a point p
//! in it is at least d − |p − c| from the surface (distance is 1-Lipschitz); the safe distance
//! is the larger of the two bounds. Neither ever exceeds the true distance (less a margin far
//! above rounding and the triangle test's edge tolerance), so a flight that skips its ray
//! query is one whose query would have found nothing: the walk's results do not depend on
//! these distances, only its speed.
//!
//! [`ClosedMesh`]: super::mesh::ClosedMesh

use std::collections::VecDeque;

use glam::DVec3;

/// The largest L∞ voxel distance the grid records (a flight of up to (k − 1)·h needs no query).
pub const MAX_SAFE_VOXELS: u8 = 8;
/// Grid value of a voxel outside the mesh.
const OUTSIDE: u8 = u8::MAX;
/// The exact distances kept near the surface: steps per voxel side …
pub const NEAR_STEPS: f64 = 32.0;
/// … up to this many voxels from the surface (beyond, the L∞ bound is as good) …
pub const NEAR_VOXELS: u8 = 4;
/// … less this margin (voxels) for rounding and the triangle test's edge tolerance, far
/// below any flight the bound decides.
const NEAR_MARGIN: f64 = 1e-6;

/// Voxel grid of safe distances (module docs).
pub(crate) struct SafeGrid {
    origin: DVec3,
    h: f64,
    dims: [usize; 3],
    /// Bricks of 4³ voxels along x and y.
    bricks: [usize; 2],
    /// Per voxel: its L∞ distance in voxels to the surface (or [`OUTSIDE`]), and its centre's
    /// distance to the surface in steps of h/[`NEAR_STEPS`], capped at [`NEAR_VOXELS`]·h
    /// ([`near_distances`]). Side by side, and stored by bricks of 4³ voxels (128 bytes), so
    /// that a photon's next few voxels are mostly in the cache lines of its last.
    cells: Vec<[u8; 2]>,
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
    /// The voxel holding `p`, if any: its coordinates and `p` in voxel units from the origin.
    #[inline]
    fn voxel(&self, p: DVec3) -> Option<([usize; 3], DVec3)> {
        let q = (p - self.origin) / self.h;
        if !(q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0) {
            return None;
        }
        let v = [q.x as usize, q.y as usize, q.z as usize];
        let [nx, ny, nz] = self.dims;
        (v[0] < nx && v[1] < ny && v[2] < nz).then_some((v, q))
    }

    /// Where voxel (i, j, k) is stored.
    #[inline]
    fn at(&self, [i, j, k]: [usize; 3]) -> usize {
        let [bx, by] = self.bricks;
        ((((k >> 2) * by + (j >> 2)) * bx + (i >> 2)) << 6)
            | ((k & 3) << 4)
            | ((j & 3) << 2)
            | (i & 3)
    }

    /// A distance from `p` within which the surface certainly is not (0 near the surface);
    /// `None` when `p` is outside the mesh (or the grid).
    #[inline]
    pub fn safe_distance(&self, p: DVec3) -> Option<f64> {
        let (v, q) = self.voxel(p)?;
        let [c, near] = self.cells[self.at(v)];
        if c == OUTSIDE {
            return None;
        }
        let coarse = (c.max(1) - 1) as f64 * self.h;
        if c > NEAR_VOXELS {
            return Some(coarse);
        }
        // The centre's distance less the point's from the centre (distances are 1-Lipschitz).
        let off = q - DVec3::new(v[0] as f64 + 0.5, v[1] as f64 + 0.5, v[2] as f64 + 0.5);
        let fine = (near as f64 / NEAR_STEPS - off.length() - NEAR_MARGIN) * self.h;
        Some(coarse.max(fine))
    }

    /// Whether `p` lies in an outside voxel (or off the grid): certainly outside the mesh.
    pub fn outside(&self, p: DVec3) -> bool {
        self.voxel(p)
            .is_none_or(|(v, _)| self.cells[self.at(v)][0] == OUTSIDE)
    }

    /// Fractions of the voxels that are (outside, surface, inside).
    pub fn fractions(&self) -> (f64, f64, f64) {
        let [nx, ny, nz] = self.dims;
        let mut counts = [0usize; 3];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    counts[match self.cells[self.at([i, j, k])][0] {
                        OUTSIDE => 0,
                        0 => 1,
                        _ => 2,
                    }] += 1;
                }
            }
        }
        let n = (nx * ny * nz) as f64;
        (
            counts[0] as f64 / n,
            counts[1] as f64 / n,
            counts[2] as f64 / n,
        )
    }

    /// The grid of the mesh (`positions`, `triangles`) whose vertices lie in [lo, hi], voxels
    /// of side `h`.
    pub fn build(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        lo: DVec3,
        hi: DVec3,
        h: f64,
    ) -> Self {
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
        let near = near_distances(positions, triangles, &cells, origin, h, dims);
        let bricks = [nx.div_ceil(4), ny.div_ceil(4)];
        let mut grid = Self {
            origin,
            h,
            dims,
            bricks,
            cells: vec![[OUTSIDE, 0]; bricks[0] * bricks[1] * nz.div_ceil(4) * 64],
        };
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let idx = grid.at([i, j, k]);
                    grid.cells[idx] = [cells[at(i, j, k)], near[at(i, j, k)]];
                }
            }
        }
        grid
    }
}

/// Per voxel, its centre's distance to the nearest triangle in steps of h/[`NEAR_STEPS`],
/// rounded down, up to [`NEAR_VOXELS`]·h (a voxel farther than that, or whose nearest
/// triangle is, holds the cap: never more than the truth). Each triangle visits the voxel
/// centres within NEAR_VOXELS·h of its bounding box, which hold every centre that close to it.
/// Only the voxels that use it are measured (inside, L∞ distance ≤ NEAR_VOXELS: `cells`), and
/// a triangle whose box is already no nearer than a voxel's distance is not.
fn near_distances(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    cells: &[u8],
    origin: DVec3,
    h: f64,
    dims: [usize; 3],
) -> Vec<u8> {
    let cap = NEAR_VOXELS * NEAR_STEPS as u8;
    let [nx, ny, nz] = dims;
    let mut near = vec![cap; nx * ny * nz];
    let reach = DVec3::splat(NEAR_VOXELS as f64 * h);
    let per_step = NEAR_STEPS / h;
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        // Voxels whose centres origin + (i + ½)·h lie in the grown box.
        let i0 = ((lo - reach - origin) / h - 0.5).ceil().max(DVec3::ZERO);
        let i1 = (hi + reach - origin) / h - 0.5;
        if i1.min_element() < 0.0 {
            continue;
        }
        for k in i0.z as usize..=(i1.z as usize).min(nz - 1) {
            for j in i0.y as usize..=(i1.y as usize).min(ny - 1) {
                for i in i0.x as usize..=(i1.x as usize).min(nx - 1) {
                    let idx = (k * ny + j) * nx + i;
                    if cells[idx] == OUTSIDE || cells[idx] > NEAR_VOXELS {
                        continue;
                    }
                    let centre =
                        origin + DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * h;
                    // The box's distance bounds the triangle's from below.
                    let gap = (lo - centre).max(centre - hi).max(DVec3::ZERO);
                    if gap.length() * per_step >= near[idx] as f64 {
                        continue;
                    }
                    let d = triangle_distance(centre, a, b, c) * per_step;
                    if d < near[idx] as f64 {
                        near[idx] = d as u8;
                    }
                }
            }
        }
    }
    near
}

/// Distance from `p` to the triangle (a, b, c): to its plane where `p` projects inside it,
/// else to the nearest of its edges (degenerate triangles: the edges only).
fn triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    let nn = n.length_squared();
    if nn > 0.0 {
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| (v - u).cross(p - u).dot(n) >= 0.0);
        if inside {
            return (p - a).dot(n).abs() / nn.sqrt();
        }
    }
    let segment = |u: DVec3, v: DVec3| {
        let e = v - u;
        let ee = e.length_squared();
        let s = if ee > 0.0 {
            ((p - u).dot(e) / ee).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (u + e * s)).length_squared()
    };
    segment(a, b).min(segment(b, c)).min(segment(c, a)).sqrt()
}

/// L∞ distance (in voxels, capped at `cap`) of each voxel to the nearest voxel whose value is
/// 0: separable, one axis at a time (min over the window of max(|offset|, distance so far)).
/// Along an axis the grid is chunks of `n` lines of `inner` voxels, a voxel's neighbour `off`
/// lines away `off · inner` voxels from it in its chunk: each offset is one pass over
/// contiguous slices.
fn linf_distance(cells: &[u8], dims: [usize; 3], cap: u8) -> Vec<u8> {
    let [nx, ny, nz] = dims;
    let mut dist: Vec<u8> = cells
        .iter()
        .map(|&c| if c == 0 { 0 } else { cap })
        .collect();
    for (n, inner) in [(nx, 1), (ny, nx), (nz, nx * ny)] {
        let prev = dist.clone();
        for (d, p) in dist.chunks_mut(n * inner).zip(prev.chunks(n * inner)) {
            for off in 1..(cap as usize).min(n) {
                let (o, k) = (off as u8, off * inner);
                let len = d.len() - k;
                for (d, &q) in d[k..].iter_mut().zip(&p[..len]) {
                    *d = (*d).min(q.max(o));
                }
                for (d, &q) in d[..len].iter_mut().zip(&p[k..]) {
                    *d = (*d).min(q.max(o));
                }
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mc::rng::Rng;

    #[test]
    fn linf_distance_is_the_capped_chebyshev_distance_to_the_zeros() {
        let dims = [13, 7, 9];
        let mut rng = Rng::new(5, 0);
        let cells: Vec<u8> = (0..13 * 7 * 9)
            .map(|_| u8::from(rng.uniform() > 0.02))
            .collect();
        for cap in [1, 3, 8, 32] {
            let fast = linf_distance(&cells, dims, cap);
            let at = |i: usize, j: usize, k: usize| (k * 7 + j) * 13 + i;
            for (k, j, i) in
                (0..9).flat_map(|k| (0..7).flat_map(move |j| (0..13).map(move |i| (k, j, i))))
            {
                let mut best = cap as usize;
                for (kk, jj, ii) in
                    (0..9).flat_map(|k| (0..7).flat_map(move |j| (0..13).map(move |i| (k, j, i))))
                {
                    if cells[at(ii, jj, kk)] == 0 {
                        let d = ii.abs_diff(i).max(jj.abs_diff(j)).max(kk.abs_diff(k));
                        best = best.min(d);
                    }
                }
                assert_eq!(fast[at(i, j, k)] as usize, best, "cap {cap} at {i} {j} {k}");
            }
        }
    }
}

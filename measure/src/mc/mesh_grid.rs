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
//! [`ClosedMesh`]: super::mesh::ClosedMesh

use std::collections::VecDeque;

use glam::DVec3;

/// The largest L∞ voxel distance the grid records (a flight of up to (k − 1)·h needs no query).
pub const MAX_SAFE_VOXELS: u8 = 8;
/// Grid value of a voxel outside the mesh.
const OUTSIDE: u8 = u8::MAX;

/// Voxel grid of safe distances (module docs).
pub(crate) struct SafeGrid {
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

    /// A distance from `p` within which the surface certainly is not (0 near the surface);
    /// `None` when `p` is outside the mesh (or the grid).
    #[inline]
    pub fn safe_distance(&self, p: DVec3) -> Option<f64> {
        let c = self.cells[self.index(p)?];
        if c == OUTSIDE {
            return None;
        }
        Some((c.max(1) - 1) as f64 * self.h)
    }

    /// Whether `p` lies in an outside voxel (or off the grid): certainly outside the mesh.
    pub fn outside(&self, p: DVec3) -> bool {
        self.index(p).is_none_or(|i| self.cells[i] == OUTSIDE)
    }

    /// Fractions of the voxels that are (outside, surface, inside).
    pub fn fractions(&self) -> (f64, f64, f64) {
        let n = self.cells.len() as f64;
        let count = |f: &dyn Fn(u8) -> bool| self.cells.iter().filter(|&&c| f(c)).count();
        (
            count(&|c| c == OUTSIDE) as f64 / n,
            count(&|c| c == 0) as f64 / n,
            count(&|c| c != OUTSIDE && c != 0) as f64 / n,
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

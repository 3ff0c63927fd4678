//! Indexed triangle mesh with the vertex attributes dermis uses, plus smooth-normal and
//! tangent generation.

use glam::{Vec2, Vec3, Vec4};
use std::collections::BTreeMap;

#[derive(Clone, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    /// xyz tangent, w = bitangent sign (+1 / -1).
    pub tangents: Vec<Vec4>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Appends `other`, offsetting its indices.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.tangents.extend_from_slice(&other.tangents);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// Area-weighted smooth normals; vertices at the same position (UV seams, poles) share
    /// one normal so the surface has no visible crease there.
    pub fn compute_smooth_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for t in self.indices.chunks(3) {
            let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
            let n = (self.positions[b] - self.positions[a])
                .cross(self.positions[c] - self.positions[a]);
            acc[a] += n;
            acc[b] += n;
            acc[c] += n;
        }
        let mut groups: BTreeMap<[i32; 3], Vec3> = BTreeMap::new();
        let key = |p: Vec3| {
            let q = p * 1.0e5;
            [q.x.round() as i32, q.y.round() as i32, q.z.round() as i32]
        };
        for (i, p) in self.positions.iter().enumerate() {
            *groups.entry(key(*p)).or_insert(Vec3::ZERO) += acc[i];
        }
        self.normals = self
            .positions
            .iter()
            .map(|p| groups[&key(*p)].try_normalize().unwrap_or(Vec3::Y))
            .collect();
    }

    /// Per-vertex tangents from UV derivatives, Gram-Schmidt orthogonalised to the normal.
    pub fn compute_tangents(&mut self) {
        let n = self.positions.len();
        let mut tan = vec![Vec3::ZERO; n];
        let mut bit = vec![Vec3::ZERO; n];
        for t in self.indices.chunks(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let (e1, e2) = (
                self.positions[b] - self.positions[a],
                self.positions[c] - self.positions[a],
            );
            let (d1, d2) = (self.uvs[b] - self.uvs[a], self.uvs[c] - self.uvs[a]);
            let det = d1.x * d2.y - d2.x * d1.y;
            if det.abs() < 1e-12 {
                continue;
            }
            let r = 1.0 / det;
            let sdir = (e1 * d2.y - e2 * d1.y) * r;
            let tdir = (e2 * d1.x - e1 * d2.x) * r;
            // Weight by geometric area so slivers near poles do not dominate.
            let w = e1.cross(e2).length();
            let (sdir, tdir) = (sdir.normalize_or_zero() * w, tdir.normalize_or_zero() * w);
            for &v in &[a, b, c] {
                tan[v] += sdir;
                bit[v] += tdir;
            }
        }
        self.tangents = (0..n)
            .map(|i| {
                let nrm = self.normals[i];
                let mut t = tan[i] - nrm * nrm.dot(tan[i]);
                if t.length_squared() < 1e-16 {
                    t = nrm.any_orthonormal_vector();
                }
                let t = t.normalize();
                let w = if nrm.cross(t).dot(bit[i]) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                t.extend(w)
            })
            .collect();
    }

    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in &self.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }

    /// Distance from `origin` along unit `dir` to the nearest triangle hit beyond `min_t`.
    pub fn ray_hit(&self, origin: Vec3, dir: Vec3, min_t: f32) -> Option<f32> {
        let mut best: Option<f32> = None;
        for t in self.indices.chunks(3) {
            let (a, b, c) = (
                self.positions[t[0] as usize],
                self.positions[t[1] as usize],
                self.positions[t[2] as usize],
            );
            // Möller–Trumbore, two-sided.
            let e1 = b - a;
            let e2 = c - a;
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-14 {
                continue;
            }
            let inv = 1.0 / det;
            let s = origin - a;
            let u = s.dot(p) * inv;
            if !(0.0..=1.0).contains(&u) {
                continue;
            }
            let q = s.cross(e1);
            let v = dir.dot(q) * inv;
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            let d = e2.dot(q) * inv;
            if d > min_t && best.is_none_or(|b| d < b) {
                best = Some(d);
            }
        }
        best
    }
}

//! Cutting a mesh along the zero set of a scalar field, so a material boundary (a neckline, a
//! hairline) runs along triangle edges and every triangle lies on one side of it.

use super::mesh::Mesh;
use glam::Vec3;
use std::collections::BTreeMap;

/// Splits every triangle of `m` that `f` changes sign across into three, with new vertices
/// where `f` is zero on its edges (position, normal and UV interpolated linearly; a new
/// vertex is shared by the two triangles of its edge, so the surface stays closed).
/// Tangents are recomputed. Also returns, for each new vertex (in order), the two vertices
/// of its edge and the fraction of the way from the first to the second.
pub fn cut(m: &Mesh, f: impl Fn(Vec3) -> f32) -> (Mesh, Vec<(u32, u32, f32)>) {
    // A value exactly zero counts as negative; nudged so no new vertex lands on an old one.
    let vals: Vec<f32> = m
        .positions
        .iter()
        .map(|&p| {
            let v = f(p);
            if v.abs() < 1e-7 {
                -1e-7
            } else {
                v
            }
        })
        .collect();
    let mut out = Mesh {
        positions: m.positions.clone(),
        normals: m.normals.clone(),
        uvs: m.uvs.clone(),
        tangents: Vec::new(),
        indices: Vec::with_capacity(m.indices.len()),
    };
    let mut on_edge: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    let mut origins = Vec::new();
    let mut split = |a: u32, b: u32, out: &mut Mesh| -> u32 {
        let (lo, hi) = (a.min(b), a.max(b));
        *on_edge.entry((lo, hi)).or_insert_with(|| {
            let (fl, fh) = (vals[lo as usize], vals[hi as usize]);
            let t = fl / (fl - fh);
            let (l, h) = (lo as usize, hi as usize);
            out.positions
                .push(m.positions[l] + (m.positions[h] - m.positions[l]) * t);
            out.normals
                .push((m.normals[l] + (m.normals[h] - m.normals[l]) * t).normalize_or_zero());
            out.uvs.push(m.uvs[l] + (m.uvs[h] - m.uvs[l]) * t);
            origins.push((lo, hi, t));
            out.positions.len() as u32 - 1
        })
    };
    for t in m.indices.chunks(3) {
        let s = [t[0], t[1], t[2]].map(|i| vals[i as usize] > 0.0);
        if s[0] == s[1] && s[1] == s[2] {
            out.indices.extend_from_slice(t);
            continue;
        }
        // Rotate (keeping the winding) so the vertex alone on its side comes first.
        let lone = if s[1] == s[2] {
            0
        } else if s[0] == s[2] {
            1
        } else {
            2
        };
        let [a, b, c] = [t[lone], t[(lone + 1) % 3], t[(lone + 2) % 3]];
        let p = split(a, b, &mut out);
        let q = split(a, c, &mut out);
        out.indices.extend_from_slice(&[a, p, q, p, b, c, p, c, q]);
    }
    out.compute_tangents();
    (out, origins)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn cuts_along_the_zero_set_and_keeps_the_surface() {
        // A unit square of two triangles, cut at x = 0.3.
        let m = Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
            tangents: Vec::new(),
            indices: vec![0, 1, 2, 0, 2, 3],
        };
        let (c, origins) = cut(&m, |p| p.x - 0.3);
        assert_eq!(origins.len(), 3);
        // The shared diagonal's cut vertex is made once: 4 + 3 new vertices.
        assert_eq!(c.positions.len(), 7);
        assert_eq!(c.indices.len(), 6 * 3);
        let area = |t: &[u32]| {
            let [a, b, d] = [t[0], t[1], t[2]].map(|i| c.positions[i as usize]);
            (b - a).cross(d - a).z * 0.5
        };
        let total: f32 = c.indices.chunks(3).map(area).sum();
        assert!((total - 1.0).abs() < 1e-6, "area {total}");
        for t in c.indices.chunks(3) {
            assert!(area(t) >= 0.0, "winding flipped");
            let mid = t.iter().map(|&i| c.positions[i as usize].x).sum::<f32>() / 3.0;
            let side = t.iter().all(|&i| {
                let x = c.positions[i as usize].x;
                (x - 0.3) * (mid - 0.3) >= -1e-6
            });
            assert!(side, "a triangle straddles the cut");
        }
        assert!(c.positions[4..].iter().all(|p| (p.x - 0.3).abs() < 1e-6));
        assert_eq!(c.tangents.len(), c.positions.len());
    }
}

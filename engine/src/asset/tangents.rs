//! Generated normals (area-weighted smooth normals, so that vertex count and skinning are
//! unchanged) and tangents (per-triangle UV gradients averaged per vertex, Gram-Schmidt
//! orthogonalised against the normal, handedness in `w`).

use glam::{Vec2, Vec3};

fn tri(indices: &[u32], t: usize) -> [usize; 3] {
    [
        indices[3 * t] as usize,
        indices[3 * t + 1] as usize,
        indices[3 * t + 2] as usize,
    ]
}

/// Smooth normals: each vertex gets the normalised sum of the (area-weighted) face normals of
/// its triangles; vertices on no or only degenerate triangles get +Y.
/// `indices` must be a validated triangle list into `positions`.
pub fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    for t in 0..indices.len() / 3 {
        let [a, b, c] = tri(indices, t);
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        if n.is_finite() {
            acc[a] += n;
            acc[b] += n;
            acc[c] += n;
        }
    }
    acc.into_iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
        .collect()
}

/// Tangents (xyz, w = handedness ±1) from the UV gradients of each triangle.
/// Where the UVs are degenerate, any unit vector perpendicular to the normal is used.
pub fn generate_tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[u32],
) -> Vec<[f32; 4]> {
    let n = positions.len();
    let mut tan = vec![Vec3::ZERO; n];
    let mut bit = vec![Vec3::ZERO; n];
    if uvs.len() == n {
        for t in 0..indices.len() / 3 {
            let [a, b, c] = tri(indices, t);
            let e1 = positions[b] - positions[a];
            let e2 = positions[c] - positions[a];
            let d1 = uvs[b] - uvs[a];
            let d2 = uvs[c] - uvs[a];
            let det = d1.x * d2.y - d2.x * d1.y;
            if det.abs() < 1e-20 || !det.is_finite() {
                continue;
            }
            let r = 1.0 / det;
            let sdir = (e1 * d2.y - e2 * d1.y) * r;
            let tdir = (e2 * d1.x - e1 * d2.x) * r;
            if !sdir.is_finite() || !tdir.is_finite() {
                continue;
            }
            for v in [a, b, c] {
                tan[v] += sdir;
                bit[v] += tdir;
            }
        }
    }
    (0..n)
        .map(|v| {
            let nrm = normals[v].try_normalize().unwrap_or(Vec3::Y);
            let t = tan[v] - nrm * nrm.dot(tan[v]);
            match t.try_normalize() {
                Some(t) => {
                    let w = if nrm.cross(t).dot(bit[v]) < 0.0 {
                        -1.0
                    } else {
                        1.0
                    };
                    [t.x, t.y, t.z, w]
                }
                None => {
                    let t = nrm.any_orthonormal_vector();
                    [t.x, t.y, t.z, 1.0]
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_in_xy_plane() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let uv = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        let idx = [0, 1, 2, 0, 2, 3];
        let n = smooth_normals(&p, &idx);
        assert!(n.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        let t = generate_tangents(&p, &n, &uv, &idx);
        for t in &t {
            assert!((Vec3::new(t[0], t[1], t[2]) - Vec3::X).length() < 1e-6);
            assert_eq!(t[3], 1.0);
        }
        // Mirrored U flips handedness.
        let uv_m: Vec<Vec2> = uv.iter().map(|u| Vec2::new(1.0 - u.x, u.y)).collect();
        let t = generate_tangents(&p, &n, &uv_m, &idx);
        assert!(t.iter().all(|t| t[3] == -1.0 && (t[0] + 1.0).abs() < 1e-6));
    }

    #[test]
    fn degenerate_uvs_give_perpendicular_unit_tangent() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let uv = [Vec2::ZERO; 3];
        let n = smooth_normals(&p, &[0, 1, 2]);
        for t in generate_tangents(&p, &n, &uv, &[0, 1, 2]) {
            let t3 = Vec3::new(t[0], t[1], t[2]);
            assert!((t3.length() - 1.0).abs() < 1e-6);
            assert!(t3.dot(Vec3::Z).abs() < 1e-6);
        }
    }
}

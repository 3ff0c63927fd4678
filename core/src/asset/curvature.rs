//! Mean curvature per vertex, computed at load from the mesh's positions and normals: what
//! the pre-integrated skin model reads as the radius of the sphere it takes the surface for.
//!
//! Each triangle's shape operator is the gradient of its interpolated normal: with edges
//! e₁, e₂ and normal differences d₁, d₂ from its first vertex, S maps eᵢ to dᵢ, and its trace
//! is tr(G⁻¹ H) with G = [eᵢ·eⱼ] and H = [eᵢ·dⱼ]; half the trace is the triangle's mean
//! curvature (exact for a sphere with exact normals: 1/r). A vertex takes the area-weighted
//! mean over the triangles around its position (vertices split along UV seams or between
//! primitives are one point here), so the field is smooth where the surface is and the same on
//! both sides of a seam. Positive where the surface is convex (normals pointing out), negative
//! where concave. Units: the mesh's own, inverted (1/m for a file in glTF's units).

use std::collections::HashMap;

use glam::Vec3;

use super::Primitive;

/// The mean curvature of a triangle (`p` its corners, `n` their normals) and its area, or
/// `None` for a degenerate one.
fn triangle(p: [Vec3; 3], n: [Vec3; 3]) -> Option<(f32, f32)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (n[1] - n[0], n[2] - n[0]);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if !(det > 1e-12 * g11 * g22) {
        return None;
    }
    let trace = (g22 * e1.dot(d1) - g12 * (e2.dot(d1) + e1.dot(d2)) + g11 * e2.dot(d2)) / det;
    let h = 0.5 * trace;
    h.is_finite().then(|| (h, 0.5 * det.sqrt()))
}

/// Sets every vertex's curvature in `primitives` (one mesh: module docs).
pub fn fill(primitives: &mut [Primitive]) {
    // One slot per distinct position.
    let mut slot_of: HashMap<[u32; 3], usize> = HashMap::new();
    let slots: Vec<Vec<usize>> = primitives
        .iter()
        .map(|p| {
            p.vertices
                .iter()
                .map(|v| {
                    let key = v.position.map(f32::to_bits);
                    let next = slot_of.len();
                    *slot_of.entry(key).or_insert(next)
                })
                .collect()
        })
        .collect();
    let mut sum = vec![(0.0f64, 0.0f64); slot_of.len()];
    for (p, slots) in primitives.iter().zip(&slots) {
        let pos = |i: u32| Vec3::from_array(p.vertices[i as usize].position);
        let nrm = |i: u32| Vec3::from_array(p.vertices[i as usize].normal).normalize_or_zero();
        for t in p.indices.chunks_exact(3) {
            let corners = [t[0], t[1], t[2]];
            let Some((h, area)) = triangle(corners.map(pos), corners.map(nrm)) else {
                continue;
            };
            for &i in &corners {
                let s = &mut sum[slots[i as usize]];
                s.0 += f64::from(h * area);
                s.1 += f64::from(area);
            }
        }
    }
    for (p, slots) in primitives.iter_mut().zip(&slots) {
        for (v, &s) in p.vertices.iter_mut().zip(slots) {
            let (ha, a) = sum[s];
            v.curvature = if a > 0.0 { (ha / a) as f32 } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::shapes::{plane_model, sphere_model};

    #[test]
    fn a_sphere_is_one_over_its_radius_and_a_plane_zero() {
        for r in [0.01, 0.3] {
            let mut m = sphere_model(r, 0.004);
            let prims = &mut m.meshes[0].primitives;
            fill(prims);
            for v in &prims[0].vertices {
                assert!((v.curvature * r - 1.0).abs() < 1e-3, "{} at r {r}", v.curvature);
            }
        }
        let mut m = plane_model(0.1, 0.004);
        let prims = &mut m.meshes[0].primitives;
        fill(prims);
        assert!(prims[0].vertices.iter().all(|v| v.curvature == 0.0));
    }

    /// A prolate spheroid (equatorial radius `a`, polar `c`, along z) with its exact normals.
    fn spheroid(a: f32, c: f32) -> Primitive {
        let mut m = sphere_model(1.0, 0.004);
        let mut p = m.meshes.remove(0).primitives.remove(0);
        for v in &mut p.vertices {
            let q = Vec3::from_array(v.position) * Vec3::new(a, a, c);
            v.position = q.to_array();
            v.normal = (q / Vec3::new(a * a, a * a, c * c)).normalize().to_array();
        }
        p
    }

    #[test]
    fn a_spheroids_mean_curvature_at_its_equator_and_poles() {
        let (a, c) = (0.02f32, 0.05f32);
        let mut prims = [spheroid(a, c)];
        fill(&mut prims);
        let equator = 0.5 * (1.0 / a + a / (c * c));
        let pole = c / (a * a);
        for v in &prims[0].vertices {
            let z = v.position[2];
            let want = if z.abs() < 1e-6 {
                equator
            } else if (z.abs() - c).abs() < 1e-6 {
                pole
            } else {
                continue;
            };
            assert!((v.curvature / want - 1.0).abs() < 0.02, "{} want {want}", v.curvature);
        }
    }

    #[test]
    fn inside_out_is_concave_and_a_split_between_primitives_does_not_show() {
        let r = 0.05;
        let mut m = sphere_model(r, 0.004);
        let prims = &mut m.meshes[0].primitives;
        for v in &mut prims[0].vertices {
            v.normal = v.normal.map(|x| -x);
        }
        fill(prims);
        for v in &prims[0].vertices {
            assert!((v.curvature * r + 1.0).abs() < 1e-3, "{}", v.curvature);
        }
        // The spheroid in one primitive and cut in two (each with all the vertices, half the
        // triangles): the vertices along the cut see both halves.
        let whole = spheroid(0.03, 0.06);
        let mut one = [whole.clone()];
        fill(&mut one);
        let cut = whole.indices.len() / 6 * 3;
        let (mut a, mut b) = (whole.clone(), whole);
        a.indices.truncate(cut);
        b.indices.drain(..cut);
        let mut two = [a, b];
        fill(&mut two);
        for (i, v) in one[0].vertices.iter().enumerate() {
            for half in &two {
                let got = half.vertices[i].curvature;
                assert!((got - v.curvature).abs() <= 1e-5 * v.curvature.abs(), "{got} {}", v.curvature);
            }
        }
    }
}

//! Curvature per vertex, computed at load from the mesh's positions and normals: what a
//! model that takes the surface for a sphere (one that samples a LUT over curvature) reads as
//! the sphere's radius, in the direction the light crosses it.
//!
//! Each triangle's shape operator is the gradient of its interpolated normal: with edges
//! e₁, e₂ and normal differences d₁, d₂ from its first vertex, S maps eᵢ to dᵢ, so
//! S v = [d₁ d₂] G⁻¹ [e₁·v, e₂·v] with G = [eᵢ·eⱼ] (exact for a sphere with exact normals:
//! 1/r in every direction), taken symmetric. A vertex takes the area-weighted mean of the
//! tensors of the triangles around its position (vertices split along UV seams or between
//! primitives are one point here, to a millionth of the mesh's size), restricted to the plane its own normal faces, and keeps
//! its principal curvatures κ₁ ≥ κ₂ with κ₁'s direction d₁. The normal curvature along a unit
//! tangent t is then κ₂ + (κ₁ − κ₂)(d₁·t)² (Euler), stored as [`Vertex::curvature`]:
//! `[a.x, a.y, a.z, κ₂]` with a = d₁·√(κ₁ − κ₂), so κ(t) = κ₂ + (a·t)² and the mean curvature
//! is κ₂ + |a|²/2. Positive where the surface is convex (normals pointing out), negative
//! where concave. Units: the mesh's own, inverted (1/m for a file in glTF's units).
//!
//! [`Vertex::curvature`]: super::Vertex::curvature

use std::collections::HashMap;

use glam::{Mat3, Vec3};

use super::Primitive;

/// The symmetric shape operator of a triangle (`p` its corners, `n` their normals) and its
/// area, or `None` for a degenerate one.
fn triangle(p: [Vec3; 3], n: [Vec3; 3]) -> Option<(Mat3, f32, f32)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (n[1] - n[0], n[2] - n[0]);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    // A sliver (a corner under ~0.06°) carries no curvature f32 can place.
    if det.is_nan() || det <= 1e-6 * g11 * g22 {
        return None;
    }
    // G⁻¹ [e₁ e₂]ᵀ: the dual basis (v ↦ the coordinates of v's part in the plane).
    let f1 = (e1 * g22 - e2 * g12) / det;
    let f2 = (e2 * g11 - e1 * g12) / det;
    // S = d₁ f₁ᵀ + d₂ f₂ᵀ (columns: S applied to x, y, z), then its symmetric part.
    let outer = |a: Vec3, b: Vec3| Mat3::from_cols(a * b.x, a * b.y, a * b.z);
    let s = outer(d1, f1) + outer(d2, f2);
    let sym = (s + s.transpose()) * 0.5;
    // Its trace in the triangle's own plane, tr(G⁻¹ [eᵢ·dⱼ]): twice the mean curvature.
    let trace = f1.dot(d1) + f2.dot(d2);
    let finite = sym.to_cols_array().iter().all(|x| x.is_finite()) && trace.is_finite();
    finite.then(|| (sym, trace, 0.5 * det.sqrt()))
}

/// `[a.x, a.y, a.z, κ₂]` (module docs) of the tensor `s` restricted to the plane normal to `n`,
/// its principal curvatures shifted together to sum to `trace` (the triangles' own traces: the
/// plane normal to `n` is not quite theirs, and cuts a facetted sphere's tensor by up to ~1 %).
fn principal(s: Mat3, trace: f32, n: Vec3) -> [f32; 4] {
    let Some(n) = n.try_normalize() else {
        return [0.0; 4];
    };
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let (a, b, c) = (u.dot(s * u), u.dot(s * w), w.dot(s * w));
    // Eigenvalues of [[a, b], [b, c]] (their gap) and the larger one's direction.
    let half_gap = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let mean = 0.5 * trace;
    let (k1, k2) = (mean + half_gap, mean - half_gap);
    let angle = 0.5 * (2.0 * b).atan2(a - c);
    let d1 = u * angle.cos() + w * angle.sin();
    let a = d1 * (k1 - k2).max(0.0).sqrt();
    [a.x, a.y, a.z, k2]
}

/// The normal curvature of `curvature` (a vertex's, module docs) along the unit tangent `t`.
pub fn along(curvature: [f32; 4], t: Vec3) -> f32 {
    let a = Vec3::new(curvature[0], curvature[1], curvature[2]);
    curvature[3] + a.dot(t).powi(2)
}

/// The mean curvature of `curvature` (a vertex's, module docs).
pub fn mean(curvature: [f32; 4]) -> f32 {
    let a = Vec3::new(curvature[0], curvature[1], curvature[2]);
    curvature[3] + 0.5 * a.length_squared()
}

/// Sets every vertex's curvature in `primitives` (one mesh: module docs).
pub fn fill(primitives: &mut [Primitive]) {
    // One slot per distinct position, to a millionth of the mesh's size (a UV sphere's pole
    // copies differ in the last bits).
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for v in primitives.iter().flat_map(|p| &p.vertices) {
        lo = lo.min(Vec3::from_array(v.position));
        hi = hi.max(Vec3::from_array(v.position));
    }
    let quantum = ((hi - lo).length() * 1e-6).max(f32::MIN_POSITIVE);
    let mut slot_of: HashMap<[i64; 3], usize> = HashMap::new();
    let slots: Vec<Vec<usize>> = primitives
        .iter()
        .map(|p| {
            p.vertices
                .iter()
                .map(|v| {
                    let key = v.position.map(|x| (x / quantum).round() as i64);
                    let next = slot_of.len();
                    *slot_of.entry(key).or_insert(next)
                })
                .collect()
        })
        .collect();
    let mut sum = vec![(Mat3::ZERO, 0.0f32, 0.0f32); slot_of.len()];
    for (p, slots) in primitives.iter().zip(&slots) {
        let pos = |i: u32| Vec3::from_array(p.vertices[i as usize].position);
        let nrm = |i: u32| Vec3::from_array(p.vertices[i as usize].normal).normalize_or_zero();
        for t in p.indices.chunks_exact(3) {
            let corners = [t[0], t[1], t[2]];
            let Some((s, trace, area)) = triangle(corners.map(pos), corners.map(nrm)) else {
                continue;
            };
            for &i in &corners {
                let slot = &mut sum[slots[i as usize]];
                slot.0 += s * area;
                slot.1 += trace * area;
                slot.2 += area;
            }
        }
    }
    for (p, slots) in primitives.iter_mut().zip(&slots) {
        for (v, &s) in p.vertices.iter_mut().zip(slots) {
            let (sa, ta, a) = sum[s];
            v.curvature = if a > 0.0 {
                principal(sa * (1.0 / a), ta / a, Vec3::from_array(v.normal))
            } else {
                [0.0; 4]
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::shapes::{plane_model, sphere_model};

    #[test]
    fn a_sphere_is_one_over_its_radius_every_way_and_a_plane_zero() {
        for r in [0.01, 0.3] {
            let mut m = sphere_model(r, 0.004);
            let prims = &mut m.meshes[0].primitives;
            fill(prims);
            for v in &prims[0].vertices {
                let n = Vec3::from_array(v.normal);
                for t in [
                    n.any_orthonormal_vector(),
                    n.cross(n.any_orthonormal_vector()),
                ] {
                    let k = along(v.curvature, t);
                    assert!((k * r - 1.0).abs() < 2e-3, "{k} at r {r}");
                }
                assert!((mean(v.curvature) * r - 1.0).abs() < 2e-3);
            }
        }
        let mut m = plane_model(0.1, 0.004);
        let prims = &mut m.meshes[0].primitives;
        fill(prims);
        assert!(prims[0].vertices.iter().all(|v| v.curvature == [0.0; 4]));
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
    fn a_spheroids_curvatures_at_its_equator_and_poles() {
        let (a, c) = (0.02f32, 0.05f32);
        let mut prims = [spheroid(a, c)];
        fill(&mut prims);
        let (mut equator, mut poles) = (0, 0);
        for v in &prims[0].vertices {
            let (p, k) = (Vec3::from_array(v.position), v.curvature);
            let close = |got: f32, want: f32| {
                assert!((got / want - 1.0).abs() < 0.02, "{got} want {want} at {p}");
            };
            if p.z.abs() < 1e-6 {
                // Around the equator 1/a, along the meridian a/c²; the mean their half sum.
                let around = Vec3::Z.cross(p).normalize();
                close(along(k, around), 1.0 / a);
                close(along(k, Vec3::Z), a / (c * c));
                close(mean(k), 0.5 * (1.0 / a + a / (c * c)));
                equator += 1;
            } else if (p.z.abs() - c).abs() < 1e-6 {
                // An umbilic: c/a² every way.
                close(along(k, Vec3::X), c / (a * a));
                close(along(k, Vec3::Y), c / (a * a));
                poles += 1;
            }
        }
        assert!(equator > 100 && poles > 100, "{equator} {poles}");
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
            assert!(
                (mean(v.curvature) * r + 1.0).abs() < 2e-3,
                "{:?}",
                v.curvature
            );
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
            let n = Vec3::from_array(v.normal);
            let (t1, t2) = (
                n.any_orthonormal_vector(),
                n.cross(n.any_orthonormal_vector()),
            );
            let scale = mean(v.curvature).abs();
            for half in &two {
                let got = half.vertices[i].curvature;
                for t in [t1, t2, (t1 + t2).normalize()] {
                    let (g, w) = (along(got, t), along(v.curvature, t));
                    assert!((g - w).abs() <= 1e-3 * scale, "{got:?} {:?}", v.curvature);
                }
            }
        }
    }
}

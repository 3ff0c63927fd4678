//! Smooth procedural primitives: lofted tubes with rounded caps (body parts) and rounded boxes
//! (props).

use super::detmath::{sin_cos, PI, TAU};
use super::mesh::Mesh;
use glam::{Vec2, Vec3};

/// A closed, lofted tube from `start` to `end`: rings of a (super)ellipse cross-section whose
/// radii follow `profile`, closed with elliptic caps at both ends.
#[derive(Clone)]
pub struct Tube {
    pub start: Vec3,
    pub end: Vec3,
    /// Direction of the first cross-section radius (made perpendicular to the axis).
    pub side: Vec3,
    /// Keys `(t, r_side, r_other, offset)`: radii in metres at axial fraction `t`, and a shift
    /// of the ring centre along `offset_dir`.
    pub profile: Vec<[f32; 4]>,
    pub offset_dir: Vec3,
    /// Axial length of each end cap, as a fraction of the tube length.
    pub caps: [f32; 2],
    /// 0 = elliptic cross-section, 1 = superellipse with exponent 4 (boxier torso).
    pub squareness: f32,
    pub segments: usize,
    pub body_rings: usize,
    pub cap_rings: usize,
    /// Atlas rectangle `[u0, v0, width, height]`.
    pub uv_rect: [f32; 4],
}

impl Tube {
    pub fn axis_frame(&self) -> (Vec3, Vec3, Vec3) {
        let a = (self.end - self.start).normalize();
        let e1 = (self.side - a * a.dot(self.side)).normalize();
        let e2 = a.cross(e1);
        (a, e1, e2)
    }

    /// Catmull-Rom interpolation of the profile keys at `t`.
    pub fn radii(&self, t: f32) -> [f32; 3] {
        let k = &self.profile;
        if t <= k[0][0] {
            return [k[0][1], k[0][2], k[0][3]];
        }
        let last = k.len() - 1;
        if t >= k[last][0] {
            return [k[last][1], k[last][2], k[last][3]];
        }
        let mut i = 0;
        while k[i + 1][0] < t {
            i += 1;
        }
        let u = (t - k[i][0]) / (k[i + 1][0] - k[i][0]);
        let p0 = k[i.saturating_sub(1)];
        let p1 = k[i];
        let p2 = k[i + 1];
        let p3 = k[(i + 2).min(last)];
        let mut out = [0.0; 3];
        for c in 0..3 {
            let (a, b, cc, d) = (p0[c + 1], p1[c + 1], p2[c + 1], p3[c + 1]);
            out[c] = 0.5
                * (2.0 * b
                    + (-a + cc) * u
                    + (2.0 * a - 5.0 * b + 4.0 * cc - d) * u * u
                    + (-a + 3.0 * b - 3.0 * cc + d) * u * u * u);
        }
        out
    }

    /// Axial positions of the rings (`t` in 0..=1) and their cap radius factors.
    fn rings(&self) -> Vec<(f32, f32)> {
        let mut out = Vec::new();
        let [c0, c1] = self.caps;
        for j in 0..self.cap_rings {
            let ang = PI * 0.5 * j as f32 / self.cap_rings as f32;
            let (s, c) = sin_cos(ang);
            out.push((c0 * (1.0 - c), s));
        }
        for j in 0..=self.body_rings {
            let t = c0 + (1.0 - c0 - c1) * j as f32 / self.body_rings as f32;
            out.push((t, 1.0));
        }
        for j in (0..self.cap_rings).rev() {
            let ang = PI * 0.5 * j as f32 / self.cap_rings as f32;
            let (s, c) = sin_cos(ang);
            out.push((1.0 - c1 * (1.0 - c), s));
        }
        out
    }

    #[cfg(test)]
    pub fn build(&self) -> Mesh {
        self.build_with_diameters().0
    }

    /// The mesh plus, per vertex, the part's full cross-section diameter (largest axis) at
    /// that vertex's ring, ignoring the cap rounding.
    pub fn build_with_diameters(&self) -> (Mesh, Vec<f32>) {
        let (a, e1, e2) = self.axis_frame();
        let len = (self.end - self.start).length();
        let rings = self.rings();
        let seg = self.segments;
        let [u0, v0, uw, vh] = self.uv_rect;
        let pad = 0.02;
        let mut m = Mesh::default();
        let mut diam = Vec::new();
        let circle: Vec<(f32, f32)> = (0..=seg)
            .map(|i| {
                let (s, c) = sin_cos(TAU * (i % seg) as f32 / seg as f32);
                // Superellipse (n = 4) radial scale, blended with the circle.
                let sq = 1.0 / (c * c * c * c + s * s * s * s).sqrt().sqrt();
                let k = 1.0 + (sq - 1.0) * self.squareness;
                (c * k, s * k)
            })
            .collect();
        let nr = rings.len();
        for (j, &(t, capf)) in rings.iter().enumerate() {
            let [r1, r2, off] = self.radii(t);
            let centre = self.start + a * (t * len) + self.offset_dir * off;
            for (i, &(c, s)) in circle.iter().enumerate() {
                let p = centre + e1 * (c * r1 * capf) + e2 * (s * r2 * capf);
                m.positions.push(p);
                diam.push(2.0 * r1.max(r2));
                let pole = capf == 0.0;
                let uf = if pole {
                    (i as f32 + 0.5).min(seg as f32) / seg as f32
                } else {
                    i as f32 / seg as f32
                };
                let vf = j as f32 / (nr - 1) as f32;
                m.uvs.push(Vec2::new(
                    u0 + uw * (pad + (1.0 - 2.0 * pad) * uf),
                    v0 + vh * (pad + (1.0 - 2.0 * pad) * vf),
                ));
            }
        }
        let row = (seg + 1) as u32;
        for j in 0..nr - 1 {
            let pole0 = rings[j].1 == 0.0;
            let pole1 = rings[j + 1].1 == 0.0;
            for i in 0..seg as u32 {
                let v00 = j as u32 * row + i;
                let v01 = v00 + 1;
                let v10 = v00 + row;
                let v11 = v10 + 1;
                if !pole0 {
                    m.indices.extend_from_slice(&[v00, v01, v11]);
                }
                if !pole1 {
                    m.indices.extend_from_slice(&[v00, v11, v10]);
                }
            }
        }
        m.compute_smooth_normals();
        m.compute_tangents();
        (m, diam)
    }
}

/// A box centred at `centre` with half extents `half`, its edges rounded with `radius`.
/// UVs are planar per face, `uv_per_m` texture repeats per metre (plus `uv_offset`).
pub fn rounded_box(
    centre: Vec3,
    half: Vec3,
    radius: f32,
    bevel_steps: usize,
    uv_per_m: f32,
    uv_offset: Vec2,
) -> Mesh {
    let r = radius.min(half.min_element() * 0.99);
    let inner = half - Vec3::splat(r);
    // Grid coordinates along one face axis of extent h: bevel, flat span, bevel.
    let coords = |h: f32| -> Vec<f32> {
        let mut v = Vec::new();
        for k in 0..bevel_steps {
            v.push(-h + r * k as f32 / bevel_steps as f32);
        }
        let flat_steps = ((2.0 * (h - r)) / 0.5).ceil().max(1.0) as usize;
        for k in 0..=flat_steps {
            v.push(-(h - r) + 2.0 * (h - r) * k as f32 / flat_steps as f32);
        }
        for k in (0..bevel_steps).rev() {
            v.push(h - r * k as f32 / bevel_steps as f32);
        }
        v
    };
    let mut mesh = Mesh::default();
    // (normal axis, sign, u axis, v axis) chosen so that u x v = normal (CCW from outside).
    let faces: [(usize, f32, usize, usize); 6] = [
        (0, 1.0, 1, 2),
        (0, -1.0, 2, 1),
        (1, 1.0, 2, 0),
        (1, -1.0, 0, 2),
        (2, 1.0, 0, 1),
        (2, -1.0, 1, 0),
    ];
    for &(n_ax, sign, u_ax, v_ax) in &faces {
        let (uu, vv) = (u_ax, v_ax);
        let cu = coords(half[uu]);
        let cv = coords(half[vv]);
        let base = mesh.positions.len() as u32;
        for &b in &cv {
            for &a in &cu {
                let mut q = Vec3::ZERO;
                q[n_ax] = sign * half[n_ax];
                q[uu] = a;
                q[vv] = b;
                let c = q.clamp(-inner, inner);
                let d = q - c;
                let n = d.normalize();
                let p = c + n * r;
                mesh.positions.push(centre + p);
                mesh.normals.push(n);
                // Planar UVs on the face plane, unwrapped (arc length ignored on bevels).
                mesh.uvs.push(Vec2::new(a, -b) * uv_per_m + uv_offset);
            }
        }
        let w = cu.len() as u32;
        for j in 0..cv.len() as u32 - 1 {
            for i in 0..w - 1 {
                let v00 = base + j * w + i;
                let (v01, v10, v11) = (v00 + 1, v00 + w, v00 + w + 1);
                mesh.indices
                    .extend_from_slice(&[v00, v01, v11, v00, v11, v10]);
            }
        }
    }
    mesh.compute_tangents();
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_volume(m: &Mesh) -> f32 {
        m.indices
            .chunks(3)
            .map(|t| {
                let (a, b, c) = (
                    m.positions[t[0] as usize],
                    m.positions[t[1] as usize],
                    m.positions[t[2] as usize],
                );
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn box_is_outward_and_closed() {
        let m = rounded_box(
            Vec3::ZERO,
            Vec3::new(1.0, 0.5, 0.25),
            0.05,
            3,
            1.0,
            Vec2::ZERO,
        );
        let v = signed_volume(&m);
        assert!((v - 1.0).abs() < 0.02, "{v}");
    }

    #[test]
    fn tube_is_outward() {
        let t = Tube {
            start: Vec3::ZERO,
            end: Vec3::Y,
            side: Vec3::X,
            profile: vec![[0.0, 0.2, 0.2, 0.0], [1.0, 0.2, 0.2, 0.0]],
            offset_dir: Vec3::Z,
            caps: [0.2, 0.2],
            squareness: 0.0,
            segments: 16,
            body_rings: 4,
            cap_rings: 4,
            uv_rect: [0.0, 0.0, 1.0, 1.0],
        };
        let m = t.build();
        assert!(signed_volume(&m) > 0.05);
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let c = Vec3::new(0.0, p.y.clamp(0.2, 0.8), 0.0);
            assert!(n.dot(*p - c) > 0.0);
        }
    }
}

//! The key light's shadow frustum for a frame: fitted to the casters' bounding sphere, so the
//! map's texels land where shadows can fall — a shadow of something inside the sphere lies
//! inside the cone of rays through it, whatever receives it — then cropped to the part of
//! that cone the camera sees ([`ShadowView::cropped_to`]): a close-up of the chest spends the
//! map on the chest, not on the legs out of the frame. A light far away compared with the
//! sphere (a measurement scene's directional light) gets an orthographic frustum. Plain data:
//! `Renderer::prepare` fits it, the shadow-map pass draws from it and receivers read it
//! through the frame uniform.

use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};

pub use crate::shading::edge_spread::SHADOW_RAMP_TEXELS;

/// A light farther than this many sphere radii gets an orthographic frustum.
const ORTHOGRAPHIC_BEYOND: f32 = 20.0;
/// Normal offset and depth bias, in texels of the map at the casters. The normal offset: half the filter's ramp, as far as its outer taps reach (a quarter
/// of it: the grazing side of a ball shadows itself, 9 % at n·l 0.02–0.05).
const NORMAL_OFFSET_TEXELS: f32 = 0.5 * SHADOW_RAMP_TEXELS;
const DEPTH_BIAS_TEXELS: f32 = 1.0;
/// A crop magnifies the map at most this much (the penumbra map's reach in grid texels and
/// the depth's precision per texel stay within what they were made for).
const MAX_ZOOM: f32 = 8.0;
/// A crop that would keep more than this fraction of the map's side is not made.
const MIN_GAIN: f32 = 0.9;

/// What receivers need of this frame's shadow map (the `shadow*` members of the frame uniform).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowView {
    /// World → the map's clip space (depth 0..1).
    pub view_proj: Mat4,
    /// Whether a map was drawn this frame (something casts).
    pub drawn: bool,
    /// One texel's world size at the casters' centre (m).
    pub texel_m: f32,
    /// The depth bias in the map's depth units.
    pub bias: f32,
    /// Depth units per metre along the light, at the casters' centre.
    pub depth_per_m: f32,
    /// Texels per side.
    pub size: u32,
}

impl ShadowView {
    /// No map: every point is lit.
    pub const NONE: Self = Self {
        view_proj: Mat4::IDENTITY,
        drawn: false,
        texel_m: 0.0,
        bias: 0.0,
        depth_per_m: 0.0,
        size: 1,
    };

    /// The frustum of a light at `light` around the sphere (`centre`, `radius`), for a map of
    /// `size`² texels. A light inside (or on) the sphere casts no shadow map: [`Self::NONE`].
    pub fn fit(light: Vec3, centre: Vec3, radius: f32, size: u32) -> Self {
        let to_light = light - centre;
        let d = to_light.length();
        if !(d.is_finite() && radius.is_finite() && radius > 0.0) || d <= radius * 1.05 {
            return Self::NONE;
        }
        let dir = to_light / d;
        let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let size = size.max(1);
        if d > ORTHOGRAPHIC_BEYOND * radius {
            // Parallel rays: look from 2r away, depth over the sphere's 2r (linear).
            let eye = centre + dir * (2.0 * radius);
            let view = glam::camera::rh::view::look_at_mat4(eye, centre, up);
            let proj = glam::camera::rh::proj::directx::orthographic(
                -radius,
                radius,
                -radius,
                radius,
                radius,
                3.0 * radius,
            );
            let texel_m = 2.0 * radius / size as f32;
            return Self {
                view_proj: proj * view,
                drawn: true,
                texel_m,
                bias: DEPTH_BIAS_TEXELS * texel_m / (2.0 * radius),
                depth_per_m: 1.0 / (2.0 * radius),
                size,
            };
        }
        let half_angle = (radius / d).asin();
        let (near, far) = (d - radius, d + radius);
        let view = glam::camera::rh::view::look_at_mat4(light, centre, up);
        let proj = glam::camera::rh::proj::directx::perspective(2.0 * half_angle, 1.0, near, far);
        let texel_m = 2.0 * d * half_angle.tan() / size as f32;
        // Depth z = far (1 − near/d')/(far − near): dz/dd' = far·near/((far − near) d'²).
        let dz_dd = far * near / ((far - near) * d * d);
        Self {
            view_proj: proj * view,
            drawn: true,
            texel_m,
            bias: DEPTH_BIAS_TEXELS * texel_m * dz_dd,
            depth_per_m: dz_dd,
            size,
        }
    }

    /// This view cropped to the shadows the camera `camera` (world → its clip space, depth
    /// 0..1) can see, for casters inside the box `lo..hi` lit from `light`: a visible shadow
    /// falls on a receiver seen by the camera whose ray to the light crosses the box, so its
    /// place in the map lies both in the light's image of the box and in the light's image of
    /// the camera's frustum cut to the depths (along the camera's axis) where such receivers
    /// can be — the box, and the box's shadow on the floor (the plane through its bottom;
    /// nothing is received below it). The map becomes the square around the intersection of
    /// the two images, magnified at most [`MAX_ZOOM`]×; a receiver outside it is lit (as
    /// outside the map). Unchanged where that would not gain, or part of either piece is
    /// behind the light.
    pub fn cropped_to(self, camera: Mat4, light: Vec3, (lo, hi): (Vec3, Vec3)) -> Self {
        if !(self.drawn && lo.is_finite() && hi.is_finite() && light.is_finite()) {
            return self;
        }
        let corners = box_corners(lo, hi);
        let Some((box_lo, box_hi)) = self.image_of(&corners) else {
            return self;
        };
        // Where the box's corners' shadows fall on the floor (an upward ray: no floor).
        // (A fixed array: the frame allocates nothing.)
        let mut reach = [Vec3::ZERO; 16];
        reach[..8].copy_from_slice(&corners);
        let mut n = 8;
        for c in corners {
            let down = light.y - c.y;
            if c.y > lo.y && down <= 1e-4 {
                return self;
            }
            if c.y > lo.y {
                reach[n] = light + (c - light) * ((light.y - lo.y) / down);
                n += 1;
            }
        }
        let Some(slab) = seen_part(camera, &reach[..n]) else {
            return self;
        };
        let Some((seen_lo, seen_hi)) = self.image_of(&slab) else {
            return self;
        };
        let lo = box_lo.max(seen_lo).max(Vec2::NEG_ONE);
        let hi = box_hi.min(seen_hi).min(Vec2::ONE);
        let side = (hi - lo).max_element();
        if !(side > 0.0 && side < 2.0 * MIN_GAIN) || (hi - lo).min_element() <= 0.0 {
            return self;
        }
        let zoom = (2.0 / side).min(MAX_ZOOM);
        let half = 1.0 / zoom;
        let c = (0.5 * (lo + hi)).clamp(Vec2::splat(half - 1.0), Vec2::splat(1.0 - half));
        // Clip x' = zoom (x − c.x w): the square [c − half, c + half] onto [−1, 1].
        let crop = Mat4::from_cols(
            Vec4::X * zoom,
            Vec4::Y * zoom,
            Vec4::Z,
            Vec4::new(-zoom * c.x, -zoom * c.y, 0.0, 1.0),
        );
        Self {
            view_proj: crop * self.view_proj,
            texel_m: self.texel_m / zoom,
            bias: self.bias / zoom,
            ..self
        }
    }

    /// Where in the map (uv: 0…1 across, y down, as receivers address it) the points inside
    /// the box `lo..hi` that the camera `camera` (world → its clip space, depth 0..1) sees can
    /// lie: the light's image of the part of the box inside the camera's frustum. Empty
    /// (lo > hi on an axis) where the camera sees none of the box; `None` where it cannot be
    /// told (no map, the matrix does not invert, part of it behind the light).
    pub fn seen_box_uv(&self, camera: Mat4, (lo, hi): (Vec3, Vec3)) -> Option<(Vec2, Vec2)> {
        if !(self.drawn && lo.is_finite() && hi.is_finite()) {
            return None;
        }
        // (The points are projected as they are found: a frame that draws the penumbra map
        // calls this, and a frame allocates nothing.)
        let (mut found, mut image) = (false, Some((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN))));
        box_in_frustum(camera, lo, hi, |p| {
            found = true;
            image = image.and_then(|(lo, hi)| {
                let q = self.image_point(p)?;
                Some((lo.min(q), hi.max(q)))
            });
        })?;
        if !found {
            return Some((Vec2::ONE, Vec2::ZERO));
        }
        let (lo, hi) = image?;
        // Clip x, y → uv (y flips).
        let uv = |x: f32, y: f32| Vec2::new(0.5 + 0.5 * x, 0.5 - 0.5 * y);
        Some((uv(lo.x, hi.y), uv(hi.x, lo.y)))
    }

    /// The rectangle (the map's clip x, y) around the light's image of `points`; `None` where
    /// one is behind the light.
    fn image_of(&self, points: &[Vec3]) -> Option<(Vec2, Vec2)> {
        let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
        for &p in points {
            let q = self.image_point(p)?;
            lo = lo.min(q);
            hi = hi.max(q);
        }
        Some((lo, hi))
    }

    /// `p` in the map's clip x, y; `None` behind the light.
    fn image_point(&self, p: Vec3) -> Option<Vec2> {
        let q = self.view_proj * p.extend(1.0);
        (!q.w.is_nan() && q.w > 1e-6).then(|| q.xy() / q.w)
    }

    /// How far receivers move their test point off the surface (m): half the ramp.
    pub fn normal_offset_m(&self) -> f32 {
        NORMAL_OFFSET_TEXELS * self.texel_m
    }

    /// The map's width at the casters (m).
    pub fn width_m(&self) -> f32 {
        self.texel_m * self.size as f32
    }
}

fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::select(glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0), hi, lo)
    })
}

/// Visits the vertices of the intersection of the box `lo..hi` with the frustum of `camera`
/// (world → clip space, depth 0..1): the corners of each inside the other and where the edges
/// of each cross the faces of the other (a convex polytope's vertices are among them, so their
/// hull is the intersection); none where they do not meet, `None` where the matrix does not
/// invert.
fn box_in_frustum(camera: Mat4, lo: Vec3, hi: Vec3, mut visit: impl FnMut(Vec3)) -> Option<()> {
    let inverse = camera.inverse();
    if !inverse.is_finite() {
        return None;
    }
    // The frustum's inside: w ± x, w ± y, z, w − z all ≥ 0 (a little slack for rounding).
    let sides = |p: Vec3| {
        let q = camera * p.extend(1.0);
        [q.w + q.x, q.w - q.x, q.w + q.y, q.w - q.y, q.z, q.w - q.z]
    };
    let in_frustum = |p: Vec3| {
        let q = camera * p.extend(1.0);
        let slack = 1e-4 * q.w.abs().max(1e-6);
        sides(p).iter().all(|&f| f >= -slack)
    };
    // The slack is the box's scale on every axis: a flat box (a plane's, thin on one axis)
    // holds the points rounding puts a hair off it.
    let scale = (hi - lo).length().max(lo.abs().max(hi.abs()).max_element());
    let in_box = |p: Vec3| {
        let e = Vec3::splat(1e-4 * scale.max(1e-6));
        p.cmpge(lo - e).all() && p.cmple(hi + e).all()
    };
    let box_c = box_corners(lo, hi);
    let frustum_c: [Vec3; 8] = std::array::from_fn(|k| {
        let ndc = Vec4::new(
            if k & 1 != 0 { 1.0 } else { -1.0 },
            if k & 2 != 0 { 1.0 } else { -1.0 },
            if k & 4 != 0 { 1.0 } else { 0.0 },
            1.0,
        );
        let q = inverse * ndc;
        q.xyz() / q.w
    });
    if frustum_c.iter().any(|p| !p.is_finite()) {
        return None;
    }
    // The twelve edges of a box-like solid of corners indexed by their x, y, z bits.
    let edges = (0..8usize).flat_map(|a| {
        [1usize, 2, 4]
            .into_iter()
            .filter(move |bit| a & bit == 0)
            .map(move |bit| (a, a | bit))
    });
    box_c
        .iter()
        .copied()
        .filter(|&p| in_frustum(p))
        .for_each(&mut visit);
    frustum_c
        .iter()
        .copied()
        .filter(|&p| in_box(p))
        .for_each(&mut visit);
    for (a, b) in edges {
        // The box's edge across the frustum's planes.
        let (p, q) = (box_c[a], box_c[b]);
        let (fp, fq) = (sides(p), sides(q));
        for (u, v) in fp.into_iter().zip(fq) {
            if (u < 0.0) != (v < 0.0) {
                let x = p + (q - p) * (u / (u - v));
                if in_frustum(x) {
                    visit(x);
                }
            }
        }
        // The frustum's edge across the box's planes.
        let (p, q) = (frustum_c[a], frustum_c[b]);
        for axis in 0..3 {
            for plane in [lo[axis], hi[axis]] {
                let (u, v) = (p[axis] - plane, q[axis] - plane);
                if (u < 0.0) != (v < 0.0) {
                    let x = p + (q - p) * (u / (u - v));
                    if in_box(x) {
                        visit(x);
                    }
                }
            }
        }
    }
    Some(())
}

/// The eight corners of the camera's frustum cut to the depths along its axis that `points`
/// span; `None` where the matrix does not invert or every point is behind the camera.
fn seen_part(camera: Mat4, points: &[Vec3]) -> Option<[Vec3; 8]> {
    let inverse = camera.inverse();
    let at = |x: f32, y: f32, z: f32| {
        let q = inverse * Vec4::new(x, y, z, 1.0);
        let p = q.xyz() / q.w;
        p.is_finite().then_some(p)
    };
    let (near, far) = (at(0.0, 0.0, 0.0)?, at(0.0, 0.0, 1.0)?);
    let axis = (far - near).try_normalize()?;
    let (mut d0, mut d1) = (f32::MAX, f32::MIN);
    for p in points {
        let d = (*p - near).dot(axis);
        d0 = d0.min(d);
        d1 = d1.max(d);
    }
    if d1.is_nan() || d1 <= 0.0 {
        return None;
    }
    let depths = [d0.max(0.0), d1];
    let mut out = [Vec3::ZERO; 8];
    let corners = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)];
    for (k, (x, y)) in corners.into_iter().enumerate() {
        let (a, b) = (at(x, y, 0.0)?, at(x, y, 1.0)?);
        let (da, db) = ((a - near).dot(axis), (b - near).dot(axis));
        for (j, depth) in depths.into_iter().enumerate() {
            let t = ((depth - da) / (db - da)).clamp(0.0, 1.0);
            out[2 * k + j] = a + (b - a) * if t.is_finite() { t } else { 0.0 };
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(v: &ShadowView, p: Vec3) -> Vec3 {
        let q = v.view_proj * p.extend(1.0);
        q.truncate() / q.w
    }

    #[test]
    fn receivers_lie_where_the_light_sees_the_box_the_camera_sees() {
        // A 0.6 × 1.8 × 0.4 m figure lit from the side and above; its map fitted to it.
        let (lo, hi) = (Vec3::new(-0.3, 0.0, -0.2), Vec3::new(0.3, 1.8, 0.2));
        let light = Vec3::new(2.0, 3.0, 1.0);
        let (centre, radius) = (0.5 * (lo + hi), 0.5 * (hi - lo).length());
        let v = ShadowView::fit(light, centre, radius, 1024);
        let area = |(a, b): (Vec2, Vec2)| (b - a).max(Vec2::ZERO).element_product();
        let camera = |eye: Vec3, at: Vec3| crate::camera::look_at(eye, at, 0.6, 16.0 / 9.0);
        // The whole figure in view: its whole image.
        let whole = v.seen_box_uv(
            camera(Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 0.9, 0.0)),
            (lo, hi),
        );
        let whole = whole.expect("a rectangle");
        let corners = box_corners(lo, hi);
        let uv = |p: Vec3| {
            let q = project(&v, p);
            Vec2::new(0.5 + 0.5 * q.x, 0.5 - 0.5 * q.y)
        };
        for c in corners {
            let p = uv(c);
            assert!(
                p.cmpge(whole.0 - 1e-4).all() && p.cmple(whole.1 + 1e-4).all(),
                "{p} {whole:?}"
            );
        }
        // A close-up of the head: a part of it, which holds the head's image.
        let head = camera(Vec3::new(0.0, 1.65, 0.6), Vec3::new(0.0, 1.6, 0.0));
        let part = v.seen_box_uv(head, (lo, hi)).expect("a rectangle");
        assert!(area(part) < 0.6 * area(whole), "{part:?} {whole:?}");
        for p in [
            Vec3::new(0.0, 1.6, 0.1),
            Vec3::new(0.1, 1.7, 0.0),
            Vec3::new(-0.1, 1.55, 0.15),
        ] {
            let p = uv(p);
            assert!(
                p.cmpge(part.0).all() && p.cmple(part.1).all(),
                "{p} {part:?}"
            );
        }
        // Looking away: nothing; from inside the box: something.
        let away = v.seen_box_uv(
            camera(Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 1.0, 10.0)),
            (lo, hi),
        );
        assert_eq!(away.map(area), Some(0.0));
        let inside = v.seen_box_uv(
            camera(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)),
            (lo, hi),
        );
        assert!(inside.map(area).unwrap_or(0.0) > 0.0);
        // No map: not known.
        assert!(ShadowView::NONE.seen_box_uv(head, (lo, hi)).is_none());
    }

    #[test]
    fn a_flat_box_wider_than_the_view_is_seen_where_the_view_meets_it() {
        // A plane's box (no height) 0.33 m across under a camera looking straight down at
        // 0.22 m of it: no corner of either lies inside the other, the seen part is where the
        // frustum's edges cross the plane.
        let (lo, hi) = (
            Vec3::new(-0.1665, 0.0, -0.1665),
            Vec3::new(0.1665, 0.0, 0.1665),
        );
        let v = ShadowView::fit(
            Vec3::new(0.0, 1000.0, 0.0),
            Vec3::new(0.0, 0.0139, 0.0),
            0.165,
            4096,
        );
        // (The edge scene's camera: 1 m up, 0.111 m either way, depth 0.01–10 m.)
        let camera = Mat4::from_cols(
            Vec4::new(-9.008198, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -0.1001001, 0.0),
            Vec4::new(0.0, 9.008198, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.0990991, 1.0),
        );
        let (a, b) = v.seen_box_uv(camera, (lo, hi)).expect("a rectangle");
        let q = project(&v, Vec3::new(1.0 / 9.008198, 0.0, 1.0 / 9.008198));
        let half = 0.5 * q.x.abs().max(q.y.abs());
        for (got, want) in [(a, Vec2::splat(0.5 - half)), (b, Vec2::splat(0.5 + half))] {
            assert!(
                (got - want).abs().max_element() < 1e-3,
                "{a} {b}: want ±{half}"
            );
        }
    }

    #[test]
    fn the_frustum_holds_the_casters_sphere() {
        for (light, r) in [
            (Vec3::new(1.5, 3.0, 2.5), 1.0),
            (Vec3::new(0.0, 1000.0, 0.0), 0.1),
            (Vec3::new(700.0, 700.0, 0.0), 0.2),
        ] {
            let v = ShadowView::fit(light, Vec3::ZERO, r, 1024);
            assert!(v.drawn);
            let toward = light.normalize();
            let side = toward.any_orthonormal_vector();
            // The sphere's nearest and farthest points and a point on its rim.
            for p in [toward * r, -toward * r, side * r * 0.999] {
                let n = project(&v, p);
                assert!(
                    n.x.abs() <= 1.0 + 1e-4 && n.y.abs() <= 1.0 + 1e-4,
                    "{p} → {n}"
                );
                assert!((-1e-4..=1.0 + 1e-4).contains(&n.z), "{p} → {n}");
            }
            // Nearer the light is smaller depth.
            assert!(project(&v, toward * r * 0.5).z < project(&v, -toward * r * 0.5).z);
            assert!(v.texel_m > 0.0 && v.bias > 0.0 && v.bias < 0.01);
        }
    }

    #[test]
    fn a_light_inside_the_casters_casts_no_map() {
        let v = ShadowView::fit(Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO, 1.0, 1024);
        assert!(!v.drawn);
        assert_eq!(v.normal_offset_m(), 0.0);
        assert!(!ShadowView::fit(Vec3::ONE, Vec3::ZERO, f32::NAN, 1024).drawn);
    }
}

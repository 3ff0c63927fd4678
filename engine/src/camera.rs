//! Follow camera: a critically damped spring on the eye position and on the look-at target.
//!
//! The spring is integrated in closed form for a target that moves linearly over the step,
//! so the result does not depend on the frame rate (only on how finely the target's own path
//! is sampled). After each step the eye is pushed out of the character's bounding capsule.

use glam::camera::rh::{proj::directx, view};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// A vertical capsule around the character (segment from `base` up `height`, radius `radius`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    pub base: Vec3,
    pub height: f32,
    pub radius: f32,
}

impl Capsule {
    /// The point of the capsule's axis closest to `p`.
    fn axis_point(&self, p: Vec3) -> Vec3 {
        let y = (p.y - self.base.y).clamp(0.0, self.height);
        Vec3::new(self.base.x, self.base.y + y, self.base.z)
    }

    pub fn contains(&self, p: Vec3) -> bool {
        p.distance(self.axis_point(p)) < self.radius
    }

    /// `p` moved to the capsule's surface (plus `margin`) if it is inside.
    pub fn push_out(&self, p: Vec3, margin: f32) -> Vec3 {
        let a = self.axis_point(p);
        let d = p - a;
        let len = d.length();
        let r = self.radius + margin;
        if len >= r {
            return p;
        }
        let dir = if len > 1e-6 { d / len } else { Vec3::Z };
        a + dir * r
    }
}

/// One critically damped spring (per axis) with angular frequency `omega`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    pub value: Vec3,
    pub velocity: Vec3,
    pub omega: f32,
    /// Where the target was at the end of the previous step.
    target: Vec3,
}

impl Spring {
    pub fn new(value: Vec3, omega: f32) -> Self {
        Self {
            value,
            velocity: Vec3::ZERO,
            omega,
            target: value,
        }
    }

    /// Advances `dt` seconds while the target moves linearly to `target`.
    pub fn step(&mut self, target: Vec3, dt: f32) {
        if dt <= 0.0 || !dt.is_finite() {
            self.target = target;
            return;
        }
        let w = self.omega;
        let u = (target - self.target) / dt; // target velocity over the step
                                             // e = x − c(t) obeys e'' + 2ωe' + ω²e = −2ωu; shift by the particular solution −2u/ω.
        let shift = -2.0 * u / w;
        let h0 = self.value - self.target - shift;
        let h0v = self.velocity - u;
        let k = h0v + w * h0;
        let decay = (-w * dt).exp();
        let h = (h0 + k * dt) * decay;
        let hv = (h0v - w * k * dt) * decay;
        self.value = target + h + shift;
        self.velocity = hv + u;
        self.target = target;
    }

    /// Jumps to `value` at rest.
    pub fn reset(&mut self, value: Vec3) {
        *self = Self::new(value, self.omega);
    }
}

/// A third-person camera that follows a character from behind and above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowCamera {
    pub eye: Spring,
    pub look: Spring,
    /// Eye offset from the character in its own frame (x right, y up, z forward; z < 0 behind).
    pub offset: Vec3,
    /// Look-at point relative to the character's feet.
    pub look_offset: Vec3,
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
}

impl FollowCamera {
    /// The springs' default angular frequencies (1/s) for the eye and the look-at point. A
    /// spring trails a target moving at speed u by 2u/ω: at 12 m/s the eye sits 4 m behind
    /// its offset.
    pub const EYE_OMEGA: f32 = 6.0;
    pub const LOOK_OMEGA: f32 = 10.0;

    pub fn new(offset: Vec3, look_offset: Vec3) -> Self {
        Self {
            eye: Spring::new(offset, Self::EYE_OMEGA),
            look: Spring::new(look_offset, Self::LOOK_OMEGA),
            offset,
            look_offset,
            fov_y: 50f32.to_radians(),
            near: 0.05,
            far: 200.0,
        }
    }

    fn desired(&self, position: Vec3, yaw: f32) -> (Vec3, Vec3) {
        let rot = glam::Quat::from_rotation_y(yaw);
        (
            position + rot * self.offset,
            position + rot * self.look_offset,
        )
    }

    /// Places the camera at rest behind the character.
    pub fn snap(&mut self, position: Vec3, yaw: f32) {
        let (eye, look) = self.desired(position, yaw);
        self.eye.reset(eye);
        self.look.reset(look);
    }

    /// A look-at target further than this (m) from the camera's is a teleport — a new run, a
    /// respawn — and the camera snaps to it: chasing it would show a second of empty floor.
    pub const SNAP_DISTANCE: f32 = 8.0;

    /// Follows the character (feet `position`, facing `yaw` about +Y) for `dt` seconds and keeps
    /// the eye outside `capsule`; snaps when the character teleported ([`Self::SNAP_DISTANCE`]).
    pub fn update(&mut self, dt: f32, position: Vec3, yaw: f32, capsule: &Capsule) {
        let (eye, look) = self.desired(position, yaw);
        if look.distance(self.look.value) > Self::SNAP_DISTANCE {
            self.snap(position, yaw);
            return;
        }
        self.eye.step(eye, dt);
        self.look.step(look, dt);
        if capsule.contains(self.eye.value) {
            self.eye.value = capsule.push_out(self.eye.value, self.near * 2.0);
        }
    }

    pub fn view(&self) -> Mat4 {
        view::look_at_mat4(self.eye.value, self.look.value, Vec3::Y)
    }

    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        directx::perspective(self.fov_y, aspect.max(1e-3), self.near, self.far) * self.view()
    }

    /// Where the camera is now, as drawn (no lens shift).
    pub fn pose(&self) -> CameraPose {
        CameraPose {
            eye: self.eye.value,
            look: self.look.value,
            fov_y: self.fov_y,
            shift: Vec2::ZERO,
            near: self.near,
            far: self.far,
        }
    }
}

/// A camera as drawn: eye, look-at point, vertical field of view, clip planes and a lens
/// shift (the image moved by `shift` in normalised device coordinates, x right, y up, so the
/// look-at point lands off centre without turning the camera).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    pub eye: Vec3,
    pub look: Vec3,
    pub fov_y: f32,
    pub shift: Vec2,
    pub near: f32,
    pub far: f32,
}

impl CameraPose {
    pub fn view(&self) -> Mat4 {
        view::look_at_mat4(self.eye, self.look, Vec3::Y)
    }

    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let shift = Mat4::from_cols(
            Vec4::X,
            Vec4::Y,
            Vec4::Z,
            Vec4::new(self.shift.x, self.shift.y, 0.0, 1.0),
        );
        shift
            * directx::perspective(self.fov_y, aspect.max(1e-3), self.near, self.far)
            * self.view()
    }
}

/// The six planes of a view-projection's clip volume (depth 0..1), for culling bounding
/// spheres: Gribb and Hartmann's rows of the clip matrix, normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    planes: [Vec4; 6],
}

impl Frustum {
    pub fn new(view_proj: Mat4) -> Self {
        let r = [
            view_proj.row(0),
            view_proj.row(1),
            view_proj.row(2),
            view_proj.row(3),
        ];
        let planes = [
            r[3] + r[0],
            r[3] - r[0],
            r[3] + r[1],
            r[3] - r[1],
            r[2],
            r[3] - r[2],
        ]
        .map(|p| p / p.truncate().length().max(1e-12));
        Self { planes }
    }

    /// Whether any of the sphere (`centre`, `radius`) may be inside (conservative near the
    /// frustum's corners).
    pub fn sphere_visible(&self, centre: Vec3, radius: f32) -> bool {
        self.planes
            .iter()
            .all(|p| p.truncate().dot(centre) + p.w >= -radius)
    }
}

/// A fixed camera looking from `eye` at `target` (for `render` and benches).
pub fn look_at(eye: Vec3, target: Vec3, fov_y: f32, aspect: f32) -> Mat4 {
    directx::perspective(fov_y, aspect.max(1e-3), 0.05, 200.0)
        * view::look_at_mat4(eye, target, Vec3::Y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frustum_keeps_what_the_camera_sees_and_drops_what_is_behind_or_aside() {
        let pose = CameraPose {
            eye: Vec3::new(0.0, 1.5, 5.0),
            look: Vec3::new(0.0, 1.0, 0.0),
            fov_y: 0.8,
            shift: Vec2::ZERO,
            near: 0.1,
            far: 100.0,
        };
        let f = Frustum::new(pose.view_proj(16.0 / 9.0));
        assert!(f.sphere_visible(Vec3::new(0.0, 1.0, 0.0), 0.1));
        // Behind the eye, beyond the far plane, far to the side: out, unless big enough to
        // reach back in.
        assert!(!f.sphere_visible(Vec3::new(0.0, 1.5, 8.0), 1.0));
        assert!(f.sphere_visible(Vec3::new(0.0, 1.5, 8.0), 3.5));
        assert!(!f.sphere_visible(Vec3::new(0.0, 1.0, -120.0), 5.0));
        assert!(!f.sphere_visible(Vec3::new(40.0, 1.0, 0.0), 2.0));
        // Just off the left edge, overlapping it by a little.
        let half_w = (0.4f32).tan() * 5.0 * 16.0 / 9.0;
        assert!(f.sphere_visible(Vec3::new(-half_w - 0.5, 1.0, 0.0), 0.6));
        assert!(!f.sphere_visible(Vec3::new(-half_w - 0.5, 1.0, 0.0), 0.2));
    }

    /// Scripted path: the character runs a curve, accelerating.
    fn path(t: f32) -> (Vec3, f32) {
        let yaw = 0.4 * t;
        (
            Vec3::new(3.0 * (0.5 * t).sin(), 0.0, 2.0 * t + 0.3 * t * t),
            yaw,
        )
    }

    fn run(hz: f32, seconds: f32) -> Vec<(f32, Vec3)> {
        let mut cam = FollowCamera::new(Vec3::new(0.0, 1.8, -3.5), Vec3::new(0.0, 1.0, 0.0));
        let (p0, y0) = path(0.0);
        cam.snap(p0, y0);
        let dt = 1.0 / hz;
        let steps = (seconds * hz).round() as usize;
        let mut out = Vec::new();
        for i in 1..=steps {
            let t = i as f32 * dt;
            let (p, yaw) = path(t);
            let capsule = Capsule {
                base: p,
                height: 1.8,
                radius: 0.4,
            };
            cam.update(dt, p, yaw, &capsule);
            assert!(
                !capsule.contains(cam.eye.value),
                "eye inside capsule at t={t}"
            );
            out.push((t, cam.eye.value));
        }
        out
    }

    #[test]
    fn frame_rate_independent_within_a_centimetre() {
        let a = run(30.0, 6.0);
        let b = run(60.0, 6.0);
        let c = run(144.0, 6.0);
        // Compare at the whole-second marks every rate hits.
        for s in 1..=6 {
            let t = s as f32;
            let at = |v: &[(f32, Vec3)]| {
                v.iter()
                    .min_by(|x, y| (x.0 - t).abs().total_cmp(&(y.0 - t).abs()))
                    .unwrap()
                    .1
            };
            let (pa, pb, pc) = (at(&a), at(&b), at(&c));
            assert!(
                pa.distance(pb) < 0.01 && pb.distance(pc) < 0.01,
                "t={t}: {pa} {pb} {pc}"
            );
        }
    }

    #[test]
    fn spring_settles_on_a_still_target() {
        let mut s = Spring::new(Vec3::ZERO, 6.0);
        for _ in 0..600 {
            s.step(Vec3::new(1.0, 2.0, 3.0), 1.0 / 60.0);
        }
        assert!(s.value.distance(Vec3::new(1.0, 2.0, 3.0)) < 1e-4);
    }

    #[test]
    fn capsule_push_out() {
        let c = Capsule {
            base: Vec3::ZERO,
            height: 2.0,
            radius: 0.5,
        };
        let p = c.push_out(Vec3::new(0.1, 1.0, 0.0), 0.0);
        assert!((p.distance(Vec3::new(0.0, 1.0, 0.0)) - 0.5).abs() < 1e-5);
        assert!(!c.contains(c.push_out(Vec3::new(0.0, 1.0, 0.0), 0.01)));
    }
}

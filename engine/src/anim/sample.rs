//! Channel sampling per the glTF 2.0 spec (Appendix C): clamping outside the key range,
//! STEP, LINEAR (quaternions: shortest-path slerp) and CUBICSPLINE (Hermite, tangents scaled
//! by the key interval; quaternions normalised).

use glam::{Quat, Vec3, Vec4};

use crate::asset::{Channel, Interpolation};

/// Where `t` falls in the key times.
enum At {
    /// Exactly one key applies (before the first, after the last, single key or STEP).
    Key(usize),
    /// Between key `i` and `i + 1`: (i, normalised u in [0,1), interval length).
    Between(usize, f32, f32),
}

fn locate(times: &[f32], interpolation: Interpolation, t: f32) -> At {
    let last = times.len().saturating_sub(1);
    if times.is_empty() || t.is_nan() || t <= times[0] {
        return At::Key(0);
    }
    if t >= times[last] {
        return At::Key(last);
    }
    // First key strictly after t (≥ 1 and ≤ last here).
    let next = times.partition_point(|&k| k <= t).clamp(1, last);
    let i = next - 1;
    if interpolation == Interpolation::Step {
        return At::Key(i);
    }
    let dt = times[next] - times[i];
    let u = if dt > 0.0 {
        ((t - times[i]) / dt).clamp(0.0, 1.0)
    } else {
        0.0
    };
    At::Between(i, u, dt)
}

/// Component `n`-vector of key `k`: for cubic spline `part` 0 = in-tangent, 1 = value,
/// 2 = out-tangent; ignored otherwise.
fn get(ch: &Channel, n: usize, k: usize, part: usize) -> Vec4 {
    let stride = if ch.interpolation == Interpolation::CubicSpline {
        3 * n
    } else {
        n
    };
    let off = if ch.interpolation == Interpolation::CubicSpline {
        part * n
    } else {
        0
    };
    let at = k * stride + off;
    let mut v = [0.0f32; 4];
    if let Some(s) = ch.values.get(at..at + n) {
        v[..n].copy_from_slice(s);
    }
    Vec4::from_array(v)
}

fn hermite(ch: &Channel, n: usize, i: usize, u: f32, dt: f32) -> Vec4 {
    let p0 = get(ch, n, i, 1);
    let m0 = get(ch, n, i, 2) * dt;
    let p1 = get(ch, n, i + 1, 1);
    let m1 = get(ch, n, i + 1, 0) * dt;
    let (u2, u3) = (u * u, u * u * u);
    p0 * (2.0 * u3 - 3.0 * u2 + 1.0)
        + m0 * (u3 - 2.0 * u2 + u)
        + p1 * (-2.0 * u3 + 3.0 * u2)
        + m1 * (u3 - u2)
}

/// Samples a translation or scale channel at time `t` (seconds).
pub fn sample_vec3(ch: &Channel, t: f32) -> Vec3 {
    let v = match locate(&ch.times, ch.interpolation, t) {
        At::Key(k) => get(ch, 3, k, 1),
        At::Between(i, u, dt) => match ch.interpolation {
            Interpolation::CubicSpline => hermite(ch, 3, i, u, dt),
            _ => get(ch, 3, i, 1).lerp(get(ch, 3, i + 1, 1), u),
        },
    };
    v.truncate()
}

fn quat(v: Vec4) -> Quat {
    let q = Quat::from_vec4(v);
    let len = q.length();
    if len > 1e-12 && len.is_finite() {
        q / len
    } else {
        Quat::IDENTITY
    }
}

/// Shortest-path spherical interpolation of unit quaternions (negates `b` when `a·b < 0`).
pub(crate) fn slerp_shortest(a: Quat, b: Quat, u: f32) -> Quat {
    let mut b = b;
    let mut d = a.dot(b);
    if d < 0.0 {
        b = -b;
        d = -d;
    }
    if d > 0.9995 {
        // Nearly parallel: normalised lerp is exact enough and avoids dividing by sin(≈0).
        return quat(Vec4::from(a).lerp(Vec4::from(b), u));
    }
    let theta = d.min(1.0).acos();
    let s = theta.sin();
    let wa = ((1.0 - u) * theta).sin() / s;
    let wb = (u * theta).sin() / s;
    quat(Vec4::from(a) * wa + Vec4::from(b) * wb)
}

/// Samples a rotation channel at time `t` (seconds); the result is a unit quaternion.
pub fn sample_quat(ch: &Channel, t: f32) -> Quat {
    match locate(&ch.times, ch.interpolation, t) {
        At::Key(k) => quat(get(ch, 4, k, 1)),
        At::Between(i, u, dt) => match ch.interpolation {
            Interpolation::CubicSpline => quat(hermite(ch, 4, i, u, dt)),
            _ => slerp_shortest(quat(get(ch, 4, i, 1)), quat(get(ch, 4, i + 1, 1)), u),
        },
    }
}

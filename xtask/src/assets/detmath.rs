//! Deterministic scalar maths.
//!
//! `f32::sin`, `powf`, `acos`… call the platform libm, whose last-bit results may differ between
//! C libraries and versions. The asset generator must be byte-for-byte reproducible, so every
//! transcendental it needs is computed here from `+ - * /` and `sqrt` only (all IEEE-754 exact-rounded).

pub const PI: f32 = std::f32::consts::PI;
pub const TAU: f32 = std::f32::consts::TAU;

/// (sin x, cos x), evaluated in f64 with a range reduction and Taylor series (|err| < 1e-12).
pub fn sin_cos(x: f32) -> (f32, f32) {
    let (s, c) = sin_cos64(x as f64);
    (s as f32, c as f32)
}

pub fn sin(x: f32) -> f32 {
    sin_cos(x).0
}

pub fn cos(x: f32) -> f32 {
    sin_cos(x).1
}

fn sin_cos64(x: f64) -> (f64, f64) {
    let tau = std::f64::consts::TAU;
    // Reduce to [-pi, pi] then to [-pi/4, pi/4] with a quadrant.
    let k = (x / tau).round();
    let r = x - k * tau;
    let q = (r / std::f64::consts::FRAC_PI_2).round();
    let y = r - q * std::f64::consts::FRAC_PI_2;
    let y2 = y * y;
    let mut s = 0.0;
    let mut c = 0.0;
    // Horner form of the Taylor series up to y^17 / y^16.
    let mut term_s = 1.0;
    let mut term_c = 1.0;
    for n in (1..=8).rev() {
        let ns = (2 * n) as f64 * (2 * n + 1) as f64;
        let nc = (2 * n - 1) as f64 * (2 * n) as f64;
        term_s = 1.0 - y2 / ns * term_s;
        term_c = 1.0 - y2 / nc * term_c;
    }
    s += y * term_s;
    c += term_c;
    match (q as i64).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// atan(x) for any x, via argument halving and a series.
fn atan64(x: f64) -> f64 {
    if x < 0.0 {
        return -atan64(-x);
    }
    if x > 1.0 {
        return std::f64::consts::FRAC_PI_2 - atan64(1.0 / x);
    }
    // Two halvings: atan(x) = 2 atan(x / (1 + sqrt(1 + x^2))).
    let mut y = x;
    for _ in 0..3 {
        y /= 1.0 + (1.0 + y * y).sqrt();
    }
    let y2 = y * y;
    let mut sum = 0.0;
    for n in (0..12).rev() {
        sum = 1.0 / (2 * n + 1) as f64 - y2 * sum;
    }
    8.0 * y * sum
}

pub fn atan2(y: f32, x: f32) -> f32 {
    let (y, x) = (y as f64, x as f64);
    let pi = std::f64::consts::PI;
    let r = if x > 0.0 {
        atan64(y / x)
    } else if x < 0.0 {
        if y >= 0.0 {
            atan64(y / x) + pi
        } else {
            atan64(y / x) - pi
        }
    } else if y > 0.0 {
        pi / 2.0
    } else if y < 0.0 {
        -pi / 2.0
    } else {
        0.0
    };
    r as f32
}

/// acos with the argument clamped to [-1, 1].
pub fn acos(x: f32) -> f32 {
    let x = x.clamp(-1.0, 1.0);
    atan2((1.0 - x * x).max(0.0).sqrt(), x)
}

pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Unit quaternion for a rotation of `angle` radians about unit `axis` (no libm).
pub fn quat_axis_angle(axis: glam::Vec3, angle: f32) -> glam::Quat {
    let (s, c) = sin_cos(angle * 0.5);
    let a = axis.normalize();
    glam::Quat::from_xyzw(a.x * s, a.y * s, a.z * s, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_std_closely() {
        for i in -200..200 {
            let x = i as f32 * 0.077;
            assert!((sin(x) - x.sin()).abs() < 1e-6, "sin {x}");
            assert!((cos(x) - x.cos()).abs() < 1e-6, "cos {x}");
            let y = i as f32 * 0.031 - 0.4;
            assert!((atan2(y, x) - y.atan2(x)).abs() < 1e-6, "atan2 {y} {x}");
        }
        for i in -10..=10 {
            let x = i as f32 / 10.0;
            assert!((acos(x) - x.acos()).abs() < 1e-5);
        }
    }
}

//! Independent closed forms of the Jensen et al. 2001 dipole, used only to check the Monte
//! Carlo reference and the lead's production dipole module (duplicated on purpose).
#![allow(dead_code)]

use std::f64::consts::PI;

/// Diffuse Fresnel reflectance fit F_dr(η) = −1.440/η² + 0.710/η + 0.668 + 0.0636 η.
pub(crate) fn f_dr(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// A = (1 + F_dr)/(1 − F_dr).
pub(crate) fn a_coef(eta: f64) -> f64 {
    let f = f_dr(eta);
    (1.0 + f) / (1.0 - f)
}

/// Closed-form total diffuse reflectance
/// R_d = (α'/2)(1 + e^{−(4/3)A√(3(1−α'))}) e^{−√(3(1−α'))}, with 1 − α' = σ_a/σ'_t.
pub(crate) fn total_rd(sigma_a: f64, sigma_s_prime: f64, eta: f64) -> f64 {
    let st = sigma_a + sigma_s_prime;
    let alpha = sigma_s_prime / st;
    let s = (3.0 * sigma_a / st).sqrt();
    let a = a_coef(eta);
    0.5 * alpha * (1.0 + (-(4.0 / 3.0) * a * s).exp()) * (-s).exp()
}

/// Standard-form dipole profile R_d(r) in mm⁻²:
/// α'/(4π) [z_r(σ_tr d_r + 1)e^{−σ_tr d_r}/d_r³ + z_v(σ_tr d_v + 1)e^{−σ_tr d_v}/d_v³].
pub(crate) fn profile_rd(r: f64, sigma_a: f64, sigma_s_prime: f64, eta: f64) -> f64 {
    let st = sigma_a + sigma_s_prime;
    let alpha = sigma_s_prime / st;
    let s_tr = (3.0 * sigma_a * st).sqrt();
    let zr = 1.0 / st;
    let zv = zr * (1.0 + 4.0 * a_coef(eta) / 3.0);
    let term = |z: f64| {
        let d = (r * r + z * z).sqrt();
        z * (s_tr * d + 1.0) * (-s_tr * d).exp() / (d * d * d)
    };
    alpha / (4.0 * PI) * (term(zr) + term(zv))
}

#[allow(clippy::too_many_arguments)]
fn simpson(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        left + right + delta / 15.0
    } else {
        simpson(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1)
            + simpson(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1)
    }
}

/// Adaptive Simpson quadrature of `f` on [a, b] to absolute tolerance `tol`.
pub(crate) fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let (fa, fb, fm) = (f(a), f(b), f(0.5 * (a + b)));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson(f, a, b, fa, fm, fb, whole, tol, 50)
}

/// ∫₀^∞ 2πr R_d(r) dr by adaptive quadrature after the substitution r = L t/(1 − t),
/// L = 1/σ_tr + z_v (so the profile's scale maps near the middle of [0, 1)).
pub(crate) fn integrated_profile_rd(sigma_a: f64, sigma_s_prime: f64, eta: f64) -> f64 {
    let st = sigma_a + sigma_s_prime;
    let s_tr = (3.0 * sigma_a * st).sqrt();
    let zv = (1.0 + 4.0 * a_coef(eta) / 3.0) / st;
    let l = zv + if s_tr > 0.0 { 1.0 / s_tr } else { 0.0 };
    let f = |t: f64| {
        if t >= 1.0 {
            return 0.0;
        }
        let r = l * t / (1.0 - t);
        let dr = l / ((1.0 - t) * (1.0 - t));
        2.0 * PI * r * profile_rd(r, sigma_a, sigma_s_prime, eta) * dr
    };
    integrate(&f, 0.0, 1.0, 1e-12)
}

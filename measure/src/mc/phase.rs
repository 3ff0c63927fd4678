//! Henyey–Greenstein phase-function sampling and direction rotation.

/// Samples cos θ of the Henyey–Greenstein phase function with anisotropy `g` from a uniform
/// `u` ∈ [0, 1). `g == 0` is exactly isotropic (cos θ = 2u − 1).
#[inline]
pub fn sample_hg_cos(g: f64, u: f64) -> f64 {
    if g == 0.0 {
        return 2.0 * u - 1.0;
    }
    let t = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    ((1.0 + g * g - t * t) / (2.0 * g)).clamp(-1.0, 1.0)
}

/// Rotates unit direction `d` by polar angle (cos θ = `cos_t`) and azimuth `phi` about
/// itself (the MCML update), returning a renormalised unit vector.
#[inline]
pub fn rotate(d: [f64; 3], cos_t: f64, phi: f64) -> [f64; 3] {
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (sin_p, cos_p) = phi.sin_cos();
    let [ux, uy, uz] = d;
    let n = if uz.abs() > 1.0 - 1e-10 {
        [sin_t * cos_p, sin_t * sin_p, uz.signum() * cos_t]
    } else {
        let tmp = (1.0 - uz * uz).sqrt();
        [
            sin_t * (ux * uz * cos_p - uy * sin_p) / tmp + ux * cos_t,
            sin_t * (uy * uz * cos_p + ux * sin_p) / tmp + uy * cos_t,
            -sin_t * cos_p * tmp + uz * cos_t,
        ]
    };
    let inv = 1.0 / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    [n[0] * inv, n[1] * inv, n[2] * inv]
}

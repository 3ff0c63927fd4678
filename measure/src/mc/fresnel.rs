//! Unpolarised dielectric Fresnel reflection/transmission at a smooth interface.

/// Fresnel reflectance for unpolarised light hitting a smooth interface from a medium of
/// index n_i into one of index n_t, `eta = n_t / n_i`, with `cos_i` ∈ [0, 1] the cosine of
/// the angle of incidence. Returns `(R, cos_t)`, `cos_t` the cosine of the refracted
/// direction. Total internal reflection gives `(1, 0)`; `eta == 1` gives exactly `(0, cos_i)`.
#[inline]
pub fn fresnel(cos_i: f64, eta: f64) -> (f64, f64) {
    let cos_i = cos_i.clamp(0.0, 1.0);
    if eta == 1.0 {
        return (0.0, cos_i);
    }
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin_t2 >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

/// Fresnel transmittance (power) computed independently from the transmission amplitudes
/// t_s = 2cosθ_i/(cosθ_i + η cosθ_t), t_p = 2cosθ_i/(η cosθ_i + cosθ_t),
/// T = η cosθ_t/cosθ_i · (t_s² + t_p²)/2. Used to check R + T = 1.
pub fn fresnel_transmittance(cos_i: f64, eta: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin_t2 >= 1.0 || cos_i == 0.0 {
        return 0.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let ts = 2.0 * cos_i / (cos_i + eta * cos_t);
    let tp = 2.0 * cos_i / (eta * cos_i + cos_t);
    eta * cos_t / cos_i * 0.5 * (ts * ts + tp * tp)
}

//! Fresnel terms shared by the models (WGSL: `shaders/fresnel.wgsl`).

/// Diffuse Fresnel reflectance F_dr(η), the polynomial fit used by Jensen 2001 and eq. 4:
/// F_dr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η. Valid for η ≥ 1; clamped to [0, 1).
pub fn diffuse_reflectance(eta: f64) -> f64 {
    let f = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    f.clamp(0.0, 0.999)
}

/// A = (1 + F_dr) / (1 − F_dr), the boundary mismatch factor of the dipole.
pub fn boundary_a(eta: f64) -> f64 {
    let f = diffuse_reflectance(eta);
    (1.0 + f) / (1.0 - f)
}

/// Unpolarised dielectric Fresnel reflectance for light arriving from outside (index 1) onto
/// a medium of relative index η, at incidence cosine `cos_i` ∈ [0, 1].
pub fn reflectance(eta: f64, cos_i: f64) -> f64 {
    let c = cos_i.clamp(0.0, 1.0);
    let sin_t2 = (1.0 - c * c) / (eta * eta);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (c - eta * cos_t) / (c + eta * cos_t);
    let rp = (eta * c - cos_t) / (eta * c + cos_t);
    if !(rs.is_finite() && rp.is_finite()) {
        return 1.0; // c = 0 exactly: grazing, everything reflects
    }
    0.5 * (rs * rs + rp * rp)
}

/// F_t = 1 − F_r.
pub fn transmittance(eta: f64, cos_i: f64) -> f64 {
    1.0 - reflectance(eta, cos_i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_matched_boundary_is_transparent() {
        assert!(reflectance(1.0, 0.3).abs() < 1e-12);
        assert!((transmittance(1.0, 1.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn normal_incidence_matches_closed_form() {
        let eta: f64 = 1.4;
        let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
        assert!((reflectance(eta, 1.0) - r0).abs() < 1e-12);
        assert_eq!(reflectance(eta, 0.0), 1.0);
    }

    #[test]
    fn diffuse_fresnel_of_skin() {
        // Jensen 2001 skin1 uses η = 1.3.
        let f = diffuse_reflectance(1.3);
        assert!((f - 0.44476).abs() < 1e-4, "{f}");
    }
}

//! Fresnel terms shared by the models (WGSL: `shaders/fresnel.wgsl`).

/// Smallest η [`diffuse_reflectance`] distinguishes (see there).
pub const ETA_MIN: f64 = 1.0 / 3.0;

/// Diffuse Fresnel reflectance F_dr(η) (internal: light diffusing inside a medium of relative
/// index η hits its boundary), the polynomial fit used by Jensen 2001 and eq. 4:
/// F_dr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η, clamped to [0, 0.999].
///
/// Hard cases (issue 4 §2):
/// * The fit is for η ≥ 1 only. For η < 1 (a medium optically thinner than its surround) the
///   internal reflectance follows from the reciprocity of diffuse transmittances across one
///   interface, T_out→in(μ) = μ² T_in→out(μ) with μ = 1/η > 1:
///   F_dr(η) = 1 − (1 − F_fit(1/η)) / η². It equals the fit at η = 1 (continuous, with a kink)
///   and stays in [0, 1). The fit is used up to 1/η = 3 (F_fit(3) = 0.94; beyond, its linear
///   term runs to the 0.999 clamp and μ²(1 − F) stops making sense), so η < 1/3 is clamped to
///   1/3 ([`ETA_MIN`]); F_dr is increasing in 1/η on the whole range (tested).
/// * At η = 1 the fit gives 0.0016, not 0 (no boundary): a fit error, left as published
///   (A(1) = 1.0032), so the models stay those of the paper.
/// * NaN is treated as η = 1.
pub fn diffuse_reflectance(eta: f64) -> f64 {
    let fit = |eta: f64| -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    let eta = if eta.is_nan() { 1.0 } else { eta.max(ETA_MIN) };
    let f = if eta >= 1.0 {
        fit(eta)
    } else {
        let mu = 1.0 / eta;
        1.0 - (1.0 - fit(mu).clamp(0.0, 0.999)) / (eta * eta)
    };
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

/// f64 twin of `fresnel_transmittance` (`shaders/fresnel.wgsl`), operation for operation:
/// with q = (η − 1)(η + 1) + c² = η² cos²θ_t, F_t = 2c√q (1/(c + √q)² + η²/(η²c + √q)²)
/// (= 1 − (r_s² + r_p²)/2 without its cancellation at grazing incidence); 0 for c ≤ 0 and past
/// the critical angle (q ≤ 0).
pub fn transmittance_shader(eta: f64, cos_i: f64) -> f64 {
    let c = cos_i.clamp(0.0, 1.0);
    let q = (eta - 1.0) * (eta + 1.0) + c * c;
    if q <= 0.0 || c <= 0.0 {
        return 0.0;
    }
    let w = q.sqrt();
    let e2 = eta * eta;
    let (a, b) = (c + w, e2 * c + w);
    (2.0 * c * w * (1.0 / (a * a) + e2 / (b * b))).clamp(0.0, 1.0)
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
    fn diffuse_fresnel_below_one_is_reciprocal_continuous_and_bounded() {
        let at_one = diffuse_reflectance(1.0);
        assert!((at_one - 0.0016).abs() < 1e-12, "{at_one}");
        for eps in [1e-6, 1e-9] {
            assert!((diffuse_reflectance(1.0 - eps) - at_one).abs() < 1e-5);
            assert!((diffuse_reflectance(1.0 + eps) - at_one).abs() < 1e-5);
        }
        let mut prev = diffuse_reflectance(0.999);
        for i in 0..=998 {
            let eta = 0.999 - i as f64 * 1e-3; // down to 0.001 (clamped at 1/3)
            let f = diffuse_reflectance(eta);
            assert!(f.is_finite() && (0.0..1.0).contains(&f), "η={eta}: {f}");
            // Monotone: the thinner the medium relative to its surround, the more of its
            // diffuse light is reflected back in at the boundary.
            assert!(f >= prev - 1e-12, "η={eta}: {f} < {prev}");
            prev = f;
        }
        let mu: f64 = 1.4;
        let external = mu * mu * (1.0 - diffuse_reflectance(mu));
        assert!((1.0 - diffuse_reflectance(1.0 / mu) - external).abs() < 1e-12);
        assert_eq!(diffuse_reflectance(0.0), diffuse_reflectance(ETA_MIN));
        assert_eq!(diffuse_reflectance(f64::NAN), at_one);
    }

    #[test]
    fn shader_twin_matches_the_physical_transmittance() {
        for eta in [0.8, 1.0, 1.3, 1.4, 2.0] {
            for i in 0..=100 {
                let c = i as f64 / 100.0;
                let (a, b) = (transmittance_shader(eta, c), transmittance(eta, c));
                // 1e-12 except at the critical angle (η = 0.8, cos = 0.6), where F_t ∝ √q is
                // ill-conditioned and both forms round q differently (both ≈ 1e-7).
                let critical = eta < 1.0 && (c - (1.0 - eta * eta).sqrt()).abs() < 1e-9;
                let bound = if critical { 1e-6 } else { 1e-12 };
                assert!((a - b).abs() < bound, "η={eta} cos={c}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn diffuse_fresnel_of_skin() {
        // Jensen 2001 skin1 uses η = 1.3.
        let f = diffuse_reflectance(1.3);
        assert!((f - 0.44476).abs() < 1e-4, "{f}");
    }
}

//! The core's discrete-ordinates transport solution (`dermis_engine::shading::transport`, what
//! `burley` reads its albedo from) against the exact index-matched half-space and the Monte
//! Carlo itself.

use dermis_engine::shading::transport::diffuse_reflectance;
use dermis_measure::mc::{self, chandrasekhar::plane_albedo};

const SKIN1_SA: [f64; 3] = [0.032, 0.17, 0.48];
const SKIN1_SSP: [f64; 3] = [0.74, 0.88, 1.01];

#[test]
fn index_matched_isotropic_matches_chandrasekhar() {
    for &omega in &[0.01, 0.3, 0.9, 0.99, 0.999] {
        let exact = plane_albedo(omega, 1.0);
        // σ_t = 1: σ_a = 1 − ω.
        let r = diffuse_reflectance(1.0 - omega, omega, 0.0, 1.0);
        assert_eq!(r.specular, 0.0);
        assert_eq!(r.per_incident, r.per_entered);
        assert!(
            (r.per_entered - exact).abs() < 1e-4,
            "ω = {omega}: {} vs exact {exact}",
            r.per_entered
        );
    }
}

/// Runs the Monte Carlo itself (modest photon count) for skin1 at η = 1.4 and compares
/// per incident power, within 4 standard errors + 0.5 %.
#[test]
fn matches_monte_carlo_run_skin1() {
    let eta = 1.4;
    for c in 0..3 {
        let m = mc::Medium::new(SKIN1_SA[c], SKIN1_SSP[c], 0.0, eta);
        let e = mc::total_reflectance(&m, 20_000, 7 + c as u64, 2);
        let r = diffuse_reflectance(SKIN1_SA[c], SKIN1_SSP[c], 0.0, eta).per_incident;
        assert!(
            (r - e.mean).abs() < 4.0 * e.std_err + 0.005 * e.mean,
            "ch{c}: {r:.4} vs MC {:.4} ± {:.4}",
            e.mean,
            e.std_err
        );
    }
}

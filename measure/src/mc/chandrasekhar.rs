//! Exact half-space results for isotropic scattering with index-matched boundaries
//! (η = 1, g = 0), from Chandrasekhar's H-function: the plane albedo for incidence μ₀ is
//! A(μ₀) = 1 − H(μ₀)√(1 − ω) (Chandrasekhar, *Radiative Transfer*, 1960). Used to check the
//! Monte Carlo in the limit where the answer is known exactly.
#![allow(dead_code)]

pub use dermis_engine::shading::transport::gauss_legendre01;

/// Chandrasekhar's H(μ) for isotropic scattering with single-scattering albedo ω ∈ (0, 1],
/// from H(μ) = 1 + (ω/2) μ H(μ) ∫₀¹ H(μ')/(μ + μ') dμ' (Nyström with 32 Gauss–Legendre
/// nodes), each iterate renormalised to the exact zeroth moment (ω/2)∫H = 1 − √(1 − ω),
/// which makes the iteration converge in ~10 steps even at ω = 1 (H(1) = 2.90781).
pub(crate) fn h_function(omega: f64, mu: f64) -> f64 {
    if omega <= 0.0 {
        return 1.0;
    }
    let (x, w) = gauss_legendre01(32);
    let target = 2.0 / omega * (1.0 - (1.0 - omega).sqrt());
    let eval = |h: &[f64], m: f64| -> f64 {
        let sum: f64 = x
            .iter()
            .zip(&w)
            .zip(h)
            .map(|((&xj, &wj), &hj)| wj * hj / (m + xj))
            .sum();
        1.0 / (1.0 - 0.5 * omega * m * sum)
    };
    let mut h = vec![1.0; x.len()];
    for _ in 0..1000 {
        let mut new: Vec<f64> = x.iter().map(|&xi| eval(&h, xi)).collect();
        let moment: f64 = new.iter().zip(&w).map(|(a, b)| a * b).sum();
        for v in &mut new {
            *v *= target / moment;
        }
        let diff = new
            .iter()
            .zip(&h)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        h = new;
        if diff < 1e-14 {
            break;
        }
    }
    eval(&h, mu)
}

/// Exact diffuse (plane) albedo of an index-matched isotropic half-space for collimated
/// incidence at cosine μ₀: 1 − H(μ₀)√(1 − ω).
pub fn plane_albedo(omega: f64, mu0: f64) -> f64 {
    1.0 - h_function(omega, mu0) * (1.0 - omega).sqrt()
}

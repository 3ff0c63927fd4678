//! The multi-scatter albedo A of a semi-infinite medium at every reduced albedo α' at once
//! ("white" Monte Carlo): the table `dermis_engine::shading::albedo` inverts.
//!
//! **What A is.** The total diffuse reflectance of the semi-infinite medium (g = 0, σ'_s the
//! reduced coefficient) under uniform, cosine-weighted incident light, behind a smooth
//! Fresnel boundary of relative index η, specular reflection excluded, **per unit power that
//! entered** the medium: the fraction of the light that goes in that comes back out. A = 1
//! for α' = 1 at every η (a white medium), A = 0 for α' = 0; per unit *incident* power it is
//! A·C(η), C(η) = 2∫F_t(μ)μ dμ (`shading::subsurface::exit_normalisation`).
//!
//! **How.** With σ_t = 1 and no absorption, a photon's path does not depend on α': only its
//! weight does, α'^n after n scattering events. So one walk per photon in the non-absorbing
//! medium, recording the number n of scattering events before it leaves, gives every α' at
//! once: A(α') = E[α'^n] over photons that entered. The entered light is drawn exactly:
//! outside directions cosine-weighted, kept with probability F_t(μ) (rejection), refracted;
//! internal Fresnel reflection all-or-none, as in [`super::walk`]. Each photon's contribution
//! α'^n rises with α', so the estimated curve is monotone in α' for any sample — the
//! property the table's inversion needs — and smooth (the nodes share their photons).
//!
//! **Long walks.** Without absorption the number of events before a photon returns is
//! heavy-tailed (P(n > N) ∝ N^{−1/2}). Walks are rouletted by length: at n = [`ROULETTE_N`]·4^k
//! a photon survives with probability ¼ and its weight is multiplied by 4 (unbiased; the
//! weight stays a power of 4), and a photon still inside after [`CAP`] events is stopped (its
//! weight reported in `capped`: it would add at most α'^CAP to a node, < e^{−20} for the
//! nodes the table measures, 1 − α' ≥ 2·10⁻⁶).
//!
//! Deterministic like every estimator here (fixed batches, one stream per batch).

use super::estimate::{run_batches, Estimate};
use super::fresnel::fresnel;
use super::rng::Rng;
use std::f64::consts::PI;

/// Length (events) at which the first length roulette is played.
pub const ROULETTE_N: u64 = 4096;
/// Events after which a walk is stopped.
pub const CAP: u64 = 1 << 24;

/// A(α') at each reduced albedo asked for, with its standard error.
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoCurve {
    pub eta: f64,
    pub albedos: Vec<f64>,
    /// A per entered power at each of `albedos`.
    pub multi: Vec<Estimate>,
    pub photons: u64,
    pub events: u64,
    /// Weight still inside at the cap (an upper bound on the bias at α' = 1; times α'^CAP at α').
    pub capped: Estimate,
}

/// Samples the inward direction of light that entered through the boundary from a uniform
/// (Lambertian) outside: (cos θ inside, azimuth). Rejection on F_t.
fn entered_direction(rng: &mut Rng, eta: f64) -> (f64, f64) {
    loop {
        let mu = rng.uniform_pos().sqrt();
        let (f, cos_t) = fresnel(mu, eta);
        if f <= 0.0 || rng.uniform() >= f {
            return (cos_t, 2.0 * PI * rng.uniform());
        }
    }
}

/// One photon: its weight (a power of 4; 0 if the length roulette ended it) and the
/// scattering events before it left, or `Err(weight)` if it was stopped at the cap.
fn walk(rng: &mut Rng, eta: f64, events: &mut u64) -> Result<(f64, u32), f64> {
    let (cos_t, _) = entered_direction(rng, eta);
    // Only z matters in a semi-infinite medium with isotropic scattering.
    let mut z = 0.0f64;
    let mut uz = cos_t;
    let inv_eta = 1.0 / eta;
    let mut weight = 1.0;
    let mut next_roulette = ROULETTE_N;
    let mut n: u64 = 0;
    let mut count: u64 = 0;
    loop {
        count += 1;
        if count > CAP {
            *events += CAP;
            return Err(weight);
        }
        if count >= next_roulette {
            next_roulette *= 4;
            if rng.uniform() >= 0.25 {
                *events += count;
                return Ok((0.0, 0));
            }
            weight *= 4.0;
        }
        let s = -rng.uniform_pos().ln();
        if uz < 0.0 && s >= -z / uz {
            // At the top boundary: Fresnel reflect or leave.
            let (r, _) = fresnel(-uz, inv_eta);
            if r > 0.0 && (r >= 1.0 || rng.uniform() < r) {
                z = 0.0;
                uz = -uz;
                continue;
            }
            *events += count;
            return Ok((weight, n.min(u32::MAX as u64) as u32));
        }
        z += uz * s;
        n += 1;
        uz = 2.0 * rng.uniform() - 1.0;
    }
}

/// A(α') (per entered power, see the module docs) at every α' of `albedos` (each in [0, 1]),
/// from `photons` photons that entered, seeded by `seed`; bit-identical for any `threads`.
pub fn multi_scatter_curve(
    eta: f64,
    albedos: &[f64],
    photons: u64,
    seed: u64,
    threads: usize,
) -> AlbedoCurve {
    assert!(
        eta.is_finite() && eta > 0.0,
        "mc: η must be positive and finite"
    );
    assert!(
        albedos.iter().all(|a| (0.0..=1.0).contains(a)),
        "mc: reduced albedos must lie in [0, 1]"
    );
    let ln: Vec<f64> = albedos.iter().map(|a| a.ln()).collect();
    let t = run_batches(photons, seed, threads, albedos.len(), |rng, t| {
        let mut events = 0;
        match walk(rng, eta, &mut events) {
            Ok((w, n)) if w > 0.0 => {
                t.refl.add(w);
                let n = n as f64;
                for (acc, l) in t.refl_bins.iter_mut().zip(&ln) {
                    let v = if n == 0.0 { w } else { w * (l * n).exp() };
                    if v > 0.0 {
                        acc.add(v);
                    }
                }
            }
            Ok(_) => {}
            Err(w) => t.capped.add(w),
        }
        t.events += events;
    });
    AlbedoCurve {
        eta,
        albedos: albedos.to_vec(),
        multi: t.refl_bins.iter().map(|a| a.estimate(t.n)).collect(),
        photons: t.n,
        events: t.events,
        capped: t.capped.estimate(t.n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mc::chandrasekhar::plane_albedo;
    use crate::mc::{total_reflectance_diffuse, Medium};
    use dermis_engine::shading::subsurface::exit_normalisation;

    #[test]
    fn index_matched_curve_is_chandrasekhars_spherical_albedo() {
        // η = 1: A(ω) = 2∫ plane_albedo(ω, μ) μ dμ exactly.
        let albedos = [0.3, 0.8, 0.95, 0.99];
        let c = multi_scatter_curve(1.0, &albedos, 40_000, 3, 2);
        let (x, w) = crate::mc::chandrasekhar::gauss_legendre01(24);
        for (a, e) in albedos.iter().zip(&c.multi) {
            let exact: f64 = x
                .iter()
                .zip(&w)
                .map(|(m, w)| 2.0 * w * m * plane_albedo(*a, *m))
                .sum();
            assert!(
                e.z_score(exact) < 4.0,
                "α' {a}: {} ± {} vs {exact}",
                e.mean,
                e.std_err
            );
        }
        // Monotone in α' whatever the noise.
        assert!(c.multi.windows(2).all(|p| p[0].mean <= p[1].mean));
    }

    #[test]
    fn the_white_walk_agrees_with_the_absorbing_walker() {
        // The same quantity from the plane-parallel walker (implicit absorption, per incident
        // power) divided by the entered fraction C(η).
        let eta = 1.4;
        let albedos = [0.6, 0.97];
        let c = multi_scatter_curve(eta, &albedos, 40_000, 5, 2);
        for (a, e) in albedos.iter().zip(&c.multi) {
            let m = Medium::new(1.0 - a, *a, 0.0, eta);
            let r = total_reflectance_diffuse(&m, 40_000, 9, 2);
            let per_entered = r.scaled(1.0 / exit_normalisation(eta));
            let d = (e.mean - per_entered.mean).abs();
            let se = (e.std_err.powi(2) + per_entered.std_err.powi(2)).sqrt();
            assert!(
                d < 4.0 * se + 1e-4,
                "α' {a}: {} vs {}",
                e.mean,
                per_entered.mean
            );
        }
    }
}

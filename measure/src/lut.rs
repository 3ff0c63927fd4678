//! The Monte Carlo bake of `preintegrated`'s LUT (`dermis_engine::shading::preintegrated`): per
//! row radius ρ and channel, the exitance of a homogeneous sphere under a directional light,
//! measured by the sphere walker ([`mc::sphere_with`]), stored as log2 M, plus the two factor
//! rows. `dermis lut` writes the shipped ones (`assets/sss/*.lut`).

use dermis_engine::shading::bake::{Bake, Budget};
use dermis_engine::shading::preintegrated::{self, row_radius_mm, Lut, LUT_U, LUT_V};
use dermis_engine::shading::Material;

use crate::mc;

/// Band edges (degrees of polar angle from the light, ascending) of the LUT's u texels:
/// texel i holds n·l ∈ [−1 + 2i/U, −1 + 2(i + 1)/U], band U − 1 − i from the light. Bands of
/// equal cos θ width have equal area, so each texel gets photons in proportion to its light.
fn band_edges() -> Vec<f64> {
    (0..=LUT_U)
        .map(|k| {
            (1.0 - 2.0 * k as f64 / LUT_U as f64)
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        })
        .collect()
}

/// The sphere rows of the LUT: per row radius ρ and channel, the exitance per unit beam
/// irradiance of a homogeneous sphere of radius ρ under a directional light, measured by the
/// Monte Carlo sphere walker ([`mc::sphere_with`]: the same transport as the reference
/// scenes, light crossing the terminator and passing through the ball included), per band of
/// n·l. Each run gets `budget.sphere` photons or, where photons walk long (albedo → 1, large
/// ρ), as many as `budget.sphere_events` events allow. ln M per texel ([`log_row`]),
/// row-major over v then u.
pub fn sphere_rows(m: &Material, budget: &Budget, threads: usize) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0f64; 3]; LUT_V * LUT_U];
    for (j, row) in out.chunks_mut(LUT_U).enumerate() {
        for c in 0..3 {
            for (t, v) in row.iter_mut().zip(sphere_row(m, j, c, budget, threads)) {
                t[c] = v;
            }
        }
    }
    out
}

/// Row `j`, channel `c` of [`sphere_rows`].
pub fn sphere_row(m: &Material, j: usize, c: usize, budget: &Budget, threads: usize) -> Vec<f64> {
    const SEED: u64 = 0x5EED_5F4E;
    let med = crate::bake::medium(m, c);
    let seed = SEED + 1000 * c as u64 + j as u64;
    sphere_run(
        &med,
        row_radius_mm(j),
        m.sigma_tr()[c],
        budget,
        seed,
        threads,
    )
}

/// One LUT row: ln M per texel (u = (n·l + 1)/2, lit side last) of a sphere of radius `rho` of
/// the medium `med` (transport coefficient `sigma_tr`, same length unit) under a directional
/// light of unit irradiance, [`log_row`] of the walker's bands: `budget.sphere` photons or,
/// where photons walk long, as many as `budget.sphere_events` events allow (a pilot run
/// measures the events per photon). The one measurement of a material's row and of a sphere
/// grid node (`crate::grid`).
pub fn sphere_run(
    med: &mc::Medium,
    rho: f64,
    sigma_tr: f64,
    budget: &Budget,
    seed: u64,
    threads: usize,
) -> Vec<f64> {
    let edges = band_edges();
    let pilot = budget.min_photons.clamp(1, 200);
    let probe = mc::sphere_with(med, rho, &edges, budget.max_events, pilot, seed ^ 0xA5A5, 1);
    let per_photon = (probe.events as f64 / pilot as f64).max(1.0);
    let n = ((budget.sphere_events as f64 / per_photon) as u64)
        .clamp(budget.min_photons, budget.sphere.max(budget.min_photons));
    let r = mc::sphere_with(med, rho, &edges, budget.max_events, n, seed, threads);
    // Texel i is band U − 1 − i.
    let values: Vec<f64> = (0..LUT_U).map(|i| r.bands.values[LUT_U - 1 - i]).collect();
    let errors: Vec<f64> = (0..LUT_U).map(|i| r.bands.std_err[LUT_U - 1 - i]).collect();
    log_row(&values, &errors, rho, sigma_tr)
}

/// Smallest exitance a texel holds (ln: −27.6).
const FLOOR: f64 = 1e-12;

/// One LUT row as ln M from the band averages `values` (± `errors`) over u, lit side last:
/// - measured bands on the lit side noisier than 2 % are smoothed by a local quadratic in
///   ln M over ±2 bands, weighted by the inverse variance of ln M (a long-walking material gets few
///   photons per band: white coat's flattest rows carry ±5 % noise before, ±3 % after);
/// - bands that are not measured (nothing exited, or a relative error above 50 %) are holes:
///   between measured bands ln M is interpolated linearly; past the last measured band on the
///   dark side the row carries on with the log slope of the last four measured bands, never
///   rising, and never falling faster than diffusion through the ball allows: e^{−σ_tr Δd},
///   d = 2ρ sin((θ − 90°)/2) the chord from the terminator (the fit is dominated by the steep
///   fall just past the terminator; deeper in, light arrives through the ball and decays
///   more slowly);
/// - a band average of an exponential over a band e^a wide exceeds the centre value by
///   sinh(a/2)/(a/2): the centre value is stored (the sampler interpolates ln M linearly,
///   exact for an exponential fall-off).
pub(crate) fn log_row(values: &[f64], errors: &[f64], rho: f64, sigma_tr: f64) -> Vec<f64> {
    let n = values.len();
    let measured: Vec<usize> = (0..n)
        .filter(|&i| values[i] > 0.0 && errors[i] <= 0.5 * values[i])
        .collect();
    let Some(&last) = measured.first() else {
        return vec![FLOOR.ln(); n];
    };
    let ln_at = smoothed(values, errors, &measured);
    let ln_at = |i: usize| ln_at[i];
    let mut ln = vec![0.0f64; n];
    for w in measured.windows(2) {
        let (a, b) = (w[0], w[1]);
        for (i, v) in ln.iter_mut().enumerate().take(b + 1).skip(a) {
            let t = (i - a) as f64 / (b - a) as f64;
            *v = ln_at(a) * (1.0 - t) + ln_at(b) * t;
        }
    }
    ln[last] = ln_at(last);
    let top = *measured.last().unwrap_or(&last);
    for v in ln.iter_mut().skip(top + 1) {
        *v = ln_at(top);
    }
    // Least-squares log slope over the last four measured bands toward the dark side.
    let fit: Vec<usize> = measured.iter().copied().take(4).collect();
    let slope = if fit.len() >= 2 {
        let mx = fit.iter().map(|&i| i as f64).sum::<f64>() / fit.len() as f64;
        let my = fit.iter().map(|&i| ln_at(i)).sum::<f64>() / fit.len() as f64;
        let sxy: f64 = fit.iter().map(|&i| (i as f64 - mx) * (ln_at(i) - my)).sum();
        let sxx: f64 = fit.iter().map(|&i| (i as f64 - mx).powi(2)).sum();
        (sxy / sxx).max(0.0)
    } else {
        0.0
    };
    // Chord from the terminator to texel i's centre (dark side: n·l < 0).
    let chord = |i: usize| {
        let mu = 2.0 * (i as f64 + 0.5) / n as f64 - 1.0;
        let past = (-mu).clamp(0.0, 1.0).asin();
        2.0 * rho * (0.5 * past).sin()
    };
    for i in (0..last).rev() {
        let diffusion = sigma_tr * (chord(i) - chord(i + 1)).max(0.0);
        ln[i] = ln[i + 1] - slope.min(diffusion);
    }
    let averaged = ln.clone();
    for i in 1..n - 1 {
        let a = 0.5 * (averaged[i + 1] - averaged[i - 1]);
        if a.abs() > 1e-6 {
            ln[i] -= ((0.5 * a).sinh() / (0.5 * a)).ln();
        }
    }
    ln.iter().map(|v| v.max(FLOOR.ln())).collect()
}

/// ln M at the noisy lit `measured` bands from a weighted local quadratic fit over ±2 measured
/// bands (weights (M/σ)²); elsewhere, or where the fit is not determined, the band's own value.
fn smoothed(values: &[f64], errors: &[f64], measured: &[usize]) -> Vec<f64> {
    let mut out: Vec<f64> = values.iter().map(|v| v.max(FLOOR).ln()).collect();
    // Only on the lit side, two bands clear of the terminator (a quadratic over five bands
    // would round off its kink), and only where noise dominates.
    let lit = values.len() / 2 + 2;
    for &i in measured
        .iter()
        .filter(|&&i| i >= lit && errors[i] > 0.02 * values[i])
    {
        // Normal equations of y = a + b x + c x², x = band − i.
        let mut m = [[0.0f64; 3]; 3];
        let mut r = [0.0f64; 3];
        let mut points = 0;
        for &k in measured.iter().filter(|&&k| k.abs_diff(i) <= 2) {
            let x = k as f64 - i as f64;
            let w = (values[k] / errors[k].max(1e-300)).powi(2);
            let basis = [1.0, x, x * x];
            for p in 0..3 {
                r[p] += w * basis[p] * values[k].ln();
                for q in 0..3 {
                    m[p][q] += w * basis[p] * basis[q];
                }
            }
            points += 1;
        }
        if points >= 4 {
            if let Some(a) = solve3(m, r) {
                out[i] = a;
            }
        }
    }
    out
}

/// The first unknown of the 3×3 system m·x = r (Cramer's rule); None if singular.
fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<f64> {
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    if !d.is_finite() || d.abs() < 1e-12 * m[0][0].powi(3).max(f64::MIN_POSITIVE) {
        return None;
    }
    let mut a = m;
    for (row, v) in a.iter_mut().zip(r) {
        row[0] = v;
    }
    let x = det(a) / d;
    x.is_finite().then_some(x)
}

/// Bakes the LUT of material `m` (tables `b`) within `budget` on `threads` threads: the
/// direct bake (the presets' shipped LUTs, and the yardstick of the grid's interpolated rows).
pub fn bake_lut(b: &Bake, m: &Material, budget: &Budget, threads: usize) -> Lut {
    // log2 M: the shader's exp2 is one instruction.
    let rows: Vec<[f64; 3]> = sphere_rows(m, budget, threads)
        .iter()
        .map(|ln| ln.map(|v| v / std::f64::consts::LN_2))
        .collect();
    preintegrated::lut_from(&rows, b, m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::{measure, QUICK_BUDGET};
    use crate::ground_truth::acceptance_material;
    use dermis_engine::shading::bake;
    use dermis_engine::shading::material::{PRESETS, SKIN1};
    use dermis_engine::shading::preintegrated::{file_name, lut, SHIPPED};

    #[test]
    fn every_preset_has_a_shipped_lut_at_the_current_budget() {
        // A shipped table baked with another budget, material or layout would be ignored
        // (and the game would bake for minutes at load): `dermis lut --out assets/sss`.
        for m in PRESETS
            .iter()
            .flat_map(|m| [m.clone(), acceptance_material(m)])
        {
            let found = SHIPPED
                .iter()
                .find_map(|b| Lut::from_bytes(b, &m, &bake::DEFAULT_BUDGET));
            let lut = found.unwrap_or_else(|| panic!("no shipped LUT for {}", file_name(&m)));
            assert!(lut.texels.iter().all(|t| t.iter().all(|v| v.is_finite())));
        }
    }

    #[test]
    fn a_shipped_row_is_what_the_bake_computes() {
        // The cheapest sphere row (the smallest sphere) re-measured with the shipped budget is
        // bit-identical to the shipped one (the bake is deterministic for any thread count).
        let lut = lut(&SKIN1);
        let j = LUT_V - 1;
        let row = sphere_row(&SKIN1, j, 0, &bake::DEFAULT_BUDGET, 2);
        for (i, v) in row.iter().enumerate() {
            let log2 = (v / std::f64::consts::LN_2) as f32;
            assert_eq!(lut.at(i, j, 0), log2, "texel {i}");
        }
    }

    #[test]
    fn small_spheres_glow_on_the_dark_side_and_the_bake_is_deterministic() {
        let b = measure(&SKIN1, QUICK_BUDGET, 2);
        let lut = bake_lut(&b, &SKIN1, &QUICK_BUDGET, 2);
        assert_eq!(lut, bake_lut(&b, &SKIN1, &QUICK_BUDGET, 1));
        // Just past the terminator (n·l = −0.1) a 2 mm sphere still glows red, more than a
        // 600 mm one; and red wraps further than blue.
        let i = (0.45 * LUT_U as f64) as usize;
        let small = LUT_V - 6;
        assert!(row_radius_mm(small) < 3.0 && row_radius_mm(0) > 500.0);
        assert!(
            lut.at(i, small, 0) > lut.at(i, 0, 0) + 1.0,
            "ln M: {} vs {}",
            lut.at(i, small, 0),
            lut.at(i, 0, 0)
        );
        assert!(lut.at(i, small, 0) > lut.at(i, small, 2));
    }

    #[test]
    fn holes_are_filled_and_the_tail_never_rises() {
        // A falling row with a hole and an unmeasured tail.
        let n = 16;
        let values: Vec<f64> = (0..n)
            .map(|i| {
                if i == 9 || i < 4 {
                    0.0
                } else {
                    (i as f64 - 15.0).exp()
                }
            })
            .collect();
        let errors: Vec<f64> = values.iter().map(|v| 0.01 * v).collect();
        let row = log_row(&values, &errors, 10.0, 0.5);
        assert!(row.iter().all(|v| v.is_finite()));
        assert!((row[9] - 0.5 * (row[8] + row[10])).abs() < 0.05, "{row:?}");
        for i in 0..n - 1 {
            assert!(row[i] <= row[i + 1] + 1e-9, "{row:?}");
        }
        // The tail falls, but no faster than diffusion through a 10 mm ball.
        assert!(row[0] < row[4]);
    }
}

//! The error metric of a model's rendered scene against the Monte Carlo reference.
//!
//! Per bin and channel the error is |ln(model / reference)|, a symmetric relative error (a
//! factor 2 too bright or too dark both score ln 2), averaged over the bins where the
//! reference is above its noise floor (value > [`NOISE_FLOOR`] standard errors and > 0).
//! A model value that is ≤ 0 or not finite scores [`LOG_ERROR_CAP`], as does any ratio
//! further off than e^10, so a black or broken image scores badly instead of being skipped.
//! The integrated error |ln(∫model / ∫reference)| compares the total exitance over all bins
//! (weights = bin measures, [`super::Scene::bin_weights`]); it is what energy conservation
//! alone gets right.

use serde::Serialize;

use super::Entry;

/// |ln| of one bin (or of the integral) is capped here; a value ≤ 0 or non-finite scores it.
pub const LOG_ERROR_CAP: f64 = 10.0;
/// Bins whose reference is not above this many standard errors are not scored.
pub const NOISE_FLOOR: f64 = 3.0;

/// How far a model is from a reference [`Entry`]. Channel means are NaN where a channel has
/// no scored bin (serialised as `null`); the `_all` fields pool the channels that have.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ErrorStats {
    /// Mean |ln(model/reference)| over the scored bins, per channel.
    pub mean_log: [f64; 3],
    /// Mean |ln(model/reference)| over every scored (bin, channel).
    pub mean_log_all: f64,
    /// |ln(∫model / ∫reference)| per channel, integrals over all bins with the weights.
    pub integrated: [f64; 3],
    /// Mean of `integrated` over the channels with a positive reference integral.
    pub integrated_all: f64,
    /// Scored bins per channel.
    pub bins: [usize; 3],
    /// Mean relative standard error SE/value of the reference over the scored bins, per
    /// channel: the Monte Carlo's own noise, to print beside the error.
    pub ref_rel_se: [f64; 3],
    /// The same over every scored (bin, channel).
    pub ref_rel_se_all: f64,
}

impl ErrorStats {
    /// Total scored (bin, channel) pairs.
    pub fn bins_total(&self) -> usize {
        self.bins.iter().sum()
    }
}

/// |ln(m/r)| with the cap; `r` must be > 0.
fn abs_log(m: f64, r: f64) -> f64 {
    if !(m.is_finite() && m > 0.0) {
        return LOG_ERROR_CAP;
    }
    (m / r).ln().abs().min(LOG_ERROR_CAP)
}

/// Whether bin `k`, channel `c` of `entry` is above its noise floor.
pub fn scored(entry: &Entry, k: usize, c: usize) -> bool {
    let (v, s) = (entry.values[k][c], entry.std_err[k][c]);
    v.is_finite() && v > 0.0 && v > NOISE_FLOOR * s
}

/// Scores `model` (one RGB value per bin of `entry`, same units) against `entry`;
/// `weights` are the bin measures for the integrals (usually [`Entry::weights`]).
pub fn log_error(model: &[[f64; 3]], entry: &Entry, weights: &[f64]) -> ErrorStats {
    let n = entry.values.len();
    assert_eq!(
        model.len(),
        n,
        "metric: model has {} bins, reference {n}",
        model.len()
    );
    assert_eq!(
        weights.len(),
        n,
        "metric: {} weights for {n} bins",
        weights.len()
    );
    let mut mean_log = [f64::NAN; 3];
    let mut integrated = [f64::NAN; 3];
    let mut bins = [0usize; 3];
    let mut ref_rel_se = [f64::NAN; 3];
    let (mut sum_all, mut se_all, mut n_all) = (0.0, 0.0, 0usize);
    let (mut int_sum, mut int_n) = (0.0, 0usize);
    for c in 0..3 {
        let (mut s, mut se, mut used) = (0.0, 0.0, 0usize);
        let (mut im, mut ir) = (0.0, 0.0);
        for k in 0..n {
            let r = entry.values[k][c];
            im += weights[k] * model[k][c];
            if r.is_finite() {
                ir += weights[k] * r;
            }
            if scored(entry, k, c) {
                s += abs_log(model[k][c], r);
                se += entry.std_err[k][c] / r;
                used += 1;
            }
        }
        bins[c] = used;
        if used > 0 {
            mean_log[c] = s / used as f64;
            ref_rel_se[c] = se / used as f64;
            sum_all += s;
            se_all += se;
            n_all += used;
        }
        if ir > 0.0 {
            integrated[c] = abs_log(im, ir);
            int_sum += integrated[c];
            int_n += 1;
        }
    }
    let mean = |s: f64, n: usize| if n > 0 { s / n as f64 } else { f64::NAN };
    ErrorStats {
        mean_log,
        mean_log_all: mean(sum_all, n_all),
        integrated,
        integrated_all: mean(int_sum, int_n),
        bins,
        ref_rel_se,
        ref_rel_se_all: mean(se_all, n_all),
    }
}

/// [`log_error`] with the entry's own bin measures.
pub fn score(model: &[[f64; 3]], entry: &Entry) -> ErrorStats {
    log_error(model, entry, &entry.weights())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ground_truth::Scene;

    fn entry() -> Entry {
        Entry {
            scene: Scene::PointLight { h_mm: 5.0 },
            edges: vec![0.0, 1.0, 2.0, 3.0, 4.0],
            values: vec![
                [0.5, 0.2, 0.1],
                [0.3, 0.1, 0.02],
                [0.1, 0.05, 0.001],
                [0.02, 0.01, 1e-5],
            ],
            std_err: vec![
                [0.005, 0.002, 0.001],
                [0.003, 0.001, 0.001],
                [0.001, 0.0005, 0.001],
                [0.001, 0.0001, 1e-4],
            ],
            photons: 1000,
        }
    }

    #[test]
    fn exact_reference_scores_zero() {
        let e = entry();
        let s = score(&e.values, &e);
        assert_eq!(s.mean_log, [0.0; 3]);
        assert_eq!(s.mean_log_all, 0.0);
        assert_eq!(s.integrated, [0.0; 3]);
        assert_eq!(s.integrated_all, 0.0);
    }

    #[test]
    fn doubled_image_scores_ln2() {
        let e = entry();
        let m: Vec<[f64; 3]> = e.values.iter().map(|v| v.map(|x| 2.0 * x)).collect();
        let s = score(&m, &e);
        let ln2 = std::f64::consts::LN_2;
        for c in 0..3 {
            assert!((s.mean_log[c] - ln2).abs() < 1e-12);
            assert!((s.integrated[c] - ln2).abs() < 1e-12);
        }
        assert!((s.mean_log_all - ln2).abs() < 1e-12);
        // Half as bright scores the same.
        let h: Vec<[f64; 3]> = e.values.iter().map(|v| v.map(|x| 0.5 * x)).collect();
        assert!((score(&h, &e).mean_log_all - ln2).abs() < 1e-12);
    }

    #[test]
    fn black_and_nan_images_score_badly() {
        let e = entry();
        let black = vec![[0.0; 3]; 4];
        let s = score(&black, &e);
        assert_eq!(s.mean_log_all, LOG_ERROR_CAP);
        assert_eq!(s.integrated_all, LOG_ERROR_CAP);
        let mut nan = e.values.clone();
        nan[1][0] = f64::NAN;
        let s = score(&nan, &e);
        assert_eq!(s.integrated[0], LOG_ERROR_CAP);
        assert!(s.mean_log[0] >= LOG_ERROR_CAP / 4.0 - 1e-12);
        assert_eq!(s.mean_log[1], 0.0);
        let mut neg = e.values.clone();
        neg[0][2] = -1.0;
        assert!(score(&neg, &e).mean_log[2] > 1.0);
        let inf = vec![[f64::INFINITY; 3]; 4];
        assert_eq!(score(&inf, &e).mean_log_all, LOG_ERROR_CAP);
    }

    #[test]
    fn bins_under_the_noise_floor_are_ignored() {
        let e = entry();
        let s = score(&e.values, &e);
        // Blue: bins 1 (0.02 ± 0.001) is scored; bins 2 (0.001 ± 0.001) and 3 (1e-5 ± 1e-4)
        // are under 3 SE.
        assert_eq!(s.bins, [4, 4, 2]);
        // A wild model value in an unscored bin changes the mean |ln| not at all (only the
        // integral, by its small weight × value).
        let mut m = e.values.clone();
        m[3][2] = 1e-9;
        m[2][2] = 5.0 * e.values[2][2];
        let s2 = score(&m, &e);
        assert_eq!(s2.mean_log[2], 0.0);
        assert_eq!(s2.bins, [4, 4, 2]);
        // The reference's own noise: mean SE/value over the scored bins.
        let want = (0.001 / 0.1 + 0.001 / 0.02) / 2.0;
        assert!((s.ref_rel_se[2] - want).abs() < 1e-12);
        // A channel with no scored bin reports NaN and stays out of the pooled mean.
        let mut dark = e.clone();
        for k in 0..4 {
            dark.values[k][2] = 0.0;
        }
        let s3 = score(&e.values, &dark);
        assert!(s3.mean_log[2].is_nan() && s3.integrated[2].is_nan());
        assert_eq!(s3.mean_log_all, 0.0);
        assert_eq!(s3.bins_total(), 8);
    }

    #[test]
    fn integrated_error_uses_the_weights() {
        let e = entry();
        // A model that moves light from bin 0 to bin 1 while keeping the weighted integral.
        let w = e.weights();
        let mut m = e.values.clone();
        let d = 0.1;
        m[0][0] -= d / w[0];
        m[1][0] += d / w[1];
        let s = log_error(&m, &e, &w);
        assert!(s.integrated[0] < 1e-12);
        assert!(s.mean_log[0] > 0.0);
    }
}

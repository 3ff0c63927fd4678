//! Small statistics for bench reports.

/// The q-quantile (0..=1) by linear interpolation (shared with the soak report).
pub use dermis_game::soak::percentile;

/// Prints a report as pretty JSON.
pub fn print_json(report: &serde_json::Value) -> Result<(), String> {
    println!(
        "{}",
        serde_json::to_string_pretty(report).map_err(|e| e.to_string())?
    );
    Ok(())
}

pub fn median(xs: &[f64]) -> f64 {
    percentile(xs, 0.5)
}

/// Paired ratio a/b: geometric mean of the per-round ratios with a 95 % confidence interval
/// (normal approximation on the log ratios). NaNs when there are fewer than 2 pairs.
pub fn ratio_ci(a: &[f64], b: &[f64]) -> (f64, f64, f64) {
    let logs: Vec<f64> = a
        .iter()
        .zip(b)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (x / y).ln())
        .collect();
    if logs.len() < 2 {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let n = logs.len() as f64;
    let mean = logs.iter().sum::<f64>() / n;
    let var = logs.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let half = 1.96 * (var / n).sqrt();
    (mean.exp(), (mean - half).exp(), (mean + half).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles() {
        let v = [3.0, 1.0, 2.0, 4.0];
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 4.0);
        assert_eq!(median(&v), 2.5);
        assert!(percentile(&[], 0.5).is_nan());
    }

    #[test]
    fn ratio_of_identical_samples_is_one() {
        let a = [1.0, 2.0, 3.0];
        let (r, lo, hi) = ratio_ci(&a, &a);
        assert!((r - 1.0).abs() < 1e-12 && (lo - 1.0).abs() < 1e-12 && (hi - 1.0).abs() < 1e-12);
        let b = [2.0, 4.1, 5.9];
        let (r, lo, hi) = ratio_ci(&b, &a);
        assert!(lo < r && r < hi && (r - 2.0).abs() < 0.05);
    }
}

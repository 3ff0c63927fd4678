//! The soak's statistics: percentiles (exact over a slice, or streamed through a fixed-size
//! log histogram), least-squares slopes with a confidence interval, 3DMark-style stability
//! over binned frame counts, and the present-interval buckets.

/// Linear-interpolated percentile (`q` in 0..=1) of unsorted values; NaN when empty.
pub fn percentile(xs: &[f64], q: f64) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let pos = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let (i, f) = (pos.floor() as usize, pos.fract());
    if i + 1 < v.len() {
        v[i] * (1.0 - f) + v[i + 1] * f
    } else {
        v[i]
    }
}

/// Least-squares slope of y over x and the half-width of its 95 % confidence interval
/// (normal approximation, residual standard error; NaN with fewer than 3 points). Memory
/// samples are autocorrelated, so the interval is a lower bound on the real uncertainty.
pub fn slope_ci(xs: &[f64], ys: &[f64]) -> (f64, f64) {
    let b = slope(xs, ys);
    let n = xs.len();
    if n < 3 || !b.is_finite() {
        return (b, f64::NAN);
    }
    let nf = n as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / nf, ys.iter().sum::<f64>() / nf);
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let rss: f64 = xs
        .iter()
        .zip(ys)
        .map(|(x, y)| (y - (my + b * (x - mx))).powi(2))
        .sum();
    (b, 1.96 * (rss / (nf - 2.0) / sxx).sqrt())
}

/// Least-squares slope of y over x.
pub fn slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    if xs.len() < 2 {
        return f64::NAN;
    }
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}

/// A streamed distribution in fixed memory: counts in log-spaced bins 0.5 % wide over
/// [`LogHistogram::LO`, `LogHistogram::HI`), one bin for everything below (zero included),
/// one for everything above, with the exact minimum and maximum. A percentile is exact to
/// the bin: within 0.25 % of the value [`percentile`] gives on the same samples, or the
/// exact minimum / maximum at the ends.
#[derive(Clone, Debug)]
pub struct LogHistogram {
    bins: Vec<u32>,
    n: u64,
    min: f64,
    max: f64,
}

impl LogHistogram {
    /// Smallest binned value (ms or a count): below it, the underflow bin.
    pub const LO: f64 = 1e-4;
    /// Largest binned value: above it, the overflow bin.
    pub const HI: f64 = 1e7;
    /// Bin width ratio.
    const RATIO: f64 = 1.005;

    fn inner_bins() -> usize {
        ((Self::HI / Self::LO).ln() / Self::RATIO.ln()).ceil() as usize
    }

    pub fn new() -> Self {
        Self {
            bins: vec![0; Self::inner_bins() + 2],
            n: 0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }

    /// Bytes this histogram holds.
    pub fn bytes(&self) -> usize {
        self.bins.capacity() * std::mem::size_of::<u32>()
    }

    pub fn len(&self) -> u64 {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Adds one value (NaN is ignored).
    pub fn add(&mut self, x: f64) {
        if x.is_nan() {
            return;
        }
        let i = if x < Self::LO {
            0
        } else if x >= Self::HI {
            self.bins.len() - 1
        } else {
            1 + (((x / Self::LO).ln() / Self::RATIO.ln()) as usize).min(Self::inner_bins() - 1)
        };
        self.bins[i] = self.bins[i].saturating_add(1);
        self.n += 1;
        self.min = self.min.min(x);
        self.max = self.max.max(x);
    }

    /// The largest value added; NaN when empty.
    pub fn max(&self) -> f64 {
        if self.n == 0 {
            f64::NAN
        } else {
            self.max
        }
    }

    /// The `q` quantile (0..=1) by the rank [`percentile`] uses, to the bin: the bin's
    /// geometric centre, clamped to the exact minimum and maximum; NaN when empty.
    pub fn percentile(&self, q: f64) -> f64 {
        if self.n == 0 {
            return f64::NAN;
        }
        let rank = (q.clamp(0.0, 1.0) * (self.n - 1) as f64).round() as u64;
        if rank == 0 {
            return self.min;
        }
        if rank == self.n - 1 {
            return self.max;
        }
        let mut seen = 0u64;
        for (i, &c) in self.bins.iter().enumerate() {
            seen += c as u64;
            if seen > rank {
                let last = self.bins.len() - 1;
                let v = if i == 0 {
                    self.min
                } else if i == last {
                    self.max
                } else {
                    Self::LO * Self::RATIO.powf(i as f64 - 0.5)
                };
                return v.clamp(self.min, self.max);
            }
        }
        self.max
    }

    /// p50, p95, p99 and max as the report writes them.
    pub fn quantiles_json(&self) -> serde_json::Value {
        serde_json::json!({
            "p50": self.percentile(0.5), "p95": self.percentile(0.95),
            "p99": self.percentile(0.99), "max": self.max(),
        })
    }
}

impl Default for LogHistogram {
    fn default() -> Self {
        Self::new()
    }
}

/// Frames counted in fixed time bins (fixed memory per second of the run, whatever the frame
/// rate): what stability is computed from.
#[derive(Clone, Debug)]
pub struct FrameBins {
    counts: Vec<u32>,
}

impl FrameBins {
    /// Bin width, s.
    pub const BIN_S: f64 = 0.1;

    /// Bins for a run of about `seconds` (it grows past that if the run does).
    pub fn with_seconds(seconds: f64) -> Self {
        // 5 % slack: a run ends on the first frame past its length.
        let n = (seconds.clamp(0.0, 86_400.0) * 1.05 / Self::BIN_S).ceil() as usize + 64;
        Self {
            counts: Vec::with_capacity(n),
        }
    }

    pub fn bytes(&self) -> usize {
        self.counts.capacity() * std::mem::size_of::<u32>()
    }

    /// Counts a frame at `t_s` (negative times count in the first bin).
    pub fn add(&mut self, t_s: f64) {
        let i = (t_s.max(0.0) / Self::BIN_S) as usize;
        if i >= self.counts.len() {
            self.counts.resize(i + 1, 0);
        }
        self.counts[i] = self.counts[i].saturating_add(1);
    }

    /// Stability as in 3DMark: worst window's mean FPS / best window's, in %. One-minute
    /// windows for runs of 5 minutes or more, else 10 equal windows, over `[t0, t1)`; a bin
    /// straddling a window edge is split by overlap. Returns (percent, windows, window
    /// length s, FPS per window).
    pub fn stability(&self, t0: f64, t1: f64) -> (f64, usize, f64, Vec<f64>) {
        let span = t1 - t0;
        if span <= 0.0 || span.is_nan() {
            return (f64::NAN, 0, 0.0, Vec::new());
        }
        let (n, w) = if span >= 300.0 {
            ((span / 60.0).floor() as usize, 60.0)
        } else {
            (10, span / 10.0)
        };
        let mut counts = vec![0.0f64; n];
        for (i, &c) in self.counts.iter().enumerate() {
            if c == 0 {
                continue;
            }
            let (a, b) = (i as f64 * Self::BIN_S, (i + 1) as f64 * Self::BIN_S);
            let first = (((a - t0) / w).floor().max(0.0)) as usize;
            let last = (((b - t0) / w).floor()) as isize;
            let last = (last.max(0) as usize).min(n.saturating_sub(1));
            for (k, count) in counts.iter_mut().enumerate().take(last + 1).skip(first) {
                let (wa, wb) = (t0 + k as f64 * w, t0 + (k + 1) as f64 * w);
                let overlap = (b.min(wb) - a.max(wa)).max(0.0);
                *count += c as f64 * overlap / Self::BIN_S;
            }
        }
        let fps: Vec<f64> = counts.iter().map(|&c| c / w).collect();
        let best = fps.iter().copied().fold(0.0, f64::max);
        let worst = fps.iter().copied().fold(f64::INFINITY, f64::min);
        let pct = if best > 0.0 {
            100.0 * worst / best
        } else {
            f64::NAN
        };
        (pct, n, w, fps)
    }
}

/// The bucket of a present interval of `periods` target periods: `round(periods)` ≤ 1 → 0
/// (on time), 2 → 1 (one period late), 3 → 2, ≥ 4 → 3 (as Android's frame-pacing library
/// reports).
pub fn present_bucket(periods: f64) -> usize {
    (periods.round().max(1.0) as usize - 1).min(3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slopes_and_their_interval() {
        assert!((slope(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0]) - 2.0).abs() < 1e-12);
        // An exact line has a zero-width interval; noise widens it around the true slope.
        let (b, half) = slope_ci(&[0.0, 1.0, 2.0, 3.0], &[1.0, 3.0, 5.0, 7.0]);
        assert!((b - 2.0).abs() < 1e-12 && half.abs() < 1e-9);
        let xs: Vec<f64> = (0..200).map(f64::from).collect();
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| 0.5 * x + if (*x as i64) % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let (b, half) = slope_ci(&xs, &ys);
        assert!(half > 0.0 && (b - 0.5).abs() < half, "{b} ± {half}");
    }

    #[test]
    fn exact_percentiles() {
        let v = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 4.0);
        assert!((percentile(&v, 0.5) - 2.5).abs() < 1e-12);
        assert!(percentile(&[], 0.5).is_nan());
    }

    #[test]
    fn the_histogram_agrees_with_exact_percentiles() {
        // A long-tailed frame-time distribution (ms) from a fixed LCG, with zeros (counts).
        let mut s = 12345u64;
        let mut xs = Vec::new();
        let mut h = LogHistogram::new();
        for i in 0..20_000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            let x = if i % 97 == 0 {
                0.0
            } else {
                2.0 + 30.0 * u.powi(6)
            };
            xs.push(x);
            h.add(x);
        }
        for q in [0.01, 0.5, 0.9, 0.95, 0.99, 0.999] {
            let (a, b) = (percentile(&xs, q), h.percentile(q));
            assert!(
                (a - b).abs() <= 0.0026 * a.abs() + 1e-9,
                "q {q}: {a} vs {b}"
            );
        }
        assert_eq!(h.percentile(0.0), 0.0);
        assert_eq!(h.percentile(1.0), h.max());
        assert_eq!(h.len(), 20_000);
        assert!(LogHistogram::new().percentile(0.5).is_nan());
        // Out of range values land in the end bins and report their exact extremes.
        let mut h = LogHistogram::new();
        h.add(1e9);
        h.add(f64::NAN);
        assert_eq!((h.len(), h.percentile(0.5)), (1, 1e9));
    }

    #[test]
    fn stability_over_bins() {
        // 10 windows over 10 s; the second half at half the rate.
        let mut bins = FrameBins::with_seconds(10.0);
        (0..300).for_each(|i| bins.add(i as f64 / 60.0));
        (0..150).for_each(|i| bins.add(5.0 + i as f64 / 30.0));
        let (pct, n, w, _) = bins.stability(0.0, 10.0);
        assert_eq!((n, w), (10, 1.0));
        assert!((pct - 50.0).abs() < 1.0, "{pct}");
        // Windows that do not fall on bin edges split the straddling bins: a steady rate
        // stays steady.
        let mut bins = FrameBins::with_seconds(30.0);
        (0..1800).for_each(|i| bins.add(i as f64 / 60.0));
        let (pct, ..) = bins.stability(2.03, 29.97);
        assert!(pct > 97.0, "{pct}");
        // One-minute windows from 5 minutes on.
        assert_eq!(FrameBins::with_seconds(1.0).stability(0.0, 600.0).1, 10);
    }

    #[test]
    fn present_buckets() {
        let b: Vec<usize> = [0.6, 1.0, 1.4, 2.1, 3.0, 7.0]
            .iter()
            .map(|&p| present_bucket(p))
            .collect();
        assert_eq!(b, [0, 0, 0, 1, 2, 3]);
    }
}

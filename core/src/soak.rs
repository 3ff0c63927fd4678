//! The platform-free half of the soak report, shared by `dermis soak` (desktop) and the
//! Android app's soak / Game Loop runs: the per-frame and per-second records, the summary
//! maths (percentiles, frames over budget, 3DMark-style stability, memory growth slope,
//! present-interval histogram), the summary text and the JSON writing.
//!
//! The report's format is `dermis-soak/1`:
//! `{"format", "status": "running" | "complete", "config": {...}, "seconds": [SecondRec],
//! "summary": {...}}` (the summary in complete reports only). Platforms may add keys (the
//! Android app adds `"thermal"` and `"android"`).

use crate::render::LiveObjects;
use crate::shading::ShadingModel;
use serde::Serialize;
use serde_json::{json, Value};
use std::path::Path;

/// The report's format tag.
pub const FORMAT: &str = "dermis-soak/1";

/// One frame.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct FrameRec {
    pub frame: usize,
    /// Submit (or present) time since the start of the run, s.
    pub t_s: f64,
    /// The CPU frame time (update + upload + encode), ms.
    pub cpu_ms: f64,
    /// The `queue.submit` call (and, on a phone, `present`), ms.
    pub submit_ms: f64,
    /// GPU time, ms; `None` when not timed.
    pub gpu_ms: Option<f64>,
    /// Interval since the previous submit / present, in target frame periods (`None` first).
    pub present_periods: Option<f64>,
    /// Heap allocations during the frame's work (0 where not counted).
    pub allocs: u64,
    /// Index of the shading tier in the config's `tiers`.
    pub tier: usize,
    pub model: &'static str,
    pub coverage: f32,
    pub lit: bool,
}

/// One second.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SecondRec {
    pub t_s: f64,
    pub frames: usize,
    pub fps: f64,
    pub cpu_ms_mean: f64,
    pub cpu_ms_max: f64,
    pub gpu_ms_mean: Option<f64>,
    pub rss_mb: Option<f64>,
    pub tier: usize,
    pub governor_changes: u64,
    pub allocs: u64,
}

impl SecondRec {
    /// The record of the frames `sec` (those since the previous second), ending at `t_s`,
    /// the previous second having ended at `prev_t_s`. `rss_mb` is left for the caller.
    pub fn of(
        sec: &[FrameRec],
        t_s: f64,
        prev_t_s: f64,
        tier: usize,
        governor_changes: u64,
    ) -> Self {
        let n = sec.len().max(1) as f64;
        let gpu: Vec<f64> = sec.iter().filter_map(|f| f.gpu_ms).collect();
        Self {
            t_s,
            frames: sec.len(),
            fps: sec.len() as f64 / (t_s - prev_t_s).max(1e-3),
            cpu_ms_mean: sec.iter().map(|f| f.cpu_ms).sum::<f64>() / n,
            cpu_ms_max: sec.iter().map(|f| f.cpu_ms).fold(0.0, f64::max),
            gpu_ms_mean: (!gpu.is_empty()).then(|| gpu.iter().sum::<f64>() / gpu.len() as f64),
            rss_mb: None,
            tier,
            governor_changes,
            allocs: sec.iter().map(|f| f.allocs).sum(),
        }
    }
}

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

/// Seconds past the warm-up below which a memory slope is not reported as a trend: the
/// allocator and driver caches still settle in the first minutes.
pub const MIN_TREND_S: f64 = 600.0;

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

/// Stability as in 3DMark: worst window's mean FPS / best window's, in %. One-minute windows
/// for runs of 5 minutes or more, else 10 equal windows, over `[t0, t1)`. Returns
/// (percent, windows, window length s, FPS per window).
pub fn stability(times: &[f64], t0: f64, t1: f64) -> (f64, usize, f64, Vec<f64>) {
    let span = t1 - t0;
    if span <= 0.0 {
        return (f64::NAN, 0, 0.0, Vec::new());
    }
    let (n, w) = if span >= 300.0 {
        ((span / 60.0).floor() as usize, 60.0)
    } else {
        (10, span / 10.0)
    };
    let mut counts = vec![0usize; n];
    for &t in times {
        if t >= t0 {
            let i = ((t - t0) / w) as usize;
            if i < n {
                counts[i] += 1;
            }
        }
    }
    let fps: Vec<f64> = counts.iter().map(|&c| c as f64 / w).collect();
    let best = fps.iter().copied().fold(0.0, f64::max);
    let worst = fps.iter().copied().fold(f64::INFINITY, f64::min);
    let pct = if best > 0.0 {
        100.0 * worst / best
    } else {
        f64::NAN
    };
    (pct, n, w, fps)
}

/// Present intervals bucketed by `round(periods)`: ≤ 1 on time, 2 → one period late, 3 →
/// two, ≥ 4 → three or more (as Android's frame-pacing library reports).
pub fn present_histogram<'a>(frames: impl IntoIterator<Item = &'a FrameRec>) -> [u64; 4] {
    let mut hist = [0u64; 4];
    for f in frames {
        if let Some(p) = f.present_periods {
            let k = (p.round().max(1.0) as usize - 1).min(3);
            hist[k] += 1;
        }
    }
    hist
}

/// Everything the summary is computed from.
pub struct SummaryInput<'a> {
    pub frames: &'a [FrameRec],
    pub seconds: &'a [SecondRec],
    /// Wall time of the run, s.
    pub elapsed: f64,
    pub budget_ms: f64,
    /// Frames before this time are left out of the steady-state statistics.
    pub warm_up_s: f64,
    pub tiers: &'a [ShadingModel],
    pub governor_changes: u64,
    pub tier_changes: u64,
    pub live_warm: Option<LiveObjects>,
    pub live_end: LiveObjects,
    pub live_changes: u64,
    pub buffers: (isize, isize),
    pub untimed: u64,
    pub runs: u32,
}

/// The summary object of a complete report.
pub fn summarize(s: &SummaryInput) -> Value {
    let steady: Vec<&FrameRec> = s.frames.iter().filter(|f| f.t_s >= s.warm_up_s).collect();
    let cpu: Vec<f64> = steady.iter().map(|f| f.cpu_ms).collect();
    let gpu: Vec<f64> = steady.iter().filter_map(|f| f.gpu_ms).collect();
    let cost: Vec<f64> = steady
        .iter()
        .map(|f| f.gpu_ms.map_or(f.cpu_ms, |g| g.max(f.cpu_ms)))
        .collect();
    let q = |v: &[f64]| {
        json!({
            "p50": percentile(v, 0.5), "p95": percentile(v, 0.95), "p99": percentile(v, 0.99),
            "max": v.iter().copied().fold(f64::NAN, f64::max),
        })
    };
    let over = cost.iter().filter(|&&c| c > s.budget_ms).count();
    let hist = present_histogram(steady.iter().copied());
    let times: Vec<f64> = s.frames.iter().map(|f| f.t_s).collect();
    let (stab, n_windows, window_s, window_fps) = stability(&times, s.warm_up_s, s.elapsed);
    let mem: Vec<(f64, f64)> = s
        .seconds
        .iter()
        .filter(|r| r.t_s >= s.warm_up_s)
        .filter_map(|r| r.rss_mb.map(|m| (r.t_s, m)))
        .collect();
    let (mt, mm): (Vec<f64>, Vec<f64>) = mem.iter().copied().unzip();
    let (growth, half) = slope_ci(&mt, &mm);
    let (growth, half) = (growth * 60.0, half * 60.0);
    let span = mt.last().zip(mt.first()).map_or(0.0, |(b, a)| b - a);
    let mut tier_frames = vec![0u64; s.tiers.len()];
    if !s.tiers.is_empty() {
        for f in s.frames {
            tier_frames[f.tier.min(s.tiers.len() - 1)] += 1;
        }
    }
    let allocs: Vec<f64> = steady.iter().map(|f| f.allocs as f64).collect();
    let fps = steady.len() as f64 / (s.elapsed - s.warm_up_s).max(1e-9);
    json!({
        "frames": s.frames.len(),
        "elapsed_s": s.elapsed,
        "steady_frames": steady.len(),
        "mean_fps": fps,
        "budget_ms": s.budget_ms,
        "cpu_frame_ms": q(&cpu),
        "submit_ms": q(&steady.iter().map(|f| f.submit_ms).collect::<Vec<_>>()),
        "gpu_frame_ms": q(&gpu),
        "frame_ms": q(&cost),
        "frames_over_budget": over,
        "frames_over_budget_pct": 100.0 * over as f64 / steady.len().max(1) as f64,
        "gpu_untimed_frames": s.untimed,
        "stability_pct": stab,
        "stability_windows": n_windows,
        "stability_window_s": window_s,
        "window_fps": window_fps,
        "memory_mb_start": mm.first(),
        "memory_mb_end": mm.last(),
        "memory_growth_mb_per_min": growth,
        "memory_growth_ci95_mb_per_min": [growth - half, growth + half],
        "memory_span_s": span,
        "memory_trend": span >= MIN_TREND_S,
        "present_histogram": {"on_time": hist[0], "late_1": hist[1], "late_2": hist[2], "late_3_plus": hist[3]},
        "allocations_per_frame": {"p50": percentile(&allocs, 0.5), "max": allocs.iter().copied().fold(f64::NAN, f64::max)},
        "tiers": s.tiers.iter().map(|m| m.name()).collect::<Vec<_>>(),
        "tier_frames": tier_frames,
        "tier_changes": s.tier_changes,
        "governor_changes": s.governor_changes,
        "gpu_objects_after_warm_up": s.live_warm,
        "gpu_objects_at_end": s.live_end,
        "gpu_object_count_changes": s.live_changes,
        "gpu_objects_constant": s.live_warm.is_some() && s.live_changes == 0,
        "gpu_buffers_live_range": [s.buffers.0, s.buffers.1],
        "game_runs": s.runs,
    })
}

/// The summary as text lines (printed by the desktop, logged to logcat on a phone).
pub fn summary_lines(config: &Value, s: &Value) -> Vec<String> {
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let mut out = Vec::new();
    out.push(format!(
        "adapter: {}   {}x{} target {} fps ({}), tiers {}",
        config["adapter"].as_str().unwrap_or("?"),
        config["size"][0],
        config["size"][1],
        config["target_fps"],
        if config["uncapped"].as_bool() == Some(true) {
            "uncapped"
        } else {
            "capped"
        },
        s["tiers"]
    ));
    out.push(format!(
        "{} frames in {:.1} s ({:.1} fps after {:.1} s warm-up), {} game runs",
        s["frames"],
        f(&s["elapsed_s"]),
        f(&s["mean_fps"]),
        f(&config["warm_up_s"]),
        s["game_runs"]
    ));
    for (name, key) in [
        ("frame (max of CPU, GPU)", "frame_ms"),
        ("CPU (update..encode)", "cpu_frame_ms"),
        ("queue.submit call", "submit_ms"),
        ("GPU", "gpu_frame_ms"),
    ] {
        let v = &s[key];
        out.push(format!(
            "  {name:<24} ms: p50 {:.2}  p95 {:.2}  p99 {:.2}  max {:.2}",
            f(&v["p50"]),
            f(&v["p95"]),
            f(&v["p99"]),
            f(&v["max"])
        ));
    }
    out.push(format!(
        "  frames over the {:.2} ms budget: {} ({:.1} %)",
        f(&s["budget_ms"]),
        s["frames_over_budget"],
        f(&s["frames_over_budget_pct"])
    ));
    out.push(format!(
        "  stability: {:.1} % (worst/best mean FPS over {} windows of {:.1} s)",
        f(&s["stability_pct"]),
        s["stability_windows"],
        f(&s["stability_window_s"])
    ));
    let ci = &s["memory_growth_ci95_mb_per_min"];
    let trend = if s["memory_trend"].as_bool() == Some(true) {
        String::new()
    } else {
        format!(
            "; only {:.0} s past the warm-up: not a trend (run ≥ {MIN_TREND_S:.0} s)",
            f(&s["memory_span_s"])
        )
    };
    out.push(format!(
        "  memory: {:.1} → {:.1} MiB, growth {:+.3} MiB/min (least squares, 95 % CI {:+.3} … {:+.3}){trend}",
        f(&s["memory_mb_start"]),
        f(&s["memory_mb_end"]),
        f(&s["memory_growth_mb_per_min"]),
        f(&ci[0]),
        f(&ci[1])
    ));
    let h = &s["present_histogram"];
    out.push(format!(
        "  present intervals: on time {}, 1 late {}, 2 late {}, 3+ late {}",
        h["on_time"], h["late_1"], h["late_2"], h["late_3_plus"]
    ));
    out.push(format!(
        "  tiers: frames per tier {} ({} changes, {} by the governor); heap allocations/frame p50 {} max {}",
        s["tier_frames"],
        s["tier_changes"],
        s["governor_changes"],
        s["allocations_per_frame"]["p50"],
        s["allocations_per_frame"]["max"]
    ));
    out.push(format!(
        "  GPU objects (pipelines, modules, bind groups, textures) constant after warm-up: {} ({} changes; live buffers {}); untimed GPU frames {}",
        s["gpu_objects_constant"], s["gpu_object_count_changes"], s["gpu_buffers_live_range"], s["gpu_untimed_frames"]
    ));
    out
}

/// The report object: `status` "running" (no summary) or "complete".
pub fn report(
    status: &str,
    config: &Value,
    seconds: &[SecondRec],
    summary: Option<&Value>,
) -> Value {
    let mut v = json!({"format": FORMAT, "status": status, "config": config, "seconds": seconds});
    if let Some(s) = summary {
        v["summary"] = s.clone();
    }
    v
}

/// Writes `value` as pretty JSON to `path` atomically (temp file + rename).
pub fn write_atomic(path: &Path, value: &Value) -> Result<(), String> {
    let tmp = path.with_extension("json.tmp");
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Resident memory in MiB (`None` where /proc is missing).
pub fn resident_mb(page_bytes: f64) -> Option<f64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: f64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * page_bytes / (1024.0 * 1024.0))
}

/// Page size: statm's resident pages against status's VmRSS (kB), rounded to a power of two;
/// 4096 when /proc cannot tell.
pub fn page_bytes() -> f64 {
    let calibrate = || -> Option<f64> {
        let status = std::fs::read_to_string("/proc/self/status").ok()?;
        let kb: f64 = status
            .lines()
            .find(|l| l.starts_with("VmRSS:"))?
            .split_whitespace()
            .nth(1)?
            .parse()
            .ok()?;
        let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
        let pages: f64 = statm.split_whitespace().nth(1)?.parse().ok()?;
        (pages > 0.0).then(|| 2f64.powf((kb * 1024.0 / pages).log2().round()))
    };
    calibrate().unwrap_or(4096.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(t_s: f64, cpu_ms: f64, periods: Option<f64>) -> FrameRec {
        FrameRec {
            frame: 0,
            t_s,
            cpu_ms,
            submit_ms: 0.0,
            gpu_ms: None,
            present_periods: periods,
            allocs: 0,
            tier: 0,
            model: "oss",
            coverage: 0.0,
            lit: true,
        }
    }

    #[test]
    fn percentiles_slope_stability() {
        let v = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 4.0);
        assert!((percentile(&v, 0.5) - 2.5).abs() < 1e-12);
        assert!(percentile(&[], 0.5).is_nan());
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
        // 10 windows over 10 s; the second half at half the rate.
        let mut times: Vec<f64> = (0..300).map(|i| i as f64 / 60.0).collect();
        times.extend((0..150).map(|i| 5.0 + i as f64 / 30.0));
        let (pct, n, w, _) = stability(&times, 0.0, 10.0);
        assert_eq!((n, w), (10, 1.0));
        assert!((pct - 50.0).abs() < 1.0, "{pct}");
        // One-minute windows from 5 minutes on.
        assert_eq!(stability(&[], 0.0, 600.0).1, 10);
    }

    #[test]
    fn histogram_and_summary() {
        let frames: Vec<FrameRec> = [None, Some(1.0), Some(0.6), Some(2.1), Some(3.0), Some(7.0)]
            .iter()
            .enumerate()
            .map(|(i, &p)| rec(i as f64, 10.0 + i as f64, p))
            .collect();
        assert_eq!(present_histogram(&frames), [2, 1, 1, 1]);
        let s = summarize(&SummaryInput {
            frames: &frames,
            seconds: &[],
            elapsed: 6.0,
            budget_ms: 12.5,
            warm_up_s: 0.0,
            tiers: &[ShadingModel::Burley],
            governor_changes: 0,
            tier_changes: 0,
            live_warm: None,
            live_end: LiveObjects::default(),
            live_changes: 0,
            buffers: (0, 0),
            untimed: 6,
            runs: 1,
        });
        assert_eq!(s["frames_over_budget"], 3);
        assert_eq!(s["present_histogram"]["late_3_plus"], 1);
        let config = json!({"adapter": "test", "size": [1, 1], "target_fps": 80.0});
        let lines = summary_lines(&config, &s);
        assert!(lines.iter().any(|l| l.contains("stability")));
        let r = report("complete", &config, &[], Some(&s));
        assert_eq!(r["format"], FORMAT);
        assert_eq!(r["summary"]["frames"], 6);
    }
}

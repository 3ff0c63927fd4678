//! The soak, shared by `dermis soak` (desktop) and the Android app's soak / Game Loop runs:
//! the [`Recorder`] (per-frame and per-second records, GPU times arriving late, the soak
//! clock that stops while paused, streamed statistics in fixed memory), the [`Writer`]
//! thread (`frames.jsonl`, the running `soak.json`, memory samples), the summary maths
//! (percentiles, frames over budget, 3DMark-style stability, memory growth slopes, the
//! present-interval histogram) and the summary text.
//!
//! The report's format is `dermis-soak/1`:
//! `{"format", "status": "running" | "complete", "config": {...}, "seconds": [SecondRec],
//! "summary": {...}}` (the summary in complete reports only). Platforms may add keys (the
//! Android app adds `"thermal"` and `"android"`).

mod recorder;
mod stats;
mod writer;

pub use dermis_engine::heap::{page_bytes, resident_mb};
pub use recorder::{FrameSample, Recorder, RecorderConfig};
pub use stats::{percentile, present_bucket, slope, slope_ci, FrameBins, LogHistogram};
pub use writer::Writer;

use dermis_engine::shading::ShadingModel;
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
    pub gpu_ms_max: Option<f64>,
    pub rss_mb: Option<f64>,
    /// Live bytes of the Rust heap, MiB (`None` when not counted).
    pub rust_heap_mb: Option<f64>,
    /// Bytes in use in the C allocator (Rust heap + the GPU driver's), MiB.
    pub malloc_mb: Option<f64>,
    pub tier: usize,
    pub governor_changes: u64,
    pub allocs: u64,
}

/// Seconds past the warm-up below which a memory slope is not reported as a trend: the
/// allocator and driver caches still settle in the first minutes.
pub const MIN_TREND_S: f64 = 600.0;

/// What a run was, beside what its [`RecorderConfig`] says: the report's `config` object.
#[derive(Clone, Debug)]
pub struct RunInfo {
    /// "desktop" or "android".
    pub platform: &'static str,
    pub adapter: String,
    pub cpu_rasterizer: bool,
    pub size: (u32, u32),
    /// Submitting as fast as possible rather than paced to the target.
    pub uncapped: bool,
    pub seed: u64,
    /// The player's chosen model (tier 0).
    pub shading: ShadingModel,
    pub governor: bool,
    pub scheduling: bool,
    /// Frames queued on the GPU at most (`None`: the swapchain decides).
    pub frames_in_flight: Option<usize>,
}

/// The report's `config` object (platforms may add keys).
pub fn config_json(cfg: &RecorderConfig, run: &RunInfo) -> Value {
    json!({
        "platform": run.platform,
        "adapter": run.adapter,
        "cpu_rasterizer": run.cpu_rasterizer,
        "seconds": cfg.seconds,
        "size": [run.size.0, run.size.1],
        "target_fps": cfg.target_fps,
        "budget_ms": cfg.budget_ms(),
        "uncapped": run.uncapped,
        "seed": run.seed,
        "shading": run.shading.name(),
        "tiers": cfg.tiers.iter().map(|m| m.name()).collect::<Vec<_>>(),
        "governor": run.governor,
        "scheduling": run.scheduling,
        "gpu_timestamps": cfg.gpu_timed,
        "frames_in_flight": run.frames_in_flight,
        "warm_up_s": cfg.warm_up_s(),
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
    let parts = &s["memory_parts"];
    out.push(format!(
        "  of which: Rust heap {:.1} → {:.1} MiB ({:+.3} MiB/min), C allocator in use (Rust heap + driver) {:.1} → {:.1} MiB ({:+.3} MiB/min), the recorder {:.2} MiB",
        f(&parts["rust_heap"]["start_mb"]),
        f(&parts["rust_heap"]["end_mb"]),
        f(&parts["rust_heap"]["growth_mb_per_min"]),
        f(&parts["malloc"]["start_mb"]),
        f(&parts["malloc"]["end_mb"]),
        f(&parts["malloc"]["growth_mb_per_min"]),
        f(&parts["recorder_mb"])
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

#[cfg(test)]
mod tests;

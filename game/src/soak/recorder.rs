//! The soak's bookkeeping, shared by every shell (`dermis soak` on the desktop, the Android
//! app's soak and Game Loop runs): per-frame records, the per-second records, GPU times that
//! arrive frames later, the soak clock (which stops while the app is paused), and the
//! statistics of the summary — all in memory that does not grow with the frame count.
//!
//! A frame's record waits in a short queue until its GPU time arrives (or the timer gives up
//! on it); then it is *final*: added to the streamed statistics and handed to the shell
//! ([`Recorder::take_final`]) to be appended to `frames.jsonl`. The recorder never keeps
//! every frame: its memory is a few fixed-size histograms, a bounded queue, and frame counts
//! per 0.1 s ([`Recorder::bytes`] says how much, reported beside the engine's memory).
//!
//! The recorder reads no clock and does no I/O: the shell passes the instants, which is what
//! makes it testable on the desktop with a simulated phone (pauses included).

use super::stats::{present_bucket, slope_ci, FrameBins, LogHistogram};
use super::{FrameRec, SecondRec, MIN_TREND_S};
use crate::governor::Needs;
use dermis_engine::render::LiveObjects;
use dermis_engine::shading::ShadingModel;
use serde_json::{json, Value};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// What a soak runs.
#[derive(Clone, Debug)]
pub struct RecorderConfig {
    /// Planned run length, s of soak clock (paused time does not count).
    pub seconds: f64,
    pub target_fps: f64,
    /// The shading tiers, best first (`FrameRec::tier` indexes them).
    pub tiers: Vec<ShadingModel>,
    /// Whether GPU times will arrive ([`Recorder::gpu_time`]); if not, frames are final at once.
    pub gpu_timed: bool,
}

impl RecorderConfig {
    /// Frames before this time are left out of the steady-state statistics: 10 % of the
    /// run, at most 2 s.
    pub fn warm_up_s(&self) -> f64 {
        (self.seconds * 0.1).min(2.0)
    }

    pub fn budget_ms(&self) -> f64 {
        1000.0 / self.target_fps
    }
}

/// One frame as a shell measured it.
#[derive(Clone, Copy, Debug)]
pub struct FrameSample {
    /// The frame driver's frame number (the key GPU times come back with).
    pub frame: usize,
    /// When the frame was handed over: the submit offscreen, the return of `present` on a
    /// surface.
    pub at: Instant,
    /// Update + upload + encode, ms.
    pub cpu_ms: f64,
    /// The submit call (and `present` on a surface), ms.
    pub submit_ms: f64,
    /// Heap allocations during the frame's work.
    pub allocs: u64,
    /// The model the session drew.
    pub model: ShadingModel,
    pub needs: Needs,
    /// The governor's changes so far.
    pub governor_changes: u64,
}

/// Frames waiting for their GPU time at most (a timer ring's slots plus slack): older ones
/// are final untimed.
const PENDING_MAX: usize = 16;

/// The soak's records and statistics.
pub struct Recorder {
    cfg: RecorderConfig,
    start: Instant,
    paused_at: Option<Instant>,
    paused: Duration,
    /// The previous frame's hand-over (`None` at the start and after a pause).
    last_at: Option<Instant>,
    frames: usize,
    pending: VecDeque<FrameRec>,
    finals: Vec<FrameRec>,
    second: SecondAcc,
    next_second: f64,
    cpu: LogHistogram,
    submit: LogHistogram,
    gpu: LogHistogram,
    cost: LogHistogram,
    allocs: LogHistogram,
    over_budget: u64,
    present: [u64; 4],
    bins: FrameBins,
    tier_frames: Vec<u64>,
    tier_changes: u64,
    last_tier: Option<usize>,
    governor_changes: u64,
    untimed: u64,
    live_warm: Option<LiveObjects>,
    live_changes: u64,
    buffers: (isize, isize),
}

/// The frames of the second in progress.
#[derive(Clone, Copy, Debug, Default)]
struct SecondAcc {
    frames: usize,
    cpu_sum: f64,
    cpu_max: f64,
    gpu_sum: f64,
    gpu_max: f64,
    gpu_n: usize,
    allocs: u64,
    t0: f64,
}

/// Whether the objects created only at load (pipelines, shader modules, bind groups,
/// textures, views, samplers) are unchanged. Buffers are left out: `queue.write_buffer`'s
/// staging buffers come and go with the frames in flight (their range is reported).
fn same_load_objects(a: &LiveObjects, b: &LiveObjects) -> bool {
    LiveObjects { buffers: 0, ..*a } == LiveObjects { buffers: 0, ..*b }
}

impl Recorder {
    /// A run whose soak clock starts at `start`.
    pub fn new(cfg: RecorderConfig, start: Instant) -> Self {
        let tiers = cfg.tiers.len();
        Self {
            bins: FrameBins::with_seconds(cfg.seconds),
            cfg,
            start,
            paused_at: None,
            paused: Duration::ZERO,
            last_at: None,
            frames: 0,
            pending: VecDeque::with_capacity(PENDING_MAX + 1),
            finals: Vec::with_capacity(256),
            second: SecondAcc::default(),
            next_second: 1.0,
            cpu: LogHistogram::new(),
            submit: LogHistogram::new(),
            gpu: LogHistogram::new(),
            cost: LogHistogram::new(),
            allocs: LogHistogram::new(),
            over_budget: 0,
            present: [0; 4],
            tier_frames: vec![0; tiers.max(1)],
            tier_changes: 0,
            last_tier: None,
            governor_changes: 0,
            untimed: 0,
            live_warm: None,
            live_changes: 0,
            buffers: (isize::MAX, isize::MIN),
        }
    }

    pub fn config(&self) -> &RecorderConfig {
        &self.cfg
    }

    /// Soak-clock seconds at `at`: wall time since the start less the time spent paused.
    pub fn clock_s(&self, at: Instant) -> f64 {
        let paused = self.paused + self.paused_at.map_or(Duration::ZERO, |p| at - p.min(at));
        (at.saturating_duration_since(self.start))
            .saturating_sub(paused)
            .as_secs_f64()
    }

    /// Stops the soak clock (the app lost its window or focus). Frames recorded while paused
    /// are an error of the shell's and count as if the clock ran.
    pub fn pause(&mut self, at: Instant) {
        if self.paused_at.is_none() {
            self.paused_at = Some(at);
        }
    }

    /// Restarts the soak clock; the first interval after a pause is not a late present.
    pub fn resume(&mut self, at: Instant) {
        if let Some(p) = self.paused_at.take() {
            self.paused += at.saturating_duration_since(p);
            self.last_at = None;
        }
    }

    pub fn is_paused(&self) -> bool {
        self.paused_at.is_some()
    }

    /// Whether the planned soak-clock time has run.
    pub fn done(&self, now: Instant) -> bool {
        self.clock_s(now) >= self.cfg.seconds
    }

    /// Frames recorded so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Records one frame; returns the record of the second it closed, if it closed one
    /// (the shell adds the memory and sends it to the report; see [`super::Writer`]).
    pub fn frame(&mut self, s: FrameSample) -> Option<SecondRec> {
        let t_s = self.clock_s(s.at);
        let period_s = 1.0 / self.cfg.target_fps;
        let present_periods = self
            .last_at
            .map(|t| s.at.saturating_duration_since(t).as_secs_f64() / period_s);
        self.last_at = Some(s.at);
        let tier = self
            .cfg
            .tiers
            .iter()
            .position(|m| *m == s.model)
            .unwrap_or(0);
        if self.last_tier.is_some_and(|t| t != tier) {
            self.tier_changes += 1;
        }
        self.last_tier = Some(tier);
        self.governor_changes = s.governor_changes;
        let rec = FrameRec {
            frame: s.frame,
            t_s,
            cpu_ms: s.cpu_ms,
            submit_ms: s.submit_ms,
            gpu_ms: None,
            present_periods,
            allocs: s.allocs,
            tier,
            model: s.model.name(),
            coverage: s.needs.coverage,
            lit: s.needs.lit,
        };
        self.frames += 1;
        let last = self.tier_frames.len() - 1;
        self.tier_frames[tier.min(last)] += 1;
        self.bins.add(t_s);
        let a = &mut self.second;
        a.frames += 1;
        a.cpu_sum += s.cpu_ms;
        a.cpu_max = a.cpu_max.max(s.cpu_ms);
        a.allocs += s.allocs;
        if self.cfg.gpu_timed {
            self.pending.push_back(rec);
            while self.pending.len() > PENDING_MAX {
                let old = self.pending.pop_front().expect("longer than PENDING_MAX");
                self.finalize(old);
            }
        } else {
            self.finalize(rec);
        }
        (t_s >= self.next_second).then(|| self.close_second(t_s, tier))
    }

    /// A GPU time measured for `frame` (ignored when that frame is already final).
    pub fn gpu_time(&mut self, frame: usize, ms: f64) {
        if let Some(rec) = self.pending.iter_mut().find(|r| r.frame == frame) {
            rec.gpu_ms = Some(ms);
            let a = &mut self.second;
            a.gpu_sum += ms;
            a.gpu_max = a.gpu_max.max(ms);
            a.gpu_n += 1;
        }
        while self.pending.front().is_some_and(|r| r.gpu_ms.is_some()) {
            let rec = self.pending.pop_front().expect("front checked");
            self.finalize(rec);
        }
    }

    /// What the GPU holds now (read once a second, outside the frame's work): load-time
    /// objects must stay constant after the warm-up.
    pub fn gpu_objects(&mut self, t_s: f64, live: LiveObjects) {
        self.buffers.0 = self.buffers.0.min(live.buffers);
        self.buffers.1 = self.buffers.1.max(live.buffers);
        match self.live_warm {
            None if t_s >= self.cfg.warm_up_s() => self.live_warm = Some(live),
            Some(w) if !same_load_objects(&w, &live) => self.live_changes += 1,
            _ => {}
        }
    }

    /// Moves the final frames (in frame order) into `out`.
    pub fn take_final(&mut self, out: &mut Vec<FrameRec>) {
        out.append(&mut self.finals);
    }

    /// Bytes the recorder holds (reported beside the process's memory).
    pub fn bytes(&self) -> usize {
        [&self.cpu, &self.submit, &self.gpu, &self.cost, &self.allocs]
            .iter()
            .map(|h| h.bytes())
            .sum::<usize>()
            + self.bins.bytes()
            + (self.pending.capacity() + self.finals.capacity()) * std::mem::size_of::<FrameRec>()
            + self.tier_frames.capacity() * 8
    }

    fn finalize(&mut self, rec: FrameRec) {
        if rec.gpu_ms.is_none() {
            self.untimed += 1;
        }
        if rec.t_s >= self.cfg.warm_up_s() {
            self.cpu.add(rec.cpu_ms);
            self.submit.add(rec.submit_ms);
            let cost = rec.gpu_ms.map_or(rec.cpu_ms, |g| g.max(rec.cpu_ms));
            self.cost.add(cost);
            if let Some(g) = rec.gpu_ms {
                self.gpu.add(g);
            }
            self.allocs.add(rec.allocs as f64);
            if cost > self.cfg.budget_ms() {
                self.over_budget += 1;
            }
            if let Some(p) = rec.present_periods {
                self.present[present_bucket(p)] += 1;
            }
        }
        self.finals.push(rec);
    }

    fn close_second(&mut self, t_s: f64, tier: usize) -> SecondRec {
        self.next_second = t_s.floor() + 1.0;
        let a = std::mem::take(&mut self.second);
        self.second.t0 = t_s;
        let n = a.frames.max(1) as f64;
        SecondRec {
            t_s,
            frames: a.frames,
            fps: a.frames as f64 / (t_s - a.t0).max(1e-3),
            cpu_ms_mean: a.cpu_sum / n,
            cpu_ms_max: a.cpu_max,
            gpu_ms_mean: (a.gpu_n > 0).then(|| a.gpu_sum / a.gpu_n as f64),
            gpu_ms_max: (a.gpu_n > 0).then_some(a.gpu_max),
            rss_mb: None,
            rust_heap_mb: None,
            malloc_mb: None,
            tier,
            governor_changes: self.governor_changes,
            allocs: a.allocs,
        }
    }

    /// Ends the run at `now`: the frames still waiting for a GPU time become final (untimed;
    /// drain the GPU timer into [`Recorder::gpu_time`] first).
    pub fn finish_frames(&mut self) {
        while let Some(rec) = self.pending.pop_front() {
            self.finalize(rec);
        }
    }

    /// The summary object of a complete report: `seconds` are the per-second records with
    /// their memory (the [`super::Writer`]'s), `elapsed` the soak-clock length of the run,
    /// `live_end` what the GPU holds at the end, `runs` the game's runs.
    pub fn summary(
        &self,
        seconds: &[SecondRec],
        elapsed: f64,
        live_end: LiveObjects,
        runs: u32,
    ) -> Value {
        let warm_up_s = self.cfg.warm_up_s();
        let steady = self.cost.len();
        let (stab, n_windows, window_s, window_fps) = self.bins.stability(warm_up_s, elapsed);
        let live_changes = self.live_changes
            + self
                .live_warm
                .is_some_and(|w| !same_load_objects(&w, &live_end)) as u64;
        let buffers = if self.buffers.0 > self.buffers.1 {
            (live_end.buffers, live_end.buffers)
        } else {
            self.buffers
        };
        let memory = |pick: fn(&SecondRec) -> Option<f64>| {
            let (mt, mm): (Vec<f64>, Vec<f64>) = seconds
                .iter()
                .filter(|r| r.t_s >= warm_up_s)
                .filter_map(|r| pick(r).map(|m| (r.t_s, m)))
                .unzip();
            let (growth, half) = slope_ci(&mt, &mm);
            let span = mt.last().zip(mt.first()).map_or(0.0, |(b, a)| b - a);
            (
                mm.first().copied(),
                mm.last().copied(),
                growth * 60.0,
                half * 60.0,
                span,
            )
        };
        let (rss0, rss1, growth, half, span) = memory(|r| r.rss_mb);
        let parts = |pick: fn(&SecondRec) -> Option<f64>| {
            let (a, b, g, h, _) = memory(pick);
            json!({"start_mb": a, "end_mb": b, "growth_mb_per_min": g,
                   "growth_ci95_mb_per_min": [g - h, g + h]})
        };
        json!({
            "frames": self.frames,
            "elapsed_s": elapsed,
            "steady_frames": steady,
            "mean_fps": steady as f64 / (elapsed - warm_up_s).max(1e-9),
            "budget_ms": self.cfg.budget_ms(),
            "cpu_frame_ms": self.cpu.quantiles_json(),
            "submit_ms": self.submit.quantiles_json(),
            "gpu_frame_ms": self.gpu.quantiles_json(),
            "frame_ms": self.cost.quantiles_json(),
            "frames_over_budget": self.over_budget,
            "frames_over_budget_pct": 100.0 * self.over_budget as f64 / steady.max(1) as f64,
            "gpu_untimed_frames": self.untimed,
            "stability_pct": stab,
            "stability_windows": n_windows,
            "stability_window_s": window_s,
            "window_fps": window_fps,
            "memory_mb_start": rss0,
            "memory_mb_end": rss1,
            "memory_growth_mb_per_min": growth,
            "memory_growth_ci95_mb_per_min": [growth - half, growth + half],
            "memory_span_s": span,
            "memory_trend": span >= MIN_TREND_S,
            "memory_parts": {
                "rust_heap": parts(|r| r.rust_heap_mb),
                "malloc": parts(|r| r.malloc_mb),
                "recorder_mb": self.bytes() as f64 / (1024.0 * 1024.0),
            },
            "present_histogram": {"on_time": self.present[0], "late_1": self.present[1],
                                  "late_2": self.present[2], "late_3_plus": self.present[3]},
            // Counts are whole numbers: the bin's value rounded (exact up to 200, where a bin holds
            // one integer; within 0.25 % above).
            "allocations_per_frame": {"p50": self.allocs.percentile(0.5).round(), "max": self.allocs.max()},
            "tiers": self.cfg.tiers.iter().map(|m| m.name()).collect::<Vec<_>>(),
            "tier_frames": self.tier_frames,
            "tier_changes": self.tier_changes,
            "governor_changes": self.governor_changes,
            "gpu_objects_after_warm_up": self.live_warm,
            "gpu_objects_at_end": live_end,
            "gpu_object_count_changes": live_changes,
            "gpu_objects_constant": self.live_warm.is_some() && live_changes == 0,
            "gpu_buffers_live_range": [buffers.0, buffers.1],
            "game_runs": runs,
        })
    }
}

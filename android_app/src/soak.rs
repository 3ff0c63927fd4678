//! The phone soak: the game on autoplay for N seconds, recording per frame the CPU frame time,
//! the present interval in target periods and the shading tier; every ~2 s thermal status and
//! headroom (a sampling thread, off the render thread); each frame's actual work duration
//! reported to an API 33 performance-hint session where there is one. At the end the summary
//! ([`dermis_core::soak`], the desktop's maths) goes to logcat and the report to
//! `soak.json` in the external files directory (and, for a Game Loop test, to the file the
//! intent's data URI names).
//!
//! Game Loop scenarios ([`scenario`]): 1 = 60 s oss, 2 = 60 s burley, 3 = 600 s oss, all at
//! 60 fps.

use crate::ndk_dl::{HintSession, Thermal, ThermalSample};
use dermis_core::governor::{Needs, Tiers};
use dermis_core::render::{Gpu, LiveObjects};
use dermis_core::shading::ShadingModel;
use dermis_core::soak::{
    page_bytes, report, resident_mb, summarize, write_atomic, FrameRec, SecondRec, SummaryInput,
};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Thermal sampling period.
const THERMAL_PERIOD: Duration = Duration::from_secs(2);
/// The running report is rewritten every this many seconds.
const WRITE_EVERY_S: usize = 10;

/// A Game Loop scenario: (seconds, shading model name).
pub fn scenario(n: i32) -> Option<(u32, &'static str)> {
    match n {
        1 => Some((60, "oss")),
        2 => Some((60, "burley")),
        3 => Some((600, "oss")),
        _ => None,
    }
}

/// What to run.
#[derive(Clone, Debug)]
pub struct SoakConfig {
    pub seconds: f64,
    pub target_fps: f64,
    pub shading: ShadingModel,
    /// The Game Loop scenario number, if a test loop.
    pub scenario: Option<i32>,
    /// Where `soak.json` goes (the external files directory).
    pub out_dir: Option<PathBuf>,
}

type ThermalThread = (mpsc::Sender<()>, JoinHandle<Vec<ThermalSample>>);

pub struct Soak {
    pub cfg: SoakConfig,
    tiers: Tiers,
    start: Option<Instant>,
    last_present: Option<Instant>,
    frames: Vec<FrameRec>,
    seconds: Vec<SecondRec>,
    second_start: usize,
    next_second: f64,
    last_second_t: f64,
    page: f64,
    warm_up_s: f64,
    tier_changes: u64,
    governor_changes: u64,
    last_tier: usize,
    live_warm: Option<LiveObjects>,
    live_changes: u64,
    buffers: (isize, isize),
    thermal: Option<ThermalThread>,
    hint: Option<HintSession>,
    hint_tried: bool,
    adapter: String,
    size: (u32, u32),
}

/// The objects created only at load (buffers left out: staging buffers come and go).
fn same_load_objects(a: &LiveObjects, b: &LiveObjects) -> bool {
    LiveObjects { buffers: 0, ..*a } == LiveObjects { buffers: 0, ..*b }
}

impl Soak {
    pub fn new(cfg: SoakConfig) -> Self {
        let expect = (cfg.seconds * cfg.target_fps * 1.1) as usize + 64;
        Soak {
            tiers: Tiers::for_choice(cfg.shading),
            warm_up_s: (cfg.seconds * 0.1).min(2.0),
            cfg,
            start: None,
            last_present: None,
            frames: Vec::with_capacity(expect),
            seconds: Vec::new(),
            second_start: 0,
            next_second: 1.0,
            last_second_t: 0.0,
            page: page_bytes(),
            tier_changes: 0,
            governor_changes: 0,
            last_tier: usize::MAX,
            live_warm: None,
            live_changes: 0,
            buffers: (isize::MAX, isize::MIN),
            thermal: None,
            hint: None,
            hint_tried: false,
            adapter: String::new(),
            size: (0, 0),
        }
    }

    fn period_s(&self) -> f64 {
        1.0 / self.cfg.target_fps
    }

    /// Called on the render thread just before a frame's work starts (the first call starts
    /// the clock, the thermal thread and the hint session).
    fn begin(&mut self, gpu: &Gpu) {
        if self.start.is_some() {
            return;
        }
        let start = Instant::now();
        self.start = Some(start);
        self.adapter = gpu.adapter_name();
        log::info!(
            "soak: {} s at {} fps, shading {} (tiers {:?}){}",
            self.cfg.seconds,
            self.cfg.target_fps,
            self.cfg.shading.name(),
            self.tiers
                .as_slice()
                .iter()
                .map(|m| m.name())
                .collect::<Vec<_>>(),
            self.cfg
                .scenario
                .map_or(String::new(), |s| format!(", Game Loop scenario {s}"))
        );
        if !self.hint_tried {
            self.hint_tried = true;
            self.hint = HintSession::for_this_thread((self.period_s() * 1e9) as i64);
        }
        if crate::ndk_dl::get().thermal_acquire.is_some() {
            let (tx, rx) = mpsc::channel::<()>();
            let thread = std::thread::Builder::new()
                .name("soak thermal".into())
                .spawn(move || {
                    let mut samples = Vec::new();
                    let Some(thermal) = Thermal::acquire() else {
                        log::warn!("AThermal_acquireManager returned null");
                        return samples;
                    };
                    loop {
                        samples.push(thermal.sample(start.elapsed().as_secs_f64()));
                        match rx.recv_timeout(THERMAL_PERIOD) {
                            Err(mpsc::RecvTimeoutError::Timeout) => {}
                            _ => break,
                        }
                    }
                    samples
                });
            match thread {
                Ok(h) => self.thermal = Some((tx, h)),
                Err(e) => log::warn!("cannot start the thermal thread: {e}"),
            }
        }
    }

    /// Records one presented frame: `work_start` when the frame's work began (after the
    /// swapchain image was acquired), `cpu_ms` update..encode, `submit_ms` submit + present,
    /// `presented` right after `present` returned; `model` the tier the session's governor
    /// drew, `needs` what the frame needed, `governor_changes` the governor's changes so far.
    #[allow(clippy::too_many_arguments)]
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        size: (u32, u32),
        work_start: Instant,
        cpu_ms: f64,
        submit_ms: f64,
        presented: Instant,
        model: ShadingModel,
        needs: Needs,
        governor_changes: u64,
    ) {
        self.governor_changes = governor_changes;
        self.begin(gpu);
        self.size = size;
        let start = self.start.unwrap_or(work_start);
        if let Some(h) = &mut self.hint {
            h.report((presented - work_start).as_nanos() as i64);
        }
        let present_periods = self
            .last_present
            .map(|t| (presented - t).as_secs_f64() / self.period_s());
        self.last_present = Some(presented);
        let tier = self
            .tiers
            .as_slice()
            .iter()
            .position(|m| *m == model)
            .unwrap_or(0);
        if tier != self.last_tier && self.last_tier != usize::MAX {
            self.tier_changes += 1;
        }
        self.last_tier = tier;
        let t_s = presented.saturating_duration_since(start).as_secs_f64();
        self.frames.push(FrameRec {
            frame: self.frames.len(),
            t_s,
            cpu_ms,
            submit_ms,
            gpu_ms: None,
            present_periods,
            allocs: 0,
            tier,
            model: model.name(),
            coverage: needs.coverage,
            lit: needs.lit,
        });
        if t_s >= self.next_second {
            self.next_second += 1.0;
            let live = LiveObjects::read(&gpu.device);
            self.buffers.0 = self.buffers.0.min(live.buffers);
            self.buffers.1 = self.buffers.1.max(live.buffers);
            match self.live_warm {
                None if t_s >= self.warm_up_s => self.live_warm = Some(live),
                Some(w) if !same_load_objects(&w, &live) => self.live_changes += 1,
                _ => {}
            }
            let mut rec = SecondRec::of(
                &self.frames[self.second_start..],
                t_s,
                self.last_second_t,
                tier,
                self.governor_changes,
            );
            rec.rss_mb = resident_mb(self.page);
            self.seconds.push(rec);
            self.second_start = self.frames.len();
            self.last_second_t = t_s;
            if self.seconds.len().is_multiple_of(WRITE_EVERY_S) {
                if let Some(dir) = &self.cfg.out_dir {
                    let r = report("running", &self.config(), &self.seconds, None);
                    if let Err(e) = write_atomic(&dir.join("soak.json"), &r) {
                        log::warn!("soak.json: {e}");
                    }
                }
            }
        }
    }

    /// Whether the run's time is up.
    pub fn done(&self) -> bool {
        self.start
            .is_some_and(|s| s.elapsed().as_secs_f64() >= self.cfg.seconds)
    }

    fn config(&self) -> Value {
        json!({
            "platform": "android",
            "android_sdk": android_activity::AndroidApp::sdk_version(),
            "device": device_name(),
            "adapter": self.adapter,
            "cpu_rasterizer": false,
            "seconds": self.cfg.seconds,
            "size": [self.size.0, self.size.1],
            "target_fps": self.cfg.target_fps,
            "budget_ms": 1000.0 / self.cfg.target_fps,
            "uncapped": false,
            "shading": self.cfg.shading.name(),
            "tiers": self.tiers.as_slice().iter().map(|m| m.name()).collect::<Vec<_>>(),
            "governor": false,
            "scheduling": false,
            "gpu_timestamps": false,
            "warm_up_s": self.warm_up_s,
            "scenario": self.cfg.scenario,
            "present_mode": "Fifo",
        })
    }

    /// Ends the run: stops the thermal thread, computes the summary, logs it and returns the
    /// complete report.
    pub fn finish(&mut self, device: &wgpu::Device, runs: u32) -> Value {
        let elapsed = self.start.map_or(0.0, |s| s.elapsed().as_secs_f64());
        let thermal = match self.thermal.take() {
            Some((tx, h)) => {
                drop(tx);
                h.join().unwrap_or_default()
            }
            None => Vec::new(),
        };
        let hint = self.hint.take().is_some();
        let live_end = LiveObjects::read(device);
        if let Some(w) = self.live_warm {
            if !same_load_objects(&w, &live_end) {
                self.live_changes += 1;
            }
        }
        if self.buffers.0 > self.buffers.1 {
            self.buffers = (live_end.buffers, live_end.buffers);
        }
        let summary = summarize(&SummaryInput {
            frames: &self.frames,
            seconds: &self.seconds,
            elapsed,
            budget_ms: 1000.0 / self.cfg.target_fps,
            warm_up_s: self.warm_up_s,
            tiers: self.tiers.as_slice(),
            governor_changes: self.governor_changes,
            tier_changes: self.tier_changes,
            live_warm: self.live_warm,
            live_end,
            live_changes: self.live_changes,
            buffers: self.buffers,
            untimed: self.frames.len() as u64,
            runs,
        });
        let config = self.config();
        for line in dermis_core::soak::summary_lines(&config, &summary) {
            log::info!("soak: {line}");
        }
        let statuses: Vec<i32> = thermal.iter().filter_map(|s| s.status).collect();
        let headroom: Vec<f32> = thermal
            .iter()
            .filter_map(|s| s.headroom)
            .filter(|h| h.is_finite())
            .collect();
        let ndk = crate::ndk_dl::get();
        let android = json!({
            "thermal_api": ndk.thermal_acquire.is_some(),
            "thermal_headroom_api": ndk.thermal_headroom.is_some(),
            "set_frame_rate_api": ndk.set_frame_rate.is_some(),
            "performance_hint_session": hint,
            "thermal_status_max": statuses.iter().max(),
            "thermal_headroom_max": headroom.iter().copied().reduce(f32::max),
        });
        log::info!("soak: {android}");
        let mut r = report("complete", &config, &self.seconds, Some(&summary));
        r["thermal"] = json!(thermal);
        r["android"] = android;
        r
    }
}

/// `ro.product.manufacturer` + `ro.product.model` (system properties, API 21).
fn device_name() -> String {
    let prop = |name: &std::ffi::CStr| {
        let mut buf = [0u8; 92]; // PROP_VALUE_MAX
                                 // SAFETY: a NUL-terminated name and a PROP_VALUE_MAX buffer, as the API requires.
        let n = unsafe { libc::__system_property_get(name.as_ptr(), buf.as_mut_ptr().cast()) };
        String::from_utf8_lossy(&buf[..n.clamp(0, 91) as usize]).into_owned()
    };
    format!(
        "{} {}",
        prop(c"ro.product.manufacturer"),
        prop(c"ro.product.model")
    )
}

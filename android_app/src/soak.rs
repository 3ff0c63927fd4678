//! The phone soak: the game on autoplay for N seconds of soak clock, recorded by the core's
//! [`Recorder`] exactly as `dermis soak` records the desktop (the same per-frame and
//! per-second records, GPU times where the device has timestamp queries, heap allocations per
//! frame, the session governor's tier, memory split into resident / C allocator / Rust heap),
//! written by the core's [`Writer`] to `frames.jsonl` and a running `soak.json` in the
//! external files directory. The soak clock stops while the app is paused or has no window.
//! On top of the desktop's report: thermal status and headroom every ~2 s (a sampling
//! thread) and each frame's work reported to an API 33 performance-hint session where there
//! is one. At the end the summary goes to logcat and the complete report to `soak.json` (and,
//! for a Game Loop test, to the file the intent's data URI names).
//!
//! Game Loop scenarios ([`scenario`]): 1 = 60 s oss, 2 = 60 s of the first screen-space model
//! (the registry's menu order), 3 = 600 s oss, all at
//! 60 fps.

use crate::ndk_dl::{HintSession, Thermal, ThermalSample};
use dermis_engine::render::{FrameTimes, Gpu, LiveObjects};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{soak_sample, Session};
use dermis_game::soak::{
    config_json, report, summary_lines, Recorder, RecorderConfig, RunInfo, Writer,
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

/// A Game Loop scenario: (seconds, shading model).
pub fn scenario(n: i32) -> Option<(u32, ShadingModel)> {
    let screen_space = || {
        ShadingModel::ALL
            .into_iter()
            .find(|m| m.effects().screen_space)
    };
    match n {
        1 => Some((60, ShadingModel::Oss)),
        2 => Some((60, screen_space()?)),
        3 => Some((600, ShadingModel::Oss)),
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
    /// Where `soak.json` and `frames.jsonl` go (the external files directory).
    pub out_dir: Option<PathBuf>,
}

type ThermalThread = (mpsc::Sender<()>, JoinHandle<Vec<ThermalSample>>);

/// A run in progress (from its first frame).
struct Run {
    rec: Recorder,
    writer: Writer,
    config: Value,
}

pub struct Soak {
    pub cfg: SoakConfig,
    run: Option<Run>,
    thermal: Option<ThermalThread>,
    hint: Option<HintSession>,
}

impl Soak {
    pub fn new(cfg: SoakConfig) -> Self {
        Soak {
            cfg,
            run: None,
            thermal: None,
            hint: None,
        }
    }

    fn period_s(&self) -> f64 {
        1.0 / self.cfg.target_fps
    }

    /// Starts the run at its first frame: the recorder, the writer, the thermal thread and
    /// the hint session.
    fn begin(&mut self, gpu: &Gpu, times: &FrameTimes, session: &Session) -> Run {
        let rec_cfg = RecorderConfig {
            seconds: self.cfg.seconds,
            target_fps: self.cfg.target_fps,
            tiers: session.governor.tiers().as_slice().to_vec(),
            gpu_timed: gpu.timestamps,
        };
        let info = RunInfo {
            platform: "android",
            adapter: gpu.adapter_name(),
            cpu_rasterizer: gpu.is_cpu(),
            size: (times.width, times.height),
            uncapped: false,
            seed: session.game.seed(),
            shading: self.cfg.shading,
            governor: session.governor.enabled,
            scheduling: session.governor.scheduling,
            frames_in_flight: None,
        };
        let mut config = config_json(&rec_cfg, &info);
        config["android_sdk"] = json!(android_activity::AndroidApp::sdk_version());
        config["device"] = json!(device_name());
        config["scenario"] = json!(self.cfg.scenario);
        config["present_mode"] = json!("Fifo");
        log::info!(
            "soak: {} s at {} fps, shading {} (tiers {}){}",
            self.cfg.seconds,
            self.cfg.target_fps,
            self.cfg.shading.name(),
            config["tiers"],
            self.cfg
                .scenario
                .map_or(String::new(), |s| format!(", Game Loop scenario {s}"))
        );
        let writer = match Writer::start(
            self.cfg.out_dir.clone(),
            config.clone(),
            WRITE_EVERY_S,
            self.cfg.seconds,
        ) {
            Ok(w) => w,
            Err(e) => {
                log::warn!("soak: {e}; frames.jsonl is not written");
                Writer::start(None, config.clone(), WRITE_EVERY_S, self.cfg.seconds)
                    .expect("a writer without files starts")
            }
        };
        self.hint = HintSession::for_this_thread((self.period_s() * 1e9) as i64);
        let start = times.start;
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
        Run {
            rec: Recorder::new(rec_cfg, start),
            writer,
            config,
        }
    }

    /// Records one presented frame: its times, the GPU times the driver harvested this
    /// frame, and what the session drew. The first frame after a pause restarts the clock.
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        times: &FrameTimes,
        harvested: &[(usize, f64)],
        session: &Session,
    ) {
        if self.run.is_none() {
            let run = self.begin(gpu, times, session);
            self.run = Some(run);
        }
        let Some(run) = &mut self.run else { return };
        if run.rec.is_paused() {
            run.rec.resume(times.start);
            log::info!(
                "soak: clock resumed at {:.1} s",
                run.rec.clock_s(times.start)
            );
        }
        if let Some(h) = &mut self.hint {
            h.report((times.presented - times.start).as_nanos() as i64);
        }
        for &(f, ms) in harvested {
            run.rec.gpu_time(f, ms);
        }
        let closed = run.rec.frame(soak_sample(times, session, true));
        if let Some(second) = closed {
            run.rec
                .gpu_objects(second.t_s, LiveObjects::read(&gpu.device));
            let mut batch = Vec::new();
            run.rec.take_final(&mut batch);
            run.writer.frames(batch);
            run.writer.second(second);
        }
    }

    /// A GPU time that arrived after the frames stopped (the driver's drain at the end).
    pub fn gpu_time(&mut self, frame: usize, ms: f64) {
        if let Some(run) = &mut self.run {
            run.rec.gpu_time(frame, ms);
        }
    }

    /// Stops the soak clock: the app was paused, lost focus or its window.
    pub fn pause(&mut self) {
        if let Some(run) = &mut self.run {
            if !run.rec.is_paused() {
                let now = Instant::now();
                run.rec.pause(now);
                log::info!("soak: clock paused at {:.1} s", run.rec.clock_s(now));
            }
        }
    }

    /// Whether the run's soak-clock time is up.
    pub fn done(&self) -> bool {
        self.run
            .as_ref()
            .is_some_and(|r| r.rec.done(Instant::now()))
    }

    /// Ends the run: stops the thermal thread, computes the summary, logs it and returns the
    /// complete report (`None` if no frame was ever drawn).
    pub fn finish(&mut self, device: &wgpu::Device, runs: u32) -> Option<Value> {
        let thermal = match self.thermal.take() {
            Some((tx, h)) => {
                drop(tx);
                h.join().unwrap_or_default()
            }
            None => Vec::new(),
        };
        let hint = self.hint.take().is_some();
        let Run {
            mut rec,
            writer,
            config,
        } = self.run.take()?;
        let elapsed = rec.clock_s(Instant::now());
        rec.finish_frames();
        let mut batch = Vec::new();
        rec.take_final(&mut batch);
        writer.frames(batch);
        let seconds = writer.finish().unwrap_or_else(|e| {
            log::warn!("soak: {e}");
            Vec::new()
        });
        let summary = rec.summary(&seconds, elapsed, LiveObjects::read(device), runs);
        for line in summary_lines(&config, &summary) {
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
        let mut r = report("complete", &config, &seconds, Some(&summary));
        r["thermal"] = json!(thermal);
        r["android"] = android;
        Some(r)
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

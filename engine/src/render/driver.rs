//! One frame driver for every shell, in the shape of wgpu's examples `framework.rs`: the shell
//! owns its window and event loop (or none), the app is a [`FrameWork`], and
//! [`FrameDriver::frame`] runs one frame of it — resize (to the output's size) → dt → update
//! → upload → encode → submit → present — into a window surface ([`SurfaceTarget`])
//! or an [`Offscreen`] target, and says when each step ended ([`FrameTimes`]).
//!
//! Options the shells differ in, all here: the clock ([`Clock`]: the wall clock, or a fixed
//! step for reproducible headless runs), swapchain-like back-pressure for offscreen targets
//! ([`FrameDriver::max_in_flight`]), waiting for the GPU after each frame
//! ([`FrameDriver::sync`]), non-stalling GPU timing of every frame ([`TimerRing`]) and
//! allocation counts between the steps (a counter from the binary's global allocator).
//! Nothing here allocates per frame.

use std::collections::VecDeque;
use std::time::Instant;

use super::offscreen::Offscreen;
use super::prepared::RenderStats;
use super::surface::{FrameStatus, SurfaceTarget};
use super::targets::Targets;
use super::timer::TimerRing;
use super::Gpu;

/// Where a frame is drawn.
pub struct FrameOutput<'a> {
    pub targets: &'a Targets,
    pub view: &'a wgpu::TextureView,
    /// The texture `view` shows (a surface image or the offscreen texture), for copies.
    pub texture: &'a wgpu::Texture,
}

/// What a frame driver drives: the app's per-frame work.
pub trait FrameWork {
    /// The output is `width` × `height` (called before every frame's update): make what
    /// depends on the size when it changed.
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32);
    /// CPU work: advance by `dt` seconds, for an output of `width` × `height`.
    fn update(&mut self, dt: f64, width: u32, height: u32);
    /// This frame's buffer writes.
    fn upload(&mut self, gpu: &Gpu);
    /// Records the frame's passes into `encoder`.
    fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        output: &FrameOutput<'_>,
    ) -> RenderStats;
}

/// The target of one frame.
pub enum Output<'a> {
    /// A window surface: acquired, drawn, presented.
    Surface(&'a mut SurfaceTarget),
    /// An offscreen target: drawn and submitted (nothing to present).
    Offscreen(&'a Offscreen),
}

/// Where a frame's `dt` comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Clock {
    /// Always this step (s): headless runs independent of the wall clock.
    Fixed(f64),
    /// The wall-clock time between the starts of consecutive frames, clamped to
    /// `min..=max`; `first` for the first frame.
    Wall { first: f64, min: f64, max: f64 },
}

impl Clock {
    /// The wall clock as the interactive shells use it: 1/60 s first, at most 0.1 s.
    pub const INTERACTIVE: Clock = Clock::Wall {
        first: 1.0 / 60.0,
        min: 0.0,
        max: 0.1,
    };
}

/// Heap allocation counts (from the driver's counter) when each step ended; all zero
/// without a counter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Allocs {
    pub start: u64,
    pub updated: u64,
    pub submitted: u64,
    /// After the frame's bookkeeping (GPU times harvested).
    pub done: u64,
}

/// When each step of one drawn frame ended.
#[derive(Clone, Copy, Debug)]
pub struct FrameTimes {
    /// Index of this frame among those the driver drew (from 0).
    pub frame: u64,
    pub dt: f64,
    pub width: u32,
    pub height: u32,
    /// Work began (after the swapchain image was acquired or the back-pressure wait).
    pub start: Instant,
    pub updated: Instant,
    /// Right before `queue.submit`.
    pub encoded: Instant,
    /// Right after `queue.submit`.
    pub submitted: Instant,
    /// Right after `present` (offscreen: = `submitted`).
    pub presented: Instant,
    pub allocs: Allocs,
    pub stats: RenderStats,
    /// The timer slot the frame was timed with (`None`: untimed).
    pub timer_slot: Option<usize>,
    pub status: FrameStatus,
}

fn ms(a: Instant, b: Instant) -> f64 {
    (b - a).as_secs_f64() * 1e3
}

impl FrameTimes {
    /// The CPU frame time: update + upload + encode (ms).
    pub fn cpu_ms(&self) -> f64 {
        ms(self.start, self.encoded)
    }

    /// The `queue.submit` call alone (ms).
    pub fn submit_ms(&self) -> f64 {
        ms(self.encoded, self.submitted)
    }

    /// Submit and present (ms).
    pub fn submit_present_ms(&self) -> f64 {
        ms(self.encoded, self.presented)
    }
}

/// Runs frames of a [`FrameWork`] (see the module docs).
pub struct FrameDriver {
    pub clock: Clock,
    /// Offscreen: at most this many frames queued on the GPU (the wait is not part of the
    /// frame's work), as a swapchain would. `None`: no limit.
    pub max_in_flight: Option<usize>,
    /// Wait for the GPU after each submit (and read the frame's GPU time at once).
    pub sync: bool,
    counter: Option<fn() -> u64>,
    timer: Option<TimerRing>,
    in_flight: VecDeque<wgpu::SubmissionIndex>,
    harvested: Vec<(usize, f64)>,
    last_gpu_ms: f64,
    last_start: Option<Instant>,
    frames: u64,
}

impl FrameDriver {
    pub fn new(clock: Clock) -> Self {
        Self {
            clock,
            max_in_flight: None,
            sync: false,
            counter: None,
            timer: None,
            in_flight: VecDeque::with_capacity(4),
            harvested: Vec::with_capacity(TimerRing::SLOTS),
            last_gpu_ms: f64::NAN,
            last_start: None,
            frames: 0,
        }
    }

    /// The interactive shells' driver (the window, the phone): the wall clock
    /// ([`Clock::INTERACTIVE`]) and every frame timed on the GPU when it can be.
    pub fn interactive(gpu: &Gpu) -> Self {
        Self::new(Clock::INTERACTIVE).with_timer(gpu)
    }

    /// Times every frame on the GPU when the device has timestamps.
    pub fn with_timer(mut self, gpu: &Gpu) -> Self {
        self.timer = TimerRing::new(gpu);
        self
    }

    /// Counts heap allocations between the steps with `counter` (a global allocator's).
    pub fn with_alloc_counter(mut self, counter: fn() -> u64) -> Self {
        self.counter = Some(counter);
        self
    }

    /// The GPU timer, when frames are timed.
    pub fn timer(&self) -> Option<&TimerRing> {
        self.timer.as_ref()
    }

    /// Frames drawn so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The latest GPU frame time known (ms; NaN before the first), a few frames old unless
    /// [`Self::sync`].
    pub fn last_gpu_ms(&self) -> f64 {
        self.last_gpu_ms
    }

    /// The GPU times `(frame, ms)` read back during the last [`Self::frame`].
    pub fn harvested(&self) -> &[(usize, f64)] {
        &self.harvested
    }

    /// What the last frame cost, as the frame-time governor sees it: the larger of its CPU
    /// time and the latest GPU time known.
    pub fn cost_ms(&self, times: &FrameTimes) -> f64 {
        let cpu = times.cpu_ms();
        if self.last_gpu_ms.is_finite() {
            cpu.max(self.last_gpu_ms)
        } else {
            cpu
        }
    }

    /// Forgets the last frame's start (after a pause the next `dt` is `first` again).
    pub fn reset_clock(&mut self) {
        self.last_start = None;
    }

    fn count(&self) -> u64 {
        self.counter.map_or(0, |c| c())
    }

    fn dt(&mut self, now: Instant) -> f64 {
        let dt = match self.clock {
            Clock::Fixed(dt) => dt,
            Clock::Wall { first, min, max } => self
                .last_start
                .map_or(first, |t| (now - t).as_secs_f64().clamp(min, max)),
        };
        self.last_start = Some(now);
        dt
    }

    /// Runs one frame of `work` into `output`: `Err` with the surface's status when there
    /// is no image to draw this time.
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        output: Output<'_>,
        work: &mut impl FrameWork,
    ) -> Result<FrameTimes, FrameStatus> {
        self.harvested.clear();
        match output {
            Output::Offscreen(o) => {
                self.back_pressure(gpu);
                let out = FrameOutput {
                    targets: &o.targets,
                    view: &o.view,
                    texture: &o.texture,
                };
                Ok(self.run(gpu, work, &out, FrameStatus::Presented))
            }
            Output::Surface(s) => {
                let (frame, status) = s.acquire(gpu)?;
                self.back_pressure(gpu);
                let view = frame
                    .texture
                    .create_view(&wgpu::TextureViewDescriptor::default());
                let out = FrameOutput {
                    targets: &s.targets,
                    view: &view,
                    texture: &frame.texture,
                };
                let mut times = self.run(gpu, work, &out, status);
                drop(view);
                s.present(gpu, frame, status);
                times.presented = Instant::now();
                Ok(times)
            }
        }
    }

    /// Waits until fewer than [`Self::max_in_flight`] frames are queued on the GPU.
    fn back_pressure(&mut self, gpu: &Gpu) {
        let Some(max) = self.max_in_flight else {
            return;
        };
        while self.in_flight.len() >= max.max(1) {
            if let Some(idx) = self.in_flight.pop_front() {
                let _ = gpu.device.poll(wgpu::PollType::Wait {
                    submission_index: Some(idx),
                    timeout: None,
                });
            }
        }
    }

    fn run(
        &mut self,
        gpu: &Gpu,
        work: &mut impl FrameWork,
        out: &FrameOutput<'_>,
        status: FrameStatus,
    ) -> FrameTimes {
        let (width, height) = (out.targets.width, out.targets.height);
        work.resize(gpu, width, height);
        let start = Instant::now();
        let dt = self.dt(start);
        let a_start = self.count();
        work.update(dt, width, height);
        let updated = Instant::now();
        let a_updated = self.count();
        work.upload(gpu);
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let frame = self.frames as usize;
        let slot = self.timer.as_mut().and_then(|r| r.begin(frame));
        if let (Some(r), Some(s)) = (&self.timer, slot) {
            r.start(&mut encoder, s);
        }
        let stats = work.encode(&mut encoder, out);
        if let (Some(r), Some(s)) = (&self.timer, slot) {
            r.end(&mut encoder, s);
        }
        let commands = encoder.finish();
        let encoded = Instant::now();
        let index = gpu.queue.submit([commands]);
        let submitted = Instant::now();
        let a_submitted = self.count();
        if let (Some(r), Some(s)) = (&self.timer, slot) {
            r.submitted(s);
        }
        if self.max_in_flight.is_some() {
            self.in_flight.push_back(index);
        }
        if self.sync {
            gpu.wait();
        }
        if self.timer.is_some() || self.max_in_flight.is_some() {
            let _ = gpu.device.poll(if self.sync {
                wgpu::PollType::wait_indefinitely()
            } else {
                wgpu::PollType::Poll
            });
        }
        if let Some(r) = &mut self.timer {
            let (harvested, last) = (&mut self.harvested, &mut self.last_gpu_ms);
            r.harvest(|f, ms| {
                if harvested.len() < harvested.capacity() {
                    harvested.push((f, ms));
                }
                *last = ms;
            });
        }
        self.frames += 1;
        FrameTimes {
            frame: frame as u64,
            dt,
            width,
            height,
            start,
            updated,
            encoded,
            submitted,
            presented: submitted,
            allocs: Allocs {
                start: a_start,
                updated: a_updated,
                submitted: a_submitted,
                done: self.count(),
            },
            stats,
            timer_slot: slot,
            status,
        }
    }

    /// Waits for the GPU and reads every GPU time still in flight: `f(frame, ms)`.
    pub fn drain(&mut self, gpu: &Gpu, mut f: impl FnMut(usize, f64)) {
        gpu.wait();
        let Some(r) = &mut self.timer else {
            return;
        };
        for _ in 0..100 {
            let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
            r.harvest(&mut f);
            if r.oldest_pending().is_none() {
                break;
            }
        }
    }
}

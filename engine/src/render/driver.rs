//! Frame helpers every shell calls (the shell owns its window and event loop, or none, and
//! the app's frame is straight-line code between them): [`FrameDriver::begin`] acquires the
//! output (a window surface's image, [`SurfaceTarget`], or an [`Offscreen`] target), waits
//! for back-pressure, works out `dt` and opens the frame's encoder; the app updates,
//! extracts, prepares and encodes into [`Frame::encoder`]; [`FrameDriver::finish`] submits,
//! presents and says when each step ended ([`FrameTimes`]). The driver calls nothing of the
//! app's.
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
use super::prepared::{PassCtx, RenderStats};
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

/// The target of one frame.
pub enum Output<'a> {
    /// A window surface: acquired, drawn, presented.
    Surface(&'a mut SurfaceTarget),
    /// An offscreen target: drawn and submitted (nothing to present).
    Offscreen(&'a Offscreen),
}

impl Output<'_> {
    /// The MSAA colour and depth targets of the output's size.
    pub fn targets(&self) -> &Targets {
        match self {
            Output::Surface(s) => &s.targets,
            Output::Offscreen(o) => &o.targets,
        }
    }
}

/// A frame begun by [`FrameDriver::begin`], handed back to [`FrameDriver::finish`]: its
/// `dt`, its size, the encoder its passes record into and the image they draw.
pub struct Frame {
    /// Index of this frame among those the driver drew (from 0).
    pub index: u64,
    pub dt: f64,
    /// The output's size in pixels.
    pub size: (u32, u32),
    pub encoder: wgpu::CommandEncoder,
    /// The image drawn (a swapchain image or the offscreen texture).
    pub view: wgpu::TextureView,
    /// The texture `view` shows, for copies.
    pub texture: wgpu::Texture,
    image: Option<wgpu::SurfaceTexture>,
    status: FrameStatus,
    start: Instant,
    updated: Instant,
    allocs: Allocs,
    timer_slot: Option<usize>,
}

impl Frame {
    /// The pass context the frame's passes record into (untimed passes: the driver's timer
    /// brackets the whole frame).
    pub fn pass_ctx<'a>(&'a mut self, output: &'a Output<'_>) -> PassCtx<'a> {
        PassCtx {
            encoder: &mut self.encoder,
            targets: output.targets(),
            output: &self.view,
            timer: None,
        }
    }
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

/// Heap allocation counts (from the driver's counter) when each step ended (`start`: once
/// the frame's encoder was opened); all zero without a counter.
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

/// The helpers a shell runs its frames with (see the module docs).
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

    /// Begins a frame into `output`: acquires its image (a surface; `Err` with the surface's
    /// status when there is none this time), waits for back-pressure, works out `dt` and
    /// opens the frame's encoder (with the GPU timer's start written when frames are timed).
    pub fn begin(&mut self, gpu: &Gpu, output: &mut Output<'_>) -> Result<Frame, FrameStatus> {
        self.harvested.clear();
        let (image, status, view, texture) = match output {
            Output::Offscreen(o) => (
                None,
                FrameStatus::Presented,
                o.view.clone(),
                o.texture.clone(),
            ),
            Output::Surface(s) => {
                let (image, status) = s.acquire(gpu)?;
                let view = image
                    .texture
                    .create_view(&wgpu::TextureViewDescriptor::default());
                let texture = image.texture.clone();
                (Some(image), status, view, texture)
            }
        };
        self.back_pressure(gpu);
        let targets = output.targets();
        let size = (targets.width, targets.height);
        let start = Instant::now();
        let dt = self.dt(start);
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let index = self.frames as usize;
        let timer_slot = self.timer.as_mut().and_then(|r| r.begin(index));
        if let (Some(r), Some(s)) = (&self.timer, timer_slot) {
            r.start(&mut encoder, s);
        }
        // Counted from here: the app's update is measured alone.
        let allocs = Allocs {
            start: self.count(),
            ..Allocs::default()
        };
        Ok(Frame {
            index: self.frames,
            dt,
            size,
            encoder,
            view,
            texture,
            image,
            status,
            start,
            updated: start,
            allocs,
            timer_slot,
        })
    }

    /// Marks the end of the frame's update (CPU work before its GPU side).
    pub fn updated(&self, frame: &mut Frame) {
        frame.updated = Instant::now();
        frame.allocs.updated = self.count();
    }

    /// Ends `frame`: the GPU timer's end, the submit, the present (a surface), the GPU times
    /// read back; `stats` is what its encode recorded.
    pub fn finish(
        &mut self,
        gpu: &Gpu,
        frame: Frame,
        output: &mut Output<'_>,
        stats: RenderStats,
    ) -> FrameTimes {
        let Frame {
            index,
            dt,
            size: (width, height),
            mut encoder,
            view,
            image,
            status,
            start,
            updated,
            allocs,
            timer_slot: slot,
            ..
        } = frame;
        if let (Some(r), Some(s)) = (&self.timer, slot) {
            r.end(&mut encoder, s);
        }
        let commands = encoder.finish();
        let encoded = Instant::now();
        let submission = gpu.queue.submit([commands]);
        let submitted = Instant::now();
        let a_submitted = self.count();
        if let (Some(r), Some(s)) = (&self.timer, slot) {
            r.submitted(s);
        }
        drop(view);
        let presented = match (output, image) {
            (Output::Surface(s), Some(image)) => {
                s.present(gpu, image, status);
                Instant::now()
            }
            _ => submitted,
        };
        if self.max_in_flight.is_some() {
            self.in_flight.push_back(submission);
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
            frame: index,
            dt,
            width,
            height,
            start,
            updated,
            encoded,
            submitted,
            presented,
            allocs: Allocs {
                submitted: a_submitted,
                done: self.count(),
                ..allocs
            },
            stats,
            timer_slot: slot,
            status,
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

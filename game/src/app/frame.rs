//! The game's frame, straight-line code every shell runs through [`GameFrame::run`] (the
//! desktop window, the Android app, `play`, the soak, `bench effects` and the steady-state
//! test), between the frame helpers of the core's
//! [`FrameDriver`](dermis_engine::render::FrameDriver), into a window surface or an offscreen
//! target:
//!
//! begin (acquire, dt) → the session updates (input, rules, animation, camera, UI, the
//! governor's tier) → the session's packet (plain data, [`Session::extract`]) → the renderer
//! prepares it ([`GameGpu::prepare`] → a `PreparedFrame`, everything encode reads) → the
//! renderer encodes that frame → finish (submit, present) → the governor is told what it
//! cost. Nothing goes back from the GPU side into the session, and nothing calls the game
//! from below.

use super::{FrameInfo, GameGpu, Session, Viewport};
use crate::lifecycle::FrameStatus;
use crate::rules::Screen;
use crate::soak::FrameSample;
use dermis_engine::asset::Model;
use dermis_engine::render::{
    FrameDriver, FrameOutput, FrameTimes, Gpu, Output, PreparedFrame, RenderStats,
};
use dermis_engine::ui::Insets;

/// A hook run after a game frame's passes are recorded: the encoder, the session, the output.
pub type AfterEncode<'h> = dyn FnMut(&mut wgpu::CommandEncoder, &Session, &FrameOutput<'_>) + 'h;

/// One game frame's inputs and results.
pub struct GameFrame<'a> {
    pub session: &'a mut Session,
    pub gpu: &'a mut GameGpu,
    pub character: &'a Model,
    /// Display density (1 on a desktop monitor).
    pub scale: f32,
    pub insets: Insets,
    /// A simulated frame cost (ms) the governor is told instead of the measured one (tests,
    /// what-if runs); `None`: the measured cost.
    pub simulated_cost_ms: Option<f64>,
    /// Called after the frame's passes are recorded, before the submit (screenshots).
    pub after_encode: Option<&'a mut AfterEncode<'a>>,
    /// What the last update did.
    pub info: FrameInfo,
    /// What the last encode drew.
    pub stats: RenderStats,
    /// The frame the last run prepared.
    pub prepared: Option<PreparedFrame>,
}

impl<'a> GameFrame<'a> {
    pub fn new(session: &'a mut Session, gpu: &'a mut GameGpu, character: &'a Model) -> Self {
        Self {
            session,
            gpu,
            character,
            scale: 1.0,
            insets: Insets::default(),
            simulated_cost_ms: None,
            after_encode: None,
            info: FrameInfo::default(),
            stats: RenderStats::default(),
            prepared: None,
        }
    }

    /// Runs one frame with `driver` into `output` (see the module docs) and feeds the
    /// session's governor what it cost (the larger of its CPU time and the latest GPU time,
    /// as the soak measures it), and the frame-time overlay the wall-clock time between
    /// frames, the CPU time and the GPU time.
    pub fn run(
        &mut self,
        driver: &mut FrameDriver,
        gpu: &Gpu,
        mut output: Output<'_>,
    ) -> Result<FrameTimes, FrameStatus> {
        let mut frame = driver.begin(gpu, &mut output)?;
        let (width, height) = frame.size;
        self.gpu.renderer.resize(gpu, frame.size);
        // Update.
        let viewport = Viewport {
            width,
            height,
            scale: self.scale,
            insets: self.insets,
        };
        self.session.gui.offer_head(self.gpu.has_head());
        self.info = self
            .session
            .update(frame.dt as f32, self.character, viewport);
        driver.updated(&mut frame);
        // Extract and prepare (play: every pipeline ready first).
        let settled = self.session.game.screen() == Screen::Play;
        let head = self.gpu.head.clone();
        let packet = self
            .session
            .extract(self.character, head.as_deref(), settled);
        let prepared = self.gpu.prepare(gpu, &packet);
        // Encode the frame just prepared (it cannot be stale).
        self.stats = self
            .gpu
            .renderer
            .encode(&prepared, &mut frame.pass_ctx(&output))
            .unwrap_or_else(|e| {
                log::error!("{e}");
                RenderStats::default()
            });
        self.prepared = Some(prepared);
        if let Some(hook) = &mut self.after_encode {
            let out = FrameOutput {
                targets: output.targets(),
                view: &frame.view,
                texture: &frame.texture,
            };
            hook(&mut frame.encoder, self.session, &out);
        }
        let times = driver.finish(gpu, frame, &mut output, self.stats);
        // The governor and the overlay.
        let cost = self
            .simulated_cost_ms
            .unwrap_or_else(|| driver.cost_ms(&times));
        self.session.record_frame(cost, times.dt);
        let gui = &mut self.session.gui;
        let interval = gui.frame_started(times.start);
        gui.record_frame_time(interval, times.cpu_ms(), driver.last_gpu_ms());
        Ok(times)
    }
}

/// What the soak records of a game frame: its times (handed over at the submit offscreen, at
/// the return of `present` on a surface, where the submit time includes the present) and
/// what the session drew.
pub fn soak_sample(times: &FrameTimes, session: &Session, surface: bool) -> FrameSample {
    let (at, submit_ms) = if surface {
        (times.presented, times.submit_present_ms())
    } else {
        (times.submitted, times.submit_ms())
    };
    FrameSample {
        frame: times.frame as usize,
        at,
        cpu_ms: times.cpu_ms(),
        submit_ms,
        allocs: times.allocs.done - times.allocs.start,
        model: session.drawn_model(),
        needs: session.needs,
        governor_changes: session.governor.changes(),
    }
}

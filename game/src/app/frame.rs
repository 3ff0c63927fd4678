//! The game as the frame driver runs it: one [`Session`] with its [`GameGpu`], drawn by
//! [`FrameDriver`](dermis_engine::render::FrameDriver) into a window surface or an offscreen target,
//! the governor fed what each frame cost. Every shell runs the game through
//! [`GameFrame::run`]: the desktop window, the Android app, `play`, the soak, `bench effects`
//! and the steady-state test.
//!
//! One frame, top to bottom: the session updates (input, rules, animation, camera, UI, the
//! governor's tier) → the session's packet (plain data, [`Session::extract`]) → the renderer
//! prepares it ([`GameGpu::last_frame`]) → the renderer encodes the prepared frame → submit.
//! Nothing goes back from the GPU side into the session.

use super::{FrameInfo, GameGpu, Session, Viewport};
use crate::lifecycle::FrameStatus;
use crate::rules::Screen;
use crate::soak::FrameSample;
use dermis_engine::asset::Model;
use dermis_engine::render::{
    FrameDriver, FrameOutput, FrameTimes, FrameWork, Gpu, Output, PassCtx, RenderStats,
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
        }
    }

    /// Runs one frame with `driver` into `output` and feeds the session's governor what it
    /// cost (the larger of its CPU time and the latest GPU time, as the soak measures it),
    /// and the frame-time overlay the wall-clock time between frames, the CPU time and the
    /// GPU time.
    pub fn run(
        &mut self,
        driver: &mut FrameDriver,
        gpu: &Gpu,
        output: Output<'_>,
    ) -> Result<FrameTimes, FrameStatus> {
        let times = driver.frame(gpu, output, self)?;
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

impl FrameWork for GameFrame<'_> {
    fn update(&mut self, dt: f64, width: u32, height: u32) {
        let viewport = Viewport {
            width,
            height,
            scale: self.scale,
            insets: self.insets,
        };
        self.session.gui.offer_head(self.gpu.has_head());
        self.info = self.session.update(dt as f32, self.character, viewport);
    }

    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) {
        self.gpu.renderer.resize(gpu, (width, height));
    }

    /// The session's packet, prepared by the renderer (play: every pipeline ready first).
    fn upload(&mut self, gpu: &Gpu) {
        let settled = self.session.game.screen() == Screen::Play;
        let head = self.gpu.head.clone();
        let packet = self
            .session
            .extract(self.character, head.as_deref(), settled);
        self.gpu.prepare(gpu, &packet);
    }

    fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        output: &FrameOutput<'_>,
    ) -> RenderStats {
        self.stats = self.gpu.encode(&mut PassCtx {
            encoder,
            targets: output.targets,
            output: output.view,
            timer: None,
        });
        if let Some(hook) = &mut self.after_encode {
            hook(encoder, self.session, output);
        }
        self.stats
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

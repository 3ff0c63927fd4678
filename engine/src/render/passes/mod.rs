//! The frame's passes, one module each, in the order a frame records them (the rows of
//! [`passes!`] below). A pass holds its own pipelines and bind groups and reads everything
//! else from the renderer's [`Resources`]; it is built only where the scene can reach what it
//! draws for ([`Pass::build`] returns `None` otherwise: no pipeline, no bind group), decides in
//! [`Pass::prepare`] whether it runs this frame and writes its constants, and records in one
//! place — [`Pass::encode`] for a pass of its own before the scene ([`Stage::Light`]),
//! [`Pass::draw`] into the scene's pass ([`Stage::Scene`]) or the frame's last pass
//! ([`Stage::Last`]), which resolves into the output.
//!
//! A new pass is its module plus its row: the row gives it a field in [`Passes`], a slot in
//! every frame's [`PassFrame`]s and [`RenderStats::passes`], its place in the frame and its
//! name in `bench frame` (`tests/render/adding_a_pass.rs` proves it for every row).

pub mod blobs;
pub mod character;
pub mod penumbra;
pub mod props;
pub mod resolve;
pub mod shadow_map;
pub mod subsurface;
pub mod ui;

use super::layouts::Layouts;
use super::light_maps::LightMaps;
use super::pipelines::{PipelineDevice, PipelineSet};
use super::prepared::{Drawn, PassFrame, PreparedFrame, RenderStats};
use super::resources::Resources;
use crate::scene::FramePacket;

/// Where a pass records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Before the scene, in passes of its own (the light's maps).
    Light,
    /// Inside the scene's pass: into the output, or the subsurface targets.
    Scene,
    /// Inside the frame's last pass, which resolves into the output (in a frame of one pass,
    /// the scene's, after the scene's draws).
    Last,
}

/// What a pass is built from: the device (and the pipeline cache its pipelines pass through),
/// the renderer's layouts and output format, the shading models the scene can reach, and
/// what the scene holds.
pub struct BuildCtx<'a> {
    pub device: &'a wgpu::Device,
    /// The `Gpu`'s pipeline cache, if it keeps one.
    pub cache: Option<&'a wgpu::PipelineCache>,
    pub queue: &'a wgpu::Queue,
    pub layouts: &'a Layouts,
    pub format: wgpu::TextureFormat,
    pub set: &'a PipelineSet,
    /// The shadow map and penumbra grid, once something casts.
    pub light_maps: Option<&'a LightMaps>,
    /// A measurement scene's shadow-only occluder is set.
    pub occluder: bool,
    /// Props are loaded.
    pub props: bool,
    /// Blob shadows are asked for and something casts one.
    pub blobs: bool,
    /// The UI is drawn (the game).
    pub ui: bool,
    /// The standard materials' pipelines the loaded subjects need.
    pub standard: &'a [character::StandardKey],
}

impl<'a> BuildCtx<'a> {
    /// What the pass's pipelines are made with.
    pub fn pipelines(&self) -> PipelineDevice<'a> {
        PipelineDevice {
            device: self.device,
            cache: self.cache,
        }
    }
}

/// One pass of the frame (see the module docs).
pub trait Pass {
    /// The pass for `ctx`, or `None` where the scene needs none.
    fn build(ctx: &BuildCtx) -> Option<Self>
    where
        Self: Sized;

    /// Whether it must be built again for what `ctx` now holds (a resource it binds was
    /// replaced, a pipeline it lacks is now needed).
    fn stale(&self, _ctx: &BuildCtx) -> bool {
        false
    }

    fn stage(&self) -> Stage;

    /// Whether it runs in `frame`, with its constants written; it may complete the frame
    /// (the frame uniform's members it owns; `uploads`).
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame;

    /// Makes what depends on the frame's size (after the renderer resized its targets).
    fn resize(&mut self, _device: &wgpu::Device, _res: &Resources) {}

    /// [`Stage::Light`]: records its own passes.
    fn encode(
        &self,
        _frame: &PreparedFrame,
        _res: &Resources,
        _encoder: &mut wgpu::CommandEncoder,
    ) -> Drawn {
        Drawn::default()
    }

    /// [`Stage::Scene`], [`Stage::Last`]: draws into the open pass (group 0 bound).
    fn draw(
        &self,
        _frame: &PreparedFrame,
        _res: &Resources,
        _pass: &mut wgpu::RenderPass<'_>,
    ) -> Drawn {
        Drawn::default()
    }
}

/// A pass's slot in every frame's [`PassFrame`]s and [`RenderStats::passes`].
pub trait Slot {
    const SLOT: usize;
}

/// Declares the passes in frame order: `name: Type,` with the type in the module `name`.
macro_rules! passes {
    ($( $(#[$doc:meta])* $name:ident: $ty:ident, )+) => {
        /// The passes a renderer has, in frame order; `None`: not built (nothing in the
        /// scene needs it).
        #[derive(Default)]
        pub struct Passes {
            $( $(#[$doc])* pub $name: Option<$name::$ty>, )+
        }

        /// Every pass's name, in frame order.
        pub const NAMES: [&str; PASS_COUNT] = [$(stringify!($name)),+];

        /// The number of passes.
        pub const PASS_COUNT: usize = [$(stringify!($name)),+].len();

        #[allow(non_camel_case_types)]
        enum Slots { $($name),+ }

        $( impl Slot for $name::$ty { const SLOT: usize = Slots::$name as usize; } )+

        impl Passes {
            /// Every pass `ctx` needs.
            pub fn build(ctx: &BuildCtx) -> Self {
                Self { $( $name: <$name::$ty as Pass>::build(ctx), )+ }
            }

            /// Builds the passes `ctx` now needs that are missing, and again those it made
            /// stale.
            pub fn refresh(&mut self, ctx: &BuildCtx) {
                $(
                    if self.$name.as_ref().is_none_or(|p| p.stale(ctx)) {
                        self.$name = <$name::$ty as Pass>::build(ctx);
                    }
                )+
            }

            /// Each built pass in frame order, by slot.
            pub fn each(&self) -> [Option<&dyn Pass>; PASS_COUNT] {
                [$( self.$name.as_ref().map(|p| p as &dyn Pass) ),+]
            }

            /// The same, to prepare and resize.
            pub fn each_mut(&mut self) -> [Option<&mut dyn Pass>; PASS_COUNT] {
                [$( self.$name.as_mut().map(|p| p as &mut dyn Pass) ),+]
            }
        }
    };
}

passes! {
    /// The key light's depth map (`shadow_map.rs`).
    shadow_map: ShadowMapPass,
    /// The distance to the nearest shadow edge (`penumbra.rs`), for models that filter
    /// their shadow with it.
    penumbra: PenumbraPass,
    /// The subject with its shading model (`character.rs`).
    character: CharacterPass,
    /// The props, instanced (`props.rs`).
    props: PropsPass,
    /// Blob shadows on the floor (`blobs.rs`).
    blobs: BlobsPass,
    /// The screen-space subsurface gather (`subsurface.rs`).
    subsurface: SubsurfacePass,
    /// The UI (`ui.rs`).
    ui: UiPass,
}

impl Passes {
    /// Runs `prepare` of every built pass in frame order, recording what each does.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) {
        for (slot, pass) in self.each_mut().into_iter().enumerate() {
            frame.passes[slot] = match pass {
                Some(p) => p.prepare(queue, packet, frame, res),
                None => PassFrame::default(),
            };
        }
    }

    /// Records the [`Stage::Light`] passes that run in `frame`.
    pub fn encode(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        encoder: &mut wgpu::CommandEncoder,
        stats: &mut RenderStats,
    ) {
        for (slot, pass) in self.running(frame, Stage::Light) {
            stats.add(slot, pass.encode(frame, res, encoder));
        }
    }

    /// Draws the passes of `stage` that run in `frame` into the open pass.
    pub fn draw(
        &self,
        stage: Stage,
        frame: &PreparedFrame,
        res: &Resources,
        pass: &mut wgpu::RenderPass<'_>,
        stats: &mut RenderStats,
    ) {
        for (slot, p) in self.running(frame, stage) {
            stats.add(slot, p.draw(frame, res, pass));
        }
    }

    /// The built passes of `stage` that run in `frame`, with their slots.
    fn running<'s>(
        &'s self,
        frame: &PreparedFrame,
        stage: Stage,
    ) -> impl Iterator<Item = (usize, &'s dyn Pass)> {
        let runs = frame.passes.map(|p| p.runs);
        self.each()
            .into_iter()
            .enumerate()
            .filter_map(move |(slot, p)| Some((slot, p?)))
            .filter(move |(slot, p)| runs[*slot] && p.stage() == stage)
    }
}

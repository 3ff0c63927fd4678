//! The frame's passes, one module each, and their table (the rows of [`passes!`] below: the
//! only place that lists them). A pass holds its own pipelines and bind groups and reads
//! everything else from the renderer's [`Resources`]; it declares the targets it creates,
//! reads and writes ([`Declared::ACCESS`]), from which the frame graph (`graph.rs`) derives
//! where it records ([`Stage`]), the frame's order ([`frame_order`]) and the transient
//! targets made for the frame's size. It is built only where the scene can reach what it
//! draws for ([`Pass::build`] returns `None` otherwise: no pipeline, no bind group), decides
//! in [`Pass::prepare`] whether it runs this frame and writes its constants, and records in
//! one place — [`Pass::encode`] for a pass of its own before the scene ([`Stage::Light`]),
//! [`Pass::draw`] into the scene's pass ([`Stage::Scene`]) or the frame's last pass
//! ([`Stage::Last`]), which resolves into the output.
//!
//! A new pass is its module plus its row: the row gives it a field in [`Passes`], a slot in
//! every frame's [`PassFrame`]s and [`RenderStats::passes`], its name in `bench frame`, and
//! its declaration its place in the frame (`tests/render/adding_a_pass.rs` proves it for
//! every row). An optional pass (one a renderer draws only when asked: the blob shadows, the
//! UI) is asked for by its row's name ([`PassId`]: `Renderer::enable(gpu, PassId::blobs)`),
//! which its `build` reads ([`BuildCtx::wanted`]).

pub mod blobs;
pub mod character;
pub mod penumbra;
pub mod props;
pub mod resolve;
pub mod shadow_map;
pub mod subsurface;
pub mod ui;

use std::sync::OnceLock;

use super::graph;
use super::layouts::Layouts;
use super::light_maps::LightMaps;
use super::material_gpu::StandardKey;
use super::pipelines::{PipelineDevice, PipelineSet};
use super::prepared::{Drawn, PassFrame, PreparedFrame, RenderStats};
use super::resources::Resources;
use crate::scene::{FramePacket, PropKind};

pub use super::graph::{Access, Stage, Target};

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
    /// A character is loaded.
    pub character: bool,
    /// Which prop kinds are loaded ([`PropKind::ALL`] order).
    pub props: [bool; PropKind::ALL.len()],
    /// The optional passes asked for (table order).
    pub wanted: [bool; PASS_COUNT],
    /// The standard materials' pipelines the loaded subjects need.
    pub standard: &'a [StandardKey],
}

impl<'a> BuildCtx<'a> {
    /// Whether the optional pass `P` was asked for.
    pub fn wanted<P: Slot>(&self) -> bool {
        self.wanted[P::SLOT]
    }

    /// Whether a pass drawing into the scene needs its split variant (the scene can reach a
    /// pass that reads [`Target::Split`]).
    pub fn split(&self) -> bool {
        self.set.needs_subsurface_pass()
    }

    /// The prop kinds loaded.
    pub fn prop_kinds(&self) -> impl Iterator<Item = PropKind> + '_ {
        PropKind::ALL
            .iter()
            .zip(self.props)
            .filter(|(_, loaded)| *loaded)
            .map(|(k, _)| *k)
    }

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

/// What a pass does with the frame's targets (see the module docs).
pub trait Declared {
    const ACCESS: Access;
}

/// Declares the passes: `name: Type,` with the type in the module `name` (the frame's order
/// comes from their declarations).
macro_rules! passes {
    ($( $(#[$doc:meta])* $name:ident: $ty:ident, )+) => {
        /// The passes a renderer has; `None`: not built (nothing in the scene needs it).
        #[derive(Default)]
        pub struct Passes {
            $( $(#[$doc])* pub $name: Option<$name::$ty>, )+
        }

        /// Every pass's name, in table order.
        pub const NAMES: [&str; PASS_COUNT] = [$(stringify!($name)),+];

        /// Every pass's declaration, in table order.
        pub const ACCESS: [Access; PASS_COUNT] = [$(<$name::$ty as Declared>::ACCESS),+];

        /// The number of passes.
        pub const PASS_COUNT: usize = [$(stringify!($name)),+].len();

        #[allow(non_camel_case_types)]
        enum Slots { $($name),+ }

        $( impl Slot for $name::$ty { const SLOT: usize = Slots::$name as usize; } )+

        /// A pass named by its row, for what asks for, switches or counts one
        /// (`Renderer::enable`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct PassId(pub usize);

        #[allow(non_upper_case_globals)]
        impl PassId {
            $( pub const $name: PassId = PassId(Slots::$name as usize); )+
        }

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

            /// Each built pass in table order, by slot.
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

/// The order the frame records the passes in (slots), derived once from their declarations
/// ([`graph::order`]; `tests/render/adding_a_pass.rs` checks it is valid).
pub fn frame_order() -> &'static [usize; PASS_COUNT] {
    static ORDER: OnceLock<[usize; PASS_COUNT]> = OnceLock::new();
    ORDER.get_or_init(|| {
        graph::order(&ACCESS).unwrap_or_else(|| {
            log::error!("the passes' declarations contradict each other: table order");
            std::array::from_fn(|i| i)
        })
    })
}

/// Where pass `slot` records.
pub fn stage(slot: usize) -> Stage {
    ACCESS[slot].stage()
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
        let mut each = self.each_mut();
        for &slot in frame_order() {
            frame.passes[slot] = match each[slot].as_mut() {
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

    /// The built passes of `stage` that run in `frame`, in frame order, with their slots.
    fn running<'s>(
        &'s self,
        frame: &PreparedFrame,
        stage: Stage,
    ) -> impl Iterator<Item = (usize, &'s dyn Pass)> {
        let runs = frame.passes.map(|p| p.runs);
        let each = self.each();
        frame_order()
            .iter()
            .filter(move |&&slot| runs[slot] && self::stage(slot) == stage)
            .filter_map(move |&slot| Some((slot, each[slot]?)))
    }

    /// Whether a built pass creates the transient target `t` (made for the frame's size).
    pub fn creates(&self, t: Target) -> bool {
        graph::transient(&ACCESS, self.each().map(|p| p.is_some())).any(|x| x == t)
    }
}

//! The wgpu renderer: a resource owner and its passes (`passes/`, one module each: shadow map,
//! penumbra, character, props, blobs, subsurface, UI, and the resolve into the output). A
//! frame is prepared from a plain packet ([`crate::scene::FramePacket`]) into a
//! [`PreparedFrame`] and encoded from that value alone: the light's maps in passes of their
//! own, then one MSAA 4× pass resolved at its end with depth never stored (the tile-friendly
//! default on phones) — tone mapping at the end of every fragment shader — except in frames
//! whose subject uses a screen-space subsurface model, whose scene pass renders into two
//! linear targets and which end with the subsurface pass. A renderer whose scene cannot
//! reach a pass's effect has no such pass, pipeline or target.

mod build;
mod counters;
mod driver;
mod frame_uniform;
mod gpu;
pub mod graph;
mod layouts;
mod light_maps;
mod material_gpu;
mod mesh;
mod model_gpu;
mod offscreen;
pub mod passes;
pub mod pfm;
pub mod pipeline_cache;
mod pipelines;
mod prepared;
mod prop_gpu;
mod readback;
mod renderer;
mod resources;
mod shadow_view;
mod skinned;
mod surface;
mod targets;
mod texture;
mod timer;

pub use counters::LiveObjects;
pub use driver::{Allocs, Clock, Frame, FrameDriver, FrameOutput, FrameTimes, Output};
pub use frame_uniform::{FrameUniform, OutputMode};
pub use gpu::{Gpu, GpuError};
pub use layouts::shadow_map_entries;
pub use light_maps::{comparison_sampler, SHADOW_MAP_SIZE};
pub use light_maps::{grid_texture as penumbra_grid_texture, placeholder as no_shadow_map};
pub use material_gpu::standard_keys;
pub use model_gpu::PipelineKey;
pub use offscreen::{f16_to_f32, Offscreen, RgbaImage, OFFSCREEN_FORMAT};
pub use passes::penumbra::{jump_steps, BLOCK as PENUMBRA_BLOCK};
pub use passes::shadow_map::caster_shader_source;
pub use passes::ui::{ui_shader_source, ui_vertex_layout};
pub use pipelines::{build_shader_source, shader_source, CharacterPipelines, PipelineSet};
pub use prepared::{
    Drawn, PassCtx, PassFrame, PreparedFrame, RenderStats, SubjectDraw, FRAMES_PREPARED,
};
pub use readback::{read_buffer, read_mapped};
pub use renderer::Renderer;
pub use shadow_view::{ShadowView, SHADOW_RAMP_TEXELS};
pub use skinned::SkinnedGpu;
pub use surface::{choose_format, FrameStatus, SurfaceOptions, SurfaceTarget};
pub use targets::{Targets, DEPTH_FORMAT, MSAA_SAMPLES, SPLIT_FORMAT};
pub use texture::{f32_to_f16, upload as upload_texture, upload_bytes, uploaded_bytes};
pub use timer::{PassTimer, TimerRing};

//! The wgpu renderer: GPU context, resources created once at load, and one render pass per
//! frame (MSAA 4× resolved at the end of the pass, depth never stored — the tile-friendly
//! default on phones). Tone mapping happens at the end of every fragment shader, so no
//! second pass is needed — except in frames whose character uses a screen-space subsurface
//! model, which end with the subsurface pass (`sss_pass.rs`); a renderer whose scene cannot
//! reach such a model has no such pass, pipeline or target.

mod character;
mod counters;
mod driver;
mod frame;
mod gpu;
mod layouts;
mod mesh;
mod model_gpu;
mod offscreen;
mod penumbra;
pub mod pipeline_cache;
mod pipelines;
mod props;
mod readback;
mod renderer;
pub mod rig;
mod shadow;
mod shadow_map;
mod sss_pass;
mod surface;
mod targets;
mod texture;
mod timer;
pub mod ui;

pub use character::CharacterGpu;
pub use counters::LiveObjects;
pub use driver::{Allocs, Clock, FrameDriver, FrameOutput, FrameTimes, FrameWork, Output};
pub use frame::{FrameUniform, Light};
pub use gpu::{Gpu, GpuError};
pub use layouts::shadow_map_entries;
pub use offscreen::{f16_to_f32, Offscreen, RgbaImage, OFFSCREEN_FORMAT};
pub use penumbra::{grid_texture as penumbra_grid_texture, jump_steps, BLOCK as PENUMBRA_BLOCK};
pub use pipelines::{build_shader_source, shader_source, CharacterPipelines, PipelineSet};
pub use props::{PropInstance, PropKind};
pub use readback::{read_buffer, read_mapped};
pub use renderer::{DrawSet, FrameView, RenderStats, Renderer};
pub use rig::{key_light, CharacterBound, CHARACTER, EXPOSURE, KEY_LIGHT_OFFSET};
pub use shadow_map::{
    caster_shader_source, comparison_sampler, placeholder as no_shadow_map, ShadowView,
    SHADOW_MAP_SIZE,
};
pub use sss_pass::SPLIT_FORMAT;
pub use surface::{choose_format, FrameStatus, SurfaceOptions, SurfaceTarget};
pub use targets::{Targets, DEPTH_FORMAT, MSAA_SAMPLES};
pub use texture::{f32_to_f16, upload as upload_texture, upload_bytes, uploaded_bytes};
pub use timer::{PassTimer, TimerRing};
pub use ui::{ui_shader_source, ui_vertex_layout, UiRenderer};

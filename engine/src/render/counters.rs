//! Live GPU-object counts from wgpu's internal counters (its `counters` feature): the proof
//! that nothing is created during play.

/// Live objects of the kinds the game must create only at load.
///
/// Textures are tracked through their views: wgpu 30's hal `textures` counter is decremented
/// on paths it never incremented (measured here: −2 per presented surface frame, about −2
/// per recreated offscreen target), so it drifts without any leak. Every texture dermis
/// creates has a view, and `texture_views` balances exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct LiveObjects {
    pub buffers: isize,
    pub texture_views: isize,
    pub bind_groups: isize,
    pub render_pipelines: isize,
    pub compute_pipelines: isize,
    pub shader_modules: isize,
    pub samplers: isize,
}

impl LiveObjects {
    pub fn read(device: &wgpu::Device) -> Self {
        let c = device.get_internal_counters();
        let h = &c.hal;
        Self {
            buffers: h.buffers.read(),
            texture_views: h.texture_views.read(),
            bind_groups: h.bind_groups.read(),
            render_pipelines: h.render_pipelines.read(),
            compute_pipelines: h.compute_pipelines.read(),
            shader_modules: h.shader_modules.read(),
            samplers: h.samplers.read(),
        }
    }
}

//! The penumbra map: the distance from every point of the key light's shadow map to the
//! nearest caster edge, by jump flooding over a grid a quarter of the map's resolution
//! (`shaders/penumbra.wgsl`). Models that declare the `penumbra` effect (`preintegrated`) read
//! it to filter their shadow by the material's profile: a receiver at signed distance d from a
//! straight shadow edge receives the fraction ESF(d) of the light, the edge-spread function of
//! its diffusion kernel (a table in its LUT), so light bleeds into the shadow as far as the
//! material carries it — also far beyond what a few filter taps reach.
//!
//! Built only when the renderer's pipelines reach such a model; run only in frames that draw
//! one with a shadow map. Cost: one seed pass (25 gathers per grid texel) and as many jump
//! passes (nine loads each) as the material's reach needs — distances beyond
//! [`REACH_MM`] are never read — over the grid: 128² for the game's 1024² map (4 jump
//! passes), independent of the screen's size.

use super::shadow_map::ShadowMap;

/// Shadow-map texels per grid texel (per side).
pub const BLOCK: u32 = 8;
/// How far from an edge a distance is needed (mm): the edge-spread table's span.
pub const REACH_MM: f32 = crate::shading::edge_spread::SPAN_MM as f32;
/// The grid's texture format: seed uv, depth, valid.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The depth step that makes an edge, in metres along the light.
pub const EDGE_GAP_M: f32 = 0.01;
/// Uniform slot stride (the minimum uniform offset alignment).
const SLOT: u64 = 256;

/// A pass's bind groups: reading target 0, reading target 1.
struct Pass {
    groups: [wgpu::BindGroup; 2],
}

pub struct Penumbra {
    /// Grid texels per side.
    pub size: u32,
    targets: [wgpu::TextureView; 2],
    /// The view holding the finished map (what receivers bind).
    pub result: wgpu::TextureView,
    seed: wgpu::RenderPipeline,
    jump: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    /// The seed pass, then one per possible jump.
    passes: Vec<Pass>,
    /// Jump passes this frame (set by `prepare`).
    jumps: std::cell::Cell<usize>,
}

/// The bind group layout of both passes.
fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("penumbra"),
        entries: &[
            super::layouts::uniform(0, fragment),
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: fragment,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: fragment,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: fragment,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
        ],
    })
}

/// The composed pass shader.
pub fn shader_source() -> String {
    crate::shader::compose("penumbra", &crate::shader::ShaderDefs::new())
        .expect("built-in shaders compose")
}

/// Steps of the jump passes for a grid of `size` texels: size/2, size/4, …, 1.
pub fn steps(size: u32) -> Vec<u32> {
    let mut out = Vec::new();
    let mut s = size.next_power_of_two() / 2;
    while s >= 1 {
        out.push(s);
        s /= 2;
    }
    out
}

/// The jump steps for a grid of `size` texels over a map `map_width_m` wide: the halvings
/// from the first power of two that reaches [`REACH_MM`] down to 1.
pub fn jump_steps(size: u32, map_width_m: f32) -> Vec<u32> {
    let texel_mm = map_width_m * 1000.0 / size.max(1) as f32;
    let reach = (REACH_MM / texel_mm.max(1e-6)).ceil().clamp(1.0, 1e6) as u32;
    steps(size)
        .into_iter()
        .filter(|&s| s <= reach.next_power_of_two())
        .collect()
}

/// A grid texture (render target and bound for loads).
pub fn grid_texture(device: &wgpu::Device, size: u32, label: &str) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

impl Penumbra {
    /// The map for `shadow` (its grid: a quarter of the shadow map's resolution).
    pub fn new(device: &wgpu::Device, shadow: &ShadowMap) -> Self {
        let size = (shadow.size / BLOCK).max(1);
        let targets = [
            grid_texture(device, size, "penumbra A"),
            grid_texture(device, size, "penumbra B"),
        ];
        let bind_layout = layout(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("penumbra"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("penumbra"),
            source: wgpu::ShaderSource::Wgsl(shader_source().into()),
        });
        let pipeline = |entry: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: super::pipeline_cache::for_device(device).as_ref(),
            })
        };
        let steps = steps(size);
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("penumbra passes"),
            size: SLOT * (steps.len() as u64 + 1),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("penumbra depth"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let group = |slot: u64, previous: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("penumbra pass"),
                layout: &bind_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &uniforms,
                            offset: slot * SLOT,
                            size: wgpu::BufferSize::new(16),
                        }),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&shadow.view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(previous),
                    },
                ],
            })
        };
        let passes = (0..=steps.len())
            .map(|k| Pass {
                groups: [group(k as u64, &targets[0]), group(k as u64, &targets[1])],
            })
            .collect();
        Self {
            size,
            result: targets[0].clone(),
            targets,
            seed: pipeline("fs_seed"),
            jump: pipeline("fs_jump"),
            uniforms,
            passes,
            jumps: std::cell::Cell::new(steps.len()),
        }
    }

    /// Writes the passes' constants for this frame: `gap` is [`EDGE_GAP_M`] in the map's
    /// depth units, `map_width_m` the shadow map's width at the casters. The jumps start at
    /// the step that reaches [`REACH_MM`].
    pub fn prepare(&self, queue: &wgpu::Queue, gap: f32, map_width_m: f32) {
        let size = self.size as f32;
        let steps = jump_steps(self.size, map_width_m);
        self.jumps.set(steps.len());
        let mut data = vec![0u8; self.passes.len() * SLOT as usize];
        for (k, chunk) in data
            .chunks_mut(SLOT as usize)
            .enumerate()
            .take(steps.len() + 1)
        {
            let step = if k == 0 { 0.0 } else { steps[k - 1] as f32 };
            let v = [step, size, BLOCK as f32, gap];
            chunk[..16].copy_from_slice(bytemuck::cast_slice(&v));
        }
        queue.write_buffer(&self.uniforms, 0, &data);
    }

    /// Records the seed pass and this frame's jump passes (one full-screen draw each; returns
    /// their number); the last writes target 0 (the one receivers bind), so the seed goes
    /// where the parity puts it.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) -> u32 {
        let jumps = self.jumps.get();
        let mut target = jumps % 2;
        for (k, p) in self.passes.iter().take(jumps + 1).enumerate() {
            let seed = k == 0;
            if !seed {
                target = 1 - target;
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(if seed {
                    "penumbra seed"
                } else {
                    "penumbra jump"
                }),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.targets[target],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(if seed { &self.seed } else { &self.jump });
            // Jumps read the other target; the seed reads none (bound: the other one).
            pass.set_bind_group(0, &p.groups[1 - target], &[]);
            pass.draw(0..3, 0..1);
        }
        jumps as u32 + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jump_steps_halve_down_to_one() {
        assert_eq!(steps(256), vec![128, 64, 32, 16, 8, 4, 2, 1]);
        assert_eq!(steps(1), Vec::<u32>::new());
        assert_eq!(steps(5), vec![4, 2, 1]);
        // The game's grid: 128 texels over ~2.1 m (16.4 mm each) need 8 texels of reach.
        assert_eq!(jump_steps(128, 2.1), vec![8, 4, 2, 1]);
        assert_eq!(jump_steps(128, 1.9), vec![16, 8, 4, 2, 1]);
        // A fine map reaches as far as its grid allows.
        assert_eq!(jump_steps(16, 0.01), steps(16));
    }
}

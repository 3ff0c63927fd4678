//! The key light's maps, shared between passes: the shadow map (drawn by the shadow-map pass,
//! read by every receiver through group 0 and by the penumbra pass) and the penumbra map's
//! grid (drawn by the penumbra pass, read by the models that filter their shadow with it);
//! the frame's bind group 0 that binds them, with 1×1 stand-ins where there are none; and a
//! measurement scene's shadow-only occluder.
//!
//! Sized for a phone: a 1024² Depth32Float shadow map (4 MiB) and a 128² grid.

use wgpu::util::DeviceExt;

use super::layouts::Layouts;
use crate::shader::uniforms::PENUMBRA_BLOCK;

/// Texels per side of the game's shadow map.
pub const SHADOW_MAP_SIZE: u32 = 1024;
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The penumbra grid's texture format: seed uv, depth, valid.
pub const PENUMBRA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The penumbra map's ping-pong grid (a texel per [`PENUMBRA_BLOCK`]² map texels); the
/// finished map is always in `targets[0]`.
pub struct PenumbraGrid {
    pub size: u32,
    pub targets: [wgpu::TextureView; 2],
}

/// The shadow map and, where a model reads it, the penumbra grid.
pub struct LightMaps {
    /// Texels per side.
    pub size: u32,
    /// Sampled by receivers and the penumbra pass.
    pub shadow: wgpu::TextureView,
    /// Rendered by the shadow-map pass.
    pub shadow_target: wgpu::TextureView,
    pub penumbra: Option<PenumbraGrid>,
}

impl LightMaps {
    /// A `size`² shadow map and, with `penumbra`, its grid.
    pub fn new(device: &wgpu::Device, size: u32, penumbra: bool) -> Self {
        let size = size.max(1);
        let texture = depth_texture(device, size, "shadow map");
        let grid = (size / PENUMBRA_BLOCK).max(1);
        Self {
            size,
            shadow: texture.create_view(&Default::default()),
            shadow_target: texture.create_view(&Default::default()),
            penumbra: penumbra.then(|| PenumbraGrid {
                size: grid,
                targets: [
                    grid_texture(device, grid, "penumbra A"),
                    grid_texture(device, grid, "penumbra B"),
                ],
            }),
        }
    }
}

/// Triangles that cast a shadow but are not drawn in the scene (a measurement scene's
/// occluder), in world space.
pub struct Occluder {
    pub vertices: wgpu::Buffer,
    pub count: u32,
}

impl Occluder {
    /// `None` for no triangles.
    pub fn new(device: &wgpu::Device, triangles: &[[f32; 3]]) -> Option<Self> {
        (!triangles.is_empty()).then(|| Self {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("shadow occluder"),
                contents: bytemuck::cast_slice(triangles),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            count: triangles.len() as u32,
        })
    }
}

/// What group 0 binds where a frame has no light maps: a 1×1 shadow map cleared to the far
/// plane (every point lit) and an empty penumbra grid; and the comparison sampler.
pub struct Defaults {
    pub no_shadow: wgpu::TextureView,
    pub no_penumbra: wgpu::TextureView,
    /// Lit where the reference depth is at most the stored one.
    pub comparison: wgpu::Sampler,
}

impl Defaults {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self {
            no_shadow: placeholder(device, queue),
            no_penumbra: grid_texture(device, 1, "no penumbra map"),
            comparison: comparison_sampler(device),
        }
    }
}

/// Group 0: the frame uniform, the shadow map with its comparison sampler, the penumbra map
/// (stand-ins from `none` where `maps` has none).
pub fn frame_group(
    device: &wgpu::Device,
    layouts: &Layouts,
    buffer: &wgpu::Buffer,
    maps: Option<&LightMaps>,
    none: &Defaults,
) -> wgpu::BindGroup {
    let shadow = maps.map_or(&none.no_shadow, |m| &m.shadow);
    let penumbra = maps
        .and_then(|m| m.penumbra.as_ref())
        .map_or(&none.no_penumbra, |g| &g.targets[0]);
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout: &layouts.frame,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(shadow),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&none.comparison),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(penumbra),
            },
        ],
    })
}

/// The comparison sampler receivers read the map with (lit where the reference depth is at
/// most the stored one).
pub fn comparison_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("shadow comparison"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    })
}

/// A 1×1 map cleared to the far plane, bound where no shadow map exists (nothing casts).
pub fn placeholder(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let view = depth_texture(device, 1, "no shadow map").create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    drop(depth_pass(&mut encoder, &view, "no shadow map"));
    queue.submit([encoder.finish()]);
    view
}

/// A `size`² depth texture the shadow pass renders and receivers sample.
fn depth_texture(device: &wgpu::Device, size: u32, label: &str) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// A penumbra grid texture (render target and bound for loads).
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
            format: PENUMBRA_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

/// A depth-only pass into `view`, cleared to the far plane and stored.
pub fn depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    label: &str,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

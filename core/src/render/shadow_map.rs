//! The key light's shadow map: the character (and a measurement scene's occluder) drawn
//! depth-only from the light once per frame, before the scene pass; every shading model reads
//! it through `light_visible` in `shaders/common.wgsl` (four bilinear depth comparisons).
//!
//! The light's frustum is fitted each frame to the casters' bounding sphere, so the map's
//! texels land where shadows can fall: a shadow of something inside the sphere lies inside
//! the cone of rays through it, whatever receives it (the character itself, the floor). A
//! light far away compared with the sphere (a measurement scene's directional light) gets an
//! orthographic frustum. Receivers beyond the far plane are compared at it; outside the map
//! nothing casts. A renderer whose scene has nothing that casts draws no such pass
//! ([`ShadowView::drawn`] false, every point lit).
//!
//! Sized for a phone: 1024² Depth32Float (4 MiB), one depth-only draw of the skinned mesh.

use glam::{Mat4, Vec3};

use super::character::CharacterGpu;
use super::layouts::{self, Layouts};
use super::mesh::vertex_layout;
use crate::shader::{compose, ShaderDefs};
use wgpu::util::DeviceExt;

/// Texels per side of the game's shadow map.
pub const SHADOW_MAP_SIZE: u32 = 1024;
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// A light farther than this many sphere radii gets an orthographic frustum.
const ORTHOGRAPHIC_BEYOND: f32 = 20.0;
/// Normal offset and depth bias, in texels of the map at the casters.
const NORMAL_OFFSET_TEXELS: f32 = 0.5;
const DEPTH_BIAS_TEXELS: f32 = 1.0;

/// What receivers need of this frame's shadow map (the `shadow*` members of the frame uniform).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowView {
    /// World → the map's clip space (depth 0..1).
    pub view_proj: Mat4,
    /// Whether a map was drawn this frame (something casts).
    pub drawn: bool,
    /// One texel's world size at the casters' centre (m).
    pub texel_m: f32,
    /// The depth bias in the map's depth units.
    pub bias: f32,
    /// Depth units per metre along the light, at the casters' centre.
    pub depth_per_m: f32,
    /// Texels per side.
    pub size: u32,
}

impl ShadowView {
    /// No map: every point is lit.
    pub const NONE: Self = Self {
        view_proj: Mat4::IDENTITY,
        drawn: false,
        texel_m: 0.0,
        bias: 0.0,
        depth_per_m: 0.0,
        size: 1,
    };

    /// The frustum of a light at `light` around the sphere (`centre`, `radius`), for a map of
    /// `size`² texels. A light inside (or on) the sphere casts no shadow map: [`Self::NONE`].
    pub fn fit(light: Vec3, centre: Vec3, radius: f32, size: u32) -> Self {
        let to_light = light - centre;
        let d = to_light.length();
        if !(d.is_finite() && radius.is_finite() && radius > 0.0) || d <= radius * 1.05 {
            return Self::NONE;
        }
        let dir = to_light / d;
        let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let size = size.max(1);
        if d > ORTHOGRAPHIC_BEYOND * radius {
            // Parallel rays: look from 2r away, depth over the sphere's 2r (linear).
            let eye = centre + dir * (2.0 * radius);
            let view = glam::camera::rh::view::look_at_mat4(eye, centre, up);
            let proj = glam::camera::rh::proj::directx::orthographic(
                -radius,
                radius,
                -radius,
                radius,
                radius,
                3.0 * radius,
            );
            let texel_m = 2.0 * radius / size as f32;
            return Self {
                view_proj: proj * view,
                drawn: true,
                texel_m,
                bias: DEPTH_BIAS_TEXELS * texel_m / (2.0 * radius),
                depth_per_m: 1.0 / (2.0 * radius),
                size,
            };
        }
        let half_angle = (radius / d).asin();
        let (near, far) = (d - radius, d + radius);
        let view = glam::camera::rh::view::look_at_mat4(light, centre, up);
        let proj = glam::camera::rh::proj::directx::perspective(2.0 * half_angle, 1.0, near, far);
        let texel_m = 2.0 * d * half_angle.tan() / size as f32;
        // Depth z = far (1 − near/d')/(far − near): dz/dd' = far·near/((far − near) d'²).
        let dz_dd = far * near / ((far - near) * d * d);
        Self {
            view_proj: proj * view,
            drawn: true,
            texel_m,
            bias: DEPTH_BIAS_TEXELS * texel_m * dz_dd,
            depth_per_m: dz_dd,
            size,
        }
    }

    /// The frame uniform's `shadow` member.
    pub fn params(&self) -> [f32; 4] {
        [
            f32::from(u8::from(self.drawn)),
            NORMAL_OFFSET_TEXELS * self.texel_m,
            self.bias,
            1.0 / self.size as f32,
        ]
    }

    /// The frame uniform's `penumbra` member for a map with a penumbra grid of `grid`
    /// texels (0: none): on, grid size, the map's width (m), the edge gap (depth units).
    pub fn penumbra_params(&self, grid: u32) -> [f32; 4] {
        let on = self.drawn && grid > 0;
        [
            f32::from(u8::from(on)),
            grid as f32,
            self.texel_m * self.size as f32,
            super::penumbra::EDGE_GAP_M * self.depth_per_m,
        ]
    }
}

/// Triangles that cast a shadow but are not drawn in the scene (a measurement scene's
/// occluder), in world space.
pub struct Occluder {
    vertices: wgpu::Buffer,
    count: u32,
}

/// The map, its depth-only pipelines and the casters' uniform.
pub struct ShadowMap {
    pub size: u32,
    /// Sampled by the scene pass (group 0, binding 1).
    pub view: wgpu::TextureView,
    /// Rendered by the shadow pass.
    target: wgpu::TextureView,
    skinned: wgpu::RenderPipeline,
    /// Built with the first occluder (measurement scenes only; the game has none).
    occluder_pipeline: Option<wgpu::RenderPipeline>,
    caster_layout: wgpu::BindGroupLayout,
    caster_buffer: wgpu::Buffer,
    caster_group: wgpu::BindGroup,
    occluder: Option<Occluder>,
    /// Whether the character casts (measurement scenes' media do not: only their occluder).
    pub character_casts: bool,
}

/// The composed caster shader (depth only).
pub fn caster_shader_source() -> String {
    compose("shadow_caster", &ShaderDefs::new()).expect("built-in shaders compose")
}

fn depth_only(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow caster"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            buffers,
        },
        // Both faces: thin parts (ears, fingers, the occluder blade) cast from either side.
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            // Slope-scaled: surfaces grazing the light move back by more.
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 1.5,
                clamp: 0.0,
            },
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: super::pipeline_cache::for_device(device).as_ref(),
    })
}

impl ShadowMap {
    pub fn new(device: &wgpu::Device, layouts: &Layouts, size: u32) -> Self {
        let size = size.max(1);
        let texture = depth_texture(device, size, "shadow map");
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let target = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let caster_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow caster"),
            entries: &[layouts::uniform(0, wgpu::ShaderStages::VERTEX)],
        });
        let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("empty"),
            entries: &[],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow caster"),
            bind_group_layouts: &[Some(&caster_layout), Some(&empty), Some(&layouts.skinned)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow caster"),
            source: wgpu::ShaderSource::Wgsl(caster_shader_source().into()),
        });
        let skinned = depth_only(
            device,
            &layout,
            &module,
            "vs_skinned",
            &[Some(vertex_layout())],
        );
        let caster_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadow caster"),
            size: 64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let caster_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow caster"),
            layout: &caster_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: caster_buffer.as_entire_binding(),
            }],
        });
        Self {
            size,
            view,
            target,
            skinned,
            occluder_pipeline: None,
            caster_layout,
            caster_buffer,
            caster_group,
            occluder: None,
            character_casts: true,
        }
    }

    /// Sets (or with an empty list removes) the shadow-only occluder: world-space triangles.
    pub fn set_occluder(&mut self, device: &wgpu::Device, triangles: &[[f32; 3]]) {
        if !triangles.is_empty() && self.occluder_pipeline.is_none() {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("shadow occluder"),
                bind_group_layouts: &[Some(&self.caster_layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("shadow occluder"),
                source: wgpu::ShaderSource::Wgsl(caster_shader_source().into()),
            });
            self.occluder_pipeline = Some(depth_only(
                device,
                &layout,
                &module,
                "vs_occluder",
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                })],
            ));
        }
        self.occluder = (!triangles.is_empty()).then(|| Occluder {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("shadow occluder"),
                contents: bytemuck::cast_slice(triangles),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            count: triangles.len() as u32,
        });
    }

    /// Whether anything casts this frame.
    pub fn casts(&self, character_drawn: bool) -> bool {
        self.occluder.is_some() || (self.character_casts && character_drawn)
    }

    /// Writes this frame's light matrix (before the frame's encode).
    pub fn prepare(&self, queue: &wgpu::Queue, view: &ShadowView) {
        queue.write_buffer(
            &self.caster_buffer,
            0,
            bytemuck::cast_slice(&view.view_proj.to_cols_array()),
        );
    }

    /// Records the depth-only pass (the skinned `character` if given and casting, the
    /// occluder); returns its draw calls.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        character: Option<&CharacterGpu>,
    ) -> u32 {
        let mut pass = depth_pass(encoder, &self.target, "shadow map");
        pass.set_bind_group(0, &self.caster_group, &[]);
        let mut draws = 0;
        if let (Some(character), true) = (character, self.character_casts) {
            pass.set_pipeline(&self.skinned);
            draws += character.draw(&mut pass);
        }
        if let (Some(o), Some(pipeline)) = (&self.occluder, &self.occluder_pipeline) {
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.draw(0..o.count, 0..1);
            draws += 1;
        }
        draws
    }
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
    let view = depth_texture(device, 1, "no shadow map")
        .create_view(&wgpu::TextureViewDescriptor::default());
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
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

/// A depth-only pass into `view`, cleared to the far plane and stored.
fn depth_pass<'e>(
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

#[cfg(test)]
mod tests {
    use super::*;

    fn project(v: &ShadowView, p: Vec3) -> Vec3 {
        let q = v.view_proj * p.extend(1.0);
        q.truncate() / q.w
    }

    #[test]
    fn the_frustum_holds_the_casters_sphere() {
        for (light, r) in [
            (Vec3::new(1.5, 3.0, 2.5), 1.0),
            (Vec3::new(0.0, 1000.0, 0.0), 0.1),
            (Vec3::new(700.0, 700.0, 0.0), 0.2),
        ] {
            let v = ShadowView::fit(light, Vec3::ZERO, r, 1024);
            assert!(v.drawn);
            let toward = light.normalize();
            let side = toward.any_orthonormal_vector();
            // The sphere's nearest and farthest points and a point on its rim.
            for p in [toward * r, -toward * r, side * r * 0.999] {
                let n = project(&v, p);
                assert!(
                    n.x.abs() <= 1.0 + 1e-4 && n.y.abs() <= 1.0 + 1e-4,
                    "{p} → {n}"
                );
                assert!((-1e-4..=1.0 + 1e-4).contains(&n.z), "{p} → {n}");
            }
            // Nearer the light is smaller depth.
            assert!(project(&v, toward * r * 0.5).z < project(&v, -toward * r * 0.5).z);
            assert!(v.texel_m > 0.0 && v.bias > 0.0 && v.bias < 0.01);
        }
    }

    #[test]
    fn a_light_inside_the_casters_casts_no_map() {
        let v = ShadowView::fit(Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO, 1.0, 1024);
        assert!(!v.drawn);
        assert_eq!(v.params()[0], 0.0);
        assert!(!ShadowView::fit(Vec3::ONE, Vec3::ZERO, f32::NAN, 1024).drawn);
    }
}

//! Static props (floor tiles, walls, furniture, obstacles), drawn instanced with the plain
//! default-lit shader. Node transforms are baked into the vertices at load.

use glam::{Mat3, Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::layouts::Layouts;
use super::mesh::GpuMesh;
use super::texture;
use crate::asset::{Model, Primitive};
use crate::camera::Frustum;

/// The props the game and the demo scene use; each is a file in `assets/props/`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PropKind {
    FloorTile,
    Wall,
    Table,
    Chair,
    Obstacle,
}

impl PropKind {
    pub const ALL: [PropKind; 5] = [
        Self::FloorTile,
        Self::Wall,
        Self::Table,
        Self::Chair,
        Self::Obstacle,
    ];

    /// File name under `assets/props/`.
    pub fn file(self) -> &'static str {
        match self {
            Self::FloorTile => "floor_tile.glb",
            Self::Wall => "wall.glb",
            Self::Table => "table.glb",
            Self::Chair => "chair.glb",
            Self::Obstacle => "obstacle.glb",
        }
    }
}

/// One placed prop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropInstance {
    pub kind: PropKind,
    pub transform: Mat4,
}

struct Part {
    mesh: GpuMesh,
    material: wgpu::BindGroup,
}

pub(super) struct PropGpu {
    pub kind: PropKind,
    parts: Vec<Part>,
    instances: wgpu::Buffer,
    /// What the instance buffer holds now (capacity reserved once): unchanged lists are not
    /// uploaded again.
    uploaded: Vec<[[f32; 4]; 4]>,
    capacity: u32,
    pub count: u32,
    pub triangles: u32,
    /// The model's bounding sphere (centre, radius) in its own space, for culling.
    pub bound: (Vec3, f32),
}

/// Instances of one kind a frame may draw.
pub const MAX_INSTANCES: u32 = 512;

impl PropGpu {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &Layouts,
        sampler: &wgpu::Sampler,
        kind: PropKind,
        model: &Model,
    ) -> Self {
        let white = texture::solid(device, queue, [255, 255, 255, 255], true);
        let textures: Vec<wgpu::TextureView> = model
            .textures
            .iter()
            .map(|t| texture::upload(device, queue, t, kind.file()))
            .collect();
        let mut parts = Vec::new();
        let mut triangles = 0;
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        let worlds = node_worlds(model);
        for (node_index, node) in model.nodes.iter().enumerate() {
            let Some(mesh) = node.mesh else { continue };
            for prim in &model.meshes[mesh].primitives {
                let baked = bake(prim, worlds[node_index]);
                let material = prim.material.map(|m| &model.materials[m]);
                let factor = material.map(|m| m.base_color_factor).unwrap_or([1.0; 4]);
                let view = material
                    .and_then(|m| m.base_color_texture)
                    .and_then(|t| textures.get(t))
                    .unwrap_or(&white);
                let factor_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("prop factor"),
                    contents: bytemuck::cast_slice(&factor),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let material = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("prop material"),
                    layout: &layouts.prop_material,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::Sampler(sampler),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: factor_buffer.as_entire_binding(),
                        },
                    ],
                });
                triangles += baked.indices.len() as u32 / 3;
                for v in &baked.vertices {
                    lo = lo.min(Vec3::from(v.position));
                    hi = hi.max(Vec3::from(v.position));
                }
                parts.push(Part {
                    mesh: GpuMesh::new(device, &baked, kind.file()),
                    material,
                });
            }
        }
        let instances = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("prop instances"),
            size: MAX_INSTANCES as u64 * 64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            kind,
            parts,
            instances,
            uploaded: Vec::with_capacity(MAX_INSTANCES as usize),
            capacity: MAX_INSTANCES,
            count: 0,
            triangles,
            bound: bounding_sphere(lo, hi),
        }
    }

    /// Whether an instance placed at `transform` may show in `frustum`.
    pub fn visible(&self, frustum: &Frustum, transform: &Mat4) -> bool {
        let (centre, radius) = self.bound;
        let scale = transform
            .x_axis
            .truncate()
            .length()
            .max(transform.y_axis.truncate().length())
            .max(transform.z_axis.truncate().length());
        frustum.sphere_visible(transform.transform_point3(centre), radius * scale)
    }

    /// Sets this kind's instance matrices (at most `MAX_INSTANCES`); uploads only when they
    /// changed. Returns whether it uploaded.
    pub fn set_instances(&mut self, queue: &wgpu::Queue, matrices: &[[[f32; 4]; 4]]) -> bool {
        let n = matrices.len().min(self.capacity as usize);
        self.count = n as u32;
        if self.uploaded[..] == matrices[..n] {
            return false;
        }
        self.uploaded.clear();
        self.uploaded.extend_from_slice(&matrices[..n]);
        if n > 0 {
            queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&matrices[..n]));
        }
        true
    }

    pub fn draw<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>) -> u32 {
        if self.count == 0 {
            return 0;
        }
        pass.set_vertex_buffer(1, self.instances.slice(..self.count as u64 * 64));
        for part in &self.parts {
            pass.set_bind_group(1, &part.material, &[]);
            pass.set_vertex_buffer(0, part.mesh.vertices.slice(..));
            pass.set_index_buffer(part.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..part.mesh.index_count, 0, 0..self.count);
        }
        self.parts.len() as u32
    }
}

/// World matrices of the rest pose (parents before children, cycles already rejected).
fn node_worlds(model: &Model) -> Vec<Mat4> {
    let mut worlds = vec![Mat4::IDENTITY; model.nodes.len()];
    let mut stack: Vec<(usize, Mat4)> = model.roots.iter().map(|&r| (r, Mat4::IDENTITY)).collect();
    while let Some((n, parent)) = stack.pop() {
        let w = parent * model.nodes[n].local.matrix();
        worlds[n] = w;
        stack.extend(model.nodes[n].children.iter().map(|&c| (c, w)));
    }
    worlds
}

/// The sphere around the box `lo`..`hi` (a point at the origin for an empty model).
fn bounding_sphere(lo: Vec3, hi: Vec3) -> (Vec3, f32) {
    if lo.cmpgt(hi).any() {
        return (Vec3::ZERO, 0.0);
    }
    ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
}

fn bake(prim: &Primitive, world: Mat4) -> Primitive {
    let normal_m = Mat3::from_mat4(world).inverse().transpose();
    let mut out = prim.clone();
    for v in &mut out.vertices {
        v.position = world.transform_point3(Vec3::from(v.position)).to_array();
        v.normal = (normal_m * Vec3::from(v.normal))
            .normalize_or_zero()
            .to_array();
        let t = Mat3::from_mat4(world) * Vec3::from_slice(&v.tangent[..3]);
        v.tangent = t.normalize_or_zero().extend(v.tangent[3]).to_array();
    }
    out
}

//! A prop kind's GPU side: its meshes with node transforms baked into the vertices at load, a
//! material bind group per part, and the instance buffer of its placements this frame (the
//! props pass draws them instanced with the plain default-lit shader).

use glam::{Mat3, Mat4, Vec3};

use super::layouts::Layouts;
use super::material_gpu::{MaterialGpu, ModelTextures};
use super::mesh::GpuMesh;
use crate::asset::{Model, Primitive};
use crate::camera::Frustum;
use crate::scene::{PropKind, Role};

struct Part {
    mesh: GpuMesh,
    material: wgpu::BindGroup,
}

pub struct PropGpu {
    pub kind: PropKind,
    parts: Vec<Part>,
    /// Triangles of one instance.
    pub triangles: u32,
    /// The model's bounding sphere (centre, radius) in its own space, for culling.
    pub bound: (Vec3, f32),
    /// Its footprint on the ground (`None`: no geometry).
    pub footprint: Option<Footprint>,
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
        let textures = ModelTextures::upload(device, queue, model);
        let mut parts = Vec::new();
        let mut triangles = 0;
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        let worlds = node_worlds(model);
        for (node_index, node) in model.nodes.iter().enumerate() {
            let Some(mesh) = node.mesh else { continue };
            for prim in &model.meshes[mesh].primitives {
                let baked = bake(prim, worlds[node_index]);
                let material = prim.material.and_then(|m| model.materials.get(m));
                let material = MaterialGpu::new(
                    device,
                    (layouts, sampler),
                    &textures,
                    material,
                    Role::Standard,
                )
                .group;
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
        Self {
            kind,
            parts,
            triangles,
            bound: bounding_sphere(lo, hi),
            footprint: Footprint::of(model),
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

    /// Draws `count` instances (instance buffer bound at slot 1); returns the draw calls.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, count: u32) -> u32 {
        for part in &self.parts {
            pass.set_bind_group(1, &part.material, &[]);
            pass.set_vertex_buffer(0, part.mesh.vertices.slice(..));
            pass.set_index_buffer(part.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..part.mesh.index_count, 0, 0..count);
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

/// A prop model's footprint on the ground, in model space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Centre (x, z) and half extents (x, z) of its bounds seen from above (m).
    pub centre: [f32; 2],
    pub half: [f32; 2],
    /// Its lowest point (m).
    pub min_y: f32,
}

impl Footprint {
    /// The bounds of `model`'s meshes in its rest pose, seen from above; `None` without
    /// geometry.
    pub fn of(model: &Model) -> Option<Self> {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        let mut stack: Vec<(usize, Mat4)> =
            model.roots.iter().map(|&r| (r, Mat4::IDENTITY)).collect();
        while let Some((n, parent)) = stack.pop() {
            let node = &model.nodes[n];
            let world = parent * node.local.matrix();
            if let Some(mesh) = node.mesh {
                for prim in &model.meshes[mesh].primitives {
                    let (a, b) = (prim.bounds.min, prim.bounds.max);
                    for i in 0..8 {
                        let corner = Vec3::new(
                            if i & 1 == 0 { a.x } else { b.x },
                            if i & 2 == 0 { a.y } else { b.y },
                            if i & 4 == 0 { a.z } else { b.z },
                        );
                        let p = world.transform_point3(corner);
                        lo = lo.min(p);
                        hi = hi.max(p);
                    }
                }
            }
            stack.extend(node.children.iter().map(|&c| (c, world)));
        }
        (lo.x <= hi.x).then_some(Self {
            centre: [(lo.x + hi.x) * 0.5, (lo.z + hi.z) * 0.5],
            half: [(hi.x - lo.x) * 0.5, (hi.z - lo.z) * 0.5],
            min_y: lo.y,
        })
    }
}

//! GPU resources of a skinned subject (the character, the showroom's head): meshes, one joint
//! palette per skin, base-colour and normal-map bind groups. Created once at load; the
//! shading models' constants are the renderer's ([`super::model_gpu`]), shared by every
//! subject.

use glam::Mat4;

use super::layouts::Layouts;
use super::mesh::GpuMesh;
use super::texture;
use crate::anim::{joint_palette, Pose};
use crate::asset::{Model, MAX_JOINTS};

/// The normal map of a primitive without one: the flat normal, alpha 0 ("no map": the
/// shader keeps the interpolated vertex normal bit for bit).
pub const FLAT_NORMAL: [u8; 4] = [128, 128, 255, 0];

struct Part {
    mesh: GpuMesh,
    /// Palette + base colour of this primitive.
    bind_group: wgpu::BindGroup,
}

struct SkinGpu {
    skin: usize,
    buffer: wgpu::Buffer,
    /// CPU scratch for the palette (reused every frame, no allocation).
    palette: Vec<Mat4>,
}

pub struct SkinnedGpu {
    parts: Vec<Part>,
    skins: Vec<SkinGpu>,
    /// Triangles drawn per frame.
    pub triangles: u32,
    /// Some part has a normal map: drawn with the normal-mapped pipelines.
    pub normal_mapped: bool,
}

impl SkinnedGpu {
    /// Uploads every skinned mesh of `model`. Errors if the glTF has no skinned mesh.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &Layouts,
        sampler: &wgpu::Sampler,
        model: &Model,
    ) -> Result<Self, String> {
        let palette_size = (MAX_JOINTS * 64) as u64;
        let mut skins: Vec<SkinGpu> = Vec::new();
        let mut parts = Vec::new();
        let mut triangles = 0;
        let mut normal_mapped = false;
        let textures: Vec<wgpu::TextureView> = model
            .textures
            .iter()
            .enumerate()
            .map(|(i, t)| {
                texture::upload(device, queue, t, &format!("{} texture {i}", model.source))
            })
            .collect();
        let white = texture::solid(device, queue, [255, 255, 255, 255], true);
        // No normal map: alpha 0 tells the shader to keep the vertex normal exactly.
        let flat = texture::solid(device, queue, FLAT_NORMAL, false);
        for node in &model.nodes {
            let (Some(mesh), Some(skin)) = (node.mesh, node.skin) else {
                continue;
            };
            let slot = match skins.iter().position(|s| s.skin == skin) {
                Some(i) => i,
                None => {
                    skins.push(SkinGpu {
                        skin,
                        buffer: device.create_buffer(&wgpu::BufferDescriptor {
                            label: Some("joint palette"),
                            size: palette_size,
                            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                            mapped_at_creation: false,
                        }),
                        palette: vec![Mat4::IDENTITY; model.skins[skin].joints.len()],
                    });
                    skins.len() - 1
                }
            };
            for prim in &model.meshes[mesh].primitives {
                let material = prim.material.map(|m| &model.materials[m]);
                let view = material
                    .and_then(|m| m.base_color_texture)
                    .and_then(|t| textures.get(t))
                    .unwrap_or(&white);
                let mapped = material
                    .and_then(|m| m.normal_texture)
                    .and_then(|t| textures.get(t));
                normal_mapped |= mapped.is_some();
                let normal_map = mapped.unwrap_or(&flat);
                let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("character part"),
                    layout: &layouts.skinned,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: skins[slot].buffer.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Sampler(sampler),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::TextureView(normal_map),
                        },
                    ],
                });
                triangles += prim.indices.len() as u32 / 3;
                parts.push(Part {
                    mesh: GpuMesh::new(device, prim, "character"),
                    bind_group,
                });
            }
        }
        if parts.is_empty() {
            return Err(format!(
                "{}: no skinned mesh to render as the character",
                model.source
            ));
        }
        Ok(Self {
            parts,
            skins,
            triangles,
            normal_mapped,
        })
    }

    /// Computes the joint palettes for `pose` placed at `world` and uploads them; returns
    /// the uploads (one per skin).
    pub fn update_pose(
        &mut self,
        queue: &wgpu::Queue,
        model: &Model,
        pose: &Pose,
        world: Mat4,
    ) -> u32 {
        for skin in &mut self.skins {
            joint_palette(model, skin.skin, pose, &mut skin.palette);
            for m in &mut skin.palette {
                *m = world * *m;
            }
            queue.write_buffer(&skin.buffer, 0, bytemuck::cast_slice(&skin.palette));
        }
        self.skins.len() as u32
    }

    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) -> u32 {
        for part in &self.parts {
            pass.set_bind_group(2, &part.bind_group, &[]);
            pass.set_vertex_buffer(0, part.mesh.vertices.slice(..));
            pass.set_index_buffer(part.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..part.mesh.index_count, 0, 0..1);
        }
        self.parts.len() as u32
    }
}

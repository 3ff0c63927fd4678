//! GPU resources of the skinned character: meshes, one joint palette per skin, base-colour
//! bind groups and one parameter buffer per shading model. Created once at load.

use glam::Mat4;

use super::layouts::Layouts;
use super::mesh::GpuMesh;
use super::texture;
use crate::anim::{joint_palette, Pose};
use crate::asset::{Model, MAX_JOINTS};
use crate::shading::{Material, ModelParams, ShadingModel};

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

pub struct CharacterGpu {
    parts: Vec<Part>,
    skins: Vec<SkinGpu>,
    params: Vec<(ShadingModel, wgpu::Buffer, wgpu::BindGroup)>,
    unlit_params: wgpu::BindGroup,
    /// Triangles drawn per frame.
    pub triangles: u32,
}

impl CharacterGpu {
    /// Uploads every skinned mesh of `model`. Errors if it has none.
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
        let textures: Vec<wgpu::TextureView> = model
            .textures
            .iter()
            .enumerate()
            .map(|(i, t)| {
                texture::upload(device, queue, t, &format!("{} texture {i}", model.source))
            })
            .collect();
        let white = texture::solid(device, queue, [255, 255, 255, 255], true);
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
        let param_buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: ModelParams::SIZE,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let bind = |buffer: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shading model params"),
                layout: &layouts.model,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            })
        };
        let params = ShadingModel::ALL
            .iter()
            .map(|&m| {
                let buffer = param_buffer(m.name());
                let group = bind(&buffer);
                (m, buffer, group)
            })
            .collect();
        let unlit_buffer = param_buffer("unlit");
        let unlit_params = bind(&unlit_buffer);
        Ok(Self {
            parts,
            skins,
            params,
            unlit_params,
            triangles,
        })
    }

    /// Recomputes every model's constants for `material` (when the material changes).
    pub fn set_material(&self, queue: &wgpu::Queue, material: &Material) {
        for (model, buffer, _) in &self.params {
            queue.write_buffer(buffer, 0, bytemuck::bytes_of(&model.params(material)));
        }
    }

    /// Computes the joint palettes for `pose` placed at `world` and uploads them.
    pub fn update_pose(&mut self, queue: &wgpu::Queue, model: &Model, pose: &Pose, world: Mat4) {
        for skin in &mut self.skins {
            joint_palette(model, skin.skin, pose, &mut skin.palette);
            for m in &mut skin.palette {
                *m = world * *m;
            }
            queue.write_buffer(&skin.buffer, 0, bytemuck::cast_slice(&skin.palette));
        }
    }

    pub(super) fn params_group(&self, model: Option<ShadingModel>) -> &wgpu::BindGroup {
        match model {
            Some(m) => {
                &self
                    .params
                    .iter()
                    .find(|(p, _, _)| *p == m)
                    .expect("all models have params")
                    .2
            }
            None => &self.unlit_params,
        }
    }

    pub(super) fn draw<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>) -> u32 {
        for part in &self.parts {
            pass.set_bind_group(2, &part.bind_group, &[]);
            pass.set_vertex_buffer(0, part.mesh.vertices.slice(..));
            pass.set_index_buffer(part.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..part.mesh.index_count, 0, 0..1);
        }
        self.parts.len() as u32
    }
}

//! GPU resources of the skinned character: meshes, one joint palette per skin, base-colour
//! and normal-map bind groups and one parameter buffer per shading model. Created once at
//! load.

use glam::Mat4;

use super::layouts::Layouts;
use super::mesh::GpuMesh;
use super::texture;
use crate::anim::{joint_palette, Pose};
use crate::asset::{Model, MAX_JOINTS};
use crate::shading::{Lut, Material, ModelParams, ShadingModel};

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

/// One shading model's constants: its uniform, its LUT (pre-integrated models) and their
/// bind group.
struct ModelGpu {
    model: ShadingModel,
    buffer: wgpu::Buffer,
    lut: Option<wgpu::Texture>,
    group: wgpu::BindGroup,
}

pub struct CharacterGpu {
    parts: Vec<Part>,
    skins: Vec<SkinGpu>,
    params: Vec<ModelGpu>,
    unlit_params: wgpu::BindGroup,
    /// Triangles drawn per frame.
    pub triangles: u32,
    /// Some part has a normal map: drawn with the normal-mapped pipelines.
    pub normal_mapped: bool,
}

impl CharacterGpu {
    /// Uploads every skinned mesh of `model`, with constants for the shading models in
    /// `models` only (a model no pipeline can draw gets no buffer, no LUT, no bake). Errors if
    /// the glTF has no skinned mesh.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &Layouts,
        sampler: &wgpu::Sampler,
        model: &Model,
        models: &[ShadingModel],
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
        let param_buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: ModelParams::SIZE,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let lut_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("LUT"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let no_lut = texture::rgba16f(device, (1, 1), "no LUT");
        texture::write_rgba16f(queue, &no_lut, &[[0.0; 4]]);
        let bind = |buffer: &wgpu::Buffer, lut: &wgpu::Texture| {
            let view = lut.create_view(&wgpu::TextureViewDescriptor::default());
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shading model params"),
                layout: &layouts.model,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&lut_sampler),
                    },
                ],
            })
        };
        let params = models
            .iter()
            .map(|&m| {
                let buffer = param_buffer(m.name());
                let lut = m
                    .effects()
                    .lut
                    .then(|| texture::rgba16f(device, Lut::SIZE, m.name()));
                let group = bind(&buffer, lut.as_ref().unwrap_or(&no_lut));
                ModelGpu {
                    model: m,
                    buffer,
                    lut,
                    group,
                }
            })
            .collect();
        let unlit_buffer = param_buffer("unlit");
        let unlit_params = bind(&unlit_buffer, &no_lut);
        Ok(Self {
            parts,
            skins,
            params,
            unlit_params,
            triangles,
            normal_mapped,
        })
    }

    /// Recomputes the constants of every model it holds for `material` (when the material
    /// changes; the shipped tables are read once per material, see `shading::bake`).
    pub fn set_material(&self, queue: &wgpu::Queue, material: &Material) {
        for m in &self.params {
            queue.write_buffer(&m.buffer, 0, bytemuck::bytes_of(&m.model.params(material)));
            if let (Some(texture), Some(lut)) = (&m.lut, m.model.lut(material)) {
                texture::write_rgba16f(queue, texture, &lut.texels);
            }
        }
    }

    /// Whether constants for `model` were made.
    pub fn has_model(&self, model: ShadingModel) -> bool {
        self.params.iter().any(|m| m.model == model)
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

    /// The bind group of `model`'s constants (`None`: the unlit baseline); `None` if the
    /// model was not loaded.
    pub(super) fn params_group(&self, model: Option<ShadingModel>) -> Option<&wgpu::BindGroup> {
        match model {
            Some(m) => self.params.iter().find(|p| p.model == m).map(|p| &p.group),
            None => Some(&self.unlit_params),
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

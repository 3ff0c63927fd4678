//! GPU resources of a skinned subject (the character, the showroom's head): meshes, one joint
//! palette per skin (group 2), one material per primitive (group 3: `material_gpu.rs`), each
//! part drawn as skin or as a standard material by its material's role (`scene::Roles`).
//! Created once at load; the shading models' constants are the renderer's
//! ([`super::model_gpu`]), shared by every subject.

use glam::{Mat4, Vec3};

use super::layouts::Layouts;
use super::material_gpu::{MaterialGpu, ModelTextures};
use super::mesh::GpuMesh;
use super::prepared::{per_frame, FRAMES_PREPARED};
use crate::anim::{joint_palette, JointBoxes, Pose};
use crate::asset::{Model, MAX_JOINTS};
use crate::scene::{Role, Roles};

/// One primitive: its mesh, its skin's palette (an index into the subject's skins) and its
/// material.
pub struct Part {
    mesh: GpuMesh,
    skin: usize,
    pub material: MaterialGpu,
    pub triangles: u32,
}

struct SkinGpu {
    skin: usize,
    /// One palette buffer and its group per prepared frame's copy.
    buffers: [wgpu::Buffer; FRAMES_PREPARED],
    groups: [wgpu::BindGroup; FRAMES_PREPARED],
    /// The palette as last posed (reused every frame, no allocation).
    palette: Vec<Mat4>,
    /// Where its joints' vertices are in bind space (for the posed box).
    reach: JointBoxes,
}

pub struct SkinnedGpu {
    parts: Vec<Part>,
    skins: Vec<SkinGpu>,
    /// Triangles drawn per frame.
    pub triangles: u32,
    /// Some skin part has a normal map: its model's normal-mapped pipelines are needed.
    pub normal_mapped: bool,
    /// Some skin part has none.
    pub plain: bool,
    /// The world box of every vertex as last posed ([`Self::pose`]); `None` before.
    pub posed: Option<(Vec3, Vec3)>,
    /// Poses so far, and the one each copy of the palettes holds.
    poses: u64,
    written: [Option<u64>; FRAMES_PREPARED],
}

impl SkinnedGpu {
    /// Uploads every skinned mesh of `model`, its materials drawn as `roles` says. Errors if
    /// the glTF has no skinned mesh.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (layouts, sampler): (&Layouts, &wgpu::Sampler),
        model: &Model,
        roles: &Roles,
    ) -> Result<Self, String> {
        let palette_size = (MAX_JOINTS * 64) as u64;
        let mut skins: Vec<SkinGpu> = Vec::new();
        let mut parts = Vec::new();
        let textures = ModelTextures::upload(device, queue, model);
        for node in &model.nodes {
            let (Some(mesh), Some(skin)) = (node.mesh, node.skin) else {
                continue;
            };
            let slot = match skins.iter().position(|s| s.skin == skin) {
                Some(i) => i,
                None => {
                    let buffers = per_frame(|_| {
                        device.create_buffer(&wgpu::BufferDescriptor {
                            label: Some("joint palette"),
                            size: palette_size,
                            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                            mapped_at_creation: false,
                        })
                    });
                    let groups = per_frame(|k| {
                        device.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some("joint palette"),
                            layout: &layouts.skinned,
                            entries: &[wgpu::BindGroupEntry {
                                binding: 0,
                                resource: buffers[k].as_entire_binding(),
                            }],
                        })
                    });
                    skins.push(SkinGpu {
                        skin,
                        buffers,
                        groups,
                        palette: vec![Mat4::IDENTITY; model.skins[skin].joints.len()],
                        reach: JointBoxes::new(model.skins[skin].joints.len()),
                    });
                    skins.len() - 1
                }
            };
            skins[slot].reach.add_mesh(model, mesh);
            for prim in &model.meshes[mesh].primitives {
                let material = prim.material.and_then(|m| model.materials.get(m));
                let role = roles.role(prim.material);
                parts.push(Part {
                    mesh: GpuMesh::new(device, prim, "character"),
                    skin: slot,
                    material: MaterialGpu::new(
                        device,
                        (layouts, sampler),
                        &textures,
                        material,
                        role,
                    ),
                    triangles: prim.indices.len() as u32 / 3,
                });
            }
        }
        if parts.is_empty() {
            return Err(format!(
                "{}: no skinned mesh to render as the character",
                model.source
            ));
        }
        let skin_parts = || parts.iter().filter(|p| p.material.role != Role::Standard);
        Ok(Self {
            triangles: parts.iter().map(|p| p.triangles).sum(),
            normal_mapped: skin_parts().any(|p| p.material.normal_mapped),
            plain: skin_parts().any(|p| !p.material.normal_mapped),
            parts,
            skins,
            posed: None,
            poses: 0,
            written: [None; FRAMES_PREPARED],
        })
    }

    /// The parts, in the file's order.
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// Computes the joint palettes for `pose` placed at `world` and the posed box
    /// ([`Self::posed`]); [`Self::write_palettes`] uploads them.
    pub fn pose(&mut self, model: &Model, pose: &Pose, world: Mat4) {
        for skin in &mut self.skins {
            joint_palette(model, skin.skin, pose, &mut skin.palette);
            for m in &mut skin.palette {
                *m = world * *m;
            }
        }
        self.posed = self
            .skins
            .iter()
            .filter_map(|s| s.reach.posed(&s.palette))
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
        self.poses += 1;
    }

    /// Writes the palettes as last posed into the copy `copy` of the per-frame buffers,
    /// unless it holds them already; returns the uploads (one per skin, or none).
    pub fn write_palettes(&mut self, queue: &wgpu::Queue, copy: usize) -> u32 {
        if self.written[copy] == Some(self.poses) {
            return 0;
        }
        for skin in &self.skins {
            queue.write_buffer(&skin.buffers[copy], 0, bytemuck::cast_slice(&skin.palette));
        }
        self.written[copy] = Some(self.poses);
        self.skins.len() as u32
    }

    /// Draws every part with the pipeline bound (group 2: the palette; group 3: the
    /// material): depth-only passes. Returns the draw calls.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, copy: usize) -> u32 {
        for part in &self.parts {
            self.draw_part(pass, part, false, copy);
        }
        self.parts.len() as u32
    }

    /// Draws `part` (its palette's copy `copy` at group 2 and, with `material`, its material
    /// at group 3).
    pub fn draw_part(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        part: &Part,
        material: bool,
        copy: usize,
    ) {
        pass.set_bind_group(2, &self.skins[part.skin].groups[copy], &[]);
        if material {
            pass.set_bind_group(3, &part.material.group, &[]);
        }
        pass.set_vertex_buffer(0, part.mesh.vertices.slice(..));
        pass.set_index_buffer(part.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..part.mesh.index_count, 0, 0..1);
    }
}

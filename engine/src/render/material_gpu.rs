//! A glTF material on the GPU: its constants ([`MaterialUniform`], declared in
//! `shader/uniforms.rs`, read by `shaders/material.wgsl`) and its textures — base colour (a
//! skin's albedo), normal, metallic-roughness, occlusion, emissive — bound as one group with
//! the textures' sampler.
//! A texture the material lacks is a 1×1 stand-in that leaves the factor as it is. Skinned
//! subjects bind it at group 3, props at group 1 (one layout, `Layouts::material`).

use super::layouts::Layouts;
use super::texture;
use crate::asset::{AlphaMode, Material, Model};
use crate::scene::{Role, Roles};
use crate::shader::uniforms::MaterialUniform;
use crate::shader::{compose, ShaderDefs};

impl MaterialUniform {
    /// The constants of `material` drawn as `role`; `None`: a primitive without a material
    /// (glTF's default material).
    pub fn new(material: Option<&Material>, role: Role) -> Self {
        let default = Material::default();
        let m = material.unwrap_or(&default);
        let base_color = match role {
            Role::Skin { .. } => {
                let a = m.skin_albedo().factor;
                [a[0], a[1], a[2], m.base_color_factor[3]]
            }
            Role::Standard => m.base_color_factor,
        };
        Self {
            base_color,
            emissive: m.emissive_factor.map(|e| e * m.emissive_strength),
            metallic: m.metallic_factor,
            roughness: m.roughness_factor,
            normal_scale: m.normal_scale,
            occlusion_strength: m.occlusion_strength,
            alpha_cutoff: match m.alpha_mode {
                AlphaMode::Mask { cutoff } => cutoff,
                _ => 0.0,
            },
            pigmented: u32::from(role == Role::Skin { pigmented: true }),
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
        }
    }
}

/// How a standard material's pipeline differs: blended, masked, both faces drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Variant {
    pub blend: bool,
    pub mask: bool,
    pub double_sided: bool,
}

impl Variant {
    pub fn of(material: Option<&Material>) -> Self {
        material.map_or(Self::default(), |m| Self {
            blend: m.alpha_mode == AlphaMode::Blend,
            mask: matches!(m.alpha_mode, AlphaMode::Mask { .. }),
            double_sided: m.double_sided,
        })
    }
}

/// The normal map of a primitive without one: the flat normal, alpha 0 ("no map": the
/// shader keeps the interpolated vertex normal bit for bit).
pub const FLAT_NORMAL: [u8; 4] = [128, 128, 255, 0];

/// A model's textures uploaded once, with the stand-ins of a texture a material lacks.
pub struct ModelTextures {
    views: Vec<wgpu::TextureView>,
    white_srgb: wgpu::TextureView,
    white_linear: wgpu::TextureView,
    flat_normal: wgpu::TextureView,
}

impl ModelTextures {
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, model: &Model) -> Self {
        Self {
            views: model
                .textures
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    texture::upload(device, queue, t, &format!("{} texture {i}", model.source))
                })
                .collect(),
            white_srgb: texture::solid(device, queue, [255; 4], true),
            white_linear: texture::solid(device, queue, [255; 4], false),
            // No normal map: alpha 0 tells the shader to keep the vertex normal exactly.
            flat_normal: texture::solid(device, queue, FLAT_NORMAL, false),
        }
    }

    fn view<'a>(
        &'a self,
        index: Option<usize>,
        stand_in: &'a wgpu::TextureView,
    ) -> &'a wgpu::TextureView {
        index.and_then(|i| self.views.get(i)).unwrap_or(stand_in)
    }
}

/// One material's bind group and what drawing it needs.
pub struct MaterialGpu {
    pub group: wgpu::BindGroup,
    pub role: Role,
    pub variant: Variant,
    /// A normal map is bound (drawn with a normal-mapped pipeline).
    pub normal_mapped: bool,
}

impl MaterialGpu {
    /// `material` of a model whose textures are `textures`, drawn as `role`.
    pub fn new(
        device: &wgpu::Device,
        (layouts, sampler): (&Layouts, &wgpu::Sampler),
        textures: &ModelTextures,
        material: Option<&Material>,
        role: Role,
    ) -> Self {
        let uniform = MaterialUniform::new(material, role);
        let buffer = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("material"),
                contents: bytemuck::bytes_of(&uniform),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let albedo = match role {
            Role::Skin { .. } => material.and_then(|m| m.skin_albedo().texture),
            Role::Standard => material.and_then(|m| m.base_color_texture),
        };
        let normal = material.and_then(|m| m.normal_texture);
        let t = textures;
        let views = [
            t.view(albedo, &t.white_srgb),
            t.view(normal, &t.flat_normal),
            t.view(
                material.and_then(|m| m.metallic_roughness_texture),
                &t.white_linear,
            ),
            t.view(material.and_then(|m| m.occlusion_texture), &t.white_linear),
            t.view(material.and_then(|m| m.emissive_texture), &t.white_srgb),
        ];
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: buffer.as_entire_binding(),
        }];
        for (k, view) in views.into_iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: k as u32 + 1,
                resource: wgpu::BindingResource::TextureView(view),
            });
        }
        entries.push(wgpu::BindGroupEntry {
            binding: 6,
            resource: wgpu::BindingResource::Sampler(sampler),
        });
        Self {
            group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("material"),
                layout: &layouts.material,
                entries: &entries,
            }),
            role,
            variant: Variant::of(material),
            normal_mapped: normal.is_some_and(|i| i < t.views.len()),
        }
    }
}

/// A standard material's pipeline: its variant and whether it has a normal map.
pub type StandardKey = (Variant, bool);

/// The standard pipelines `model` drawn as `roles` needs.
pub fn standard_keys(model: &Model, roles: &Roles) -> Vec<StandardKey> {
    let mut keys: Vec<StandardKey> = model
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .filter(|p| roles.role(p.material) == Role::Standard)
        .map(|p| {
            let material = p.material.and_then(|i| model.materials.get(i));
            let mapped = material.and_then(|m| m.normal_texture).is_some();
            (Variant::of(material), mapped)
        })
        .collect();
    keys.sort();
    keys.dedup();
    keys
}

/// The composed WGSL of a standard part's pipeline.
pub fn standard_source((variant, mapped): StandardKey, split: bool) -> String {
    let mut defs = ShaderDefs::new().flag("STANDARD");
    for (on, flag) in [
        (mapped, "NORMAL_MAP"),
        (variant.mask, "ALPHA_MASK"),
        (variant.blend, "ALPHA_BLEND"),
        (variant.double_sided, "DOUBLE_SIDED"),
        (split, "SCREEN_SPACE"),
    ] {
        if on {
            defs = defs.flag(flag);
        }
    }
    compose("character", &defs).expect("built-in shaders compose (checked by tests)")
}

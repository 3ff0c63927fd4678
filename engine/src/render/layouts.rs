//! Bind group layouts, created once.

/// Group 0: the frame uniform, the shadow map and the penumbra map. Group 1: a shading model's
/// parameters (and LUT). Group 2: a skin's joint palette. Group 3: a material (its uniform,
/// base colour, normal, metallic-roughness, occlusion and emissive textures, their sampler:
/// `material_gpu.rs`). Props bind a material at group 1.
pub struct Layouts {
    pub frame: wgpu::BindGroupLayout,
    pub model: wgpu::BindGroupLayout,
    pub skinned: wgpu::BindGroupLayout,
    pub material: wgpu::BindGroupLayout,
}

pub(super) fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Bindings 1–3 of the frame group: the key light's shadow map, its comparison sampler and
/// the penumbra map (`penumbra.rs`).
pub fn shadow_map_entries(visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 3] {
    [
        wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 3,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
    ]
}

fn texture(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn sampler(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

impl Layouts {
    pub fn new(device: &wgpu::Device) -> Self {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let make = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        Self {
            // The frame uniform, the key light's shadow map and its comparison sampler.
            frame: make("frame", &{
                let [map, sampler, penumbra] = shadow_map_entries(wgpu::ShaderStages::FRAGMENT);
                [uniform(0, vf), map, sampler, penumbra]
            }),
            // The model's uniform and, for models that sample a LUT, their LUT.
            model: make(
                "shading model",
                &[
                    uniform(0, wgpu::ShaderStages::FRAGMENT),
                    texture(1),
                    sampler(2),
                ],
            ),
            skinned: make("joint palette", &[uniform(0, wgpu::ShaderStages::VERTEX)]),
            material: make(
                "material",
                &[
                    uniform(0, wgpu::ShaderStages::FRAGMENT),
                    texture(1),
                    texture(2),
                    texture(3),
                    texture(4),
                    texture(5),
                    sampler(6),
                ],
            ),
        }
    }
}

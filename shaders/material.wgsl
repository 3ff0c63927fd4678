// A glTF material's constants (`MaterialUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs; filled by engine/src/render/material_gpu.rs) and textures: a
// skinned subject binds them at group 3, props (INSTANCED) at group 1. A texture the material
// lacks is a stand-in that leaves its factor as it is.
#import common
#import MaterialUniform

#ifdef INSTANCED
@group(1) @binding(0) var<uniform> material: MaterialUniform;
@group(1) @binding(1) var base_color_map: texture_2d<f32>;
@group(1) @binding(2) var normal_map: texture_2d<f32>;
@group(1) @binding(3) var metallic_roughness_map: texture_2d<f32>;
@group(1) @binding(4) var occlusion_map: texture_2d<f32>;
@group(1) @binding(5) var emissive_map: texture_2d<f32>;
@group(1) @binding(6) var material_sampler: sampler;
#else
@group(3) @binding(0) var<uniform> material: MaterialUniform;
@group(3) @binding(1) var base_color_map: texture_2d<f32>;
@group(3) @binding(2) var normal_map: texture_2d<f32>;
@group(3) @binding(3) var metallic_roughness_map: texture_2d<f32>;
@group(3) @binding(4) var occlusion_map: texture_2d<f32>;
@group(3) @binding(5) var emissive_map: texture_2d<f32>;
@group(3) @binding(6) var material_sampler: sampler;
#endif

// Base colour × factor (linear rgb, alpha).
fn material_base(uv: vec2<f32>) -> vec4<f32> {
    return textureSample(base_color_map, material_sampler, uv) * material.base_color;
}

#ifdef NORMAL_MAP
// The shading normal: the normal map's (rgb = (xyz + 1) / 2, +y toward decreasing v, x and y
// scaled by the material), in the interpolated tangent frame (the bitangent points toward
// increasing v, so the map's +y is −b); alpha 0 (the stand-in): the vertex normal as it is.
fn material_normal(normal: vec3<f32>, tangent: vec4<f32>, uv: vec2<f32>) -> vec3<f32> {
    let m = textureSample(normal_map, material_sampler, uv);
    let n = safe_normalize(normal, vec3<f32>(0.0, 1.0, 0.0));
    var t = tangent.xyz - n * dot(n, tangent.xyz);
    t = safe_normalize(t, select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(n.x) > 0.9));
    let b = cross(n, t) * select(1.0, -1.0, tangent.w < 0.0);
    let k = m.xyz * 2.0 - 1.0;
    let xy = k.xy * material.normal_scale;
    let mapped = safe_normalize(t * xy.x - b * xy.y + n * k.z, n);
    return select(normal, mapped, m.a > 0.5);
}
#else
// A mesh without a normal map: the vertex normal.
fn material_normal(normal: vec3<f32>, tangent: vec4<f32>, uv: vec2<f32>) -> vec3<f32> {
    return normal;
}
#endif

// (metallic, roughness) × their texture (B, G).
fn material_metallic_roughness(uv: vec2<f32>) -> vec2<f32> {
    let t = textureSample(metallic_roughness_map, material_sampler, uv);
    return vec2<f32>(material.metallic * t.b, material.roughness * t.g);
}

// The occlusion of ambient light (R), weighted by the material's strength.
fn material_occlusion(uv: vec2<f32>) -> f32 {
    let o = textureSample(occlusion_map, material_sampler, uv).r;
    return 1.0 + material.occlusion_strength * (o - 1.0);
}

fn material_emissive(uv: vec2<f32>) -> vec3<f32> {
    return textureSample(emissive_map, material_sampler, uv).rgb * material.emissive;
}

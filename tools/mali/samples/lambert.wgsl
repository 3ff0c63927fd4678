// Sample for tools/mali: textured Lambert + ambient, UBOs in sets 0..2.
struct Camera { view_proj: mat4x4<f32>, eye: vec4<f32> };
struct Model { world: mat4x4<f32>, normal_mat: mat4x4<f32> };
struct Material { albedo: vec4<f32>, light_dir: vec4<f32>, light_color: vec4<f32>, ambient: vec4<f32> };

@group(0) @binding(0) var<uniform> camera: Camera;
@group(1) @binding(0) var<uniform> model: Model;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
@group(2) @binding(2) var albedo_smp: sampler;

struct VsIn { @location(0) pos: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32> };
struct VsOut { @builtin(position) clip: vec4<f32>, @location(0) normal: vec3<f32>, @location(1) uv: vec2<f32> };

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var o: VsOut;
    let world = model.world * vec4<f32>(v.pos, 1.0);
    o.clip = camera.view_proj * world;
    o.normal = (model.normal_mat * vec4<f32>(v.normal, 0.0)).xyz;
    o.uv = v.uv;
    return o;
}

@fragment
fn fs_main(i: VsOut) -> @location(0) vec4<f32> {
    let n = normalize(i.normal);
    let base = textureSample(albedo_tex, albedo_smp, i.uv) * material.albedo;
    let ndl = max(dot(n, -material.light_dir.xyz), 0.0);
    let rgb = base.rgb * (material.ambient.rgb + material.light_color.rgb * ndl);
    return vec4<f32>(rgb, base.a);
}

// Sample for tools/mali: GPU skinning from a read-only storage buffer (vertex stage),
// Blinn-Phong with two textures and an array-of-lights uniform block (fragment stage).
struct Camera { view_proj: mat4x4<f32>, eye: vec4<f32> };
struct Light { pos: vec4<f32>, color: vec4<f32> };
struct Lights { count: vec4<u32>, lights: array<Light, 4> };
struct Material { albedo: vec4<f32>, shininess: vec4<f32> };

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> lights: Lights;
@group(1) @binding(0) var<storage, read> joints: array<mat4x4<f32>>;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
@group(2) @binding(2) var spec_tex: texture_2d<f32>;
@group(2) @binding(3) var smp: sampler;

struct VsIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) joint_ids: vec4<u32>,
    @location(4) weights: vec4<f32>,
};
struct VsOut { @builtin(position) clip: vec4<f32>, @location(0) world_pos: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32> };

@vertex
fn vs_main(v: VsIn) -> VsOut {
    let skin = joints[v.joint_ids.x] * v.weights.x + joints[v.joint_ids.y] * v.weights.y
             + joints[v.joint_ids.z] * v.weights.z + joints[v.joint_ids.w] * v.weights.w;
    let world = skin * vec4<f32>(v.pos, 1.0);
    var o: VsOut;
    o.clip = camera.view_proj * world;
    o.world_pos = world.xyz;
    o.normal = (skin * vec4<f32>(v.normal, 0.0)).xyz;
    o.uv = v.uv;
    return o;
}

@fragment
fn fs_main(i: VsOut) -> @location(0) vec4<f32> {
    let n = normalize(i.normal);
    let v = normalize(camera.eye.xyz - i.world_pos);
    let albedo = textureSample(albedo_tex, smp, i.uv).rgb * material.albedo.rgb;
    let ks = textureSample(spec_tex, smp, i.uv).r;
    var rgb = vec3<f32>(0.0);
    for (var k = 0u; k < min(lights.count.x, 4u); k = k + 1u) {
        let l = normalize(lights.lights[k].pos.xyz - i.world_pos);
        let h = normalize(l + v);
        let diff = max(dot(n, l), 0.0);
        let spec = pow(max(dot(n, h), 0.0), material.shininess.x) * ks;
        rgb = rgb + (albedo * diff + vec3<f32>(spec)) * lights.lights[k].color.rgb;
    }
    return vec4<f32>(rgb, 1.0);
}

// Sample for tools/mali: Ward anisotropic BRDF with a normal map (heavier ALU + SFU).
struct Camera { view_proj: mat4x4<f32>, eye: vec4<f32> };
struct Model { world: mat4x4<f32> };
struct Material { albedo: vec4<f32>, alpha_xy: vec4<f32>, light_pos: vec4<f32>, light_color: vec4<f32> };

@group(0) @binding(0) var<uniform> camera: Camera;
@group(1) @binding(0) var<uniform> model: Model;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
@group(2) @binding(2) var normal_tex: texture_2d<f32>;
@group(2) @binding(3) var smp: sampler;

struct VsIn { @location(0) pos: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) tangent: vec4<f32>, @location(3) uv: vec2<f32> };
struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
};

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var o: VsOut;
    let world = model.world * vec4<f32>(v.pos, 1.0);
    o.clip = camera.view_proj * world;
    o.world_pos = world.xyz;
    o.normal = (model.world * vec4<f32>(v.normal, 0.0)).xyz;
    o.tangent = vec4<f32>((model.world * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    o.uv = v.uv;
    return o;
}

const PI: f32 = 3.14159265;

@fragment
fn fs_main(i: VsOut) -> @location(0) vec4<f32> {
    let ng = normalize(i.normal);
    let t0 = normalize(i.tangent.xyz - ng * dot(ng, i.tangent.xyz));
    let b0 = cross(ng, t0) * i.tangent.w;
    let nm = textureSample(normal_tex, smp, i.uv).xyz * 2.0 - 1.0;
    let n = normalize(t0 * nm.x + b0 * nm.y + ng * nm.z);
    let t = normalize(t0 - n * dot(n, t0));
    let b = cross(n, t);
    let l = normalize(material.light_pos.xyz - i.world_pos);
    let v = normalize(camera.eye.xyz - i.world_pos);
    let h = normalize(l + v);
    let ndl = max(dot(n, l), 0.0);
    let ndv = max(dot(n, v), 1e-4);
    let ax = material.alpha_xy.x;
    let ay = material.alpha_xy.y;
    let hx = dot(h, t) / ax;
    let hy = dot(h, b) / ay;
    let hn = max(dot(h, n), 1e-4);
    let spec = exp(-2.0 * (hx * hx + hy * hy) / (1.0 + hn)) / (4.0 * PI * ax * ay * sqrt(max(ndl * ndv, 1e-4)));
    let albedo = textureSample(albedo_tex, smp, i.uv).rgb * material.albedo.rgb;
    let rgb = (albedo / PI + vec3<f32>(spec)) * material.light_color.rgb * ndl;
    return vec4<f32>(pow(rgb, vec3<f32>(1.0 / 2.2)), 1.0);
}

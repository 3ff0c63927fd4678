// Props (floor, walls, furniture, obstacles): one plain default-lit shader, instanced.
// No subsurface code is imported here.
#import common

@group(1) @binding(0) var base_color: texture_2d<f32>;
@group(1) @binding(1) var base_sampler: sampler;

struct PropMaterial {
    factor: vec4<f32>,
};
@group(1) @binding(2) var<uniform> material: PropMaterial;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(3) uv: vec2<f32>,
    // The instance's model matrix, one column per attribute.
    @location(8) m0: vec4<f32>,
    @location(9) m1: vec4<f32>,
    @location(10) m2: vec4<f32>,
    @location(11) m3: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let m = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let world = m * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    // Props use uniform scale only, so the model matrix transforms normals correctly.
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    return out;
}

fn prop_radiance(in: VertexOut) -> vec3<f32> {
    let albedo = textureSample(base_color, base_sampler, in.uv).rgb * material.factor.rgb;
    let n = safe_normalize(in.normal, vec3<f32>(0.0, 1.0, 0.0));
    let to_light = frame.light_pos - in.world_pos;
    let d = max(length(to_light), 1e-3);
    let l = to_light / d;
    let v = safe_normalize(frame.camera_pos - in.world_pos, n);
    // The character's shadow falls on the floor and the props (the key light's shadow map).
    let e = frame.light_intensity * frame.light_color / (d * d) * max(dot(n, l), 0.0)
        * light_visible(in.world_pos, n);
    let h = safe_normalize(l + v, n);
    let spec = 0.04 * pow(max(dot(n, h), 0.0), 32.0) * 5.0;
    return frame.ambient * albedo + e * (albedo * INV_PI + vec3<f32>(spec));
}

#ifdef SCREEN_SPACE
// In a frame with the subsurface pass: linear radiance, exit factor 0 (nothing to spread).
struct SplitOut {
    @location(0) colour: vec4<f32>,
    @location(1) spread: vec4<f32>,
};

@fragment
fn fs_main(in: VertexOut) -> SplitOut {
    var out: SplitOut;
    out.colour = vec4<f32>(prop_radiance(in), 0.0);
    out.spread = vec4<f32>(0.0);
    return out;
}
#else
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return finish(prop_radiance(in));
}
#endif

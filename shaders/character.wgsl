// The skinned character: vertex skinning + the selected shading model (`shading_model` is an
// alias bound per pipeline to ward / dipole / oss / ...).
#import common
#import skinning
#import shading_model

@group(2) @binding(1) var base_color: texture_2d<f32>;
@group(2) @binding(2) var base_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) joints: vec4<u32>,
    @location(5) weights: vec4<f32>,
    @location(6) thickness: f32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) thickness: f32,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let skin = skin_matrix(v.joints, v.weights);
    let world = skin * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    out.normal = (skin * vec4<f32>(v.normal, 0.0)).xyz;
    out.tangent = vec4<f32>((skin * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    out.uv = v.uv;
    out.thickness = v.thickness;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let albedo = textureSample(base_color, base_sampler, in.uv).rgb;
    var s = make_surface(in.world_pos, in.normal, in.tangent, albedo, in.thickness);
    // Curvature radius from screen-space derivatives: how far the surface moves per unit of
    // normal change across a pixel (large on flat parts, small on fingers and ears).
    let dn = length(fwidth(in.normal));
    let dp = length(fwidth(in.world_pos));
    s.curvature_radius = min(dp / max(dn, 1e-6), FLAT_RADIUS_M);
    return finish(shade(s));
}

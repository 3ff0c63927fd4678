// The skinned character: vertex skinning + the selected shading model (`shading_model` is an
// alias bound per pipeline to ward / dipole / oss / ...) on the skin, and the cloth BRDF
// (common.wgsl) elsewhere: the base colour's alpha is the skin mask (1: skin; the loader sets
// it to 1 for materials that declare no mask), blended across its edges.
#import common
#import skinning
#import shading_model

@group(2) @binding(1) var base_color: texture_2d<f32>;
@group(2) @binding(2) var base_sampler: sampler;
#ifdef NORMAL_MAP
// Tangent-space normal map (rgb = (xyz + 1) / 2, +y toward decreasing v); alpha 0: none (the
// flat default of a part without one). Only in the pipelines of meshes that have one.
@group(2) @binding(3) var normal_map: texture_2d<f32>;
#endif

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

#ifdef NORMAL_MAP
// The shading normal: the normal map's, in the interpolated tangent frame (the bitangent
// points toward increasing v, so the map's +y is −b); without a map, the vertex normal as it is.
fn shading_normal(in: VertexOut) -> vec3<f32> {
    let m = textureSample(normal_map, base_sampler, in.uv);
    let n = safe_normalize(in.normal, vec3<f32>(0.0, 1.0, 0.0));
    var t = in.tangent.xyz - n * dot(n, in.tangent.xyz);
    t = safe_normalize(t, select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(n.x) > 0.9));
    let b = cross(n, t) * select(1.0, -1.0, in.tangent.w < 0.0);
    let k = m.xyz * 2.0 - 1.0;
    let mapped = safe_normalize(t * k.x - b * k.y + n * k.z, n);
    return select(in.normal, mapped, m.a > 0.5);
}
#else
// A mesh without a normal map: the vertex normal.
fn shading_normal(in: VertexOut) -> vec3<f32> {
    return in.normal;
}
#endif

fn surface_at(in: VertexOut, albedo: vec3<f32>) -> Surface {
    var s = make_surface(in.world_pos, shading_normal(in), in.tangent, albedo, in.thickness);
    // Curvature radius from screen-space derivatives: how far the surface moves per unit of
    // normal change across a pixel (large on flat parts, small on fingers and ears).
    let dn = length(fwidth(in.normal));
    let dp = length(fwidth(in.world_pos));
    s.curvature_radius = min(dp / max(dn, 1e-6), FLAT_RADIUS_M);
    return s;
}

#ifdef SCREEN_SPACE
// Spatial models write two targets: radiance that stays (rgb) with the exit factor (a), and
// the irradiance the subsurface pass spreads (rgb) with the pixel's size in mm (a): the
// world-space step between neighbouring pixels, minus its part along the view ray, is the
// pixel's footprint on the plane facing the camera at this depth.
struct SplitOut {
    @location(0) colour: vec4<f32>,
    @location(1) spread: vec4<f32>,
};

// Cloth writes exit 0 and a zero pixel size: the pass leaves it as it is and its
// neighbours take it for "not skin"; a partly skin pixel spreads the irradiance its skin part
// received and takes its share of what comes back.
@fragment
fn fs_main(in: VertexOut) -> SplitOut {
    let tex = textureSample(base_color, base_sampler, in.uv);
    let s = surface_at(in, tex.rgb);
    let skin = tex.a;
    let dx = dpdx(in.world_pos);
    let dy = dpdy(in.world_pos);
    let px = 0.5 * (length(dx - s.v * dot(s.v, dx)) + length(dy - s.v * dot(s.v, dy)));
    // Cloth first: the skin model then runs with only the cloth's colour left to carry.
    var out: SplitOut;
    out.colour = vec4<f32>(0.0);
    out.spread = vec4<f32>(0.0);
    if (skin < 1.0) {
        out.colour = vec4<f32>(cloth_radiance(s) * (1.0 - skin), 0.0);
    }
    if (skin > 0.0) {
        let p = shade_split(s);
        out.colour = vec4<f32>(out.colour.rgb + p.local * skin, p.exit * skin);
        out.spread = vec4<f32>(p.spread, max(px * 1000.0, 1e-6));
    }
    return out;
}
#else
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let tex = textureSample(base_color, base_sampler, in.uv);
    let s = surface_at(in, tex.rgb);
    let skin = tex.a;
    // Cloth first: the skin model then runs with only the cloth's colour left to carry.
    var c = vec3<f32>(0.0);
    if (skin < 1.0) {
        c = cloth_radiance(s) * (1.0 - skin);
    }
    if (skin > 0.0) {
        c = c + shade(s) * skin;
    }
    return finish(c);
}
#endif

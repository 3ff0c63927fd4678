// Shared by every pass: the per-frame uniform, the shading surface, light and tone mapping.

#import consts
// The frame's uniform (`FrameUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs; filled by engine/src/render/frame_uniform.rs).
#import FrameUniform

@group(0) @binding(0) var<uniform> frame: FrameUniform;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
@group(0) @binding(3) var penumbra_map: texture_2d<f32>;

// What a shading model sees at one pixel (world space, unit vectors).
struct Surface {
    pos: vec3<f32>,
    n: vec3<f32>,
    t: vec3<f32>,
    b: vec3<f32>,
    v: vec3<f32>,
    l: vec3<f32>,
    // Distance to the light (m), never below 1 mm.
    light_dist: f32,
    // Light intensity × colour (before distance falloff), times `visibility`.
    light: vec3<f32>,
    // The key light's shadow test at this point (1: lit), already in `light`.
    visibility: f32,
    // Where it was tested in the shadow map: uv, depth, and w 1 inside the map (0: outside,
    // or no map this frame).
    shadow_coord: vec4<f32>,
    // Base colour (texture × factor), linear; a pigmented skin's albedo per texel.
    albedo: vec3<f32>,
    // The albedo is the skin's pigment (its texel's albedo): the skin models render a medium
    // whose diffuse reflectance is `albedo`; otherwise the medium's own.
    pigmented: bool,
    // Material thickness through this point (m).
    thickness: f32,
    // Radius of curvature of the surface here (m: the mesh's curvature along the light);
    // FLAT_RADIUS_M where unknown, flat or concave.
    curvature_radius: f32,
    // The light the subject returns here from its own lit surface (interreflection): its
    // irradiance per unit of the key light's intensity × colour and of the skin's diffuse
    // reflectance squared (1/m²; asset::bounce); 0 where unknown.
    bounce: f32,
};

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if (len2 < 1e-24) {
        return fallback;
    }
    return v * inverseSqrt(len2);
}

// World point `p` moved `offset` (a vector of at most unit length) times the normal offset,
// in the shadow map: uv, depth (beyond the far plane: at it), w 1 inside the map's frustum
// (0 outside, or when no map was drawn this frame).
fn shadow_coord(p: vec3<f32>, offset: vec3<f32>) -> vec4<f32> {
    let q = frame.shadow_view_proj * vec4<f32>(p + offset * frame.shadow_normal_offset, 1.0);
    let ndc = q.xyz / max(q.w, 1e-20);
    let uv = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    let inside = frame.shadow_drawn != 0u && q.w > 0.0 && all(uv >= vec2<f32>(0.0))
        && all(uv <= vec2<f32>(1.0));
    return vec4<f32>(uv, min(ndc.z, 1.0), select(0.0, 1.0, inside));
}

// The fraction of the key light that reaches a point at shadow-map coordinate `c` (1: lit,
// 0: in shadow): one bilinear depth comparison (2×2 texels). Outside the map nothing casts.
fn light_visible_coord(c: vec4<f32>) -> f32 {
    if (c.w < 0.5) {
        return 1.0;
    }
    // Four bilinear comparisons on a square (SHADOW_RAMP_TEXELS − 1) texels wide: a tent, so
    // across a straight edge the visibility ramps linearly over SHADOW_RAMP_TEXELS texels.
    let h = 0.5 * (SHADOW_RAMP_TEXELS - 1.0) * frame.shadow_texel;
    let z = c.z - frame.shadow_bias;
    return 0.25 * (textureSampleCompareLevel(shadow_map, shadow_sampler, c.xy + vec2<f32>(-h, -h), z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, c.xy + vec2<f32>(h, -h), z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, c.xy + vec2<f32>(-h, h), z)
        + textureSampleCompareLevel(shadow_map, shadow_sampler, c.xy + vec2<f32>(h, h), z));
}

// The key light's visibility where light seen at a point past its terminator entered the
// matter: on the ray toward the light, `path` (m) from the point — as far as the light ran
// through matter to it, never further (a crease the light grazes, tested centimetres out,
// landed past whatever shadows it). The ray is one texel of the light's map: the point's own
// coordinate serves, at that depth (one bilinear comparison). `v` where no map covers it.
fn entry_visibility(s: Surface, path: f32, v: f32) -> f32 {
    let m = frame.shadow_view_proj;
    let p = vec4<f32>(s.pos + s.l * (path + frame.shadow_normal_offset), 1.0);
    let z = dot(vec4<f32>(m[0].z, m[1].z, m[2].z, m[3].z), p);
    let w = dot(vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w), p);
    let depth = min(z / max(w, 1e-20), 1.0);
    let entered = textureSampleCompareLevel(shadow_map, shadow_sampler, s.shadow_coord.xy, depth - frame.shadow_bias);
    return select(v, entered, s.shadow_coord.w > 0.5);
}

// The key light's visibility at `p`, moved off its surface by `offset` (see shadow_coord).
fn light_visible(p: vec3<f32>, offset: vec3<f32>) -> f32 {
    return light_visible_coord(shadow_coord(p, offset));
}

// Where light that leaves at a surface point entered, for the shadow test, in the shadow map:
// a point lit from the front is tested where it is (moved off the surface along n, more as the
// light grazes); one lit from behind (translucency, the wrap past the terminator) received its
// light where the ray toward the light leaves the material, thickness / |n·l| further along l.
fn entry_shadow_coord(pos: vec3<f32>, n: vec3<f32>, l: vec3<f32>, thickness: f32) -> vec4<f32> {
    let nl = dot(n, l);
    let behind = nl < 0.0;
    let p = select(pos, pos + l * (thickness / max(-nl, 0.05)), behind);
    let offset = select(n * sqrt(max(1.0 - nl * nl, 0.0)), l, behind);
    return shadow_coord(p, offset);
}

fn make_surface(pos: vec3<f32>, normal: vec3<f32>, tangent: vec4<f32>, albedo: vec3<f32>,
                thickness: f32) -> Surface {
    var s: Surface;
    s.pos = pos;
    s.n = safe_normalize(normal, vec3<f32>(0.0, 1.0, 0.0));
    // Gram–Schmidt; a tangent parallel to n falls back to any perpendicular.
    var t = tangent.xyz - s.n * dot(s.n, tangent.xyz);
    if (dot(t, t) < 1e-12) {
        t = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(s.n.x) > 0.9);
        t = t - s.n * dot(s.n, t);
    }
    s.t = normalize(t);
    let handedness = select(1.0, -1.0, tangent.w < 0.0);
    s.b = cross(s.n, s.t) * handedness;
    s.v = safe_normalize(frame.camera_pos - pos, s.n);
    let to_light = frame.light_pos - pos;
    s.light_dist = max(length(to_light), LIGHT_D_MIN_M);
    s.l = safe_normalize(to_light, s.n);
    s.albedo = albedo;
    s.pigmented = false;
    s.thickness = max(thickness, 0.0);
    s.shadow_coord = entry_shadow_coord(pos, s.n, s.l, s.thickness);
    s.visibility = light_visible_coord(s.shadow_coord);
    s.light = frame.light_intensity * frame.light_color * s.visibility;
    s.curvature_radius = FLAT_RADIUS_M;
    s.bounce = 0.0;
    return s;
}

// Irradiance at normal incidence from the point light (inverse square).
fn irradiance(s: Surface) -> vec3<f32> {
    return s.light / (s.light_dist * s.light_dist);
}

// The same before the shadow test.
fn unshadowed_irradiance(s: Surface) -> vec3<f32> {
    return frame.light_intensity * frame.light_color / (s.light_dist * s.light_dist);
}

// The irradiance the subject returns to this point from its own lit surface (`bounce`), a
// skin of diffuse reflectance `a` throughout (its shadows on itself not counted).
fn returned_irradiance(s: Surface, a: vec3<f32>) -> vec3<f32> {
    return (a * s.bounce) * (frame.light_intensity * frame.light_color);
}

// Narkowicz's fit of the ACES filmic curve.
fn tonemap(x: vec3<f32>) -> vec3<f32> {
    let c = max(x, vec3<f32>(0.0));
    return clamp((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

// Exposure, tone mapping and (where the target is not sRGB) the sRGB encode.
fn finish(radiance: vec3<f32>) -> vec4<f32> {
    if (frame.raw_output != 0u) {
        return vec4<f32>(radiance, 1.0);
    }
    var c = tonemap(radiance * frame.exposure);
    if (frame.srgb_encode != 0u) {
        c = srgb_encode(c);
    }
    return vec4<f32>(c, 1.0);
}

// Shared by every pass: the per-frame uniform, the shading surface, light and tone mapping.

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;

struct Frame {
    view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    // xyz: point-light position (m); w: radiant intensity.
    light_pos: vec4<f32>,
    // rgb: light colour (linear).
    light_color: vec4<f32>,
    // rgb: ambient radiance (linear).
    ambient: vec4<f32>,
    // x: exposure; y: 1 when the target is not an sRGB format and we encode by hand;
    // z: 1 to write raw radiance (HDR float targets, numerical checks).
    output: vec4<f32>,
    // The key light's shadow map (core/src/render/shadow_map.rs): world → its clip space.
    shadow_view_proj: mat4x4<f32>,
    // x: 1 when a shadow map was drawn this frame (0: nothing casts, every point is lit);
    // y: normal offset (m, half a texel); z: depth bias; w: one texel in uv.
    shadow: vec4<f32>,
    // The penumbra map (core/src/render/penumbra.rs): x 1 when drawn this frame; y its grid
    // size; z the shadow map's width (m); w the depth step of an edge (depth units).
    penumbra: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
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
    // Light intensity × colour (before distance falloff).
    light: vec3<f32>,
    // Base colour (texture × factor), linear.
    albedo: vec3<f32>,
    // Material thickness through this point (m).
    thickness: f32,
    // Radius of curvature of the surface here (m); FLAT_RADIUS_M where unknown.
    curvature_radius: f32,
};

const FLAT_RADIUS_M: f32 = 1e6;

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if (len2 < 1e-24) {
        return fallback;
    }
    return v * inverseSqrt(len2);
}

// The fraction of the key light that reaches world point `p` (1: lit, 0: in shadow), from
// the shadow map: four bilinear depth comparisons half a texel apart (a 2-texel tent), the
// point moved `offset` (unit vector) by the normal offset first so a lit surface does not
// shadow itself. Outside the map's frustum nothing casts: lit.
fn light_visible(p: vec3<f32>, offset: vec3<f32>) -> f32 {
    if (frame.shadow.x < 0.5) {
        return 1.0;
    }
    let q = frame.shadow_view_proj * vec4<f32>(p + offset * frame.shadow.y, 1.0);
    if (q.w <= 0.0) {
        return 1.0;
    }
    let ndc = q.xyz / q.w;
    let uv = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 1.0;
    }
    // Beyond the far plane (a receiver behind every caster): compared at the far plane.
    let depth = min(ndc.z, 1.0) - frame.shadow.z;
    let h = 0.5 * frame.shadow.w;
    var lit = 0.0;
    lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-h, -h), depth);
    lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(h, -h), depth);
    lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-h, h), depth);
    lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(h, h), depth);
    return 0.25 * lit;
}

// Where light that leaves at a surface point entered, for the shadow test: a point lit from
// the front is tested where it is (moved off the surface along n); one lit from behind
// (translucency, the wrap past the terminator) received its light where the ray toward the
// light leaves the material, the thickness / |n·l| further along l.
fn light_visible_at(pos: vec3<f32>, n: vec3<f32>, l: vec3<f32>, thickness: f32) -> f32 {
    let nl = dot(n, l);
    if (nl >= 0.0) {
        // The offset grows as the light grazes (sin of its angle to n), where acne would.
        return light_visible(pos, n * sqrt(max(1.0 - nl * nl, 0.0)));
    }
    return light_visible(pos + l * (thickness / max(-nl, 0.05)), l);
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
    s.v = safe_normalize(frame.camera_pos.xyz - pos, s.n);
    let to_light = frame.light_pos.xyz - pos;
    s.light_dist = max(length(to_light), 1e-3);
    s.l = safe_normalize(to_light, s.n);
    s.albedo = albedo;
    s.thickness = max(thickness, 0.0);
    s.light = frame.light_pos.w * frame.light_color.rgb
        * light_visible_at(pos, s.n, s.l, s.thickness);
    s.curvature_radius = FLAT_RADIUS_M;
    return s;
}

// Irradiance at normal incidence from the point light (inverse square).
fn irradiance(s: Surface) -> vec3<f32> {
    return s.light / (s.light_dist * s.light_dist);
}

// Cloth (and whatever else is not skin: hair, eyes), the same under every shading model: a
// wrapped Lambert lobe (light wraps past the terminator as it does through fibres; the
// (1 + w)² keeps its integral that of Lambert) brightened toward grazing views by a sheen
// tinted by the fibres' colour (velvet-like), on the textured albedo.
const CLOTH_WRAP: f32 = 0.3;
const CLOTH_SHEEN: f32 = 0.5;

fn cloth_radiance(s: Surface) -> vec3<f32> {
    let wrapped = max(dot(s.n, s.l) + CLOTH_WRAP, 0.0) / ((1.0 + CLOTH_WRAP) * (1.0 + CLOTH_WRAP));
    let g = 1.0 - max(dot(s.n, s.v), 0.0);
    let brdf = INV_PI + CLOTH_SHEEN * g * g * g;
    return s.albedo * (frame.ambient.rgb + irradiance(s) * wrapped * brdf);
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
    if (frame.output.z > 0.5) {
        return vec4<f32>(radiance, 1.0);
    }
    var c = tonemap(radiance * frame.output.x);
    if (frame.output.y > 0.5) {
        c = srgb_encode(c);
    }
    return vec4<f32>(c, 1.0);
}

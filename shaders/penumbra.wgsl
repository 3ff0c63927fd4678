// The penumbra map (core/src/render/penumbra.rs): for every texel of a coarse grid over the
// key light's shadow map, the nearest edge of a caster seen from the light — where its depth
// steps back by more than a gap — and that caster's depth. A receiver reads it to know how far
// it is from the nearest shadow edge, so a model can filter its shadow by the material's
// diffusion profile (preintegrated: the edge-spread function in its LUT).
//
// Seed pass: a texel holds its own block of the shadow map when a depth step lies in it or on
// its border. Jump flooding (Rong & Tan 2006): passes with steps N/2, N/4, …, 1 each keep the
// nearest seed among nine texels a step apart.
//
// Texel: xy the seed's position (uv of the map), z the caster's depth there, w 1 (0: none).

struct Jump {
    // x: this pass's step (texels of the grid); y: grid size; z: shadow-map texels per grid
    // texel; w: the depth step that makes an edge (depth units).
    step: vec4<f32>,
};

@group(0) @binding(0) var<uniform> jump: Jump;
@group(0) @binding(1) var depth_map: texture_depth_2d;
@group(0) @binding(2) var depth_sampler: sampler;
@group(0) @binding(3) var previous: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_seed(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = jump.step.y;
    let block = jump.step.z;
    let map = size * block;
    let centre = at.xy / size;
    // Nine 2×2 gathers, two map texels apart, cover the block and a one-texel border.
    var lo = 1.0;
    var hi = 0.0;
    for (var j = -1; j <= 1; j = j + 1) {
        for (var i = -1; i <= 1; i = i + 1) {
            let d = textureGather(depth_map, depth_sampler,
                centre + vec2<f32>(f32(i), f32(j)) * (2.0 / map));
            lo = min(lo, min(min(d.x, d.y), min(d.z, d.w)));
            hi = max(hi, max(max(d.x, d.y), max(d.z, d.w)));
        }
    }
    if (hi - lo > jump.step.w) {
        return vec4<f32>(centre, lo, 1.0);
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_jump(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = i32(jump.step.y);
    let step = i32(jump.step.x);
    let here = vec2<i32>(at.xy);
    let uv = at.xy / jump.step.y;
    var best = vec4<f32>(0.0);
    var best_d2 = 1e30;
    for (var j = -1; j <= 1; j = j + 1) {
        for (var i = -1; i <= 1; i = i + 1) {
            let p = here + vec2<i32>(i, j) * step;
            if (any(p < vec2<i32>(0)) || any(p >= vec2<i32>(size))) {
                continue;
            }
            let s = textureLoad(previous, p, 0);
            let d = s.xy - uv;
            let d2 = dot(d, d);
            if (s.w > 0.5 && d2 < best_d2) {
                best = s;
                best_d2 = d2;
            }
        }
    }
    return best;
}

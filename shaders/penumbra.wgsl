// The penumbra map (core/src/render/passes/penumbra.rs): for every texel of a coarse grid over the
// key light's shadow map, the nearest edge of a caster seen from the light — where its depth
// steps back by more than a gap — and that caster's depth. A receiver reads it to know how far
// it is from the nearest shadow edge, so a model can filter its shadow by the material's
// diffusion profile (preintegrated: the edge-spread function in its LUT).
//
// Seed pass: a grid texel (8×8 map texels) is a seed when a depth step lies in its block or on
// its one-texel border. Jump flooding (Rong & Tan 2006): passes with halving steps each keep
// the nearest seed among nine texels a step apart. Loops are written out, so a static cycle
// count sees every fetch.
//
// Texel: xy the seed's position (uv of the map), z the caster's depth there, w 1 (0: none).

struct Jump {
    // This pass's step (grid texels; 0: the seed pass).
    step: f32,
    // The grid's size (texels per side).
    grid: f32,
    // Shadow-map texels per grid texel.
    block: f32,
    // The depth step that makes an edge (the map's depth units).
    edge_gap: f32,
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

// (min, max) of `r` and the 2×2 map texels around `at`.
fn widen(r: vec2<f32>, at: vec2<f32>) -> vec2<f32> {
    let d = textureGather(depth_map, depth_sampler, at);
    return vec2<f32>(min(r.x, min(min(d.x, d.y), min(d.z, d.w))),
                     max(r.y, max(max(d.x, d.y), max(d.z, d.w))));
}

@fragment
fn fs_seed(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = jump.grid;
    let centre = at.xy / size;
    // 5×5 gathers two map texels apart: the 8×8 block and a one-texel border.
    let step = vec2<f32>(2.0 / (size * jump.block));
    var r = vec2<f32>(1.0, 0.0);
    r = widen(r, centre + vec2<f32>(-2.0, -2.0) * step);
    r = widen(r, centre + vec2<f32>(-1.0, -2.0) * step);
    r = widen(r, centre + vec2<f32>(0.0, -2.0) * step);
    r = widen(r, centre + vec2<f32>(1.0, -2.0) * step);
    r = widen(r, centre + vec2<f32>(2.0, -2.0) * step);
    r = widen(r, centre + vec2<f32>(-2.0, -1.0) * step);
    r = widen(r, centre + vec2<f32>(-1.0, -1.0) * step);
    r = widen(r, centre + vec2<f32>(0.0, -1.0) * step);
    r = widen(r, centre + vec2<f32>(1.0, -1.0) * step);
    r = widen(r, centre + vec2<f32>(2.0, -1.0) * step);
    r = widen(r, centre + vec2<f32>(-2.0, 0.0) * step);
    r = widen(r, centre + vec2<f32>(-1.0, 0.0) * step);
    r = widen(r, centre + vec2<f32>(0.0, 0.0) * step);
    r = widen(r, centre + vec2<f32>(1.0, 0.0) * step);
    r = widen(r, centre + vec2<f32>(2.0, 0.0) * step);
    r = widen(r, centre + vec2<f32>(-2.0, 1.0) * step);
    r = widen(r, centre + vec2<f32>(-1.0, 1.0) * step);
    r = widen(r, centre + vec2<f32>(0.0, 1.0) * step);
    r = widen(r, centre + vec2<f32>(1.0, 1.0) * step);
    r = widen(r, centre + vec2<f32>(2.0, 1.0) * step);
    r = widen(r, centre + vec2<f32>(-2.0, 2.0) * step);
    r = widen(r, centre + vec2<f32>(-1.0, 2.0) * step);
    r = widen(r, centre + vec2<f32>(0.0, 2.0) * step);
    r = widen(r, centre + vec2<f32>(1.0, 2.0) * step);
    r = widen(r, centre + vec2<f32>(2.0, 2.0) * step);
    if (r.y - r.x > jump.edge_gap) {
        return vec4<f32>(centre, r.x, 1.0);
    }
    return vec4<f32>(0.0);
}

// `best` or the seed held at grid texel `p`, whichever is nearer to `uv`. A texel off the
// grid needs no test: an out-of-bounds load returns zero (no seed) or, where the driver
// clamps, an edge texel's real seed, whose distance is then measured like any other.
fn nearer(best: vec4<f32>, p: vec2<i32>, uv: vec2<f32>) -> vec4<f32> {
    let s = textureLoad(previous, p, 0);
    let ds = s.xy - uv;
    let db = best.xy - uv;
    if (s.w > 0.5 && (best.w < 0.5 || dot(ds, ds) < dot(db, db))) {
        return s;
    }
    return best;
}

@fragment
fn fs_jump(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let step = i32(jump.step);
    let here = vec2<i32>(at.xy);
    let uv = at.xy / jump.grid;
    var best = vec4<f32>(0.0);
    best = nearer(best, here + vec2<i32>(-1, -1) * step, uv);
    best = nearer(best, here + vec2<i32>(0, -1) * step, uv);
    best = nearer(best, here + vec2<i32>(1, -1) * step, uv);
    best = nearer(best, here + vec2<i32>(-1, 0) * step, uv);
    best = nearer(best, here + vec2<i32>(0, 0) * step, uv);
    best = nearer(best, here + vec2<i32>(1, 0) * step, uv);
    best = nearer(best, here + vec2<i32>(-1, 1) * step, uv);
    best = nearer(best, here + vec2<i32>(0, 1) * step, uv);
    best = nearer(best, here + vec2<i32>(1, 1) * step, uv);
    return best;
}

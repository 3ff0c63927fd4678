// The penumbra map (engine/src/render/passes/penumbra.rs): for every texel of a coarse grid
// over the key light's shadow map, the nearest edge of a caster seen from the light — where
// its depth steps back by more than a gap — and that caster's depth. A receiver reads it to
// know how far it is from the nearest shadow edge, so a model can filter its shadow by the
// material's diffusion profile (a LUT model: the edge-spread function in its LUT).
//
// Seed pass: a grid texel (a block of PENUMBRA_BLOCK² map texels) is a seed when a caster's
// edge lies in its block or on its one-texel border: a depth step that breaks the local slope
// by more than a gap (see `edge`); its depth is the edge's near side. Jump flooding (Rong & Tan 2006): passes with
// halving steps each keep the nearest seed among nine texels a step apart. Loops are written
// out, so a static cycle count sees every fetch.
//
// Texel: xy the seed's position (uv of the map), z the caster's depth there, w 1 (0: none).

#import consts
#import fullscreen

// One pass's constants (`PenumbraUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs).
#import PenumbraUniform

// The seed pass's strips are written out for blocks of 8 × 8 map texels: a block of another
// size in the Rust side's constant stops the composition here.
const_assert PENUMBRA_BLOCK == 8u;

@group(0) @binding(0) var<uniform> jump: PenumbraUniform;
@group(0) @binding(1) var depth_map: texture_depth_2d;
@group(0) @binding(2) var depth_sampler: sampler;
@group(0) @binding(3) var previous: texture_2d<f32>;

// `z` or, where the step b → c is a caster's edge, the depth of its near side if nearer; two
// lines at once. A step is an edge where it breaks the local slope: it differs by more than
// the gap from both of its neighbouring steps (a → b, c → e). A smooth surface turned far
// from the light has large but nearly equal steps and is no edge however steep; a silhouette
// over what lies behind it (or over nothing: the cleared depth 1) breaks the slope on both
// sides.
fn edge(z: f32, a: vec2<f32>, b: vec2<f32>, c: vec2<f32>, e: vec2<f32>) -> f32 {
    let s = c - b;
    let broken = min(abs(s - (b - a)), abs(s - (e - c))) > vec2<f32>(jump.edge_gap);
    let near = select(vec2<f32>(2.0), min(b, c), broken);
    return min(z, min(near.x, near.y));
}

// `z` and the nearest edge among the steps of a strip of 2 × 12 map texels: six gathers `at`,
// `at` + `along`, … (two texels apart), each turned by `turn` so that .w, .z are the first
// line's texels and .x, .y the second's, in order along the strip. Each line's nine middle
// steps are tested; its end texels only give the end steps their neighbours.
fn strip(z: f32, at: vec2<f32>, along: vec2<f32>, turn: bool) -> f32 {
    var g0 = textureGather(depth_map, depth_sampler, at);
    var g1 = textureGather(depth_map, depth_sampler, at + along);
    var g2 = textureGather(depth_map, depth_sampler, at + 2.0 * along);
    var g3 = textureGather(depth_map, depth_sampler, at + 3.0 * along);
    var g4 = textureGather(depth_map, depth_sampler, at + 4.0 * along);
    var g5 = textureGather(depth_map, depth_sampler, at + 5.0 * along);
    if (turn) {
        // A column strip: the left column is .w, .x and the right .z, .y of each gather.
        g0 = g0.zyxw;
        g1 = g1.zyxw;
        g2 = g2.zyxw;
        g3 = g3.zyxw;
        g4 = g4.zyxw;
        g5 = g5.zyxw;
    }
    var r = z;
    r = edge(r, g0.wx, g0.zy, g1.wx, g1.zy);
    r = edge(r, g0.zy, g1.wx, g1.zy, g2.wx);
    r = edge(r, g1.wx, g1.zy, g2.wx, g2.zy);
    r = edge(r, g1.zy, g2.wx, g2.zy, g3.wx);
    r = edge(r, g2.wx, g2.zy, g3.wx, g3.zy);
    r = edge(r, g2.zy, g3.wx, g3.zy, g4.wx);
    r = edge(r, g3.wx, g3.zy, g4.wx, g4.zy);
    r = edge(r, g3.zy, g4.wx, g4.zy, g5.wx);
    r = edge(r, g4.wx, g4.zy, g5.wx, g5.zy);
    return r;
}

@fragment
fn fs_seed(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = jump.grid;
    // The block's centre: a texel corner (block texels 0…7, the corner at 4).
    let centre = at.xy / size;
    let texel = 1.0 / (size * f32(PENUMBRA_BLOCK));
    // The 10×10 of the block and its one-texel border (texels −1…8; a step into a
    // neighbour's block seeds both), each line with one more texel at either end: five strips
    // of two rows (−1/0, 1/2, …, 7/8) along x, then five of two columns along y.
    let x = vec2<f32>(2.0 * texel, 0.0);
    let y = vec2<f32>(0.0, 2.0 * texel);
    let first = centre - 5.0 * vec2<f32>(texel);
    var z = 2.0;
    z = strip(z, vec2<f32>(first.x, centre.y - 4.0 * texel), x, false);
    z = strip(z, vec2<f32>(first.x, centre.y - 2.0 * texel), x, false);
    z = strip(z, vec2<f32>(first.x, centre.y), x, false);
    z = strip(z, vec2<f32>(first.x, centre.y + 2.0 * texel), x, false);
    z = strip(z, vec2<f32>(first.x, centre.y + 4.0 * texel), x, false);
    z = strip(z, vec2<f32>(centre.x - 4.0 * texel, first.y), y, true);
    z = strip(z, vec2<f32>(centre.x - 2.0 * texel, first.y), y, true);
    z = strip(z, vec2<f32>(centre.x, first.y), y, true);
    z = strip(z, vec2<f32>(centre.x + 2.0 * texel, first.y), y, true);
    z = strip(z, vec2<f32>(centre.x + 4.0 * texel, first.y), y, true);
    if (z <= 1.0) {
        return vec4<f32>(centre, z, 1.0);
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

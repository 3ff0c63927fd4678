// The penumbra map (engine/src/render/passes/penumbra.rs): for every texel of a coarse grid
// over the key light's shadow map, the nearest edge of a caster seen from the light — where
// its depth steps back by more than a gap — and that caster's depth. A receiver reads it to
// know how far it is from the nearest shadow edge, so a model can filter its shadow by the
// material's diffusion profile (a LUT model: the edge-spread function in its LUT).
//
// Seed pass: a grid texel (a block of PENUMBRA_BLOCK² map texels) is a seed when a caster's
// edge crosses its block's border: a depth step that breaks the local slope by more than a
// gap (see `line`) on one of the border's rows and columns (block texels −1, 0 and 7, 8: two
// pairs of neighbouring lines each way, so that 16 gathers serve them all); its depth is the
// edge's near side, its position the mean of the places where the outline crosses the inner
// line of each pair (block texels 0 and 7): on the outline's own line where it runs straight
// across the block, so a receiver's distance to the nearest seed is its distance to the
// outline (seeds at the blocks' centres, up to 4 texels off it, scalloped the penumbra). An outline that meets the block crosses its border unless it lies
// wholly inside it (a caster's image under 8 texels across, whose shadow edge then keeps
// the plain test). Jump flooding (Rong & Tan 2006): passes with halving steps each keep the nearest seed
// among nine texels a step apart. Loops are written out, so a static cycle count sees every
// fetch.
//
// Texel: xy the seed's position (uv of the map: on the outline), z the caster's depth there,
// w 1 (0: none).

#import consts
#import fullscreen

// One pass's constants (`PenumbraUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs).
#import PenumbraUniform

// The seed pass's lines are written out for blocks of 8 × 8 map texels: a block of another
// size in the Rust side's constant stops the composition here.
const_assert PENUMBRA_BLOCK == 8u;

@group(0) @binding(0) var<uniform> jump: PenumbraUniform;
@group(0) @binding(1) var depth_map: texture_depth_2d;
@group(0) @binding(2) var depth_sampler: sampler;
@group(0) @binding(3) var previous: texture_2d<f32>;

// `z` or the nearest edge on one line of ten map texels (block texels −1…8, in order): the
// depth of an edge's near side, if nearer (.x); the sum of the line's edge positions, in
// block texels along it (.y: the step between texels k − 1 and k lies at k), and their
// count (.z). A step is an edge where it breaks the local slope:
// it differs by more than the gap from both of its neighbouring steps (an end step from the
// one it has). A smooth surface turned far from the light has large but nearly equal steps
// and is no edge however steep; a silhouette over what lies behind it (or over nothing: the
// cleared depth 1) breaks the slope on both sides.
fn line(z: f32, a: vec4<f32>, b: vec4<f32>, c: vec2<f32>) -> vec3<f32> {
    let t = array<f32, 10>(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w, c.x, c.y);
    let s0 = t[1] - t[0];
    let s1 = t[2] - t[1];
    let s2 = t[3] - t[2];
    let s3 = t[4] - t[3];
    let s4 = t[5] - t[4];
    let s5 = t[6] - t[5];
    let s6 = t[7] - t[6];
    let s7 = t[8] - t[7];
    let s8 = t[9] - t[8];
    // How far each step's slope breaks from the one before.
    let d1 = abs(s1 - s0);
    let d2 = abs(s2 - s1);
    let d3 = abs(s3 - s2);
    let d4 = abs(s4 - s3);
    let d5 = abs(s5 - s4);
    let d6 = abs(s6 - s5);
    let d7 = abs(s7 - s6);
    let d8 = abs(s8 - s7);
    let gap = jump.edge_gap;
    var r = z;
    var at = 0.0;
    var n = 0.0;
    let e0 = d1 > gap;
    r = min(r, select(2.0, min(t[0], t[1]), e0));
    n += select(0.0, 1.0, e0);
    let e1 = min(d1, d2) > gap;
    r = min(r, select(2.0, min(t[1], t[2]), e1));
    at += select(0.0, 1.0, e1);
    n += select(0.0, 1.0, e1);
    let e2 = min(d2, d3) > gap;
    r = min(r, select(2.0, min(t[2], t[3]), e2));
    at += select(0.0, 2.0, e2);
    n += select(0.0, 1.0, e2);
    let e3 = min(d3, d4) > gap;
    r = min(r, select(2.0, min(t[3], t[4]), e3));
    at += select(0.0, 3.0, e3);
    n += select(0.0, 1.0, e3);
    let e4 = min(d4, d5) > gap;
    r = min(r, select(2.0, min(t[4], t[5]), e4));
    at += select(0.0, 4.0, e4);
    n += select(0.0, 1.0, e4);
    let e5 = min(d5, d6) > gap;
    r = min(r, select(2.0, min(t[5], t[6]), e5));
    at += select(0.0, 5.0, e5);
    n += select(0.0, 1.0, e5);
    let e6 = min(d6, d7) > gap;
    r = min(r, select(2.0, min(t[6], t[7]), e6));
    at += select(0.0, 6.0, e6);
    n += select(0.0, 1.0, e6);
    let e7 = min(d7, d8) > gap;
    r = min(r, select(2.0, min(t[7], t[8]), e7));
    at += select(0.0, 7.0, e7);
    n += select(0.0, 1.0, e7);
    let e8 = d8 > gap;
    r = min(r, select(2.0, min(t[8], t[9]), e8));
    at += select(0.0, 8.0, e8);
    n += select(0.0, 1.0, e8);
    return vec3<f32>(r, at, n);
}

// The edges found so far: the nearest depth (x), the sum of the inner lines' edge positions
// in block texels (yz) and their count (w). Each pair of lines is one outer (block texel −1
// or 8: the depth only) and one inner (0 or 7: its positions too; an edge crosses both).
// Rows `up` (.w .z of each gather, a gather two texels across) and `down` (.x .y) as lines;
// the inner one `up` where `inner_up`, at block row centre `y`.
fn rows(acc: vec4<f32>, y: f32, inner_up: bool, g0: vec4<f32>, g1: vec4<f32>, g2: vec4<f32>, g3: vec4<f32>, g4: vec4<f32>) -> vec4<f32> {
    let up = line(acc.x, vec4<f32>(g0.wz, g1.wz), vec4<f32>(g2.wz, g3.wz), g4.wz);
    let down = line(up.x, vec4<f32>(g0.xy, g1.xy), vec4<f32>(g2.xy, g3.xy), g4.xy);
    let inner = select(down, up, inner_up);
    return vec4<f32>(down.x, acc.y + inner.y, acc.z + inner.z * y, acc.w + inner.z);
}

// Columns (.w .x of each gather, a gather two texels down, and .z .y) as lines; the inner one
// `left` where `inner_left`, at block column centre `x`.
fn columns(acc: vec4<f32>, x: f32, inner_left: bool, g0: vec4<f32>, g1: vec4<f32>, g2: vec4<f32>, g3: vec4<f32>, g4: vec4<f32>) -> vec4<f32> {
    let left = line(acc.x, vec4<f32>(g0.wx, g1.wx), vec4<f32>(g2.wx, g3.wx), g4.wx);
    let right = line(left.x, vec4<f32>(g0.zy, g1.zy), vec4<f32>(g2.zy, g3.zy), g4.zy);
    let inner = select(right, left, inner_left);
    return vec4<f32>(right.x, acc.y + inner.z * x, acc.z + inner.y, acc.w + inner.z);
}

@fragment
fn fs_seed(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = jump.grid;
    // The block's centre: a texel corner (block texels 0…7, the corner at 4).
    let centre = at.xy / size;
    let texel = 1.0 / (size * f32(PENUMBRA_BLOCK));
    // A gather at the corner o + (2i, 2j) texels holds block texels 2i − 1, 2i across and
    // 2j − 1, 2j down (.w .z the upper pair, .x .y the lower). Lines over the block and its
    // one-texel border (texels −1…8; a step into a neighbour's block seeds both): the rows
    // −1, 0, 7, 8 and the same columns, two gathers' pairs each way.
    let o = centre - 4.0 * vec2<f32>(texel);
    let g = array<vec2<f32>, 5>(o, o + vec2<f32>(2.0 * texel), o + vec2<f32>(4.0 * texel),
                                o + vec2<f32>(6.0 * texel), o + vec2<f32>(8.0 * texel));
    var z = vec4<f32>(2.0, 0.0, 0.0, 0.0);
    z = rows(z, 0.5, false, textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[1].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[2].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[3].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[0].y)));
    z = rows(z, 7.5, true, textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[4].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[1].x, g[4].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[2].x, g[4].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[3].x, g[4].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[4].y)));
    z = columns(z, 0.5, false, textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[1].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[2].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[3].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[0].x, g[4].y)));
    z = columns(z, 7.5, true, textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[0].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[1].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[2].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[3].y)),
        textureGather(depth_map, depth_sampler, vec2<f32>(g[4].x, g[4].y)));
    if (z.x <= 1.0) {
        // The edges' mean position: on the edge's line where it is straight across the block.
        // (An outline across a corner may meet the outer lines only: the block's centre.)
        let mean = select(vec2<f32>(4.0), z.yz / max(z.w, 1.0), z.w > 0.5);
        return vec4<f32>(o + mean * texel, z.x, 1.0);
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

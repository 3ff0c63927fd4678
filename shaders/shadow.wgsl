// Blob (contact) shadows: one instanced draw of ground quads, one per caster, each darkening
// the ground under it with a soft rounded-box falloff computed here (no texture). Multiply
// blended on colour; alpha (the subsurface pass's marker) and the spread target are
// write-masked off by the pipeline, so nothing but the ground's colour changes.
#import common

struct BlobIn {
    // xyz: the footprint's centre on the (lifted) ground; w: darkness at the centre (0..1).
    @location(0) centre: vec4<f32>,
    // xy: the footprint's local x axis in world xz (unit); zw: half extents of its core box (m).
    @location(1) axes: vec4<f32>,
    // x: corner radius around the core box (m); y: width of the soft edge (m).
    @location(2) shape: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // The position in the footprint's frame (m).
    @location(0) local: vec2<f32>,
    @location(1) @interpolate(flat) half_size: vec2<f32>,
    @location(2) @interpolate(flat) shape: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, b: BlobIn) -> VertexOut {
    // Two triangles covering the footprint plus its rounding and soft edge.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let extent = b.axes.zw + vec2<f32>(b.shape.x + b.shape.y);
    let local = corners[vi] * extent;
    let ax = b.axes.xy;
    let xz = b.centre.xz + local.x * ax + local.y * vec2<f32>(-ax.y, ax.x);
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(xz.x, b.centre.y, xz.y, 1.0);
    out.local = local;
    out.half_size = b.axes.zw;
    out.shape = vec3<f32>(b.shape.x, b.shape.y, b.centre.w);
    return out;
}

// 1 − darkness: the factor the ground's colour is multiplied by.
fn blob_factor(in: VertexOut) -> f32 {
    // Signed distance to the rounded footprint (negative inside).
    let q = abs(in.local) - in.half_size;
    let d = length(max(q, vec2<f32>(0.0))) + min(max(q.x, q.y), 0.0) - in.shape.x;
    let soft = max(in.shape.y, 1e-3);
    // Full darkness a soft width inside the edge, none a soft width outside.
    let t = 1.0 - smoothstep(-soft, soft, d);
    return 1.0 - in.shape.z * t;
}

#ifdef SCREEN_SPACE
#import split_out

// In a frame with the subsurface pass: the spread irradiance and the exit factor are
// write-masked off (they stay as the scene wrote them).
@fragment
fn fs_main(in: VertexOut) -> SplitOut {
    var out: SplitOut;
    // This target holds radiance before the tone map, whose toe is steeper than linear
    // (about x^1.4 at the ground's level): k^0.7 here darkens the displayed ground as k does
    // after the tone map in the one-pass frame, so the blob does not change when the
    // governor moves between a screen-space and a one-pass model.
    out.colour = vec4<f32>(vec3<f32>(pow(blob_factor(in), 0.7)), 1.0);
    out.spread = vec4<f32>(1.0);
    out.exit = vec4<f32>(1.0);
    return out;
}
#else
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(vec3<f32>(blob_factor(in)), 1.0);
}
#endif

// The UI: textured, vertex-coloured quads in pixel coordinates, drawn from the skin atlas.
// The atlas holds straight-alpha sRGB-encoded texels; vertex colours are premultiplied
// display values. The result is premultiplied alpha (blend One, OneMinusSrcAlpha); when the
// target is an sRGB format (`params.screen.z == 1`) it is decoded to linear so the hardware's
// re-encode gives back the authored colours.

// Its constants (`UiUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs).
#import UiUniform

@group(0) @binding(0) var<uniform> params: UiUniform;
@group(0) @binding(1) var atlas: texture_2d<f32>;
@group(0) @binding(2) var atlas_sampler: sampler;

struct VertexIn {
    @location(0) position: vec2<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) color: vec4<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let ndc = v.position / params.screen.xy * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0);
    out.clip = vec4<f32>(ndc, 0.0, 1.0);
    out.uv = v.uv;
    out.color = v.color;
    return out;
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + vec3<f32>(0.055)) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let t = textureSample(atlas, atlas_sampler, in.uv);
    var c = vec4<f32>(t.rgb * t.a, t.a) * in.color;
    if (params.screen.z > 0.5 && c.a > 0.0) {
        c = vec4<f32>(srgb_to_linear(c.rgb / c.a) * c.a, c.a);
    }
    return c;
}

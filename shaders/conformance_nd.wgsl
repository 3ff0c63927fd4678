// GPU conformance harness, nondimensional kernel (driver: measure/src/conformance/harness.rs).
// Not a composer module: appended, with a per-function `nd_probe`, to the composition of one
// `*_nd` module (or `fresnel`) as the renderer imports it, in f32, or with flag REAL_F16
// after `enable f16;` so the very same functions run in half precision. Inputs are 8 f32 per
// item (converted to `real` by nd_probe), the output one vec4<f32>.

@group(0) @binding(0) var<storage, read> nd_in: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> nd_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn conformance_nd(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&nd_out)) {
        return;
    }
    nd_out[i] = nd_probe(nd_in[2u * i], nd_in[2u * i + 1u]);
}

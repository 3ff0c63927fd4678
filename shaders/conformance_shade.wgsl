// GPU conformance harness, f32 kernel (driver: measure/src/conformance/harness.rs).
// Not a shared composer module: the harness composes it after `shading_model` with the
// model's flags, i.e. exactly the model code the renderer's character pipeline composes (same
// alias, same flags), and a per-model `conformance_probe`, with the Frame uniform at
// @group(0) and ModelParams at @group(1) bound as in the renderer.
// Each item builds a Surface the way make_surface does (light distance ≥ 1 mm, thickness ≥ 0)
// and writes shade(s) and the model's sub-function probe.

// One item (`ConformanceInput`, generated from its Rust declaration in the harness).
#import ConformanceInput

@group(2) @binding(0) var<storage, read> conformance_in: array<ConformanceInput>;
@group(2) @binding(1) var<storage, read_write> conformance_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn conformance_shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&conformance_in)) {
        return;
    }
    let x = conformance_in[i];
    var s: Surface;
    s.pos = vec3<f32>(0.0);
    s.n = x.n.xyz;
    s.t = x.t.xyz;
    s.b = x.b.xyz;
    s.v = x.v.xyz;
    s.l = x.l.xyz;
    s.light_dist = max(x.light.w, LIGHT_D_MIN_M);
    s.light = x.light.rgb;
    s.visibility = 1.0;
    s.shadow_coord = vec4<f32>(0.0);
    s.albedo = x.albedo.rgb;
    // The f64 references shade the medium itself (no pigment).
    s.pigmented = false;
    s.thickness = max(x.albedo.w, 0.0);
    s.curvature_radius = FLAT_RADIUS_M;
    // No light returned by a subject (the f64 twins model one point).
    s.bounce = 0.0;
    conformance_out[2u * i] = vec4<f32>(shade(s), 0.0);
    conformance_out[2u * i + 1u] = vec4<f32>(conformance_probe(s, x.probe.x), 0.0);
}

// The key light's shadow map (engine/src/render/passes/shadow_map.rs): casters drawn
// depth-only from the light. The skinned character through its joint palette; a measurement
// scene's occluder as world-space triangles.
#import skinning

// Its constants (`CasterUniform`, generated from its Rust declaration in
// engine/src/shader/uniforms.rs).
#import CasterUniform

@group(0) @binding(0) var<uniform> caster: CasterUniform;

struct SkinnedIn {
    @location(0) position: vec3<f32>,
    @location(4) joints: vec4<u32>,
    @location(5) weights: vec4<f32>,
};

@vertex
fn vs_skinned(v: SkinnedIn) -> @builtin(position) vec4<f32> {
    return caster.view_proj * (skin_matrix(v.joints, v.weights) * vec4<f32>(v.position, 1.0));
}

@vertex
fn vs_occluder(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return caster.view_proj * vec4<f32>(position, 1.0);
}

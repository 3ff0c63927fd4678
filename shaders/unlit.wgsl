// Baseline for cost ratios: the texture colour on the skin, no lighting (the cloth, as under
// every model, gets the cloth BRDF of common.wgsl).
#import common

struct ModelParams {
    unused: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

fn shade(s: Surface) -> vec3<f32> {
    return s.albedo;
}

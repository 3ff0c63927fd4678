// Baseline for cost ratios: the skin's albedo, no lighting.
#import common

struct ModelParams {
    unused: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

fn shade(s: Surface) -> vec3<f32> {
    return s.albedo;
}

// Baseline for cost ratios: the skin's albedo, no lighting (it reads no model uniform).
#import common

fn shade(s: Surface) -> vec3<f32> {
    return s.albedo;
}

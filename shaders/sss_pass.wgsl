// The screen-space subsurface pass (Burley-style disk sampling with exact ring masses): it
// exists only while the character's model is a spatial one. Each skin pixel gathers the
// irradiance its neighbours received, ring by ring: a ring [r_k, r_k+1) of the diffusion
// profile carries the power fraction mass_k (the profile's exact integral over the ring, per
// channel) and is sampled in `angles` directions at one radius drawn per pixel and ring with
// density ∝ r inside the ring (the profile is piecewise constant per ring, so the estimate
// is unbiased; a fixed radius aliases a narrow irradiance peak into rings), the directions
// turned per pixel and by the golden angle from ring to ring. Radii are in mm on the surface, mapped to pixels with each pixel's
// own size in mm (written by the character pass). A sample that is off screen, not skin, or
// at another depth (its pixel size differs by more than `depth_tolerance`) counts as the
// centre pixel: energy stays where the surface is. Output: radiance that stayed + exit ·
// exitance (the exit factor per channel, from its own target: the pigment's way out), then
// exposure, tone mapping and encoding as every other pass.
// Driver: engine/src/render/passes/subsurface.rs.
#import common
#import consts
#import fullscreen

// The kernel (`KernelUniform`, generated from its Rust declaration in
// engine/src/shading/subsurface.rs): one ring per `Ring`, its mass per channel and its outer
// radius (mm); ring k starts where ring k − 1 ends, ring 0 at the centre's radius.
#import KernelUniform

@group(1) @binding(0) var<uniform> kernel: KernelUniform;
@group(1) @binding(1) var colour_tex: texture_2d<f32>;
@group(1) @binding(2) var spread_tex: texture_2d<f32>;
@group(1) @binding(3) var spread_sampler: sampler;
// The exit factor per channel (pigment included): what turns the gathered exitance into
// radiance toward the viewer.
@group(1) @binding(4) var exit_tex: texture_2d<f32>;

fn frame_background() -> vec4<f32> {
    return kernel.background;
}

const GOLDEN_ANGLE: f32 = 2.39996322972865;

// A per-pixel, per-ring number in [0, 1) (a 2D integer hash).
fn hash(p: vec2<u32>, k: u32) -> f32 {
    var h = p.x * 1664525u + p.y * 1013904223u + k * 2654435769u;
    h = (h ^ (h >> 16u)) * 2246822519u;
    h = (h ^ (h >> 13u)) * 3266489917u;
    h = h ^ (h >> 16u);
    return f32(h >> 8u) / 16777216.0;
}

@fragment
fn fs_main(@builtin(position) clip: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(spread_tex));
    let p = vec2<i32>(clip.xy);
    let colour = textureLoad(colour_tex, p, 0);
    let centre = textureLoad(spread_tex, p, 0);
    if (colour.a < -0.99) {
        return frame_background();
    }
    if (colour.a <= 0.0 || centre.a <= 0.0) {
        return finish(colour.rgb);
    }
    let px_per_mm = 1.0 / centre.a;
    let rings = min(kernel.ring_count, MAX_RINGS);
    let angles = max(kernel.angles, 1u);
    let step = 2.0 * PI / f32(angles);
    var m = kernel.centre_mass * centre.rgb;
    var inner = kernel.centre_radius_mm;
    let pixel = vec2<u32>(p);
    let turn = hash(pixel, 0u) * step;
    for (var k = 0u; k < rings; k = k + 1u) {
        let ring = kernel.rings[k];
        let outer = ring.outer_mm;
        let u = hash(pixel, k + 1u);
        let r_mm = sqrt(inner * inner + u * (outer * outer - inner * inner));
        inner = outer;
        let r_px = r_mm * px_per_mm;
        if (r_px < 0.5) {
            m = m + ring.mass * centre.rgb;
            continue;
        }
        var sum = vec3<f32>(0.0);
        for (var j = 0u; j < angles; j = j + 1u) {
            let a = turn + f32(k) * GOLDEN_ANGLE + f32(j) * step;
            let at = clip.xy + r_px * vec2<f32>(cos(a), sin(a));
            var e = centre.rgb;
            if (all(at >= vec2<f32>(0.0)) && all(at < size)) {
                let s = textureSampleLevel(spread_tex, spread_sampler, at / size, 0.0);
                if (s.a > 0.0 && abs(s.a - centre.a) <= kernel.depth_tolerance * centre.a) {
                    e = s.rgb;
                }
            }
            sum = sum + e;
        }
        m = m + ring.mass * sum / f32(angles);
    }
    return finish(colour.rgb + textureLoad(exit_tex, p, 0).rgb * m);
}

// Mobile tier: pre-integrated skin (Penner & Borshukov 2011). The material's measured
// diffusion profile is integrated once over spheres of every radius under a directional light
// (core/src/shading/preintegrated.rs) into a LUT over (n·l, curvature); per pixel one fetch
// per channel, no pass. A point light's irradiance is blurred by lifting the light by the
// kernel's Poisson height (the Poisson kernel is its own semigroup: blurring the irradiance of
// a light at height h with a Poisson kernel of height s gives the light at height h + s).
#import common
#import subsurface

@group(1) @binding(1) var lut: texture_2d<f32>;
@group(1) @binding(2) var lut_sampler: sampler;

// Exitance per unit irradiance of the lifted light, per channel.
fn lifted_response(s: Surface, lift_mm: f32, v: f32, channel: u32) -> f32 {
    // Height of the light over the tangent plane and its distance (mm).
    let d = s.light_dist * 1000.0;
    let h = dot(s.n, s.l) * d;
    let hl = h + lift_mm;
    let d2 = d * d + 2.0 * h * lift_mm + lift_mm * lift_mm;
    let mu = clamp(hl * inverseSqrt(max(d2, 1e-12)), -1.0, 1.0);
    // The LUT holds M/E_beam over (n·l, curvature): u = (n·l + 1)/2.
    let m = textureSampleLevel(lut, lut_sampler, vec2<f32>(0.5 * (mu + 1.0), v), 0.0);
    // Irradiance scale of the lifted light relative to the real one (normal incidence).
    let scale = (d * d) / max(d2, 1e-12);
    return m[channel] * scale;
}

fn shade(s: Surface) -> vec3<f32> {
    let exit = sss_exit(s);
    // Curvature axis: v = R0 / (R0 + ρ).
    let rho_mm = s.curvature_radius * 1000.0;
    let v = model.misc.w / (model.misc.w + rho_mm);
    let e = irradiance(s);
    let response = vec3<f32>(
        lifted_response(s, model.lift.r, v, 0u),
        lifted_response(s, model.lift.g, v, 1u),
        lifted_response(s, model.lift.b, v, 2u),
    );
    let ambient = PI * frame.ambient.rgb * model.albedo.rgb;
    return exit * (ambient + e * response + sss_translucency(s));
}

// A fourth model: transport-exact albedo with a normalised-diffusion wrap over curvature.
// Profile R(r) = A k (e^{-kr} + e^{-kr/3}) / (8π r). CPU: core/src/shading/burley.rs.
#import common
#import fresnel
#import burley_nd

struct ModelParams {
    // rgb: surface albedo A (transport solution); w: η.
    albedo: vec4<f32>,
    // rgb: k = s/ℓ (mm⁻¹); w: mm of r per metre of light distance.
    k: vec4<f32>,
    // x: unused, y: r_min (mm), z: minimum light distance (m), w: wrap strength.
    misc: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

// R(r) in mm⁻², r in mm.
fn burley_profile(r_mm: f32) -> vec3<f32> {
    let r = max(r_mm, model.misc.y);
    // R = k² · R̃(k r) (burley_nd.wgsl).
    let k = model.k.rgb;
    return k * k * burley_rd_nd(k * r, model.albedo.rgb);
}

// Exitance of a locally flat medium under irradiance E is F_t(θ_i) A E (the profile
// integrates to A); across a curved surface the light that diffuses a distance ~1/k wraps
// around the terminator by w = 1/(k ρ) per channel (ρ the radius of curvature), with the
// energy-normalised wrap (n·l + w)/(1 + w)². On flat ground w → 0 and the local result is exact.
fn shade(s: Surface) -> vec3<f32> {
    let eta = model.albedo.w;
    let nl = dot(s.n, s.l);
    let rho_mm = s.curvature_radius * 1000.0;
    let w = min(vec3<f32>(1.0) / max(model.k.rgb * rho_mm, vec3<f32>(1e-6)), vec3<f32>(1.0)) * model.misc.w;
    let wrapped = max(vec3<f32>(nl) + w, vec3<f32>(0.0)) / ((1.0 + w) * (1.0 + w));
    let ft = fresnel_transmittance(eta, max(nl, 0.25));
    let direct = irradiance(s) * INV_PI * ft * model.albedo.rgb * wrapped;
    return frame.ambient.rgb * model.albedo.rgb + direct;
}

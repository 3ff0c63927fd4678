// Christensen–Burley normalised diffusion in the paper's scaled set-up: a fourth model.
// R(r) = A k (e^{-kr} + e^{-kr/3}) / (8π r). CPU: core/src/shading/burley.rs.
#import common
#import fresnel
#import burley_nd

struct ModelParams {
    // rgb: surface albedo A (transport solution); w: η.
    albedo: vec4<f32>,
    // rgb: k = s/ℓ (mm⁻¹); w: mm of r per metre of light distance.
    k: vec4<f32>,
    // x: area (mm²), y: r_min (mm), z: minimum light distance (m).
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

fn shade(s: Surface) -> vec3<f32> {
    let r = max(s.light_dist, model.misc.z) * model.k.w;
    let eta = model.albedo.w;
    let ft = fresnel_transmittance(eta, dot(s.n, s.l)) * fresnel_transmittance(eta, dot(s.n, s.v));
    let direct = s.light * burley_profile(r) * (ft * INV_PI * model.misc.x);
    return frame.ambient.rgb * model.albedo.rgb + direct;
}

// The paper's scaled BSSRDF (§3.2, eq. 2–4): Jensen's dipole R_d(r) with r the scaled distance
// to the light, S_d = F_t(ω_i) R_d(r) F_t(ω_o) / π. The dipole uses a grey texture (§4.1).
// CPU: core/src/shading/dipole.rs.
#import common
#import fresnel
#import dipole_nd

struct ModelParams {
    // rgb: σ_tr (mm⁻¹); w: η.
    sigma_tr: vec4<f32>,
    // rgb: z_r (mm); w: mm of r per metre of light distance.
    z_r: vec4<f32>,
    // rgb: z_v (mm); w: area (mm²) turning R_d into a reflectance.
    z_v: vec4<f32>,
    // rgb: α'; w: minimum light distance (m).
    albedo: vec4<f32>,
    // rgb: total diffuse reflectance R_d (ambient term).
    total: vec4<f32>,
    // rgb: σ'_t = 1/ℓ (mm⁻¹).
    sigma_t: vec4<f32>,
    // rgb: σ_tr ℓ = √(3σ_a/σ'_t); w: z_v/ℓ = 1 + 4A/3 (standard form's nondimensional inputs).
    nd: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

// R_d(r) in mm⁻², r in mm.
fn dipole_profile(r: f32) -> vec3<f32> {
#ifdef DIPOLE_PRINTED
    let s = model.sigma_tr.rgb;
    let zr = model.z_r.rgb;
    let zv = model.z_v.rgb;
    let dr = sqrt(zr * zr + r * r);
    let dv = sqrt(zv * zv + r * r);
    // Eq. 3 as printed: both terms divided by σ'_t; the virtual one also keeps z_v.
    let real = (s * dr + 1.0) * exp(-s * dr) / (model.sigma_t.rgb * dr * dr * dr);
    let virt = zv * (s * dv + 1.0) * exp(-s * dv) / (model.sigma_t.rgb * dv * dv * dv);
    return model.albedo.rgb * (0.25 * INV_PI) * (real + virt);
#else
    // Standard form in units of ℓ = 1/σ'_t (dipole_nd.wgsl): R_d = σ'_t² · R̃_d(σ'_t r).
    let t = model.sigma_t.rgb;
    return t * t * dipole_rd_nd(t * r, model.nd.rgb, model.nd.w, model.albedo.rgb);
#endif
}

fn shade(s: Surface) -> vec3<f32> {
    let r = max(s.light_dist, model.albedo.w) * model.z_r.w;
    let eta = model.sigma_tr.w;
    let ft = fresnel_transmittance(eta, dot(s.n, s.l)) * fresnel_transmittance(eta, dot(s.n, s.v));
    let direct = s.light * dipole_profile(r) * (ft * INV_PI * model.z_v.w);
    return frame.ambient.rgb * model.total.rgb + direct;
}

// The paper's scaled BSSRDF (§3.2, eq. 2–4): Jensen's dipole R_d(r) with r the scaled distance
// to the light, S_d = F_t(ω_i) R_d(r) F_t(ω_o) / π. The dipole uses a grey texture (§4.1).
// CPU: engine/src/shading/dipole.rs.
#import common
#import fresnel
#import dipole_nd

// `DipoleUniform`, generated from its Rust declaration (engine/src/shading/dipole.rs).
#import DipoleUniform

@group(1) @binding(0) var<uniform> model: DipoleUniform;

// R_d(r) in mm⁻², r in mm.
fn dipole_profile(r: f32) -> vec3<f32> {
#ifdef DIPOLE_PRINTED
    let s = model.sigma_tr;
    let zr = model.z_r;
    let zv = model.z_v;
    let dr = sqrt(zr * zr + r * r);
    let dv = sqrt(zv * zv + r * r);
    // Eq. 3 as printed: both terms divided by σ'_t; the virtual one also keeps z_v.
    let real = (s * dr + 1.0) * exp(-s * dr) / (model.sigma_t_prime * dr * dr * dr);
    let virt = zv * (s * dv + 1.0) * exp(-s * dv) / (model.sigma_t_prime * dv * dv * dv);
    return model.albedo * (0.25 * INV_PI) * (real + virt);
#else
    // Standard form in units of ℓ = 1/σ'_t (dipole_nd.wgsl): R_d = σ'_t² · R̃_d(σ'_t r).
    let t = model.sigma_t_prime;
    return t * t * dipole_rd_nd(t * r, model.s_nd, model.zv_nd, model.albedo);
#endif
}

fn shade(s: Surface) -> vec3<f32> {
    let r = max(s.light_dist, model.light_d_min_m) * model.r_mm_per_m;
    let eta = model.eta;
    let ft = fresnel_transmittance(eta, dot(s.n, s.l)) * fresnel_transmittance(eta, dot(s.n, s.v));
    let direct = s.light * dipole_profile(r) * (ft * INV_PI * model.area_mm2);
    return frame.ambient * model.total + direct;
}

// The authors' OSS colour model (§3.3, eq. 5–6). CPU: engine/src/shading/oss.rs.
// As printed (`oss`): f_d is a cubic in the depth d (mm) with material-only coefficients
// precomputed on the CPU. `oss-stable` (flag OSS_STABLE): positive, bounded terms.
#import common
#import ward_lobe
#import oss_nd

// `OssUniform`, generated from its Rust declaration (engine/src/shading/oss.rs).
#import OssUniform

@group(1) @binding(0) var<uniform> model: OssUniform;

fn oss_colour(d: f32) -> vec3<f32> {
#ifdef OSS_STABLE
    // On the optical depths σ_a d and σ'_s P d (oss_nd.wgsl).
    return oss_fd_stable_nd(model.sigma_a * d, model.sp * d, model.fdr);
#else
    return model.c0 + d * (model.c1 + d * (model.c2 + d * model.c3));
#endif
}

fn shade(s: Surface) -> vec3<f32> {
    let fd = oss_colour(s.thickness * model.depth_mm_per_m);
    let tex = select(vec3<f32>(1.0), s.albedo, model.textured > 0.5);
    let nl = max(dot(s.n, s.l), 0.0);
    let dl = max(s.light_dist, model.light_d_min_m);
    // Eq. 6: f_d (ρ_d cos θ + 20 ρ_ts / d^2.5). The translucency term is its own fall-off
    // with the light distance d: it scales the light's intensity, not the inverse-square
    // irradiance (which would make it d^-4.5).
    let translucency = 20.0 * model.rho_ts / pow(dl, 2.5) * s.light;
    let e0 = irradiance(s);
    let diffuse = fd * tex * (model.rho_d * nl * e0 + translucency) * INV_PI;
    let specular = e0 * nl * ward_specular(s, model.rho_s, model.alpha_x, model.alpha_y);
    let ambient = frame.ambient * fd * tex * model.rho_d;
    // As printed f_d can be negative (thick layers): radiance is clamped at 0.
    return max(ambient + diffuse + vec3<f32>(specular), vec3<f32>(0.0));
}

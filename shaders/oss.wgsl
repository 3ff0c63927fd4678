// The authors' OSS colour model (§3.3, eq. 5–6). CPU: core/src/shading/oss.rs.
// As printed (`oss`): f_d is a cubic in the depth d (mm) with material-only coefficients
// precomputed on the CPU. `oss-stable` (flag OSS_STABLE): positive, bounded terms.
#import common
#import ward_lobe
#import oss_nd

struct ModelParams {
    // f_d = c0 + c1 d + c2 d² + c3 d³ per channel; c0.w: mm of depth per metre of thickness.
    c0: vec4<f32>,
    c1: vec4<f32>,
    c2: vec4<f32>,
    c3: vec4<f32>,
    // x: ρ_d, y: ρ_ts, z: minimum light distance (m) for d^-2.5, w: textured flag.
    misc: vec4<f32>,
    // x: ρ_s, y: α_x, z: α_y.
    lobe: vec4<f32>,
    // rgb: σ_a (mm⁻¹); w: F_dr(η). Stable form only.
    sigma_a: vec4<f32>,
    // rgb: σ'_s P(g) (mm⁻¹). Stable form only.
    sp: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

fn oss_colour(d: f32) -> vec3<f32> {
#ifdef OSS_STABLE
    // On the optical depths σ_a d and σ'_s P d (oss_nd.wgsl).
    return oss_fd_stable_nd(model.sigma_a.rgb * d, model.sp.rgb * d, model.sigma_a.w);
#else
    return model.c0.rgb + d * (model.c1.rgb + d * (model.c2.rgb + d * model.c3.rgb));
#endif
}

fn shade(s: Surface) -> vec3<f32> {
    let fd = oss_colour(s.thickness * model.c0.w);
    let tex = select(vec3<f32>(1.0), s.albedo, model.misc.w > 0.5);
    let nl = max(dot(s.n, s.l), 0.0);
    let dl = max(s.light_dist, model.misc.z);
    // Eq. 6: f_d (ρ_d cos θ + 20 ρ_ts / d^2.5). The translucency term is its own fall-off
    // with the light distance d: it scales the light's intensity, not the inverse-square
    // irradiance (which would make it d^-4.5).
    let translucency = 20.0 * model.misc.y / pow(dl, 2.5) * s.light;
    let e0 = irradiance(s);
    let diffuse = fd * tex * (model.misc.x * nl * e0 + translucency) * INV_PI;
    let specular = e0 * nl * ward_specular(s, model.lobe.x, model.lobe.y, model.lobe.z);
    let ambient = frame.ambient.rgb * fd * tex * model.misc.x;
    // As printed f_d can be negative (thick layers): radiance is clamped at 0.
    return max(ambient + diffuse + vec3<f32>(specular), vec3<f32>(0.0));
}

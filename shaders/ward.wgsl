// Ward anisotropic BRDF (paper eq. 1; Walter 2005 standard form). CPU: engine/src/shading/ward.rs.
// Diffuse colour = the dipole's total diffuse reflectance R_d(α') × texture (§4.1).
#import common
#import ward_lobe

// `WardUniform`, generated from its Rust declaration (engine/src/shading/ward.rs).
#import WardUniform

@group(1) @binding(0) var<uniform> model: WardUniform;

fn shade(s: Surface) -> vec3<f32> {
    let tex = select(vec3<f32>(1.0), s.albedo, model.textured > 0.5);
    let kd = model.rho_d * tex;
    let ambient = frame.ambient * kd * model.slider_ambient;
    let nl = dot(s.n, s.l);
    if (nl <= 0.0) {
        return ambient;
    }
    let spec = ward_specular(s, model.rho_s, model.alpha_x, model.alpha_y);
    return ambient + irradiance(s) * nl * (kd * INV_PI * model.slider_diffuse + vec3<f32>(spec * model.slider_specular));
}

// Ward anisotropic BRDF (paper eq. 1; Walter 2005 standard form). CPU: core/src/shading/ward.rs.
// Diffuse colour = the dipole's total diffuse reflectance R_d(α') × texture (§4.1).
#import common
#import ward_lobe

struct ModelParams {
    // rgb: R_d(α'); w: 1 when the texture tints the diffuse colour.
    rho_d: vec4<f32>,
    // x: ρ_s, y: α_x, z: α_y.
    lobe: vec4<f32>,
    // The paper's sliders: x diffuse, y ambient, z specular.
    sliders: vec4<f32>,
};

@group(1) @binding(0) var<uniform> model: ModelParams;

fn shade(s: Surface) -> vec3<f32> {
    let tex = select(vec3<f32>(1.0), s.albedo, model.rho_d.w > 0.5);
    let kd = model.rho_d.rgb * tex;
    let ambient = frame.ambient.rgb * kd * model.sliders.y;
    let nl = dot(s.n, s.l);
    if (nl <= 0.0) {
        return ambient;
    }
    let spec = ward_specular(s, model.lobe.x, model.lobe.y, model.lobe.z);
    return ambient + irradiance(s) * nl * (kd * INV_PI * model.sliders.x + vec3<f32>(spec * model.sliders.z));
}

// The standard glTF material's lighting, shared by the props and a character's non-skin
// parts: metallic-roughness with a GGX distribution, Smith's height-correlated visibility and
// Schlick's Fresnel for the specular lobe, Lambert for the diffuse part of a dielectric; the
// key light (its shadow in `s.light`) and the ambient radiance (occluded; its specular part
// approximated by F0, there being no environment map).
#import common

fn pbr_radiance(s: Surface, base: vec3<f32>, metallic: f32, roughness: f32, occlusion: f32) -> vec3<f32> {
    let f0 = mix(vec3<f32>(0.04), base, metallic);
    let diffuse_colour = base * (1.0 - metallic);
    let ambient = frame.ambient * occlusion * (diffuse_colour + f0);
    let nl = dot(s.n, s.l);
    if (nl <= 0.0) {
        return ambient;
    }
    let nv = max(dot(s.n, s.v), 1e-4);
    let h = safe_normalize(s.l + s.v, s.n);
    let nh = max(dot(s.n, h), 0.0);
    let vh = max(dot(s.v, h), 0.0);
    let a = clamp(roughness * roughness, 2e-3, 1.0);
    let a2 = a * a;
    let q = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * q * q);
    let vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    let f = f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - vh, 5.0);
    let specular = f * (d * vis);
    let diffuse = (vec3<f32>(1.0) - f) * diffuse_colour * INV_PI;
    return ambient + irradiance(s) * nl * (diffuse + specular);
}

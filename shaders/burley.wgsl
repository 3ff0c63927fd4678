// Spatial model: Christensen–Burley normalised diffusion, R(r) = A (e^{−r/d} + e^{−r/3d})/(8π d r)
// with d = ℓ_d / s(A) from the diffuse mean free path ℓ_d = 1/σ_tr of each channel (their
// "dmfp" fit), spread over the screen by the subsurface pass in rings whose masses are the
// profile's exact integrals. Fresnel only for oblique incidence, no translucency table.
// CPU: core/src/shading/burley.rs.
#import common
#import subsurface

fn shade_split(s: Surface) -> Split {
    return sss_split(s);
}

fn shade(s: Surface) -> vec3<f32> {
    return sss_local(s);
}

// Spatial model: the material's diffusion profile as measured by the project's Monte Carlo
// (normal-incidence pencil beam, tabulated in rings), spread over the screen by the
// subsurface pass (`sss_pass.wgsl`); oblique incidence and translucency from measured tables.
// CPU: core/src/shading/tabulated.rs. Kernel and tables: core/src/shading/bake.rs.
#import common
#import subsurface

fn shade_split(s: Surface) -> Split {
    return sss_split(s);
}

fn shade(s: Surface) -> vec3<f32> {
    return sss_local(s);
}

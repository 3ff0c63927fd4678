// Mobile tier: pre-integrated skin (Penner & Borshukov 2011). The response of spheres of
// every radius under a directional light, measured once per material by the Monte Carlo
// sphere walker (engine/src/shading/preintegrated.rs), in a LUT over (n·l, curvature); per pixel
// one fetch, no pass. A point light's irradiance is blurred by lifting the light by the
// kernel's Poisson height (the Poisson kernel is its own semigroup: blurring the irradiance of
// a light at height h with a Poisson kernel of height s gives the light at height h + s).
#import common
#import consts
#import subsurface

@group(1) @binding(1) var lut: texture_2d<f32>;
@group(1) @binding(2) var lut_sampler: sampler;

// LUT rows (engine/src/shading/preintegrated.rs; their counts from `consts`): the sphere
// response over (n·l, curvature), then the exit/entry Fresnel factors over cos θ, then the
// backlit slab's transmittance over log2(t/SLAB_FIRST_MM)/LUT_SLAB_SPAN, then the
// edge-spread function (log2) over the signed distance to a shadow edge
// (engine/src/shading/edge_spread.rs), spanning ±PENUMBRA_SPAN_MM quadratically.
fn lut_row(u: f32, row: f32) -> vec4<f32> {
    let u_tex = (clamp(u, 0.0, 1.0) * (LUT_U - 1.0) + 0.5) / LUT_U;
    return textureSampleLevel(lut, lut_sampler, vec2<f32>(u_tex, (row + 0.5) / LUT_TEXTURE_ROWS), 0.0);
}

// The slab row's coordinate for a thickness of `t_mm`.
fn slab_u(t_mm: f32) -> f32 {
    return log2(max(t_mm, SLAB_FIRST_MM) / SLAB_FIRST_MM) / LUT_SLAB_SPAN;
}

// The key light's visibility past the terminator (n·l < 0; `v` the surface's test). The
// sphere rows hold light that entered the ball of radius ρ on its lit side, where the ray
// toward the light leaves it, 2ρ|n·l| along l: that point is tested. A part thinner than its
// ball (an ear) was lit on its far side, where the surface's own test looked.
fn wrap_visibility(s: Surface, v: f32) -> f32 {
    let back = -dot(s.n, s.l);
    let ball = 2.0 * s.curvature_radius;
    if (back <= 0.0 || s.thickness < ball) {
        return v;
    }
    return light_visible_coord(shadow_coord(s.pos + s.l * (ball * back), s.l));
}

// The key light's visibility per channel. `v` is the shadow map's test at this point; near the
// edge of a caster's shadow it becomes the edge-spread function of the material's kernel at the
// point's signed distance from that edge (the penumbra map gives the nearest edge of a caster
// in front of the point; within the test's ramp its fraction places the edge more
// finely): light bleeds into the shadow as far as the material carries it, red furthest.
fn penumbra(s: Surface, v: f32) -> vec3<f32> {
    let nl = dot(s.n, s.l);
    let c = s.shadow_coord;
    if (frame.penumbra_drawn == 0u || nl <= 0.0 || c.w < 0.5) {
        return vec3<f32>(wrap_visibility(s, v));
    }
    let grid = frame.penumbra_grid;
    let cell = vec2<i32>(min(c.xy * grid, vec2<f32>(grid - 1.0)));
    let seed = textureLoad(penumbra_map, cell, 0);
    if (seed.w < 0.5 || seed.z >= c.z - frame.edge_gap) {
        return vec3<f32>(v);
    }
    // Across the light's image plane, stretched onto the surface by the incidence.
    let to_mm = frame.shadow_width * MM_PER_M / max(nl, 0.25);
    let texel_mm = frame.shadow_texel * to_mm;
    var d = select(-1.0, 1.0, v >= 0.5) * max(length(seed.xy - c.xy) * to_mm, 0.5 * SHADOW_RAMP_TEXELS * texel_mm);
    if (v > 0.0 && v < 1.0) {
        // The filtered test ramps linearly over SHADOW_RAMP_TEXELS texels.
        d = (v - 0.5) * SHADOW_RAMP_TEXELS * texel_mm;
    }
    let t = sign(d) * sqrt(min(abs(d) / PENUMBRA_SPAN_MM, 1.0));
    return exp2(lut_row(0.5 * (t + 1.0), LUT_PENUMBRA_ROW).rgb);
}

fn shade(s: Surface) -> vec3<f32> {
    let exit = lut_row(dot(s.n, s.v), LUT_CURVATURE_ROWS).r;
    // Curvature axis: v = R0 / (R0 + ρ), within the curvature rows.
    let rho_mm = s.curvature_radius * MM_PER_M;
    let v = model.lut_r0_mm / (model.lut_r0_mm + rho_mm);
    let v_tex = min(v * LUT_CURVATURE_ROWS, LUT_CURVATURE_ROWS - 0.5) / LUT_TEXTURE_ROWS;
    // The light lifted by each channel's Poisson height s_c: its distance² over the tangent
    // plane, d² + 2 h s_c + s_c² (h its height, mm), scales each channel's irradiance; one
    // fetch at the cosine of the light lifted by the channels' mean height serves all three.
    let d = s.light_dist * MM_PER_M;
    let h = dot(s.n, s.l) * d;
    let lift = model.lift;
    let d2 = max(vec3<f32>(d * d) + 2.0 * h * lift + lift * lift, vec3<f32>(1e-12));
    let mean = dot(lift, vec3<f32>(1.0 / 3.0));
    let mu = clamp((h + mean) * inverseSqrt(max(d * d + 2.0 * h * mean + mean * mean, 1e-12)), -1.0, 1.0);
    // The sphere response M/E_beam: u = (n·l + 1)/2.
    // The rows hold log2 M (an exponential fall-off past the terminator interpolates exactly).
    let m = exp2(textureSampleLevel(lut, lut_sampler, vec2<f32>(0.5 * (mu + 1.0), v_tex), 0.0).rgb);
    let response = m * (d * d) / d2;
    // Translucency (subsurface.wgsl's, with its Fresnel and slab tables read from the LUT)
    // beyond what the sphere rows already carry: they hold the light that crosses a ball of
    // radius ρ, whose chord along the light here is 2ρ·back, so only a part thinner than its
    // curvature implies (an ear, a finger) adds the difference of the two slabs.
    let back = max(-dot(s.n, s.l), 0.0);
    let entry = lut_row(back, LUT_CURVATURE_ROWS).g;
    let slab = lut_row(slab_u(sss_back_path_mm(s, back)), LUT_CURVATURE_ROWS + 1.0).rgb;
    let ball = lut_row(slab_u(sss_chord_mm(s, back)), LUT_CURVATURE_ROWS + 1.0).rgb;
    let through = back * entry * max(slab - ball, vec3<f32>(0.0));
    let ambient = PI * frame.ambient * model.uniform_albedo;
    // The light before its shadow test (s.light carries the hard test), so the response
    // can take the penumbra's per-channel visibility instead; translucency keeps the hard
    // test, made where it enters on the far side.
    let full = select(s.light, frame.light_intensity * frame.light_color, frame.shadow_drawn != 0u);
    let e_full = full / (s.light_dist * s.light_dist);
    let lit = penumbra(s, s.visibility);
    // A pigmented texel: its factor in and out (one pass sees only this texel).
    let t = sss_pigment(s);
    return exit * t * t * (ambient + e_full * response * lit + irradiance(s) * through);
}

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
// (u outside 0…1 reads the row's end: the LUT's sampler clamps to its edge.)
fn lut_row(u: f32, row: f32) -> vec4<f32> {
    let u_tex = u * ((LUT_U - 1.0) / LUT_U) + 0.5 / LUT_U;
    return textureSampleLevel(lut, lut_sampler, vec2<f32>(u_tex, (row + 0.5) / LUT_TEXTURE_ROWS), 0.0);
}

// The slab row's coordinate for a thickness of `t_mm`.
fn slab_u(t_mm: f32) -> f32 {
    return (log2(max(t_mm, SLAB_FIRST_MM)) - log2(SLAB_FIRST_MM)) * (1.0 / LUT_SLAB_SPAN);
}

// The key light's visibility past the terminator (n·l < 0; `v` the surface's test), for the
// sphere rows' wrap and the translucency alike: where the light entered, as far along the
// ray toward the light as it ran through matter (`sss_back_path_mm`: the chord 2ρ|n·l|
// through the ball of the surface's curvature, or the slab's path t/|n·l| through a part
// thinner than its ball — an ear; `entry_visibility`).
// (`back` = max(−n·l, 0), `path_mm` that path: the caller's.)
fn wrap_visibility(s: Surface, v: f32, back: f32, path_mm: f32) -> f32 {
    // At least as far as the material's reach (`entry_reach_mm`) where the slab allows: a
    // rim the ball makes thinner than it is (an ear's) is otherwise tested inside itself.
    let slab = s.thickness * model.mm_per_m / max(back, 1e-3);
    let test_mm = max(path_mm, min(slab, model.entry_reach_mm));
    return select(v, entry_visibility(s, test_mm * (1.0 / MM_PER_M), v), back > 0.0);
}

// The key light's visibility per channel, as log2 per channel (.rgb) and a factor (.a), so the
// caller adds it to the LUT's log2 response before its one exp2. `v` is the shadow map's test at this point; near the
// edge of a caster's shadow it becomes the edge-spread function of the material's kernel at the
// point's signed distance from that edge (the penumbra map gives the nearest edge of a caster
// in front of the point; within the test's ramp its fraction places the edge more
// finely): light bleeds into the shadow as far as the material carries it, red furthest.
fn penumbra(s: Surface, v: f32, back: f32, path_mm: f32) -> vec4<f32> {
    let nl = dot(s.n, s.l);
    let c = s.shadow_coord;
    if (frame.penumbra_drawn == 0u || nl <= 0.0 || c.w < 0.5) {
        return vec4<f32>(0.0, 0.0, 0.0, wrap_visibility(s, v, back, path_mm));
    }
    // (c.xy = 1 lands one past the grid's last texel: the load is kept to the grid, or reads
    // no seed.)
    let seed = textureLoad(penumbra_map, vec2<i32>(c.xy * frame.penumbra_grid), 0);
    // The signed distance in the map (uv): to the seed, at least half the test's ramp; within
    // the ramp (the filtered test ramps linearly over SHADOW_RAMP_TEXELS texels), from it.
    let ramp = 0.5 * SHADOW_RAMP_TEXELS * frame.shadow_texel;
    let delta = seed.xy - c.xy;
    let far = max(sqrt(dot(delta, delta)), ramp);
    let d = select(select(-far, far, v >= 0.5), (2.0 * v - 1.0) * ramp, v > 0.0 && v < 1.0);
    // In mm across the light's image plane, stretched onto the surface by the incidence;
    // the row's coordinate goes as its square root.
    let x = abs(d) * frame.shadow_width * (MM_PER_M / PENUMBRA_SPAN_MM) / max(nl, 0.25);
    let t = sign(d) * sqrt(min(x, 1.0));
    let esf = vec4<f32>(lut_row(0.5 * (t + 1.0), LUT_PENUMBRA_ROW).rgb, 1.0);
    // No caster's edge in front of the point within reach: the test as it is.
    return select(vec4<f32>(0.0, 0.0, 0.0, v), esf, seed.w > 0.5 && seed.z < c.z - frame.edge_gap);
}

fn shade(s: Surface) -> vec3<f32> {
    // Not below EXIT_COSINE_MIN: no dark outline at silhouettes (subsurface.rs).
    let exit = lut_row(max(dot(s.n, s.v), EXIT_COSINE_MIN), LUT_CURVATURE_ROWS).r;
    // Curvature axis: v = R0 / (R0 + ρ), within the curvature rows.
    let rho_mm = s.curvature_radius * MM_PER_M;
    let v = model.lut_r0_mm / (model.lut_r0_mm + rho_mm);
    let v_tex = min(v * (LUT_CURVATURE_ROWS / LUT_TEXTURE_ROWS), (LUT_CURVATURE_ROWS - 0.5) / LUT_TEXTURE_ROWS);
    // The light lifted by each channel's Poisson height s_c: its distance² over the tangent
    // plane, d² + 2 h s_c + s_c² (h its height, mm), scales each channel's irradiance, and
    // each channel reads the rows at its own lifted cosine μ_c = (h + s_c)/d_c: the entry
    // (Fresnel transmittance) and the oblique response the rows hold, at the incidence the
    // lifted light has for that channel.
    // The lift fades with the distance r from the light's foot past LIFT_REACH lifts: far out
    // the irradiance barely changes across the kernel, so it is the light's own, not the
    // lifted light's (a Poisson kernel's tail, ∝ s/r³, would keep lighting it from the foot).
    let d = s.light_dist * MM_PER_M;
    let h = dot(s.n, s.l) * d;
    let reach2 = model.lift * model.lift * (LIFT_REACH * LIFT_REACH);
    let lift = model.lift * reach2 / (reach2 + max(d * d - h * h, 0.0));
    let d2 = max(lift * (2.0 * h + lift) + d * d, vec3<f32>(1e-12));
    let u = 0.5 * clamp((h + lift) * inverseSqrt(d2), vec3<f32>(-1.0), vec3<f32>(1.0)) + 0.5;
    // The light before its shadow test (s.light carries the hard test; with no map it is
    // 1), so the response can take the penumbra's per-channel visibility instead;
    // translucency keeps the hard test, made where it enters on the far side.
    let back = max(-dot(s.n, s.l), 0.0);
    let path = sss_back_path_mm(s, back);
    let lit = penumbra(s, s.visibility, back, path);
    // The sphere response M/E_beam: u = (n·l + 1)/2, times the visibility and the irradiance
    // at normal incidence E = I/d² (mm: its d² cancels the lift's).
    // The rows hold log2 M (an exponential fall-off past the terminator interpolates exactly).
    let log_m = vec3<f32>(
        textureSampleLevel(lut, lut_sampler, vec2<f32>(u.r, v_tex), 0.0).r,
        textureSampleLevel(lut, lut_sampler, vec2<f32>(u.g, v_tex), 0.0).g,
        textureSampleLevel(lut, lut_sampler, vec2<f32>(u.b, v_tex), 0.0).b,
    );
    let light = frame.light_intensity * frame.light_color * (lit.a * MM_PER_M * MM_PER_M);
    let response = exp2(log_m + lit.rgb) / d2;
    // Translucency (subsurface.wgsl's, with its Fresnel and slab tables read from the LUT)
    // beyond what the sphere rows already carry: they hold the light that crosses a ball of
    // radius ρ, whose chord along the light here is 2ρ·back, so only a part thinner than its
    // curvature implies (an ear, a finger) adds the difference of the two slabs, lit as the
    // wrap is (`lit.a`: past the terminator it is `wrap_visibility`).
    // (Its irradiance I/d² in mm, as the response's.)
    let entry = lut_row(back, LUT_CURVATURE_ROWS).g;
    let slab = lut_row(slab_u(path), LUT_CURVATURE_ROWS + 1.0).rgb;
    let ball = lut_row(slab_u(sss_chord_mm(s, back)), LUT_CURVATURE_ROWS + 1.0).rgb;
    let through = (back * entry / (d * d)) * max(slab - ball, vec3<f32>(0.0));
    // The ambient light and the light the subject returns here from its own lit surface
    // (interreflection: the glow in a cast shadow), both reflected diffusely.
    let ambient = model.uniform_albedo * (PI * frame.ambient + returned_irradiance(s, model.uniform_albedo));
    // A pigmented texel: its factor in and out (one pass sees only this texel), t² =
    // albedo / the medium's (`sss_pigment`'s square, without its root).
    let t2 = select(vec3<f32>(1.0), max(s.albedo, vec3<f32>(0.0)) / max(model.uniform_albedo, vec3<f32>(1e-6)), s.pigmented);
    return exit * t2 * (ambient + (response + through) * light);
}

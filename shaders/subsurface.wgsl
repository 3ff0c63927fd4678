// Shared by the spatial subsurface models (their descriptors start from `subsurface::SPATIAL`):
// their one uniform, the oblique-incidence and translucency tables, the exit distribution; and
// the screen-space models' whole shader (composed with SCREEN_SPACE: they differ only in their
// constants and kernel, not in code).
// CPU twin: engine/src/shading/subsurface.rs (`Params`, `split`, `translucency`).
//
// Units: the tables are per unit incident power; thickness in mm; lengths on the surface in mm.
// Exitance M leaves the smooth boundary with the radiance M · F_t(η, n·v) / (π C(η)),
// C(η) = ∫ F_t(η, μ) 2μ dμ, so the radiance integrates back to M over the hemisphere.
#import common
#import consts
#import fresnel

// `SubsurfaceUniform`, generated from its Rust declaration (engine/src/shading/subsurface.rs).
#import SubsurfaceUniform

@group(1) @binding(0) var<uniform> model: SubsurfaceUniform;

// What a spatial model's pixel contributes: radiance that stays put, irradiance that the
// screen-space pass spreads with the diffusion kernel, and the exit factor that turns the
// spread exitance into radiance toward the viewer.
struct Split {
    local: vec3<f32>,
    spread: vec3<f32>,
    exit: vec3<f32>,
};

// A pigmented texel's factor T per channel (1 without a pigment): a thin absorbing layer over
// the medium, crossed once on the way in and once on the way out, T² = A / the medium's own
// reflectance under uniform light, so uniform light returns the texel's albedo A.
fn sss_pigment(s: Surface) -> vec3<f32> {
    if (!s.pigmented) {
        return vec3<f32>(1.0);
    }
    return sqrt(max(s.albedo, vec3<f32>(0.0)) / max(model.uniform_albedo, vec3<f32>(1e-6)));
}

fn sss_oblique(mu: f32) -> vec3<f32> {
    let x = sqrt(clamp(mu, 0.0, 1.0)) * f32(OBLIQUE_NODES - 1u);
    let i = min(u32(x), OBLIQUE_NODES - 2u);
    let f = x - f32(i);
    return mix(model.oblique[i].rgb, model.oblique[i + 1u].rgb, f);
}

fn sss_shift(mu: f32) -> vec3<f32> {
    let x = sqrt(clamp(mu, 0.0, 1.0)) * f32(OBLIQUE_NODES - 1u);
    let i = min(u32(x), OBLIQUE_NODES - 2u);
    let f = x - f32(i);
    return mix(model.shift[i].rgb, model.shift[i + 1u].rgb, f);
}

// dδ/dμ of the shift table (linear in √μ: dδ/dμ = dδ/d√μ / (2√μ)).
fn sss_shift_slope(mu: f32) -> vec3<f32> {
    let q = sqrt(clamp(mu, 0.0, 1.0));
    let steps = f32(OBLIQUE_NODES - 1u);
    let i = min(u32(q * steps), OBLIQUE_NODES - 2u);
    return (model.shift[i + 1u].rgb - model.shift[i].rgb) * steps / (2.0 * max(q, 1e-3));
}

// The irradiance each channel spreads, weighted by q(μ): taken where the light that leaves
// here entered, δ_c(μ) mm back toward the light along the surface (obliquely entering light
// travels on before it leaves; the light is analytic, so its irradiance can be evaluated
// there). The shift points away from the foot of the light, so the map x → x − δ is an
// outward flow of radius ρ → ρ − δ(ρ) (ρ the distance to the foot along the surface); its
// area ratio ((ρ − δ)/ρ)(1 − dδ/dρ), with dδ/dρ = δ'(μ) dμ/dρ and dμ/dρ = −μ sinθ / d for a
// light at distance d, keeps the spread power equal to the received power.
fn sss_spread(s: Surface) -> vec3<f32> {
    let nl = dot(s.n, s.l);
    let along = s.l - s.n * nl;
    let len = length(along);
    let dir = select(vec3<f32>(0.0), along / max(len, 1e-12), len > 1e-9);
    let rho = len * s.light_dist * model.mm_per_m;
    let delta = min(sss_shift(max(nl, 0.0)), vec3<f32>(rho));
    let ddelta = -sss_shift_slope(max(nl, 0.0)) * max(nl, 0.0) * len / (s.light_dist * model.mm_per_m);
    // One call per channel, each with its own shift: no vector indexed by a loop counter (with
    // wgpu's index clamping, Valhall kept such a vector in memory: 46 G57 cycles, now 10).
    return vec3<f32>(
        sss_spread_channel(s, dir, rho, delta.x, ddelta.x, vec3<f32>(1.0, 0.0, 0.0)),
        sss_spread_channel(s, dir, rho, delta.y, ddelta.y, vec3<f32>(0.0, 1.0, 0.0)),
        sss_spread_channel(s, dir, rho, delta.z, ddelta.z, vec3<f32>(0.0, 0.0, 1.0)),
    );
}

// One channel (`pick`: its unit vector) of `sss_spread`, with that channel's shift `delta` (mm)
// and its slope term `ddelta`; `dir` the surface direction away from the light's foot, `rho`
// (mm) the distance to it. The light as it reaches this point (occluded here: nothing is
// spread from here).
fn sss_spread_channel(s: Surface, dir: vec3<f32>, rho: f32, delta: f32, ddelta: f32,
                      pick: vec3<f32>) -> f32 {
    let back = dir * (delta / model.mm_per_m);
    let d = s.l * s.light_dist - back;
    let r = max(length(d), 1e-3);
    // On a curved surface the entry point's normal is turned toward the light by δ/ρ_c
    // (at most 1 rad).
    let tilt = min(delta / max(s.curvature_radius * model.mm_per_m, 1e-3), 1.0);
    let n = normalize(s.n + dir * tilt);
    let mu = max(dot(n, d) / r, 0.0);
    let area = select(1.0, (rho - delta) / rho, rho > 1e-6) * max(1.0 - ddelta, 0.0);
    let seen = light_visible(s.pos + back, s.n);
    return dot(s.light * sss_oblique(mu), pick) * seen / (r * r) * mu * area;
}

fn sss_exit(s: Surface) -> f32 {
    return fresnel_transmittance(model.eta, max(dot(s.n, s.v), EXIT_COSINE_MIN)) * model.exit_norm;
}

#ifdef TRANSLUCENCY
// Diffuse transmittance through `t_mm` of material: the table holds ln T at thicknesses
// log-spaced SLAB_FIRST_MM · 2^k mm, ln T linear in the thickness between them (deep in a
// medium light decays exponentially with depth); past the thickest node ln T goes on at the
// slope of the last interval (half that node wide).
fn sss_slab(t_mm: f32) -> vec3<f32> {
    let last = SLAB_NODES - 1u;
    let x = log2(max(t_mm, SLAB_FIRST_MM) / SLAB_FIRST_MM);
    if (x >= f32(last)) {
        let thickest = SLAB_FIRST_MM * exp2(f32(last));
        let slope = (model.slab[last].rgb - model.slab[last - 1u].rgb) / (0.5 * thickest);
        return exp(model.slab[last].rgb + slope * (t_mm - thickest));
    }
    let i = min(u32(x), last - 1u);
    let f = clamp(t_mm / (SLAB_FIRST_MM * exp2(f32(i))) - 1.0, 0.0, 1.0);
    return exp(mix(model.slab[i].rgb, model.slab[i + 1u].rgb, f));
}

#endif

// The chord (mm) along the light through the sphere of the surface's curvature, from a point
// lit from behind at `back` = −n·l.
fn sss_chord_mm(s: Surface, back: f32) -> f32 {
    return 2.0 * s.curvature_radius * model.mm_per_m * back;
}

// How far (mm) light from behind travels through the material to this point: the ray toward
// the light leaves through the curved side (the chord) or through the far face, the thickness
// t / |n·l| away (a slab), whichever it meets first. A sphere (t = 2ρ): the chord; a flat
// part: the slab's path, long at grazing light (so a thick jaw turned from the light does not
// glow as if it were a thin chord).
fn sss_back_path_mm(s: Surface, back: f32) -> f32 {
    return min(sss_chord_mm(s, back), s.thickness * model.mm_per_m / max(back, 1e-3));
}

// Light through the material from behind (n·l < 0), spread locally (models whose
// composition sets TRANSLUCENCY; the others have no such code).
fn sss_translucency(s: Surface) -> vec3<f32> {
#ifdef TRANSLUCENCY
    let back = max(-dot(s.n, s.l), 0.0);
    let path = sss_back_path_mm(s, back);
    // Entry through the far face: its Fresnel transmission relative to normal incidence.
    let entry = fresnel_transmittance(model.eta, back) * model.inv_entry;
    return irradiance(s) * back * entry * sss_slab(path);
#else
    return vec3<f32>(0.0);
#endif
}

// The medium at a pixel: radiance that stays (ambient, translucency), irradiance to spread
// and the exit factor; the pigment taken in with the spread irradiance and out with what
// leaves (what stays crosses this texel's layer both ways).
fn sss_split(s: Surface) -> Split {
    var out: Split;
    let t = sss_pigment(s);
    let exit = sss_exit(s);
    out.exit = exit * t;
    out.spread = sss_spread(s) * t;
    // Ambient: uniform radiance L_a gives irradiance π L_a, reflected with the medium's
    // reflectance under uniform light; so is the light the subject returns here from its own
    // lit surface (smooth over the kernel's reach).
    let diffuse = PI * frame.ambient + returned_irradiance(s, model.uniform_albedo);
    out.local = exit * t * t * (model.uniform_albedo * diffuse + sss_translucency(s));
    return out;
}

// The pixel on its own: what the screen-space pass gives where the irradiance is uniform
// (the kernel integrates to the albedo).
fn sss_local(s: Surface) -> vec3<f32> {
    let p = sss_split(s);
    return p.local + p.exit * model.albedo * p.spread;
}

#ifdef SCREEN_SPACE
// The screen-space models (this module is theirs, their uniform and kernel their own): the
// split the subsurface pass spreads, and the pixel on its own.
fn shade_split(s: Surface) -> Split {
    return sss_split(s);
}

fn shade(s: Surface) -> vec3<f32> {
    return sss_local(s);
}
#endif

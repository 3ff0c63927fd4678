// The skinned subject, one pipeline per part kind: vertex skinning, then for a skin part the
// selected shading model (`shading_model`, an alias bound per pipeline to ward / dipole / oss
// / ...) and for a STANDARD part the glTF metallic-roughness lighting the props share
// (`pbr.wgsl`). A part's material is bound at group 3 (`material.wgsl`).
#import common
#import skinning
#import material
#ifdef STANDARD
#import pbr
#else
#import shading_model
#endif

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) joints: vec4<u32>,
    @location(5) weights: vec4<f32>,
    @location(6) thickness: f32,
    @location(7) curvature: vec4<f32>,
    @location(12) bounce: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) thickness: f32,
    // The curvature along the light (1/m) and the light the subject returns here (`bounce`).
    @location(5) shape: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let skin = skin_matrix(v.joints, v.weights);
    let world = skin * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    out.normal = (skin * vec4<f32>(v.normal, 0.0)).xyz;
    out.tangent = vec4<f32>((skin * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    out.uv = v.uv;
    // Thickness and curvature in the mesh's units, scaled as the skin scales them (a fitted
    // export).
    let scale = max(length(out.normal), 1e-6);
    out.thickness = v.thickness * scale;
    // The surface's curvature along the light's direction across it, κ₂ + (a·t)²
    // (asset::curvature: a turns with the skin, κ goes as 1/scale), where the light is overhead
    // the mean curvature. Taken per vertex (a's sign is arbitrary; its square is not) and
    // interpolated.
    let n = out.normal / scale;
    let to_light = frame.light_pos - world.xyz;
    let along = to_light - n * dot(n, to_light);
    let a = (skin * vec4<f32>(v.curvature.xyz, 0.0)).xyz / (scale * sqrt(scale));
    let a2 = select(0.5 * dot(a, a), pow(dot(a, along), 2.0) / dot(along, along),
                    dot(along, along) > 1e-6 * dot(to_light, to_light));
    // The light the subject returns to this point from its own lit surface (asset::bounce:
    // its first two spherical-harmonic bands in the light's direction; s turns with the
    // skin), per unit of the light's intensity and of the skin's diffuse reflectance squared.
    let s = (skin * vec4<f32>(v.bounce.xyz, 0.0)).xyz / scale;
    let d2 = max(dot(to_light, to_light), LIGHT_D_MIN_M * LIGHT_D_MIN_M);
    let bounce = max(0.25 * v.bounce.w + 0.5 * dot(s, to_light) * inverseSqrt(d2), 0.0) / d2;
    out.shape = vec2<f32>(v.curvature.w / scale + a2, bounce);
    return out;
}

// The shading surface at a fragment: the material's normal (its map where the pipeline has
// one; flipped on the back of a double-sided part), the albedo.
fn surface_at(in: VertexOut, albedo: vec3<f32>, front: bool) -> Surface {
    var normal = material_normal(in.normal, in.tangent, in.uv);
#ifdef DOUBLE_SIDED
    normal = select(-normal, normal, front);
#endif
    var s = make_surface(in.world_pos, normal, in.tangent, albedo, in.thickness);
    // The mesh's curvature along the light (vs_main); a concave or flat part is flat. (A
    // concave part's lit side taken as a ball of its radius scored 0.001 better on the face
    // bench for 0.09 G52 cycles: the affordable tier's price could not take it.)
    s.curvature_radius = 1.0 / max(in.shape.x, 1.0 / FLAT_RADIUS_M);
    // (Interpolated at a sample past the triangle's edge it can dip below 0.)
    s.bounce = max(in.shape.y, 0.0);
    return s;
}

#ifdef STANDARD
// A standard part's radiance and coverage: base colour × factor (masked below its cutoff),
// the PBR lighting, the emission; alpha where the part blends.
fn standard(in: VertexOut, front: bool) -> vec4<f32> {
    let base = material_base(in.uv);
#ifdef ALPHA_MASK
    if (base.a < material.alpha_cutoff) {
        discard;
    }
#endif
    let s = surface_at(in, base.rgb, front);
    let mr = material_metallic_roughness(in.uv);
    let c = pbr_radiance(s, base.rgb, mr.x, mr.y, material_occlusion(in.uv)) + material_emissive(in.uv);
#ifdef ALPHA_BLEND
    return vec4<f32>(c, base.a);
#else
    return vec4<f32>(c, 1.0);
#endif
}
#else
// A skin part's surface: its albedo is the pigment where the material says so.
fn skin_surface(in: VertexOut, front: bool) -> Surface {
    var s = surface_at(in, material_base(in.uv).rgb, front);
    s.pigmented = material.pigmented != 0u;
    return s;
}
#endif

#ifdef SCREEN_SPACE
#import split_out

// A frame with the subsurface pass: the three targets (`SplitOut`). The pixel's size: the
// world-space step between neighbouring pixels, minus its part along the view ray, its
// footprint on the plane facing the camera at this depth.
@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> SplitOut {
    var out: SplitOut;
#ifdef STANDARD
    // Not skin: it stays, nothing to spread, exit 0. A blended part's pipeline writes only
    // the colour, premultiplied, over what is behind it (the marker stays).
    let c = standard(in, front);
#ifdef ALPHA_BLEND
    out.colour = vec4<f32>(c.rgb * c.a, c.a);
#else
    out.colour = vec4<f32>(c.rgb, 0.0);
#endif
    out.spread = vec4<f32>(0.0);
    out.exit = vec4<f32>(0.0);
#else
    let s = skin_surface(in, front);
    let dx = dpdx(in.world_pos);
    let dy = dpdy(in.world_pos);
    let px = 0.5 * (length(dx - s.v * dot(s.v, dx)) + length(dy - s.v * dot(s.v, dy)));
    let p = shade_split(s);
    out.colour = vec4<f32>(p.local, 1.0);
    out.spread = vec4<f32>(p.spread, max(px * MM_PER_M, 1e-6));
    out.exit = vec4<f32>(p.exit, 0.0);
#endif
    return out;
}
#else
@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
#ifdef STANDARD
    let c = standard(in, front);
    return vec4<f32>(finish(c.rgb).rgb, c.a);
#else
    return finish(shade(skin_surface(in, front)));
#endif
}
#endif

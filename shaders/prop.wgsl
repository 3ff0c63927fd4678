// Props (floor, walls, furniture, obstacles), instanced: the standard glTF material's lighting
// (`pbr.wgsl`, shared with a character's non-skin parts), their material at group 1
// (`material.wgsl`, INSTANCED). No subsurface code is imported here.
#import common
#import material
#import pbr

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    // The instance's model matrix, one column per attribute.
    @location(8) m0: vec4<f32>,
    @location(9) m1: vec4<f32>,
    @location(10) m2: vec4<f32>,
    @location(11) m3: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let m = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let world = m * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    // Props use uniform scale only, so the model matrix transforms normals correctly.
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.tangent = vec4<f32>((m * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    out.uv = v.uv;
    return out;
}

fn prop_radiance(in: VertexOut) -> vec3<f32> {
    let base = material_base(in.uv);
    let n = material_normal(in.normal, in.tangent, in.uv);
    // The character's shadow falls on the floor and the props (the key light's shadow map).
    let s = make_surface(in.world_pos, n, in.tangent, base.rgb, 0.0);
    let mr = material_metallic_roughness(in.uv);
    return pbr_radiance(s, base.rgb, mr.x, mr.y, material_occlusion(in.uv)) + material_emissive(in.uv);
}

#ifdef SCREEN_SPACE
#import split_out

// In a frame with the subsurface pass: linear radiance, marker 0, nothing to spread.
@fragment
fn fs_main(in: VertexOut) -> SplitOut {
    var out: SplitOut;
    out.colour = vec4<f32>(prop_radiance(in), 0.0);
    out.spread = vec4<f32>(0.0);
    out.exit = vec4<f32>(0.0);
    return out;
}
#else
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return finish(prop_radiance(in));
}
#endif

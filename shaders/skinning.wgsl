// Linear blend skinning with a joint palette of at most MAX_JOINTS matrices (256: 16 KiB, the
// GLES3 minimum uniform block size). palette[j] = jointWorld[j] · inverseBind[j].
#import consts

@group(2) @binding(0) var<uniform> palette: array<mat4x4<f32>, MAX_JOINTS>;

fn skin_matrix(joints: vec4<u32>, weights: vec4<f32>) -> mat4x4<f32> {
    let j = min(joints, vec4<u32>(MAX_JOINTS - 1u));
    return palette[j.x] * weights.x + palette[j.y] * weights.y
         + palette[j.z] * weights.z + palette[j.w] * weights.w;
}

//! The character's joint hierarchy in its bind pose (A-pose, all joint rotations identity).

use glam::{Mat4, Vec3};

pub struct Joint {
    pub name: &'static str,
    pub parent: Option<usize>,
    /// Bind-pose world position (metres).
    pub pos: Vec3,
    /// End of the bone segment used for skin weights (bind-pose world position).
    pub tail: Vec3,
}

pub const HIPS: usize = 0;
pub const SPINE: usize = 1;
pub const CHEST: usize = 2;
pub const NECK: usize = 3;
pub const HEAD: usize = 4;
/// First joint of the left arm chain (shoulder, upper arm, lower arm, hand); right = +4.
pub const ARM_L: usize = 5;
pub const ARM_R: usize = 9;
/// First joint of the left leg chain (upper leg, lower leg, foot); right = +3.
pub const LEG_L: usize = 13;
pub const LEG_R: usize = 16;
pub const SHOULDER: usize = 0;
pub const UPPER_ARM: usize = 1;
pub const LOWER_ARM: usize = 2;
pub const HAND: usize = 3;
pub const UPPER_LEG: usize = 0;
pub const LOWER_LEG: usize = 1;
pub const FOOT: usize = 2;

/// Arm direction in the bind pose for side `s` (+1 = character's left = +X).
pub fn arm_dir(s: f32) -> Vec3 {
    Vec3::new(0.616 * s, -0.788, 0.0).normalize()
}

pub const UPPER_ARM_LEN: f32 = 0.28;
pub const LOWER_ARM_LEN: f32 = 0.25;
pub const UPPER_LEG_LEN: f32 = 0.42;
pub const LOWER_LEG_LEN: f32 = 0.415;
pub const HIP_Y: f32 = 0.92;
pub const ANKLE_Y: f32 = 0.085;

pub fn shoulder_pos(s: f32) -> Vec3 {
    Vec3::new(0.035 * s, 1.42, -0.015)
}
pub fn upper_arm_pos(s: f32) -> Vec3 {
    Vec3::new(0.175 * s, 1.41, -0.02)
}
pub fn elbow_pos(s: f32) -> Vec3 {
    upper_arm_pos(s) + arm_dir(s) * UPPER_ARM_LEN
}
pub fn wrist_pos(s: f32) -> Vec3 {
    elbow_pos(s) + arm_dir(s) * LOWER_ARM_LEN
}
pub fn hip_pos(s: f32) -> Vec3 {
    Vec3::new(0.09 * s, HIP_Y, 0.0)
}
pub fn knee_pos(s: f32) -> Vec3 {
    hip_pos(s) - Vec3::Y * UPPER_LEG_LEN
}
pub fn ankle_pos(s: f32) -> Vec3 {
    Vec3::new(0.09 * s, ANKLE_Y, 0.0)
}

pub fn joints() -> Vec<Joint> {
    let j = |name, parent, pos: Vec3, tail: Vec3| Joint {
        name,
        parent,
        pos,
        tail,
    };
    let mut v = vec![
        j(
            "hips",
            None,
            Vec3::new(0.0, 0.97, 0.0),
            Vec3::new(0.0, 0.86, 0.0),
        ),
        j(
            "spine",
            Some(HIPS),
            Vec3::new(0.0, 1.08, -0.01),
            Vec3::new(0.0, 1.25, -0.01),
        ),
        j(
            "chest",
            Some(SPINE),
            Vec3::new(0.0, 1.25, -0.01),
            Vec3::new(0.0, 1.46, -0.015),
        ),
        j(
            "neck",
            Some(CHEST),
            Vec3::new(0.0, 1.46, -0.015),
            Vec3::new(0.0, 1.56, -0.005),
        ),
        j(
            "head",
            Some(NECK),
            Vec3::new(0.0, 1.56, -0.005),
            Vec3::new(0.0, 1.70, -0.005),
        ),
    ];
    for (s, names) in [
        (1.0, ["shoulder_L", "upper_arm_L", "lower_arm_L", "hand_L"]),
        (-1.0, ["shoulder_R", "upper_arm_R", "lower_arm_R", "hand_R"]),
    ] {
        let base = v.len();
        v.push(j(names[0], Some(CHEST), shoulder_pos(s), upper_arm_pos(s)));
        v.push(j(names[1], Some(base), upper_arm_pos(s), elbow_pos(s)));
        v.push(j(names[2], Some(base + 1), elbow_pos(s), wrist_pos(s)));
        v.push(j(
            names[3],
            Some(base + 2),
            wrist_pos(s),
            wrist_pos(s) + arm_dir(s) * 0.1,
        ));
    }
    for (s, names) in [
        (1.0, ["upper_leg_L", "lower_leg_L", "foot_L"]),
        (-1.0, ["upper_leg_R", "lower_leg_R", "foot_R"]),
    ] {
        let base = v.len();
        v.push(j(names[0], Some(HIPS), hip_pos(s), knee_pos(s)));
        v.push(j(names[1], Some(base), knee_pos(s), ankle_pos(s)));
        v.push(j(
            names[2],
            Some(base + 1),
            ankle_pos(s),
            Vec3::new(0.09 * s, 0.03, 0.15),
        ));
    }
    debug_assert_eq!(v[ARM_R].name, "shoulder_R");
    debug_assert_eq!(v[LEG_R].name, "upper_leg_R");
    v
}

/// Local bind translation of joint `i` (its rotation is identity in the bind pose).
pub fn local_translation(js: &[Joint], i: usize) -> Vec3 {
    match js[i].parent {
        Some(p) => js[i].pos - js[p].pos,
        None => js[i].pos,
    }
}

/// Inverse bind matrix: inverse of the joint's bind-pose world matrix.
pub fn inverse_bind(js: &[Joint], i: usize) -> Mat4 {
    // World matrix is the product of the local translations up the chain.
    let mut world = Mat4::IDENTITY;
    let mut k = Some(i);
    while let Some(j) = k {
        world = Mat4::from_translation(local_translation(js, j)) * world;
        k = js[j].parent;
    }
    world.inverse()
}

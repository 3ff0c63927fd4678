//! Procedural animation clips (`idle`, `run`, `jump`), sampled at 30 fps into LINEAR keys.
//! Legs use analytic two-bone IK so planted feet stay on the ground.

use super::detmath::{acos, cos, quat_axis_angle, sin, smoothstep, PI, TAU};
use super::skeleton::*;
use glam::{Quat, Vec3};

pub const FPS: f32 = 30.0;

/// One sampled pose: root translation and every joint's local rotation.
#[derive(Clone)]
pub struct Pose {
    pub hips: Vec3,
    pub rot: Vec<Quat>,
}

pub struct Clip {
    pub name: &'static str,
    pub times: Vec<f32>,
    pub poses: Vec<Pose>,
    pub looping: bool,
}

fn rx(a: f32) -> Quat {
    quat_axis_angle(Vec3::X, a)
}
fn ry(a: f32) -> Quat {
    quat_axis_angle(Vec3::Y, a)
}
fn rz(a: f32) -> Quat {
    quat_axis_angle(Vec3::Z, a)
}

/// Per-side arm parameters: `lower` brings the A-pose arm towards the body, `swing` about X
/// (positive = backwards), `elbow` flexion (positive = forearm forwards).
struct Arm {
    lower: f32,
    swing: f32,
    elbow: f32,
    shrug: f32,
}

/// Per-side leg target: ankle position in world (bind) space and foot pitch (positive = toes down).
struct Leg {
    ankle: Vec3,
    pitch: f32,
}

struct Body {
    hips: Vec3,
    hips_rot: Quat,
    spine: Quat,
    chest: Quat,
    neck: Quat,
    head: Quat,
    arms: [Arm; 2],
    legs: [Leg; 2],
}

/// Two-bone IK for one leg: returns (upper, lower, foot) local rotations.
fn leg_ik(hips: Vec3, hips_rot: Quat, s: f32, target: &Leg) -> [Quat; 3] {
    let hip_local = hip_pos(s) - Vec3::new(0.0, 0.97, 0.0);
    let v = hips_rot.inverse() * (target.ankle - hips) - hip_local;
    let (l1, l2) = (UPPER_LEG_LEN, LOWER_LEG_LEN);
    let d = v.length().clamp(0.05, l1 + l2 - 1.0e-4);
    let vdir = v.normalize();
    let cos_knee = (l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2);
    let knee = PI - acos(cos_knee);
    let beta = acos((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d));
    let hinge = vdir.cross(Vec3::Z).normalize();
    let thigh_dir = quat_axis_angle(hinge, beta) * vdir;
    let upper = Quat::from_rotation_arc(-Vec3::Y, thigh_dir);
    let lower = rx(knee);
    // Foot: world pitch as requested, whatever the leg does.
    let world_foot = hips_rot * rx(target.pitch);
    let parent = hips_rot * upper * lower;
    let foot = (parent.inverse() * world_foot).normalize();
    [upper.normalize(), lower, foot]
}

fn pose(b: &Body) -> Pose {
    let n = joints().len();
    let mut rot = vec![Quat::IDENTITY; n];
    rot[HIPS] = b.hips_rot;
    rot[SPINE] = b.spine;
    rot[CHEST] = b.chest;
    rot[NECK] = b.neck;
    rot[HEAD] = b.head;
    for (k, s) in [(0usize, 1.0f32), (1, -1.0)] {
        let arm = if k == 0 { ARM_L } else { ARM_R };
        let a = &b.arms[k];
        rot[arm + SHOULDER] = rz(a.shrug * s);
        rot[arm + UPPER_ARM] = rx(a.swing) * rz(-a.lower * s);
        let hinge = arm_dir(s).cross(Vec3::Z).normalize();
        rot[arm + LOWER_ARM] = quat_axis_angle(hinge, a.elbow);
        rot[arm + HAND] = quat_axis_angle(hinge, 0.12);
        let leg = if k == 0 { LEG_L } else { LEG_R };
        let [u, l, f] = leg_ik(b.hips, b.hips_rot, s, &b.legs[k]);
        rot[leg + UPPER_LEG] = u;
        rot[leg + LOWER_LEG] = l;
        rot[leg + FOOT] = f;
    }
    Pose { hips: b.hips, rot }
}

fn sample(name: &'static str, duration: f32, looping: bool, f: impl Fn(f32) -> Body) -> Clip {
    let frames = (duration * FPS).round() as usize;
    let mut times = Vec::new();
    let mut poses = Vec::new();
    for i in 0..=frames {
        let t = duration * i as f32 / frames as f32;
        times.push(t);
        poses.push(pose(&f(t)));
    }
    // Keep quaternions in one hemisphere between neighbouring keys so LINEAR slerps the short way.
    for i in 1..poses.len() {
        for j in 0..poses[i].rot.len() {
            if poses[i].rot[j].dot(poses[i - 1].rot[j]) < 0.0 {
                poses[i].rot[j] = -poses[i].rot[j];
            }
        }
    }
    if looping {
        // Seamless: the last key is exactly the first.
        poses[frames] = poses[0].clone();
    }
    Clip {
        name,
        times,
        poses,
        looping,
    }
}

const STAND_Y: f32 = 0.97;

fn relaxed_arm(swing: f32, elbow: f32) -> Arm {
    Arm {
        lower: 0.52,
        swing,
        elbow,
        shrug: 0.0,
    }
}

fn planted(s: f32, lift: f32, z: f32, pitch: f32) -> Leg {
    Leg {
        ankle: Vec3::new(0.09 * s, ANKLE_Y + lift, z),
        pitch,
    }
}

fn idle(t: f32) -> Body {
    let ph = TAU * t / 2.0;
    let breath = sin(ph);
    let sway = sin(ph + 0.6);
    Body {
        hips: Vec3::new(0.008 * sway, STAND_Y - 0.014 + 0.004 * breath, 0.0),
        hips_rot: rz(-0.012 * sway),
        spine: rx(0.012 * breath) * rz(0.014 * sway),
        chest: rx(-0.025 * breath),
        neck: rx(0.01 * breath),
        head: ry(0.06 * sin(ph + 1.3)) * rx(-0.02 * breath),
        arms: [
            Arm {
                shrug: 0.02 * breath,
                ..relaxed_arm(-0.03 + 0.03 * sin(ph + 0.4), 0.2 + 0.04 * breath)
            },
            Arm {
                shrug: 0.02 * breath,
                ..relaxed_arm(-0.03 + 0.03 * sin(ph + 0.9), 0.2 + 0.04 * breath)
            },
        ],
        legs: [planted(1.0, 0.0, 0.0, 0.0), planted(-1.0, 0.0, 0.0, 0.0)],
    }
}

/// Run-cycle foot for leg phase `p` in [0, 1): stance 0..0.36 then swing.
fn run_leg(s: f32, p: f32) -> Leg {
    let stance = 0.36;
    let (front, back) = (0.21, -0.21);
    if p < stance {
        let u = p / stance;
        let z = front + (back - front) * u;
        // Heel strike toes-up, flat, then push off onto the toes.
        let push = smoothstep(0.6, 1.0, u);
        let pitch = -0.15 * (1.0 - smoothstep(0.0, 0.2, u)) + 0.55 * push;
        Leg {
            ankle: Vec3::new(0.09 * s, ANKLE_Y + 0.12 * sin(pitch.max(0.0)), z),
            pitch,
        }
    } else {
        let u = (p - stance) / (1.0 - stance);
        let z = back + (front - back) * (0.5 - 0.5 * cos(PI * u));
        let early = u * (1.3 - 0.3 * u);
        let lift = 0.26 * sin(PI * early) + 0.12 * sin(0.55) * (1.0 - smoothstep(0.0, 0.3, u));
        let pitch = 0.55 + (-0.15 - 0.55) * smoothstep(0.0, 1.0, u);
        Leg {
            ankle: Vec3::new(0.09 * s, ANKLE_Y + lift, z),
            pitch,
        }
    }
}

fn run(t: f32) -> Body {
    let period = 0.7;
    let p = t / period;
    let ph = TAU * p;
    let bob = cos(TAU * 2.0 * (p - 0.18));
    let arm = |side_phase: f32| {
        let c = cos(ph + side_phase);
        Arm {
            lower: 0.42,
            swing: 0.62 * c - 0.12,
            elbow: 1.45 - 0.3 * c,
            shrug: 0.03,
        }
    };
    Body {
        hips: Vec3::new(0.0, 0.92 - 0.02 * bob, 0.0),
        hips_rot: ry(-0.13 * cos(ph)) * rz(0.035 * sin(ph)),
        spine: rx(0.14) * ry(0.09 * cos(ph)),
        chest: rx(0.05) * ry(0.12 * cos(ph)),
        neck: ry(-0.05 * cos(ph)),
        head: rx(-0.14) * ry(-0.05 * cos(ph)),
        arms: [arm(0.0), arm(PI)],
        legs: [run_leg(1.0, p % 1.0), run_leg(-1.0, (p + 0.5) % 1.0)],
    }
}

/// Jump keys: (time, hips dy, foot lift, spine pitch, arm swing, elbow, foot pitch).
const JUMP_KEYS: [[f32; 7]; 8] = [
    [0.00, 0.000, 0.00, 0.00, 0.00, 0.20, 0.00],
    [0.20, -0.200, 0.00, 0.38, 0.85, 0.35, 0.00],
    [0.33, 0.060, 0.03, -0.04, -2.10, 0.40, 0.60],
    [0.42, 0.150, 0.30, 0.14, -1.70, 0.60, 0.35],
    [0.50, 0.175, 0.44, 0.26, -1.30, 0.80, 0.20],
    [0.62, 0.000, 0.00, 0.10, -0.70, 0.50, 0.05],
    [0.72, -0.150, 0.00, 0.32, -0.35, 0.45, 0.00],
    [0.90, 0.000, 0.00, 0.00, 0.00, 0.20, 0.00],
];

fn jump(t: f32) -> Body {
    let k = &JUMP_KEYS;
    let mut i = 0;
    while i + 2 < k.len() && t > k[i + 1][0] {
        i += 1;
    }
    let u = smoothstep(k[i][0], k[i + 1][0], t);
    let v: Vec<f32> = (1..7)
        .map(|c| k[i][c] + (k[i + 1][c] - k[i][c]) * u)
        .collect();
    let (dy, lift, spine, swing, elbow, pitch) = (v[0], v[1], v[2], v[3], v[4], v[5]);
    Body {
        hips: Vec3::new(0.0, STAND_Y + dy, 0.0),
        hips_rot: rx(0.3 * spine),
        spine: rx(0.5 * spine),
        chest: rx(0.4 * spine),
        neck: Quat::IDENTITY,
        head: rx(-0.9 * spine),
        arms: [relaxed_arm(swing, elbow), relaxed_arm(swing, elbow)],
        legs: [
            planted(1.0, lift, 0.02 * lift, pitch),
            planted(-1.0, lift, 0.02 * lift, pitch),
        ],
    }
}

pub fn clips() -> Vec<Clip> {
    vec![
        sample("idle", 2.0, true, idle),
        sample("run", 0.7, true, run),
        sample("jump", 0.9, false, jump),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loops_are_seamless_and_unit() {
        for c in clips() {
            let (a, b) = (&c.poses[0], c.poses.last().unwrap());
            if c.looping {
                assert_eq!(a.hips, b.hips, "{}", c.name);
                for (x, y) in a.rot.iter().zip(&b.rot) {
                    assert!((*x - *y).length() < 1e-6 || (*x + *y).length() < 1e-6);
                }
            }
            for p in &c.poses {
                for q in &p.rot {
                    assert!((q.length() - 1.0).abs() < 1e-4);
                }
            }
        }
    }
}

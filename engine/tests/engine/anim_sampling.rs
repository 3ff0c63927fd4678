//! Channel sampling edge cases: before the first key, after the last, single key, STEP,
//! LINEAR (shortest-path slerp), CUBICSPLINE (Hermite with tangents scaled by the interval),
//! and Pose behaviour (apply, blend, world update, no allocation).

use dermis_engine::anim::{joint_palette, sample_quat, sample_vec3, Pose};
use dermis_engine::asset::{
    AnimationClip, Channel, Interpolation, Model, Node, Property, Skin, Transform,
};
use glam::{Mat4, Quat, Vec3};

fn ch(property: Property, interpolation: Interpolation, times: &[f32], values: &[f32]) -> Channel {
    Channel {
        node: 0,
        property,
        interpolation,
        times: times.to_vec(),
        values: values.to_vec(),
    }
}

fn close3(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

fn close_q(a: Quat, b: Quat) -> bool {
    // Same rotation (q and -q are equal rotations).
    a.dot(b).abs() > 1.0 - 1e-6
}

#[test]
fn linear_vec3_clamps_and_interpolates() {
    let c = ch(
        Property::Translation,
        Interpolation::Linear,
        &[1.0, 3.0],
        &[0., 0., 0., 2., 4., 6.],
    );
    assert!(
        close3(sample_vec3(&c, -5.0), Vec3::ZERO),
        "before first key → first value"
    );
    assert!(close3(sample_vec3(&c, 1.0), Vec3::ZERO));
    assert!(close3(sample_vec3(&c, 2.0), Vec3::new(1., 2., 3.)));
    assert!(close3(sample_vec3(&c, 2.5), Vec3::new(1.5, 3., 4.5)));
    assert!(close3(sample_vec3(&c, 3.0), Vec3::new(2., 4., 6.)));
    assert!(
        close3(sample_vec3(&c, 99.0), Vec3::new(2., 4., 6.)),
        "after last key → last value"
    );
    assert!(
        close3(sample_vec3(&c, f32::NAN), Vec3::ZERO),
        "NaN time → first key"
    );
}

#[test]
fn single_key_is_constant() {
    for interp in [Interpolation::Step, Interpolation::Linear] {
        let c = ch(Property::Scale, interp, &[0.5], &[2., 3., 4.]);
        for t in [-1.0, 0.0, 0.5, 10.0] {
            assert!(close3(sample_vec3(&c, t), Vec3::new(2., 3., 4.)));
        }
    }
    let c = ch(
        Property::Scale,
        Interpolation::CubicSpline,
        &[0.5],
        &[9., 9., 9., 2., 3., 4., 7., 7., 7.],
    );
    assert!(
        close3(sample_vec3(&c, 3.0), Vec3::new(2., 3., 4.)),
        "cubic: the value, not a tangent"
    );
    let q = Quat::from_rotation_y(0.7);
    let c = ch(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0],
        &q.to_array(),
    );
    assert!(close_q(sample_quat(&c, 5.0), q));
}

#[test]
fn step_holds_previous_key() {
    let c = ch(
        Property::Translation,
        Interpolation::Step,
        &[0., 1., 2.],
        &[0., 0., 0., 1., 1., 1., 2., 2., 2.],
    );
    assert!(close3(sample_vec3(&c, 0.0), Vec3::ZERO));
    assert!(close3(sample_vec3(&c, 0.999), Vec3::ZERO));
    assert!(close3(sample_vec3(&c, 1.0), Vec3::ONE));
    assert!(close3(sample_vec3(&c, 1.5), Vec3::ONE));
    assert!(close3(sample_vec3(&c, 2.5), Vec3::splat(2.)));
}

#[test]
fn cubic_spline_hermite_with_scaled_tangents() {
    // Keys at t=1 and t=3 (interval 2), values 0 and 1, out-tangent of key 0 = 1 (per second),
    // in-tangent of key 1 = 0.5. Spec: p(s) = h00 p0 + h10 (dt·b0) + h01 p1 + h11 (dt·a1).
    let values = [
        9., 9., 9., /* a0 (unused) */ 0., 0., 0., /* v0 */ 1., 2., 0., /* b0 */
        0.5, 0., 0., /* a1 */ 1., 1., 1., /* v1 */ 9., 9., 9., /* b1 (unused) */
    ];
    let c = ch(
        Property::Translation,
        Interpolation::CubicSpline,
        &[1.0, 3.0],
        &values,
    );
    let dt = 2.0f32;
    for s in [0.0f32, 0.25, 0.5, 0.75] {
        let (s2, s3) = (s * s, s * s * s);
        let h00 = 2. * s3 - 3. * s2 + 1.;
        let h10 = s3 - 2. * s2 + s;
        let h01 = -2. * s3 + 3. * s2;
        let h11 = s3 - s2;
        let p0 = Vec3::ZERO;
        let p1 = Vec3::ONE;
        let m0 = dt * Vec3::new(1., 2., 0.);
        let m1 = dt * Vec3::new(0.5, 0., 0.);
        let want = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
        assert!(close3(sample_vec3(&c, 1.0 + s * dt), want), "s={s}");
    }
    assert!(close3(sample_vec3(&c, 0.0), Vec3::ZERO));
    assert!(close3(sample_vec3(&c, 5.0), Vec3::ONE));
    // Midpoint by hand: 0.5·0 + 0.125·(2,4,0) + 0.5·(1,1,1) − 0.125·(1,0,0) = (0.625, 1, 0.5).
    assert!(close3(sample_vec3(&c, 2.0), Vec3::new(0.625, 1.0, 0.5)));
}

#[test]
fn cubic_spline_quaternion_is_normalized() {
    let a = Quat::IDENTITY;
    let b = Quat::from_rotation_z(1.0);
    let zero = [0.0f32; 4];
    let mut values = Vec::new();
    for q in [a, b] {
        values.extend_from_slice(&zero);
        values.extend_from_slice(&q.to_array());
        values.extend_from_slice(&zero);
    }
    let c = ch(
        Property::Rotation,
        Interpolation::CubicSpline,
        &[0.0, 1.0],
        &values,
    );
    for t in [0.1, 0.5, 0.9] {
        let q = sample_quat(&c, t);
        assert!((q.length() - 1.0).abs() < 1e-6);
    }
    assert!(close_q(sample_quat(&c, 1.0), b));
}

#[test]
fn linear_quaternion_takes_the_shortest_path() {
    // Key 1 is stored with the opposite sign: +170° about Y as -q. Naive lerp would go the
    // long way round; the spec's slerp negates it when the dot product is negative.
    let a = Quat::from_rotation_y(0.0);
    let b = Quat::from_rotation_y(170f32.to_radians());
    let neg_b = -b;
    let mut values = a.to_array().to_vec();
    values.extend_from_slice(&neg_b.to_array());
    let c = ch(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0, 1.0],
        &values,
    );
    let mid = sample_quat(&c, 0.5);
    assert!(
        close_q(mid, Quat::from_rotation_y(85f32.to_radians())),
        "{mid:?}"
    );
    assert!((mid.length() - 1.0).abs() < 1e-6);
    // And a plain case: a quarter of the way from 0° to 90°.
    let mut values = a.to_array().to_vec();
    values.extend_from_slice(&Quat::from_rotation_x(std::f32::consts::FRAC_PI_2).to_array());
    let c = ch(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0, 4.0],
        &values,
    );
    assert!(close_q(
        sample_quat(&c, 1.0),
        Quat::from_rotation_x(std::f32::consts::FRAC_PI_8)
    ));
}

/// Three nodes: 0 root (translated), 1 child of 0, 2 skinned mesh node (not needed here).
fn chain_model() -> Model {
    let node = |parent, children: Vec<usize>, t: Vec3| Node {
        name: None,
        parent,
        children,
        local: Transform {
            translation: t,
            ..Default::default()
        },
        mesh: None,
        skin: None,
    };
    Model {
        source: "chain".into(),
        nodes: vec![
            node(None, vec![1], Vec3::new(0., 1., 0.)),
            node(Some(0), vec![], Vec3::new(0., 0., 2.)),
        ],
        roots: vec![0],
        meshes: vec![],
        skins: vec![Skin {
            name: None,
            joints: vec![0, 1],
            inverse_bind: vec![
                Mat4::IDENTITY,
                Mat4::from_translation(Vec3::new(0., -1., -2.)),
            ],
        }],
        materials: vec![],
        textures: vec![],
        animations: vec![AnimationClip {
            name: Some("turn".into()),
            duration: 1.0,
            channels: vec![Channel {
                node: 0,
                property: Property::Rotation,
                interpolation: Interpolation::Linear,
                times: vec![0.0, 1.0],
                values: [
                    Quat::IDENTITY.to_array(),
                    Quat::from_rotation_y(1.0).to_array(),
                ]
                .concat(),
            }],
        }],
        warnings: vec![],
    }
}

#[test]
fn pose_apply_blend_and_world() {
    let m = chain_model();
    let mut pose = Pose::new(&m);
    // Rest pose: child world = parent · child.
    assert!(close3(
        pose.worlds[1].transform_point3(Vec3::ZERO),
        Vec3::new(0., 1., 2.)
    ));
    let mut palette = [Mat4::ZERO; 2];
    joint_palette(&m, 0, &pose, &mut palette);
    assert!(
        palette[1].abs_diff_eq(Mat4::IDENTITY, 1e-6),
        "rest pose: world · IBM = I"
    );

    // t is clamped to [0, duration].
    pose.apply_clip(&m.animations[0], 5.0);
    assert!(close_q(pose.locals[0].rotation, Quat::from_rotation_y(1.0)));
    pose.update_world(&m);
    let want = Quat::from_rotation_y(1.0) * Vec3::new(0., 0., 2.) + Vec3::Y;
    assert!(close3(pose.worlds[1].transform_point3(Vec3::ZERO), want));

    // Crossfade halfway from rest toward the clip's end pose.
    pose.reset(&m);
    pose.blend_clip(&m.animations[0], 1.0, 0.5);
    assert!(close_q(pose.locals[0].rotation, Quat::from_rotation_y(0.5)));
    pose.blend_clip(&m.animations[0], 1.0, 0.0);
    assert!(
        close_q(pose.locals[0].rotation, Quat::from_rotation_y(0.5)),
        "weight 0: unchanged"
    );
    pose.blend_clip(&m.animations[0], 1.0, 1.0);
    assert!(
        close_q(pose.locals[0].rotation, Quat::from_rotation_y(1.0)),
        "weight 1 = apply"
    );
    // Untouched properties keep the rest values.
    assert!(close3(pose.locals[0].translation, Vec3::Y));
}

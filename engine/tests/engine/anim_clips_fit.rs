//! A user's character in the runner (issue 28, item 4, the asset half): its clips found by
//! name (overridable, a one-line error naming what is missing) and its size fitted to the
//! runner's height from its bind-pose bounds, whatever units its exporter chose.

use crate::external;

use dermis_engine::anim::{
    bind_pose_bounds, clip_by_role, find_clips, fit_to_height, ClipRole as Role,
};
use dermis_engine::asset::{load_gltf, Aabb, Model};
use glam::Vec3;

const RUNNER: [Role; 3] = [Role::Idle, Role::Run, Role::Jump];

fn character() -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/character.glb");
    load_gltf(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn clip_name(m: &Model, i: Option<usize>) -> &str {
    i.and_then(|i| m.animations[i].name.as_deref())
        .unwrap_or("-")
}

#[test]
fn the_project_characters_clips() {
    let m = character();
    let c = find_clips(&m, &[], &RUNNER).unwrap();
    assert_eq!(
        (c.idle, c.run, c.jump, c.death),
        (Some(0), Some(1), Some(2), None)
    );
    let e = find_clips(&m, &[], &[Role::Run, Role::Death]).unwrap_err();
    assert!(
        e.contains("no death clip found by name")
            && e.contains("its clips: \"idle\", \"run\", \"jump\""),
        "{e}"
    );
    assert!(e.contains("character.glb") && !e.contains('\n'), "{e}");
    // An explicit name overrides the search; one that names no clip is an error.
    let c = find_clips(&m, &[(Role::Death, "JUMP"), (Role::Idle, "#1")], &RUNNER).unwrap();
    assert_eq!((c.death, c.idle), (Some(2), Some(1)));
    let e = find_clips(&m, &[(Role::Run, "sprint")], &[]).unwrap_err();
    assert!(e.contains("no clip \"sprint\" for run"), "{e}");
    let e = find_clips(&m, &[(Role::Run, "#7")], &[]).unwrap_err();
    assert!(e.contains("no clip \"#7\" for run"), "{e}");
}

#[test]
fn words_beat_substrings_and_shorter_names_win() {
    let mut m = character();
    let names = [
        "Armature|RunningJump",
        "Armature|Jump",
        "Run_Loop_Fast",
        "Sprinting",
    ];
    m.animations.truncate(1);
    let clip = m.animations[0].clone();
    m.animations = names
        .iter()
        .map(|n| dermis_engine::asset::AnimationClip {
            name: Some(n.to_string()),
            ..clip.clone()
        })
        .collect();
    // jump: both have the word, the shorter name wins; run: "running" is a word of its own,
    // so "run" takes Run_Loop_Fast; idle: nothing.
    assert_eq!(clip_name(&m, clip_by_role(&m, Role::Jump)), "Armature|Jump");
    assert_eq!(clip_by_role(&m, Role::Run), Some(2));
    assert_eq!(clip_by_role(&m, Role::Idle), None);
    m.animations.remove(2);
    // No word "run": then "running" (the role's second word) is.
    assert_eq!(clip_by_role(&m, Role::Run), Some(0));
    m.animations.remove(0);
    // No word at all: a substring ("sprint" in "Sprinting").
    assert_eq!(clip_name(&m, clip_by_role(&m, Role::Run)), "Sprinting");
}

#[test]
fn the_external_characters_clips() {
    for name in external::EXTERNAL_MODELS {
        let Some(path) = external::external_model(name) else {
            continue;
        };
        let m = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
        let found = find_clips(&m, &[], &RUNNER);
        println!("{name}: {found:?}");
        if name.contains("Quaternius") {
            let c = found.unwrap();
            let got: Vec<&str> = Role::ALL.iter().map(|r| clip_name(&m, c.get(*r))).collect();
            assert_eq!(
                got,
                [
                    "HumanArmature|Female_Idle",
                    "HumanArmature|Female_Run",
                    "HumanArmature|Female_Jump",
                    "HumanArmature|Female_Death",
                ]
            );
        } else if name.contains("Fox") {
            let e = found.unwrap_err();
            assert!(
                e.contains("no idle, jump clip") && e.contains("\"Survey\", \"Walk\", \"Run\""),
                "{e}"
            );
            let c =
                find_clips(&m, &[(Role::Idle, "survey"), (Role::Jump, "Walk")], &RUNNER).unwrap();
            assert_eq!(clip_name(&m, c.run), "Run");
        } else {
            // One unnamed clip: named by index.
            let e = found.unwrap_err();
            assert!(e.contains("#0 (unnamed)"), "{e}");
            let all = [(Role::Idle, "#0"), (Role::Run, "#0"), (Role::Jump, "#0")];
            assert!(find_clips(&m, &all, &RUNNER).is_ok());
        }
    }
}

fn height(b: Aabb) -> f32 {
    b.max.y - b.min.y
}

/// Bounds after the fit.
fn fitted(b: Aabb, h: f32) -> Aabb {
    let f = fit_to_height(b, h).unwrap();
    Aabb {
        min: f.apply(b.min),
        max: f.apply(b.max),
    }
}

#[test]
fn any_size_is_fitted_to_the_runner() {
    let m = character();
    let b = bind_pose_bounds(&m).unwrap();
    assert!((height(b) - 1.755).abs() < 0.01, "{b:?}");
    assert!(b.min.y.abs() < 0.01, "feet on the floor: {b:?}");

    // The same figure exported 30 cm tall (its armature scaled, as exporters do).
    let mut small = m.clone();
    let root = small
        .nodes
        .iter()
        .position(|n| n.name.as_deref() == Some("hips"))
        .unwrap();
    small.nodes[root].local.scale = Vec3::splat(0.30 / 1.755);
    let s = bind_pose_bounds(&small).unwrap();
    assert!((height(s) - 0.30).abs() < 0.005, "{s:?}");

    let (a, c) = (fitted(b, 1.75), fitted(s, 1.75));
    for (p, q) in [(a.min, c.min), (a.max, c.max)] {
        assert!((p - q).length() < 1e-3, "{a:?} vs {c:?}");
    }
    assert!((height(a) - 1.75).abs() < 1e-4 && a.min.y.abs() < 1e-5);
    assert!(((a.min + a.max) * 0.5).x.abs() < 1e-5 && ((a.min + a.max) * 0.5).z.abs() < 1e-5);

    let flat = Aabb {
        min: Vec3::ZERO,
        max: Vec3::new(1.0, 0.0, 1.0),
    };
    assert!(fit_to_height(flat, 1.75).is_none());
    assert!(fit_to_height(b, -1.0).is_none());
    assert!(fit_to_height(b, f32::NAN).is_none());
}

/// The Quaternius woman as her file poses her is 4.6 m tall (an exporter's 100× armature
/// scale); fitted, she is the runner's height, standing on the floor.
#[test]
fn an_export_a_hundred_times_too_large() {
    let Some(path) = external::external_model("QuaterniusWomanTankTop/WomanTankTop.glb") else {
        return;
    };
    let m = load_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let b = bind_pose_bounds(&m).unwrap();
    println!(
        "WomanTankTop bind-pose bounds {b:?}, height {:.2} m",
        height(b)
    );
    assert!(height(b) > 4.0 && height(b) < 5.0, "{b:?}");
    let a = fitted(b, 1.75);
    assert!(
        (height(a) - 1.75).abs() < 1e-4 && a.min.y.abs() < 1e-4,
        "{a:?}"
    );
}

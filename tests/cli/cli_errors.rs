//! Bad input to the CLI gives a one-line error and a non-zero exit status, never a panic.

use crate::external;

use std::process::Command;

fn dermis(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The stderr lines that count: not blank, and not libwayland's `XDG_RUNTIME_DIR` complaint
/// (which the windowed commands may still print in containers).
fn error_lines(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.contains("XDG_RUNTIME_DIR"))
        .collect()
}

fn assert_one_line_error(args: &[&str], needle: &str) {
    let (ok, stderr) = dermis(args);
    assert!(!ok, "{args:?} succeeded");
    assert!(
        !stderr.contains("memory allocation") && !stderr.contains("stack backtrace"),
        "{args:?}: {stderr}"
    );
    let lines = error_lines(&stderr);
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: expected one line, got:\n{stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("internal error"),
        "{args:?}: {stderr}"
    );
    assert!(
        stderr.contains(needle),
        "{args:?}: `{needle}` not in: {stderr}"
    );
}

#[test]
fn missing_file() {
    assert_one_line_error(&["pose", "--model", "/nonexistent/x.glb"], "x.glb");
    assert_one_line_error(
        &[
            "render",
            "--model",
            "/nonexistent/y.gltf",
            "--out",
            "/tmp/dermis-never.png",
        ],
        "y.gltf",
    );
}

#[test]
fn corrupt_gltf() {
    let dir = std::env::temp_dir().join(format!("dermis-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("corrupt.glb");
    std::fs::write(&bad, b"glTF\x02\x00\x00\x00garbage").unwrap();
    assert_one_line_error(&["pose", "--model", bad.to_str().unwrap()], "corrupt.glb");
    let json = dir.join("broken.gltf");
    std::fs::write(&json, b"{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [").unwrap();
    assert_one_line_error(&["pose", "--model", json.to_str().unwrap()], "broken.gltf");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_names_and_bad_values() {
    assert_one_line_error(
        &["render", "--shading", "phong", "--out", "/tmp/x.png"],
        "phong",
    );
    assert_one_line_error(
        &["render", "--material", "marble", "--out", "/tmp/x.png"],
        "marble",
    );
    assert_one_line_error(&["render", "--size", "0x10", "--out", "/tmp/x.png"], "0x10");
    assert_one_line_error(
        &["render", "--light", "1,nan,2", "--out", "/tmp/x.png"],
        "1,nan,2",
    );
}

#[test]
fn out_of_range_clip() {
    let cesium = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/character.glb");
    assert_one_line_error(
        &["pose", "--model", cesium.to_str().unwrap(), "--clip", "99"],
        "clip",
    );
}

/// A user's character with a skin choice or a clip its file lacks: one line naming what is
/// missing and what the file has, before any window or GPU work.
#[test]
fn users_character_bad_choices() {
    let Some(woman) = external::external_model("QuaterniusWomanTankTop/WomanTankTop.glb") else {
        return;
    };
    let woman = woman.to_str().unwrap();
    let out = tmp_dir("users_character").join("x.png");
    let out = out.to_str().unwrap();
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "--model", woman, "--out", out];
        args.extend_from_slice(extra);
        args.into_iter().map(str::to_string).collect::<Vec<_>>()
    };
    let cases: [(Vec<String>, &str); 4] = [
        (render(&["--skin", "Bogus"]), "no material \"Bogus\""),
        (render(&["--skin", "Skin=nopreset"]), "unknown preset"),
        (
            ["play", "--model", woman, "--run-clip", "nosuchclip"]
                .map(str::to_string)
                .to_vec(),
            "no clip \"nosuchclip\" for run",
        ),
        (
            ["--model", woman, "--death-clip", "nosuch"]
                .map(str::to_string)
                .to_vec(),
            "no clip \"nosuch\" for death",
        ),
    ];
    for (args, needle) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_one_line_error(&args, needle);
    }
}

#[test]
fn profile_bad_input() {
    let h = |v: &'static str| ["profile", "--shading", "ward", "--light-height-mm", v];
    assert_one_line_error(
        &["profile", "--shading", "phong", "--light-height-mm", "5"],
        "phong",
    );
    for bad in ["0", "-1", "nan", "inf", "1e9"] {
        assert_one_line_error(&h(bad), "light-height-mm");
    }
    assert_one_line_error(&["profile", "--shading", "ward"], "required");
    for (edges, needle) in [
        ("0,2,1", "increasing"),
        ("0,1,1", "increasing"),
        ("-1,2", "out of range"),
        ("0,nan", "finite"),
        ("5", "at least 2"),
        ("0,x", "x"),
    ] {
        let mut args = h("5").to_vec();
        args.extend(["--edges-mm", edges]);
        assert_one_line_error(&args, needle);
    }
    for eta in ["0", "-1", "nan"] {
        let mut args = h("5").to_vec();
        args.extend(["--eta", eta]);
        assert_one_line_error(&args, "eta");
    }
    for g in ["1", "-1", "1.5", "nan"] {
        let mut args = h("5").to_vec();
        args.extend(["--g", g]);
        assert_one_line_error(&args, "--g");
    }
}

#[test]
fn bench_shading_and_shaders_bad_input() {
    let out = std::env::temp_dir().join(format!("dermis-bench-cli-{}", std::process::id()));
    let out = out.to_str().unwrap();
    for rounds in ["0", "1", "100000"] {
        assert_one_line_error(
            &["bench", "shading", "--out", out, "--rounds", rounds],
            "rounds",
        );
    }
    assert_one_line_error(
        &[
            "bench",
            "shading",
            "--out",
            out,
            "--mali",
            "/nonexistent/m.json",
        ],
        "m.json",
    );
    assert_one_line_error(&["shaders", "--spirv", "/proc/dermis-no"], "dermis-no");
    let _ = std::fs::remove_dir_all(out);
}

fn tmp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("dermis-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Numeric flags are range-checked before anything is allocated or loaded: absurd values give
/// one line naming the flag (and, for counts below the minimum, the minimum), never an abort.
#[test]
fn numeric_flags_out_of_range() {
    let dir = tmp_dir("numeric");
    let out = dir.join("o");
    let out = out.to_str().unwrap();
    let png = dir.join("o.png");
    let png = png.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["soak", "--seconds", "1e12", "--out", out], "--seconds"),
        (&["soak", "--seconds", "0", "--out", out], "--seconds"),
        (&["soak", "--seconds", "-5", "--out", out], "--seconds"),
        (&["soak", "--seconds", "nan", "--out", out], "--seconds"),
        (&["soak", "--seconds", "inf", "--out", out], "--seconds"),
        (&["soak", "--target-fps", "0", "--out", out], "--target-fps"),
        (
            &["soak", "--target-fps", "nan", "--out", out],
            "--target-fps",
        ),
        (
            &["play", "--autoplay", "--frames", "100000000000"],
            "maximum",
        ),
        (&["play", "--autoplay", "--frames", "0"], "minimum of 121"),
        (&["play", "--autoplay", "--frames", "120"], "minimum of 121"),
        (&["play", "--autoplay", "--frames", "-1"], "--frames"),
        (&["play", "--fps", "0"], "--fps"),
        (&["play", "--fps", "NaN"], "--fps"),
        (&["render", "--time=-1", "--out", png], "--time"),
        (&["render", "--time", "-1", "--out", png], "--time"),
        (&["render", "--time", "NaN", "--out", png], "--time"),
        (&["render", "--time", "inf", "--out", png], "--time"),
        (&["render", "--time", "1e30", "--out", png], "--time"),
        (&["pose", "--model", "x.glb", "--time", "NaN"], "--time"),
        (&["pose", "--model", "x.glb", "--time=-1"], "--time"),
        (&["bench", "effects", "--rounds", "0"], "minimum of 2"),
        (&["bench", "effects", "--rounds", "1"], "minimum of 2"),
        (&["bench", "effects", "--frames", "0"], "minimum of 10"),
        (
            &["bench", "effects", "--rounds", "99999999999999999999"],
            "maximum",
        ),
        (&["bench", "frame", "--rounds", "1"], "minimum of 2"),
        (&["bench", "frame", "--rounds", "0"], "minimum of 2"),
        (&["bench", "frame", "--frames", "9"], "minimum of 10"),
        (&["bench", "frame", "--frames", "1e9"], "--frames"),
        (&["--frames", "0"], "minimum of 1"),
        (&["demo", "--frames", "100000000000"], "maximum"),
        (&["surfaces", "--count", "0"], "minimum of 1"),
    ];
    for (args, needle) in cases {
        assert_one_line_error(args, needle);
    }
    assert!(
        !std::path::Path::new(out).exists(),
        "a rejected soak made its --out"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Output paths are checked before the work starts: an unwritable place or a non-PNG image
/// name fails at once, with nothing loaded or rendered.
#[test]
fn output_paths_checked_first() {
    let dir = tmp_dir("outputs");
    let jpg = dir.join("x.jpg");
    let jpg = jpg.to_str().unwrap();
    let a_dir = dir.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--out", jpg], "use .png"),
        (&["render", "--out", "/proc/dermis-no/x.png"], "dermis-no"),
        (&["render", "--out", "/proc/x.png"], "/proc"),
        (&["render", "--out", a_dir], "use .png"),
        (
            &["soak", "--seconds", "1", "--out", "/proc/dermis-no"],
            "dermis-no",
        ),
        (&["play", "--screenshots", "/proc/dermis-no"], "dermis-no"),
        (
            &["bench", "frame", "--out", "/proc/dermis-no/b.json"],
            "dermis-no",
        ),
        (&["bench", "frame", "--out", a_dir], "use .json"),
        (&["--frames", "1", "--screenshot", jpg], "use .png"),
        (
            &["--frames", "1", "--screenshot", "/proc/dermis-no/s.png"],
            "dermis-no",
        ),
        (&["demo", "--frames", "1", "--screenshot", jpg], "use .png"),
    ];
    for (args, needle) in cases {
        let start = std::time::Instant::now();
        assert_one_line_error(args, needle);
        assert!(
            start.elapsed() < std::time::Duration::from_secs(20),
            "{args:?} took {:?}",
            start.elapsed()
        );
    }
    assert!(!std::path::Path::new(jpg).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Offscreen commands need no display: with `XDG_RUNTIME_DIR` unset (containers) they print
/// nothing on stderr (libwayland's probe used to complain twice).
#[test]
fn headless_render_is_quiet_without_xdg_runtime_dir() {
    let dir = tmp_dir("quiet");
    let png = dir.join("r.png");
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(["render", "--size", "16x16", "--out", png.to_str().unwrap()])
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && stderr.contains("adapter") {
        eprintln!("skipping: no GPU adapter: {stderr}");
        return;
    }
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    assert!(png.is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A settings file's bad lines are reported (file, line, what was dropped); the rest is kept.
#[test]
fn settings_file_bad_lines_are_reported() {
    let dir = tmp_dir("settings");
    let path = dir.join("settings.txt");
    std::fs::write(&path, "shading=bogus\nbest=-5\nbest=3\n").unwrap();
    // No display: the window fails after the settings are read.
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(["--frames", "1", "--settings", path.to_str().unwrap()])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    let lines = error_lines(&stderr);
    let file = path.display().to_string();
    assert!(
        lines
            .iter()
            .any(|l| l.contains(&file) && l.contains("line 1") && l.contains("bogus")),
        "{stderr}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.contains(&file) && l.contains("line 2") && l.contains("-5")),
        "{stderr}"
    );
    assert!(!lines.iter().any(|l| l.contains("line 3")), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every `--shading` help lists the model names.
#[test]
fn shading_help_lists_the_models() {
    for args in [
        &["--help"][..],
        &["demo", "--help"],
        &["render", "--help"],
        &["play", "--help"],
        &["soak", "--help"],
        &["bench", "effects", "--help"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
            .args(args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}");
        let text = String::from_utf8_lossy(&out.stdout);
        let line = text
            .lines()
            .find(|l| l.contains("--shading"))
            .unwrap_or_else(|| panic!("{args:?}: no --shading in\n{text}"));
        for name in ["ward", "oss-stable", "burley", "tabulated", "preintegrated"] {
            assert!(line.contains(name), "{args:?}: `{name}` not in {line}");
        }
    }
}

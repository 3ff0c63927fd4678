//! Bad input to the CLI gives a one-line error and a non-zero exit status, never a panic.

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

fn assert_one_line_error(args: &[&str], needle: &str) {
    let (ok, stderr) = dermis(args);
    assert!(!ok, "{args:?} succeeded");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
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
        ("-1,2", "≥ 0"),
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

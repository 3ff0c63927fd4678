//! A real window under Xvfb: `dermis --frames 60 --screenshot FILE` presents 60 frames and
//! saves the last one, which must show the lit character on the floor. A `--frames` run is a
//! smoke test: it neither reads nor writes the user's settings.

use std::process::Command;

#[test]
fn window_presents_and_screenshots_under_xvfb() {
    let have_xvfb = Command::new("xvfb-run").arg("--help").output().is_ok();
    if !have_xvfb {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("xvfb-run is required in CI (apt: xvfb xauth)");
        }
        eprintln!("skipping: xvfb-run not installed (apt install xvfb xauth)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("dermis-smoke-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("window.png");
    // The user's saved settings (a model, a best score) must not change what it shows.
    let config = dir.join("config");
    let saved = config.join("dermis/settings.txt");
    std::fs::create_dir_all(saved.parent().unwrap()).unwrap();
    let text = "shading=ward\nbest=999\n";
    std::fs::write(&saved, text).unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(env!("CARGO_BIN_EXE_dermis"))
        .args(["--frames", "60", "--screenshot"])
        .arg(&shot)
        .env("WINIT_UNIX_BACKEND", "x11")
        .env("XDG_CONFIG_HOME", &config)
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "dermis window failed:\nstdout: {}\nstderr: {}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let img = image::open(&shot).unwrap().to_rgba8();
    assert!(
        img.width() >= 640 && img.height() >= 360,
        "{}x{}",
        img.width(),
        img.height()
    );
    // Not a blank frame: many distinct colours, and some warm (skin) pixels.
    let mut colours = std::collections::HashSet::new();
    let mut warm = 0;
    for p in img.pixels() {
        colours.insert((p[0] / 8, p[1] / 8, p[2] / 8));
        if p[0] as i32 > p[2] as i32 + 20 && p[0] > 60 {
            warm += 1;
        }
    }
    assert!(colours.len() > 50, "only {} colours", colours.len());
    assert!(
        warm > 500,
        "only {warm} warm pixels: is the character visible?"
    );
    assert_eq!(
        std::fs::read_to_string(&saved).unwrap(),
        text,
        "settings touched"
    );
    // Without XDG_RUNTIME_DIR (a container, CI) nothing complains about it.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "stderr: {stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

//! `dermis soak` end to end: the real binary writes a well-formed report (no timing
//! thresholds: tests run in debug on whatever adapter there is; CI runs a longer release soak).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::Value;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dermis-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}\n{text}", path.display()))
}

fn check_frames_jsonl(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let mut n = 0;
    // A killed run may end in a partial line (no newline): ignore it.
    let whole = text.rfind('\n').map_or("", |i| &text[..i]);
    for line in whole.lines() {
        let f: Value = serde_json::from_str(line).unwrap_or_else(|e| panic!("{e}: {line}"));
        for key in [
            "frame",
            "t_s",
            "cpu_ms",
            "submit_ms",
            "gpu_ms",
            "present_periods",
            "allocs",
            "tier",
            "model",
            "coverage",
            "lit",
        ] {
            assert!(f.get(key).is_some(), "frame record lacks {key}: {line}");
        }
        assert!(f["cpu_ms"].as_f64().unwrap() >= 0.0);
        n += 1;
    }
    n
}

#[test]
fn soak_writes_report_chart_and_summary() {
    let dir = tmp_dir("soak");
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(["soak", "--seconds", "30", "--size", "640x360", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "soak failed:\nstdout: {stdout}\nstderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    for word in [
        "p50",
        "p99",
        "over the",
        "stability",
        "memory",
        "present intervals",
        "tiers",
    ] {
        assert!(stdout.contains(word), "summary lacks `{word}`:\n{stdout}");
    }

    let report = read_json(&dir.join("soak.json"));
    assert_eq!(report["format"], "dermis-soak/1");
    assert_eq!(report["status"], "complete");
    let config = &report["config"];
    assert_eq!(config["seconds"].as_f64(), Some(30.0));
    // No --shading: the one default is tier 0.
    let default = dermis_engine::shading::ShadingModel::DEFAULT.name();
    assert_eq!(config["tiers"][0], default);
    assert!(config["adapter"].is_string());
    let seconds = report["seconds"].as_array().expect("seconds");
    assert!(!seconds.is_empty());
    for s in seconds {
        for key in [
            "t_s",
            "frames",
            "fps",
            "cpu_ms_mean",
            "rss_mb",
            "tier",
            "allocs",
        ] {
            assert!(s.get(key).is_some(), "second record lacks {key}: {s}");
        }
    }
    if cfg!(target_os = "linux") {
        assert!(seconds[0]["rss_mb"].as_f64().unwrap() > 1.0);
    }
    let s = &report["summary"];
    let frames = s["frames"].as_u64().expect("frames");
    assert!(frames > 0);
    for group in ["frame_ms", "cpu_frame_ms"] {
        for q in ["p50", "p95", "p99", "max"] {
            assert!(s[group][q].as_f64().is_some(), "{group}.{q}: {s}");
        }
    }
    for key in [
        "frames_over_budget",
        "stability_pct",
        "stability_windows",
        "memory_growth_mb_per_min",
        "tier_frames",
        "tier_changes",
        "governor_changes",
        "gpu_objects_constant",
        "gpu_frame_ms",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}: {s}");
    }
    assert_eq!(
        s["stability_windows"], 10,
        "runs under 5 min use 10 windows"
    );
    let h = &s["present_histogram"];
    let total: u64 = ["on_time", "late_1", "late_2", "late_3_plus"]
        .iter()
        .map(|k| h[k].as_u64().expect(k))
        .sum();
    assert!(total <= frames);
    let tier_total: u64 = s["tier_frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(tier_total, frames);
    // The pipelines of every tier exist from load: tier changes create no GPU objects.
    assert_eq!(s["gpu_objects_constant"], true, "{s}");

    assert_eq!(check_frames_jsonl(&dir.join("frames.jsonl")) as u64, frames);
    let png = std::fs::read(dir.join("soak.png")).expect("chart");
    assert!(png.starts_with(b"\x89PNG") && png.len() > 1000);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_killed_soak_keeps_its_data() {
    let dir = tmp_dir("soak-killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(["soak", "--seconds", "120", "--size", "320x180", "--out"])
        .arg(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let (json, frames) = (dir.join("soak.json"), dir.join("frames.jsonl"));
    // Killed once the report exists and frames have been written (however slow the machine:
    // the test is that what was written survives the kill, not how fast it was written).
    let whole_line = |p: &Path| std::fs::read_to_string(p).is_ok_and(|t| t.contains('\n'));
    let start = Instant::now();
    while !(json.exists() && whole_line(&frames)) && start.elapsed() < Duration::from_secs(90) {
        std::thread::sleep(Duration::from_millis(100));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let report = read_json(&json);
    assert_eq!(report["status"], "running");
    assert!(!report["seconds"].as_array().unwrap().is_empty());
    assert!(check_frames_jsonl(&frames) > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

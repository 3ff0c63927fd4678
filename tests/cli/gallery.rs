//! The gallery (docs/gallery/) is what `dermis render` produces now: every line of
//! docs/gallery/shots.txt is rendered again by the binary and compared with its committed
//! image, and every committed image has its line. Regenerate with `bash tools/gallery.sh`.

use crate::external;

use std::path::{Path, PathBuf};
use std::process::Command;

fn gallery() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/gallery")
}

/// (name, `dermis render` arguments) per non-comment line of shots.txt.
fn shots() -> Vec<(String, Vec<String>)> {
    let list = std::fs::read_to_string(gallery().join("shots.txt")).unwrap();
    list.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            let mut words = l.split_whitespace().map(str::to_owned);
            let name = words.next().unwrap();
            (name, words.collect())
        })
        .collect()
}

#[test]
fn every_gallery_image_has_its_render_command() {
    let names: Vec<String> = shots().into_iter().map(|(n, _)| n).collect();
    assert!(!names.is_empty());
    for entry in std::fs::read_dir(gallery()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "png") {
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(
                names.contains(&stem),
                "{} is not made by docs/gallery/shots.txt (add its line or delete it)",
                path.display()
            );
        }
    }
}

/// Tolerance: mean |Δ| ≤ 1/255 and at most 0.5 % of channels off by more than 24/255 (a
/// driver may move an edge, not the shading).
#[test]
fn gallery_images_match_what_dermis_render_produces() {
    let tmp = std::env::temp_dir().join(format!("dermis-gallery-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let mut failures = Vec::new();
    for (name, args) in shots() {
        // A shot of a third-party character needs `../shared` (CI has it).
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let outside = args.iter().filter(|a| a.starts_with("../shared/"));
        if !outside
            .into_iter()
            .all(|a| external::present(&root.join(a)))
        {
            continue;
        }
        let out = tmp.join(format!("{name}.png"));
        let run = Command::new(env!("CARGO_BIN_EXE_dermis"))
            .arg("render")
            .args(&args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "dermis render {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&run.stderr)
        );
        let fresh = image::open(&out).unwrap().to_rgba8();
        let committed_path = gallery().join(format!("{name}.png"));
        let committed = image::open(&committed_path)
            .unwrap_or_else(|e| panic!("{}: {e}", committed_path.display()))
            .to_rgba8();
        if fresh.dimensions() != committed.dimensions() {
            failures.push(format!(
                "{name}: {:?} rendered, {:?} committed",
                fresh.dimensions(),
                committed.dimensions()
            ));
            continue;
        }
        let diffs: Vec<u8> = fresh
            .as_raw()
            .iter()
            .zip(committed.as_raw())
            .map(|(a, b)| a.abs_diff(*b))
            .collect();
        let mean = diffs.iter().map(|d| *d as f64).sum::<f64>() / diffs.len() as f64;
        let big = diffs.iter().filter(|d| **d > 24).count() as f64 / diffs.len() as f64;
        println!(
            "{name}: mean |Δ| {mean:.3}/255, {:.3} % off by > 24",
            big * 100.0
        );
        if mean > 1.0 || big > 0.005 {
            failures.push(format!(
                "{name}: mean |Δ| {mean:.2}/255, {:.2} % off by > 24",
                big * 100.0
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(
        failures.is_empty(),
        "the gallery no longer matches `dermis render` (regenerate with `bash tools/gallery.sh \
         target/debug/dermis`):\n{}",
        failures.join("\n")
    );
}

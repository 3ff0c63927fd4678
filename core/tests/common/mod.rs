//! Helpers shared by dermis-core's integration tests (they also run on Android bionic, under
//! qemu: `cargo xtask android-test`; the paths below are the host's, compiled in).
#![allow(dead_code)]

use std::path::PathBuf;

use dermis_core::app::{Session, Viewport};
use dermis_core::ui::Rect;
use glam::{Vec3, Vec4Swizzles};

/// The folder holding third-party models, outside the repository.
pub fn external_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/assets-external")
}

/// A third-party model by its path under `../shared/assets-external` (e.g.
/// `"Fox/Fox.glb"`). When it is missing: panics if `CI=true` (CI must have them), otherwise
/// prints why to stderr and returns `None` so the caller can skip.
pub fn external_model(name: &str) -> Option<PathBuf> {
    let path = external_dir().join(name);
    if path.is_file() {
        return Some(path);
    }
    let why = format!("external model {} not found", path.display());
    if std::env::var("CI").map(|v| v == "true").unwrap_or(false) {
        panic!("{why} (CI=true: third-party models are required)");
    }
    // Written to stderr directly: libtest captures `eprintln!` of passing tests, and a skip
    // the user never sees is a hidden one.
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipping: {why}");
    None
}

/// The five third-party models the tests use.
pub const EXTERNAL_MODELS: [&str; 5] = [
    "CesiumMan/CesiumMan.glb",
    "Fox/Fox.glb",
    "RiggedFigure/RiggedFigure.glb",
    "RiggedSimple/RiggedSimple.glb",
    "QuaterniusWomanTankTop/WomanTankTop.glb",
];

/// The repository's test data folder, `tests/data` at the workspace root (where the
/// generators in `tools/hostile-corpus` and `tools/skin-golden` write it).
pub fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data")
}

/// Whether `a` lies inside `b` (logical units, 0.01 slack).
pub fn inside(a: &Rect, b: &Rect) -> bool {
    a.x >= b.x - 0.01
        && a.y >= b.y - 0.01
        && a.x + a.w <= b.x + b.w + 0.01
        && a.y + a.h <= b.y + b.h + 0.01
}

/// The screen rectangle (logical units) of the box `lo..hi` (world) as the session draws it.
pub fn on_screen(s: &Session, vp: &Viewport, lo: Vec3, hi: Vec3) -> Rect {
    let aspect = vp.width as f32 / vp.height as f32;
    let m = s.view().view_proj(aspect);
    let (w, h) = (vp.width as f32 / vp.scale, vp.height as f32 / vp.scale);
    let (mut a, mut b) = ([f32::MAX; 2], [f32::MIN; 2]);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let p = m * c.extend(1.0);
        assert!(p.w > 0.0);
        let ndc = p.xy() / p.w;
        let (x, y) = ((ndc.x + 1.0) * 0.5 * w, (1.0 - ndc.y) * 0.5 * h);
        a = [a[0].min(x), a[1].min(y)];
        b = [b[0].max(x), b[1].max(y)];
    }
    Rect::new(a[0], a[1], b[0] - a[0], b[1] - a[1])
}

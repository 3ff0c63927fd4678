//! Helpers shared by dermis-core's integration tests (they also run on Android bionic, under
//! qemu: `cargo xtask android-test`; the paths below are the host's, compiled in).
#![allow(dead_code)]

use std::path::PathBuf;

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

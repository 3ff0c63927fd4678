//! Where the integration tests of every crate find their data: the repository's
//! `tests/data`, and the third-party models under `../shared/assets-external` beside the
//! checkout. A missing third-party model fails the test where `CI=true` (CI has them) and is
//! otherwise one `skipping:` line on the terminal and a skipped check. Included by each test
//! binary (`#[path]`); the paths are the host's, compiled in (the bionic tests under qemu see
//! the host's files).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The workspace root: the nearest folder above the crate's manifest holding `Cargo.lock`.
pub fn workspace_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .find(|d| d.join("Cargo.lock").is_file())
        .unwrap_or(manifest)
        .to_path_buf()
}

/// The project's assets (`assets/`).
pub fn assets_dir() -> PathBuf {
    workspace_root().join("assets")
}

/// The repository's test data folder, `tests/data` (where the generators in
/// `tools/hostile-corpus` and `tools/skin-golden` write it).
pub fn data_dir() -> PathBuf {
    workspace_root().join("tests/data")
}

/// The folder holding third-party models, outside the repository.
pub fn external_dir() -> PathBuf {
    workspace_root().join("../shared/assets-external")
}

/// Whether `path` exists; if not, panics where `CI=true`, else prints why and returns false.
pub fn present(path: &Path) -> bool {
    if path.exists() {
        return true;
    }
    let why = format!("external model {} not found", path.display());
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{why} (CI=true: third-party models are required)");
    }
    // Written to stderr directly: libtest captures `eprintln!` of passing tests, and a skip
    // the user never sees is a hidden one.
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipping: {why}");
    false
}

/// A third-party model by its path under `../shared/assets-external` (e.g. `"Fox/Fox.glb"`),
/// `None` (after the `skipping:` line) where it is missing outside CI.
pub fn external_model(name: &str) -> Option<PathBuf> {
    let path = external_dir().join(name);
    present(&path).then_some(path)
}

/// The five third-party models the tests use.
pub const EXTERNAL_MODELS: [&str; 5] = [
    "CesiumMan/CesiumMan.glb",
    "Fox/Fox.glb",
    "RiggedFigure/RiggedFigure.glb",
    "RiggedSimple/RiggedSimple.glb",
    "QuaterniusWomanTankTop/WomanTankTop.glb",
];

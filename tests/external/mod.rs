//! Third-party models for the package's integration tests, as dermis-core's tests find them
//! (`core/tests/common`): under `../shared/assets-external`, beside the checkout. A missing
//! model fails the test where `CI=true` (CI has them) and is otherwise one `skipping:` line
//! on the terminal and a skipped check.
#![allow(dead_code)]

use std::path::PathBuf;

/// The folder holding third-party models, outside the repository.
pub fn external_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets-external")
}

/// Whether `path` exists; if not, panics where `CI=true`, else prints why and returns false.
pub fn present(path: &std::path::Path) -> bool {
    if path.exists() {
        return true;
    }
    let why = format!("external model {} not found", path.display());
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{why} (CI=true: third-party models are required)");
    }
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipping: {why}");
    false
}

/// A third-party model by its path under `../shared/assets-external`, `None` (after the
/// `skipping:` line) where it is missing outside CI.
pub fn external_model(name: &str) -> Option<PathBuf> {
    let path = external_dir().join(name);
    present(&path).then_some(path)
}

//! Where the desktop build finds its assets.

use std::path::PathBuf;

/// `$DERMIS_ASSETS`, else `./assets` if it exists, else the source tree's `assets/`.
pub fn assets_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("DERMIS_ASSETS") {
        return PathBuf::from(dir);
    }
    let local = PathBuf::from("assets");
    if local.join("character.glb").is_file() {
        return local;
    }
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

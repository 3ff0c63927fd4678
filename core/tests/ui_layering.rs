//! Layering: the engine modules (`ui`, `pool`, `render`) never depend on the game; the game
//! may use everything.

use std::path::Path;

fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    if dir.is_file() {
        out.push((
            dir.display().to_string(),
            std::fs::read_to_string(dir).unwrap(),
        ));
        return;
    }
    for entry in std::fs::read_dir(dir).unwrap() {
        sources(&entry.unwrap().path(), out);
    }
}

#[test]
fn engine_modules_do_not_import_the_game() {
    let core = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for module in ["ui", "pool.rs", "render"] {
        sources(&core.join(module), &mut files);
    }
    assert!(files.len() > 5);
    for (path, text) in files {
        for needle in ["crate::game", "super::game", "dermis_core::game"] {
            assert!(!text.contains(needle), "{path} uses {needle}");
        }
    }
}

//! The rules of the house about who imports whom, read from the sources: the game's rules,
//! the scene's plain data, the governor and the other engine modules below the renderer
//! import no renderer; no engine module imports the game or the app around it; the core
//! depends on no window system or Android crate. (A scan of `use` paths: a planted
//! `use crate::render::Renderer;` in `game/` fails it.)

use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The module paths `text` uses (`use` lines and `crate::…` paths in code), comments aside.
fn uses_module(text: &str, module: &str) -> Vec<String> {
    let patterns = [
        format!("crate::{module}::"),
        format!("crate::{module};"),
        format!("crate::{{{module}"),
        format!("super::{module}::"),
        format!("dermis_core::{module}::"),
    ];
    text.lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//"))
        .filter(|l| {
            patterns.iter().any(|p| l.contains(p.as_str()))
                || (l.starts_with("use crate::{") && l.contains(&format!(" {module}")))
        })
        .map(str::to_string)
        .collect()
}

fn core_src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("core/src")
}

/// Files of `core/src` whose path (relative, `/`-separated) starts with one of `prefixes`.
fn files_of(prefixes: &[&str]) -> Vec<(String, String)> {
    let root = core_src();
    sources(&root)
        .into_iter()
        .filter_map(|p| {
            let rel = p
                .strip_prefix(&root)
                .ok()?
                .to_string_lossy()
                .replace('\\', "/");
            prefixes
                .iter()
                .any(|x| rel.starts_with(x))
                .then(|| (rel, std::fs::read_to_string(&p).unwrap()))
        })
        .collect()
}

#[test]
fn below_the_renderer_nothing_imports_it() {
    let below = [
        "game/",
        "scene/",
        "governor.rs",
        "shading/",
        "anim/",
        "asset/",
        "camera.rs",
        "ui/",
        "pool.rs",
        "shader/",
    ];
    let files = files_of(&below);
    assert!(files.len() > 30, "only {} files scanned", files.len());
    for (file, text) in files {
        let found = uses_module(&text, "render");
        assert!(found.is_empty(), "{file} imports the renderer: {found:?}");
    }
}

#[test]
fn no_engine_module_imports_the_game_or_the_app() {
    let root = core_src();
    let mut scanned = 0;
    for p in sources(&root) {
        let rel = p
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel.starts_with("app/") || rel.starts_with("game/") || rel == "lib.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        for module in ["game", "app"] {
            let found = uses_module(&text, module);
            assert!(found.is_empty(), "{rel} imports `{module}`: {found:?}");
        }
        scanned += 1;
    }
    assert!(scanned > 60, "only {scanned} files scanned");
    // The game's rules do not know the app around them either.
    for (file, text) in files_of(&["game/"]) {
        let found = uses_module(&text, "app");
        assert!(found.is_empty(), "{file} imports the app: {found:?}");
    }
}

#[test]
fn the_core_depends_on_no_window_system_or_android_crate() {
    let manifest =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("core/Cargo.toml"))
            .unwrap();
    for krate in [
        "winit",
        "android-activity",
        "android_activity",
        "ndk",
        "jni",
    ] {
        let dep = manifest
            .lines()
            .map(str::trim)
            .any(|l| l.starts_with(&format!("{krate} ")) || l.starts_with(&format!("{krate}=")));
        assert!(!dep, "dermis-core depends on {krate}");
    }
}

#[test]
fn the_scan_finds_a_planted_import() {
    let planted = "//! docs\nuse crate::render::Renderer;\nfn f() {}\n";
    assert_eq!(uses_module(planted, "render").len(), 1);
    let grouped = "use crate::{anim::Pose, render::Gpu};\n";
    assert_eq!(uses_module(grouped, "render").len(), 1);
    let comment = "// crate::render::Renderer is drawn elsewhere\n";
    assert!(uses_module(comment, "render").is_empty());
    assert!(uses_module("use crate::scene::PropKind;\n", "render").is_empty());
}

//! The rules of the house the compiler cannot see, read from the sources. The compiler holds
//! the crates' layering: `dermis-engine` cannot name `dermis-game` (the game depends on the
//! engine), and neither can name `dermis-measure` or the shells. What is left is inside a
//! crate: the engine's modules below the renderer (the scene's plain data, shading, assets,
//! animation, the UI, the composer) import no renderer; the game's rules and its governor
//! import neither the renderer nor the app around them; and the platform-free crates depend
//! on no window system or Android crate. (A scan of `use` paths: a planted
//! `use crate::render::Renderer;` in `engine/src/scene/` fails it.)

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
        format!("dermis_engine::{module}::"),
        format!("dermis_game::{module}::"),
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

/// Files of the crate folder `krate` (`engine`, `game`) under `src/` whose path (relative,
/// `/`-separated) starts with one of `prefixes`.
fn files_of(krate: &str, prefixes: &[&str]) -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(krate)
        .join("src");
    sources(&root)
        .into_iter()
        .filter_map(|p| {
            let rel = p
                .strip_prefix(&root)
                .ok()?
                .to_string_lossy()
                .replace('\\', "/");
            prefixes.iter().any(|x| rel.starts_with(x)).then(|| {
                (
                    format!("{krate}/src/{rel}"),
                    std::fs::read_to_string(&p).unwrap(),
                )
            })
        })
        .collect()
}

#[test]
fn below_the_renderer_nothing_imports_it() {
    let below = [
        "scene/",
        "shading/",
        "anim/",
        "asset/",
        "camera.rs",
        "ui/",
        "pool.rs",
        "shader/",
    ];
    let mut files = files_of("engine", &below);
    files.extend(files_of("game", &["rules/", "governor.rs"]));
    assert!(files.len() > 30, "only {} files scanned", files.len());
    for (file, text) in files {
        let found = uses_module(&text, "render");
        assert!(found.is_empty(), "{file} imports the renderer: {found:?}");
    }
}

#[test]
fn the_games_rules_do_not_know_the_app_around_them() {
    let files = files_of("game", &["rules/"]);
    assert!(files.len() >= 4, "only {} files scanned", files.len());
    for (file, text) in files {
        let found = uses_module(&text, "app");
        assert!(found.is_empty(), "{file} imports the app: {found:?}");
    }
}

#[test]
fn the_platform_free_crates_depend_on_no_window_system_or_android_crate() {
    for krate in ["engine", "game"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(krate)
            .join("Cargo.toml");
        let manifest = std::fs::read_to_string(&path).unwrap();
        for dep in [
            "winit",
            "android-activity",
            "android_activity",
            "ndk",
            "jni",
        ] {
            let found = manifest
                .lines()
                .map(str::trim)
                .any(|l| l.starts_with(&format!("{dep} ")) || l.starts_with(&format!("{dep}=")));
            assert!(!found, "{krate}/Cargo.toml depends on {dep}");
        }
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
